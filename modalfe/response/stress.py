"""Stress and electric field recovered from an FE solution, their peaks over a cycle, and the load that
reaches a material limit.

At the quadrature points of every element of a part (scikit-fem ``Basis.interpolate(u).grad``):

    S = sym grad u (Voigt, engineering shears),  E = -grad phi,  sigma = c^E S - e^T E

(e-form, IEEE Std 176-1987 eq. (30); c^E and e rotated for the part's poling as in the assembly).
A harmonic state a + i b varies as a cos(wt) - b sin(wt). The peak over the cycle of a quantity that is
the square root of a quadratic form (|E|, von Mises) is exact: the largest eigenvalue of the 2 x 2
form in (cos, sin). The largest principal stress is sampled at 72 phases (relative error below
1 - cos(2.5 deg) = 1e-3) at the points whose peak stress norm could still exceed the best found.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from modalfe.errors import SceneError

# von Mises as a quadratic form in the Voigt stress (xx, yy, zz, yz, xz, xy): 1/2 [(s1-s2)^2 + ...] + 3 tau^2
_VM = np.array([[1, -0.5, -0.5, 0, 0, 0], [-0.5, 1, -0.5, 0, 0, 0], [-0.5, -0.5, 1, 0, 0, 0],
                [0, 0, 0, 3, 0, 0], [0, 0, 0, 0, 3, 0], [0, 0, 0, 0, 0, 3]], dtype=float)
# squared Frobenius norm of the stress tensor: an upper bound of every principal stress's square
_NORM = np.diag([1.0, 1, 1, 2, 2, 2])
PHASES = 72


@dataclass(frozen=True)
class Peak:
    """Largest value over a part and a cycle, and where: ``value`` [Pa or V/m] at ``point`` (x, y, z) [m]."""

    value: float
    point: tuple[float, float, float]


@dataclass(frozen=True)
class PartStress:
    """Peaks of one part per unit load: von Mises and largest principal (tensile) stress [Pa], and the
    electric field magnitude [V/m] (None where the part carries no potential)."""

    part: str
    material: str
    von_mises: Peak
    principal: Peak
    field: Peak | None


@dataclass(frozen=True)
class PartFields:
    """Fields of one part at the quadrature points of its cells (``elements``, indices into the mesh):
    ``points`` (3, nel, nq) [m], ``weights`` (nel, nq) [m^3] (the quadrature's dx), ``strain`` (6, nel, nq)
    Voigt with engineering shears [-], ``stress`` (6, nel, nq) [Pa], ``field`` (3, nel, nq) [V/m] or None where
    the part carries no potential."""

    elements: np.ndarray
    points: np.ndarray
    weights: np.ndarray
    strain: np.ndarray
    stress: np.ndarray
    field: np.ndarray | None


def part_fields(model, x: np.ndarray, part: str) -> PartFields:
    """Strain, stress and electric field of one part from a full DOF vector ``x`` (real or complex), by the
    module docstring's relations."""
    from skfem import Basis, ElementVector

    from modalfe.models.part_material import material_of
    from modalfe.models.solid import element_for

    dm, scene = model.mesh, model.scene
    if part not in dm.parts:
        raise SceneError(f"stress: no part '{part}'; parts: {sorted(dm.parts)}")
    mat, tensors = material_of(scene, scene.assembly().part(part), model.frame)
    scalar = element_for(scene.mesh)
    elements = dm.parts[part]
    ub = Basis(dm.mesh, ElementVector(scalar), intorder=2 * scene.mesh.order, elements=elements)
    x = np.asarray(x)

    def grads(basis, values):
        if np.iscomplexobj(values):
            return (np.asarray(basis.interpolate(values.real).grad)
                    + 1j * np.asarray(basis.interpolate(values.imag).grad))
        return np.asarray(basis.interpolate(values).grad)

    G = grads(ub, x[: model.n_u])  # (3, 3, nel, nq): G[i, j] = d u_i / d x_j
    S = np.stack([G[0, 0], G[1, 1], G[2, 2], G[1, 2] + G[2, 1], G[0, 2] + G[2, 0], G[0, 1] + G[1, 0]])
    C, e, _ = tensors(ub)  # constant (6, 6), (3, 6), or one per point (nel, nq, ...) where poled radially
    stress = np.einsum("...ab,...b->a...", C, np.moveaxis(S, 0, -1))
    field = None
    if mat.is_piezoelectric and model.n_phi:
        pb = Basis(dm.mesh, scalar, intorder=2 * scene.mesh.order, elements=elements)
        phi = np.zeros(pb.N, dtype=x.dtype)
        phi[model.phi_dofs] = x[model.n_u:]
        field = -grads(pb, phi)
        stress = stress - np.einsum("...ia,...i->a...", e, np.moveaxis(field, 0, -1))
    return PartFields(np.asarray(elements), np.asarray(ub.global_coordinates()), np.asarray(ub.dx), S, stress, field)


def von_mises(stress: np.ndarray) -> np.ndarray:
    """Von Mises stress [Pa] of a real Voigt stress (6, ...) [Pa]: sqrt(s^T Q s) with the module's form Q."""
    s = np.moveaxis(np.asarray(stress, dtype=float), 0, -1)
    return np.sqrt(np.maximum(np.einsum("...k,kl,...l->...", s, _VM, s), 0.0))


def von_mises_peak(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Peak over a cycle [Pa] of the von Mises stress of the harmonic Voigt stress a cos(wt) - b sin(wt), a and b
    (6, n) [Pa]: exact (module docstring)."""
    return _cycle_peak(np.asarray(a, dtype=float), np.asarray(b, dtype=float), _VM)


def _cycle_peak(a: np.ndarray, b: np.ndarray, Q: np.ndarray | None) -> np.ndarray:
    """Peak over a cycle of sqrt(s^T Q s) with s(t) = a cos t - b sin t; a, b (k, n)."""
    if Q is None:
        aa, bb, ab = (np.sum(a * a, 0), np.sum(b * b, 0), np.sum(a * b, 0))
    else:
        aa, bb, ab = (np.einsum("kn,kl,ln->n", a, Q, a), np.einsum("kn,kl,ln->n", b, Q, b),
                      np.einsum("kn,kl,ln->n", a, Q, b))
    top = 0.5 * (aa + bb) + np.sqrt(0.25 * (aa - bb) ** 2 + ab**2)
    return np.sqrt(np.maximum(top, 0.0))


def _principal_peak(stress: np.ndarray) -> tuple[float, int]:
    """(largest principal stress over the cycle, flat index of its point) from stress (6, n) complex."""
    a, b = stress.real, stress.imag
    bound = _cycle_peak(a, b, _NORM)
    order = np.argsort(-bound)
    t = np.linspace(0, 2 * np.pi, PHASES, endpoint=False)
    best, where = -np.inf, int(order[0])
    for start in range(0, len(order), 256):
        idx = order[start:start + 256]
        if bound[idx[0]] <= best:
            break
        s = a[:, idx, None] * np.cos(t) - b[:, idx, None] * np.sin(t)  # (6, m, phases)
        T = np.empty((*s.shape[1:], 3, 3))
        for (i, j), k in zip(((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)), range(6), strict=True):
            T[..., i, j] = T[..., j, i] = s[k]
        top = np.linalg.eigvalsh(T)[..., -1].max(axis=1)
        k = int(np.argmax(top))
        if top[k] > best:
            best, where = float(top[k]), int(idx[k])
    return best, where


def part_peaks(model, x: np.ndarray, parts=None) -> list[PartStress]:
    """Peaks over a cycle of von Mises, largest principal stress and |E| per part, for the harmonic state
    ``x`` (full DOF, complex; a real vector is a static state), for ``parts`` (default: every part)."""
    names = list(parts) if parts else list(model.mesh.parts)
    out = []
    for name in names:
        fields = part_fields(model, np.asarray(x, dtype=complex), name)
        field = fields.field
        p = fields.points.reshape(3, -1)
        s = fields.stress.reshape(6, -1)
        vm = _cycle_peak(s.real, s.imag, _VM)
        i = int(np.argmax(vm))
        principal, j = _principal_peak(s)
        e_peak = None
        if field is not None:
            f = field.reshape(3, -1)
            e = _cycle_peak(f.real, f.imag, None)
            k = int(np.argmax(e))
            e_peak = Peak(float(e[k]), tuple(map(float, p[:, k])))
        out.append(PartStress(name, model.scene.assembly().part(name).material,
                              Peak(float(vm[i]), tuple(map(float, p[:, i]))),
                              Peak(principal, tuple(map(float, p[:, j]))), e_peak))
    return out


def limit_loads(peaks: list[PartStress], scene) -> list[dict]:
    """For every part, the load amplitude [load units] that reaches each limit of its material: the
    depolarising (coercive) field by |E| and the tensile strength by the largest principal stress;
    "no limit in the table" where the material gives none."""
    from modalfe.scene.materials import strength_limits

    rows = []
    for p in peaks:
        limits = strength_limits(p.material, scene)
        for key, peak in (("depolarising_field", p.field), ("tensile_strength", p.principal)):
            if peak is None:
                continue
            limit = getattr(limits, key) if limits is not None else None
            rows.append({"part": p.part, "material": p.material, "limit": key,
                         "limit_value": limit, "source": None if limits is None or limit is None else limits.source,
                         "peak_per_unit_load": peak.value,
                         "load_to_limit": None if limit is None or peak.value <= 0 else limit / peak.value})
    return rows
