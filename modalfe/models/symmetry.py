"""Mirror symmetry: a scene may be solved on the half (quarter) of the device on one side of its mid-planes
(``Scene.symmetry``); these two maps are the only place that knows how the solved part relates to the whole.

``fold`` sends points of the whole device into the solved part (a point in a mirrored half reads its image,
with the displacement component normal to that plane negated); ``unfold`` mirrors points and vector fields
of the solved part into the whole device. The modes a symmetric model returns are the ones symmetric about
its planes, so the displacement normal to a plane is odd across it and the others even.
"""

from __future__ import annotations

import numpy as np


def mirror_planes(scene) -> list[tuple[int, float]]:
    """(axis index, 2 x plane coordinate [m]) of every mirror plane of ``scene``: a point's image along that
    axis is ``twice_plane - x``."""
    lo, hi = scene.full_assembly().bounds
    return [("xyz".index(a), lo["xyz".index(a)] + hi["xyz".index(a)]) for a in scene.symmetry]


def mirrored(points: np.ndarray, axis: int, twice_plane: float) -> np.ndarray:
    """Copy of ``points`` (3, n) reflected about the plane ``x[axis] = twice_plane / 2``."""
    image = np.array(points, dtype=float, copy=True)
    image[axis] = twice_plane - image[axis]
    return image


def fold(scene, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(points (3, n) moved into the solved part, sign (3, n) of each displacement component there):
    a point beyond a mirror plane reads its image, the component normal to the plane negated."""
    p = np.array(points, dtype=float, copy=True)
    sign = np.ones_like(p)
    for axis, twice in mirror_planes(scene):
        far = p[axis] > 0.5 * twice
        p[axis, far] = twice - p[axis, far]
        sign[axis, far] = -1.0
    return p, sign


def unfold(scene, points: np.ndarray, *fields: np.ndarray) -> tuple[np.ndarray, ...]:
    """(points, *fields) of the whole device from those of the solved part: points (3, n) and vector fields
    (3, n) each get their mirror images appended per plane (normal component negated), n doubling per plane."""
    points = np.asarray(points, dtype=float)
    fields = [np.asarray(f) for f in fields]
    for axis, twice in mirror_planes(scene):
        points = np.hstack([points, mirrored(points, axis, twice)])
        flipped = []
        for f in fields:
            image = np.array(f, copy=True)
            image[axis] = -image[axis]
            flipped.append(np.hstack([f, image]))
        fields = flipped
    return (points, *fields)


def _cells(model) -> tuple[np.ndarray, int]:
    """(connectivity in VTK order, VTK cell type) of the model's mesh."""
    from skfem.io.meshio import HEX_MAPPING

    dm = model.mesh
    if dm.element == "hex":
        return dm.mesh.t[HEX_MAPPING[:8]].T, 12  # VTK_HEXAHEDRON
    return dm.mesh.t.T, 10  # VTK_TETRA


def whole_device_mesh(model, fields: dict[str, np.ndarray]):
    """(points (n, 3), cells in VTK vertex order, VTK cell type, per-point vector fields (n, 3) from ``fields``
    (3, n_vertices) each, per-cell part ids, part names) of a solid model's whole device: a symmetric model is
    mirrored, normal components of vector fields negated, mirrored cells reordered to keep a positive volume."""
    scene = model.scene
    mesh = model.mesh.mesh
    points = mesh.p[:, : mesh.nvertices].T.copy()  # a curved mesh's higher-order nodes follow its vertices
    cells, kind = _cells(model)
    part_id = np.zeros(len(cells), dtype=int)
    names = list(model.mesh.parts)
    for i, name in enumerate(names):
        part_id[model.mesh.parts[name]] = i
    fields = {k: v.T.copy() for k, v in fields.items()}  # (n, 3)
    for k, twice in mirror_planes(scene):
        mirror = mirrored(points.T, k, twice).T
        flipped = cells[:, [1, 0, 3, 2, 5, 4, 7, 6]] if kind == 12 else cells[:, [1, 0, 2, 3]]
        cells = np.vstack([cells, flipped + len(points)])  # reordered: mirrored cells keep a positive volume
        points = np.vstack([points, mirror])
        part_id = np.concatenate([part_id, part_id])
        for name, value in fields.items():
            m = value.copy()
            m[:, k] *= -1
            fields[name] = np.vstack([value, m])
    return points, cells, kind, fields, part_id, names
