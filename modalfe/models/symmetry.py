"""Mirror symmetry: a scene may be solved on the half (quarter) of the device on one side of its mid-planes
(``Scene.symmetry``); these two maps are the only place that knows how the solved part relates to the whole.

``fold`` sends points of the whole device into the solved part (a point in a mirrored half reads its image,
with the displacement component normal to that plane negated); ``unfold`` mirrors points and vector fields
of the solved part into the whole device. The modes a symmetric model returns are the ones symmetric about
its planes, so the displacement normal to a plane is odd across it and the others even; about a plane of
``Scene.antisymmetry`` the other way round (every component of the image negated once more).
"""

from __future__ import annotations

import numpy as np


def mirror_planes(scene) -> list[tuple[int, float]]:
    """(axis index, 2 x plane coordinate [m]) of every mirror plane of ``scene``: a point's image along that
    axis is ``twice_plane - x``."""
    lo, hi = scene.full_assembly().bounds
    return [("xyz".index(a), lo["xyz".index(a)] + hi["xyz".index(a)]) for a in scene.mirror_axes]


def image_signs(scene) -> list[np.ndarray]:
    """Per plane of ``mirror_planes``: the sign (3,) of each displacement component in the image, the normal one
    negated about a plane of symmetry, the two others about one of antisymmetry."""
    signs = []
    for axis, parity in [("xyz".index(a), 1.0) for a in scene.symmetry] + \
                        [("xyz".index(a), -1.0) for a in scene.antisymmetry]:
        sign = np.full(3, parity)
        sign[axis] = -parity
        signs.append(sign)
    return signs


def mirrored(points: np.ndarray, axis: int, twice_plane: float) -> np.ndarray:
    """Copy of ``points`` (3, n) reflected about the plane ``x[axis] = twice_plane / 2``."""
    image = np.array(points, dtype=float, copy=True)
    image[axis] = twice_plane - image[axis]
    return image


def fold(scene, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(points (3, n) moved into the solved part, sign (3, n) of each displacement component there):
    a point beyond a mirror plane reads its image, its components signed by ``image_signs``."""
    p = np.array(points, dtype=float, copy=True)
    sign = np.ones_like(p)
    for (axis, twice), flip in zip(mirror_planes(scene), image_signs(scene)):
        far = p[axis] > 0.5 * twice
        p[axis, far] = twice - p[axis, far]
        sign[:, far] *= flip[:, None]
    return p, sign


def unfold(scene, points: np.ndarray, *fields: np.ndarray) -> tuple[np.ndarray, ...]:
    """(points, *fields) of the whole device from those of the solved part: points (3, n) and vector fields
    (3, n) each get their mirror images appended per plane (signed by ``image_signs``), n doubling per plane."""
    points = np.asarray(points, dtype=float)
    fields = [np.asarray(f) for f in fields]
    for (axis, twice), flip in zip(mirror_planes(scene), image_signs(scene)):
        points = np.hstack([points, mirrored(points, axis, twice)])
        fields = [np.hstack([f, f * flip[:, None]]) for f in fields]
    return (points, *fields)


# a mirrored cell's vertex list: position j holds the image of the copied cell's vertex MIRRORED_ORDER[j] (VTK order),
# which keeps its volume positive (an involution: the copied cell's position of the image's j is MIRRORED_ORDER[j] too)
VTK_HEXAHEDRON, VTK_TETRA = 12, 10  # VTK's cell type numbers (vtkCellType.h)
MIRRORED_ORDER = {VTK_HEXAHEDRON: np.array([1, 0, 3, 2, 5, 4, 7, 6]), VTK_TETRA: np.array([1, 0, 2, 3])}
# a scikit-fem hexahedron's corners in VTK's vertex order: skfem.io.meshio.HEX_MAPPING[:8] (scikit-fem's meshio
# conversion), written here as importing that module loads meshio's every format and rich, 0.1 s of one core in
# `show`'s drawing process
VTK_HEX_CORNERS = np.array([0, 3, 6, 2, 1, 5, 7, 4])


def solved_elements(model, cells: np.ndarray, corners: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(the solved mesh's element (n,), the local vertex number (n, m) in it, the displacement components' sign
    (3, n)) of ``whole_device_mesh``'s cells ``cells`` (n,) and vertex positions ``corners`` (n, m) in their VTK
    lists: a mirrored copy is its solved element, vertices reordered (``MIRRORED_ORDER``), components signed by
    ``image_signs``."""
    solved = model.mesh.mesh.t.shape[1]
    kind = _cells(model)[1]
    copy = np.asarray(cells) // solved  # bit l: mirrored about plane l (``unfold``'s doubling per plane)
    vertex = np.array(corners, copy=True)
    sign = np.ones((3, len(copy)))
    for level, flip in enumerate(image_signs(model.scene)):
        image = (copy >> level) & 1 == 1
        vertex[image] = MIRRORED_ORDER[kind][vertex[image]]
        sign[:, image] *= flip[:, None]
    return np.asarray(cells) % solved, (VTK_HEX_CORNERS[vertex] if kind == VTK_HEXAHEDRON else vertex), sign



def _cells(model) -> tuple[np.ndarray, int]:
    """(connectivity in VTK order, VTK cell type) of the model's mesh."""
    dm = model.mesh
    if dm.element == "hex":
        return dm.mesh.t[VTK_HEX_CORNERS].T, VTK_HEXAHEDRON
    return dm.mesh.t.T, VTK_TETRA


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
    for (k, twice), flip in zip(mirror_planes(scene), image_signs(scene)):
        mirror = mirrored(points.T, k, twice).T
        cells = np.vstack([cells, cells[:, MIRRORED_ORDER[kind]] + len(points)])  # volumes kept positive
        points = np.vstack([points, mirror])
        part_id = np.concatenate([part_id, part_id])
        for name, value in fields.items():
            fields[name] = np.vstack([value, value * flip])
    return points, cells, kind, fields, part_id, names
