"""Loads beyond the drive voltage, and outputs at points and face groups.

A load is one of (per unit of its amplitude: a force or pressure given as (0, 0, 2) N or 2 Pa gives the same
results as (0, 0, 1) N or 1 Pa, its value sets only the direction and sign, ``Load.magnitude``):

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

import numpy as np
import scipy.sparse as sp

from modalfe.errors import SceneError
from modalfe.models.axisymmetric import AxisymmetricModel
from modalfe.scene.loads import Load, check_forcing

MEAN_PREFIX = "mean:"


def output_points(scene, outputs) -> dict[str, np.ndarray]:
    """Points [m] for named outputs: a face group's centre (e.g. ``foot_1``: the foot tip), or
    explicit coordinates given as (x, y, z); the names checked by ``check_outputs``."""
    assembly = scene.full_assembly()
    out = {}
    for item in outputs:
        if isinstance(item, str):
            centres = []
            for f in assembly.faces[item]:
                axis, c, lo, hi = assembly.part(f.part).face_bounds(f.side, f.window)
                centre = [(lo[k] + hi[k]) / 2 for k in range(3)]
                centre[axis] = c
                centres.append(centre)
            out[item] = np.mean(centres, axis=0)
        else:
            name, point = item
            out[str(name)] = np.asarray(point, dtype=float)
    return out


def check_outputs(scene, outputs, point_field: str = "outputs") -> None:
    """One name, one output, before any solve: every face group named (``GROUP``, ``mean:GROUP``) exists, no name
    is given twice, and no point takes a face group's name (``point_field`` names where points come from)."""
    faces = scene.full_assembly().faces
    seen = set()
    for item in outputs:
        point = not isinstance(item, str)
        name = str(item[0]) if point else item
        field = point_field if point else "outputs"
        if name in seen:
            raise SceneError(f"{field}: '{name}' given twice; one name, one output")
        seen.add(name)
        if point and name in faces:
            raise SceneError(f"{field}: '{name}' is a face group of the scene (its centre is an output by that name); "
                             f"give the point a name of its own")
        group = name[len(MEAN_PREFIX):] if _is_mean(name) else name
        if not point and group not in faces:
            raise SceneError(f"outputs: no face group '{group}'; known: {sorted(faces)}")


def load_vector(model, load: Load) -> tuple[np.ndarray, np.ndarray]:
    """(f, x_p): full DOF load per unit ``load`` (per N along a force, per Pa of a pressure, whatever their value)
    and the prescribed part of the response (the driven electrodes' potential for a voltage, zero otherwise); the
    response is T x_free + x_p."""
    check_forcing(model.scene, load)
    if load.kind == "voltage":
        return model.voltage_load(1.0), model.prescribed_potential(1.0)
    f = np.zeros(model.ndofs)
    if load.kind == "base-acceleration":
        f[: model.n_u] = -(model.M[: model.n_u, : model.n_u] @ rigid_translation(model, load.axis))
        return f, np.zeros(model.ndofs)
    traction = model.face_load(load) if isinstance(model, AxisymmetricModel) else face_traction_load(model, load)
    f[: model.n_u] = traction / load.magnitude
    return f, np.zeros(model.ndofs)


def rigid_translation(model, axis: str) -> np.ndarray:
    """u DOF vector (n_u,) of a unit rigid translation along ``axis`` (nodal Lagrange/serendipity DOFs:
    one on every DOF of that component)."""
    r = np.zeros(model.n_u)
    dofs = model.u_basis.get_dofs(elements=np.arange(model.u_basis.mesh.t.shape[1]))
    r[dofs.all(f"u^{'xyz'.index(axis) + 1}")] = 1.0
    return r


def rigid_translations(model) -> np.ndarray:
    """(3, ndofs) unit rigid translations along x, y, z on the displacement unknowns (solid model: the vector
    element's unknowns cycle x, y, z at each node); the axisymmetric model's own (radial, its twin, the axis:
    ``AxisymmetricModel.rigid_translations``). SceneError naming the fidelity on a beam or plate model."""
    if hasattr(model, "rigid_translations"):
        return model.rigid_translations()
    if not hasattr(model, "u_basis"):
        raise SceneError("fidelity: rigid translations need the 3-D solid or the axisymmetric model")
    r = np.zeros((3, model.ndofs))
    for d, axis in enumerate("xyz"):
        r[d, : model.n_u] = rigid_translation(model, axis)
    return r


def face_traction_load(model, load: Load) -> np.ndarray:
    """u DOF load (n_u,) of a force (total over the whole device's face group, spread by area) or a normal
    pressure on a face group, as given (``load_vector`` takes it per unit); the half (quarter) model takes the part
    of the group it keeps."""
    from skfem import LinearForm

    from modalfe.models.facets import facet_basis

    dm = model.mesh
    if load.group not in dm.faces:  # the mirror image of a face kept by the symmetric model
        return np.zeros(model.n_u)
    fb = facet_basis(dm.mesh, model.u_basis.elem, dm.faces[load.group], intorder=2 * model.scene.mesh.order)
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
    check_outputs(model.scene, outputs)
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
    from modalfe.geometry.parts import Box

    if isinstance(model, AxisymmetricModel):  # the revolved body's mean, exact over the circumference
        return model.face_mean(group)
    full = model.scene.full_assembly()
    if not all(isinstance(full.part(f.part), Box) for f in full.faces[group]):
        return _facet_mean_operator(model, group, full)
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


def _facet_mean_operator(model, group: str, full) -> sp.csr_matrix:
    """(3, ndofs) area mean of the displacement over a face group of curved or imported parts: the integral of each
    displacement component over the group's mesh facets (the curved geometry's own quadrature) over their area."""
    from skfem import LinearForm

    from modalfe.models.facets import facet_basis

    if model.scene.assembly().faces.get(group) != full.faces[group]:  # ``full``: the whole device's assembly
        raise SceneError(f"outputs: {MEAN_PREFIX}{group} lies on a mirror plane of the half model; solve the whole "
                         f"device (--set 'symmetry=[]')")
    device_mesh = model.mesh
    fb = facet_basis(device_mesh.mesh, model.u_basis.elem, device_mesh.faces[group],
                     intorder=2 * model.scene.mesh.order)
    rows = [LinearForm(lambda v, w, k=k: v[k]).assemble(fb) for k in range(3)]
    area = float(fb.dx.sum())
    if not area > 0:
        raise SceneError(f"outputs: face group '{group}' has no area in the mesh")
    block = sp.csr_matrix(np.vstack(rows) / area)
    return sp.hstack([block, sp.csr_matrix((3, model.K.shape[0] - block.shape[1]))], format="csr")


def harmonic_state(model, load: Load, frequency: float, *, damping=None, reference_omega: float | None = None
                   ) -> np.ndarray:
    """Full DOF response (complex) per unit ``load`` at ``frequency`` [Hz] by one direct solve of
    (A - omega^2 B + i omega C) x = T^T f; ``damping`` (``modalfe.response.forced.Damping``) as in
    ``harmonic_response``, none when None. At 0 Hz this is the static response (supports must hold the body)."""
    from modalfe.solve.linalg import factorize, solve_complex

    T = model.constraints("short").T
    f, x_p = load_vector(model, load)
    w = 2 * np.pi * float(frequency)
    A = (T.T @ (model.K - w**2 * model.M) @ T).tocsr()
    if damping is not None:
        C = model.rayleigh_damping(*damping.rayleigh_at(reference_omega or w))
        A = (A + 1j * w * (T.T @ C @ T)).tocsr()
        return T @ solve_complex(A, T.T @ f) + x_p
    solve, _ = factorize(A)
    return T @ solve(T.T @ f) + x_p
