"""Loads beyond the drive voltage, and outputs at points and face groups.

A load is one of (per unit of its amplitude):

- ``voltage``: 1 V on the driven electrodes, f = -K x_1V (``Model.voltage_load``);
- ``force GROUP=Fx,Fy,Fz``: a total force [N] on a face group, spread uniformly by area
  (traction F / A, like the scene's face springs, so a half model carries its share);
- ``pressure GROUP=P``: a normal pressure [Pa] pushing into the body, traction -P n with n the
  outward normal of the face;
- ``base-acceleration AXIS``: the clamps and the face springs' anchors move rigidly with an
  acceleration of 1 m/s^2 along AXIS. With u = u_rel + r u_b (r the rigid translation along AXIS,
  K r = 0 for the body, the springs pull on u - r u_b) the relative motion obeys
  M u_rel'' + K u_rel = -M r a (Clough & Penzien, Dynamics of Structures, 2nd ed. 1993, sec. 26-2);
  outputs are relative to the base, the absolute acceleration is -omega^2 u_rel + a.

Outputs: a face group's name (its centre point, as before), ``mean:GROUP`` (the area mean of the
displacement over the face group) or ``(name, (x, y, z))`` [m].
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from modalfe.errors import SceneError

KINDS = ("voltage", "force", "pressure", "base-acceleration")
UNITS = {"voltage": "V", "force": "N", "pressure": "Pa", "base-acceleration": "m/s^2"}
MEAN_PREFIX = "mean:"


@dataclass(frozen=True)
class Load:
    """One load case: ``kind`` (one of KINDS), the face ``group`` it acts on (force, pressure),
    ``value`` (force: (Fx, Fy, Fz) [N] in total; pressure: (P,) [Pa]), ``axis`` (base acceleration)."""

    kind: str = "voltage"
    group: str | None = None
    value: tuple[float, ...] = ()
    axis: str | None = None

    def __post_init__(self) -> None:
        field = "drive.load"
        if self.kind not in KINDS:
            raise SceneError(f"{field}: kind must be one of {', '.join(KINDS)}, got {self.kind!r}")
        object.__setattr__(self, "value", tuple(float(x) for x in self.value))
        if self.kind in ("force", "pressure"):
            if not isinstance(self.group, str) or not self.group:
                raise SceneError(f"{field}.group: a {self.kind} needs a face group")
            n = 3 if self.kind == "force" else 1
            if len(self.value) != n or not all(math.isfinite(x) for x in self.value):
                what = "Fx, Fy, Fz [N]" if n == 3 else "one pressure [Pa]"
                raise SceneError(f"{field}.value: a {self.kind} needs {what}, got {list(self.value)}")
            if not any(self.value):
                raise SceneError(f"{field}.value: the {self.kind} is zero")
        if self.kind == "base-acceleration" and self.axis not in ("x", "y", "z"):
            raise SceneError(f"{field}.axis: base acceleration needs an axis x, y or z, got {self.axis!r}")

    @property
    def unit(self) -> str:
        """Unit of one load: the results are per this unit."""
        return UNITS[self.kind]

    def describe(self) -> str:
        if self.kind == "voltage":
            return "voltage on the driven electrodes"
        if self.kind == "force":
            return f"force ({', '.join(f'{x:g}' for x in self.value)}) N on '{self.group}', spread by area"
        if self.kind == "pressure":
            return f"pressure {self.value[0]:g} Pa on '{self.group}'"
        return f"base acceleration along {self.axis} (clamps and spring anchors move rigidly)"

    @classmethod
    def parse(cls, text: str, field: str = "drive.load") -> Load:
        """``voltage``, ``force GROUP=Fx,Fy,Fz``, ``pressure GROUP=P`` or ``base-acceleration x|y|z``."""
        if not isinstance(text, str):
            raise SceneError(f"{field}: expected a load such as 'force actuator=0,0,1', got {text!r}")
        words = text.strip().split(None, 1)
        kind = words[0].replace("_", "-") if words else ""
        rest = words[1].strip() if len(words) > 1 else ""
        if kind == "voltage" and not rest:
            return cls()
        if kind == "base-acceleration":
            return cls(kind=kind, axis=rest or None)
        match = re.fullmatch(r"([^=\s]+)\s*=\s*(.+)", rest)
        if kind in ("force", "pressure") and match:
            try:
                numbers = tuple(float(x) for x in match.group(2).split(","))
            except ValueError:
                raise SceneError(f"{field}: expected numbers after '{match.group(1)}=', got {text!r}") from None
            return cls(kind=kind, group=match.group(1), value=numbers)
        raise SceneError(f"{field}: expected 'voltage', 'force GROUP=FX,FY,FZ', 'pressure GROUP=P' or "
                         f"'base-acceleration x|y|z', got {text!r}")

    @classmethod
    def from_value(cls, value, field: str = "drive.load") -> Load:
        """A Load, a text (``parse``) or a table ``{kind, group, value, axis}`` from a scene file."""
        if isinstance(value, Load):
            return value
        if isinstance(value, str):
            return cls.parse(value, field)
        if not isinstance(value, Mapping):
            raise SceneError(f"{field}: must be a text such as 'force actuator=0,0,1' or a table "
                             f"{{kind, group, value, axis}}, got {value!r}")
        unknown = sorted(set(value) - {"kind", "group", "value", "axis"})
        if unknown:
            raise SceneError(f"{field}.{unknown[0]}: unknown key; known: axis, group, kind, value")
        kind = value.get("kind", "voltage")
        if not isinstance(kind, str):
            raise SceneError(f"{field}.kind: must be one of {', '.join(KINDS)}, got {kind!r}")
        raw = value.get("value", ())
        raw = [raw] if isinstance(raw, (int, float)) and not isinstance(raw, bool) else raw
        if not isinstance(raw, (list, tuple)) or not all(isinstance(x, (int, float)) and not isinstance(x, bool)
                                                         for x in raw):
            raise SceneError(f"{field}.value: must be a number or an array of numbers, got {raw!r}")
        group = value.get("group")
        if group is not None and not isinstance(group, str):
            raise SceneError(f"{field}.group: must be a face group name, got {group!r}")
        return cls(kind=kind.replace("_", "-"), group=group, value=tuple(raw), axis=value.get("axis"))


def check_load(scene, load: Load) -> None:
    """Refuse a load the scene cannot take, before any solve: a missing face group or driven electrode, or a
    load that is not symmetric about the mirror planes of a half (quarter) model."""
    if load.kind == "voltage":
        if "drive" not in scene.electrodes.values():
            raise SceneError("drive.load: the scene has no driven electrode to apply a voltage to; give a force, "
                             "pressure or base acceleration (--force GROUP=FX,FY,FZ, --pressure GROUP=P, "
                             "--base-acceleration z, or drive.load)")
        return
    full = scene.full_assembly()
    if load.kind in ("force", "pressure") and load.group not in full.faces:
        raise SceneError(f"drive.load.group: no face group '{load.group}'; known: {sorted(full.faces)}")
    for axis in scene.symmetry:
        k = "xyz".index(axis)
        if load.kind == "base-acceleration" and load.axis == axis:
            raise SceneError(f"drive.load.axis: a base acceleration along {axis} is antisymmetric about the "
                             f"{axis} mid-plane the model keeps (symmetry); set symmetry = [] to solve it")
        if load.kind in ("force", "pressure"):
            lo, hi = _group_bounds(full, load.group)
            mid = 0.5 * (full.bounds[0][k] + full.bounds[1][k])
            if not math.isclose(lo[k] + hi[k], 2 * mid, rel_tol=0, abs_tol=1e-9 * (full.bounds[1][k] + 1)):
                raise SceneError(f"drive.load.group: '{load.group}' is not symmetric about the {axis} mid-plane "
                                 f"the model keeps (symmetry); load a symmetric group or set symmetry = []")
            if load.kind == "force" and load.value[k] != 0:
                raise SceneError(f"drive.load.value: a force along {axis} is antisymmetric about the {axis} "
                                 f"mid-plane the model keeps (symmetry); set symmetry = [] to solve it")


def _group_bounds(assembly, group: str) -> tuple[np.ndarray, np.ndarray]:
    los, his = [], []
    for f in assembly.faces[group]:
        _, _, lo, hi = assembly.part(f.part).face_bounds(f.side, f.window)
        los.append(lo)
        his.append(hi)
    return np.min(los, axis=0), np.max(his, axis=0)


def load_vector(model, load: Load) -> tuple[np.ndarray, np.ndarray]:
    """(f, x_p): full DOF load per unit ``load`` and the prescribed part of the response (the driven
    electrodes' potential for a voltage, zero otherwise); the response is T x_free + x_p."""
    check_load(model.scene, load)
    if load.kind == "voltage":
        return model.voltage_load(1.0), model.prescribed_potential(1.0)
    f = np.zeros(model.ndofs)
    if load.kind == "base-acceleration":
        f[: model.n_u] = -(model.M[: model.n_u, : model.n_u] @ rigid_translation(model, load.axis))
        return f, np.zeros(model.ndofs)
    f[: model.n_u] = face_traction_load(model, load)
    return f, np.zeros(model.ndofs)


def rigid_translation(model, axis: str) -> np.ndarray:
    """u DOF vector (n_u,) of a unit rigid translation along ``axis`` (nodal Lagrange/serendipity DOFs:
    one on every DOF of that component)."""
    r = np.zeros(model.n_u)
    dofs = model.u_basis.get_dofs(elements=np.arange(model.u_basis.mesh.t.shape[1]))
    r[dofs.all(f"u^{'xyz'.index(axis) + 1}")] = 1.0
    return r


def face_traction_load(model, load: Load) -> np.ndarray:
    """u DOF load (n_u,) of a force (total over the whole device's face group, spread by area) or a normal
    pressure on a face group; the half (quarter) model takes the part of the group it keeps."""
    from skfem import FacetBasis, LinearForm

    dm = model.mesh
    if load.group not in dm.faces:  # the mirror image of a face kept by the symmetric model
        return np.zeros(model.n_u)
    fb = FacetBasis(dm.mesh, model.u_basis.elem, facets=dm.faces[load.group], intorder=2 * model.scene.mesh.order)
    if load.kind == "force":
        t = np.asarray(load.value) / model.scene.full_assembly().face_area(load.group)

        @LinearForm
        def traction(v, _):
            return t[0] * v[0] + t[1] * v[1] + t[2] * v[2]
    else:
        p = load.value[0]

        @LinearForm
        def traction(v, w):
            return -p * (w.n[0] * v[0] + w.n[1] * v[1] + w.n[2] * v[2])
    return traction.assemble(fb)


def output_operators(model, outputs) -> dict[str, sp.csr_matrix]:
    """Name -> (3, ndofs) rows giving (ux, uy, uz) [m] of an output from a full DOF vector: a face group's
    centre point (``foot_1``), the area mean over a face group (``mean:foot_1``) or a point (name, (x, y, z))."""
    from modalfe.response.forced import output_points

    out = {}
    points = output_points(model.scene, [o for o in outputs if not _is_mean(o)])
    for name, p in points.items():
        out[name] = model.displacement_probes(p.reshape(1, 3))
    for o in outputs:
        if _is_mean(o):
            out[o] = face_mean_operator(model, o[len(MEAN_PREFIX):])
    return {name: out[name] for name in _names(outputs)}


def _is_mean(item) -> bool:
    return isinstance(item, str) and item.startswith(MEAN_PREFIX)


def _names(outputs) -> list[str]:
    return [o if isinstance(o, str) else str(o[0]) for o in outputs]


def face_mean_operator(model, group: str, *, per_element: int = 4) -> sp.csr_matrix:
    """(3, ndofs) area mean of the displacement over a face group of the whole device: the midpoint rule on
    cells ``per_element`` times finer than the mesh (error O((h / 4)^2) of the displacement's curvature),
    points beyond a mirror plane read their images (``Model.displacement_probes``)."""
    full = model.scene.full_assembly()
    if group not in full.faces:
        raise SceneError(f"outputs: no face group '{group}' for {MEAN_PREFIX}{group}; known: {sorted(full.faces)}")
    spacing = float(model.mesh.size) / per_element
    rows, weights = [], []
    for f in full.faces[group]:
        axis, c, lo, hi = full.part(f.part).face_bounds(f.side, f.window)
        grids = []
        for k in range(3):
            if k == axis:
                grids.append(np.array([c]))
                continue
            n = int(min(200, max(2, math.ceil((hi[k] - lo[k]) / spacing))))
            grids.append(lo[k] + (np.arange(n) + 0.5) * (hi[k] - lo[k]) / n)
        X, Y, Z = np.meshgrid(*grids, indexing="ij")
        pts = np.column_stack([X.ravel(), Y.ravel(), Z.ravel()])
        area = float(np.prod([hi[k] - lo[k] for k in range(3) if k != axis]))
        P = model.displacement_probes(pts)  # rows component-major: all ux, all uy, all uz
        n = len(pts)
        rows.append(sp.vstack([sp.csr_matrix(P[j * n:(j + 1) * n].mean(axis=0)) for j in range(3)]))
        weights.append(area)
    total = sum(weights)
    return sum((w / total) * R for w, R in zip(weights, rows, strict=True)).tocsr()


def harmonic_state(model, load: Load, frequency: float, *, damping=None, reference_omega: float | None = None
                   ) -> np.ndarray:
    """Full DOF response (complex) per unit ``load`` at ``frequency`` [Hz] by one direct solve of
    (A - omega^2 B + i omega C) x = T^T f; ``damping`` (``modalfe.response.forced.Damping``) as in
    ``harmonic_response``, none when None. At 0 Hz this is the static response (supports must hold the body)."""
    from scipy.sparse.linalg import splu

    from modalfe.solve.linalg import factorize

    T = model.constraints("short").T
    f, x_p = load_vector(model, load)
    w = 2 * np.pi * float(frequency)
    A = (T.T @ (model.K - w**2 * model.M) @ T).tocsr()
    if damping is not None:
        alpha, beta = damping.rayleigh_at(reference_omega or w)
        K_mech = sp.block_diag([model.K[: model.n_u, : model.n_u], sp.csr_matrix((model.n_phi, model.n_phi))])
        A = (A + 1j * w * (T.T @ (alpha * model.M + beta * K_mech) @ T)).tocsr()
    if damping is None:
        solve, _ = factorize(A)
    else:
        solve = splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True}).solve
    return T @ solve((T.T @ f).astype(A.dtype)) + x_p
