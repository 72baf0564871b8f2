"""Devices from files: CAD (STEP, BREP), gmsh scripts (.geo) and meshes (.msh), with their gmsh physical groups
named as the scene's parts and face groups.

A CAD file carries shapes but no names gmsh keeps (STEP labels and BREP have no physical groups): name the pieces
in a ``.geo`` script that merges it, e.g. ``Merge "plate.step"; Physical Volume("plate") = {1};
Physical Surface("clamp") = {5};``. A ``.geo`` file may as well build the geometry itself (``SetFactory
("OpenCASCADE")``). CAD and scripts are meshed here with tetrahedra (quadratic and curved on the CAD surfaces when
``order`` is 2); a ``.msh`` file is read as it is. Lengths: STEP files are converted to metres from the unit they
declare (OpenCASCADE's ``Geometry.OCCTargetUnit``); BREP, ``.geo`` and ``.msh`` files hold no unit and are read
in metres.

A scene naming such a file (``[geometry] file = ...``) gets an ``ImportedAssembly`` (``imported``): its parts are
``ImportedPart``s, read from the file's physical volumes (bounding box, volume) and its face groups from its
physical surfaces, each on the part it bounds (a poled one for a surface between two parts); the mesh step then
calls ``read_geometry``.

The mesh returned follows ``modalfe.models.mesh``: one meshio volume cell block with the cell sets
``part:NAME`` and one facet block (corner nodes only, as skfem matches boundary facets by their vertices) with
``face:NAME``.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import modalfe.caches as caches
from modalfe.errors import MeshError, SceneError
from modalfe.geometry.gmsh_model import gmsh_session
from modalfe.geometry.parts import Assembly, Face
from modalfe.geometry.shapes import _Shape, normalized_poling

CAD = (".step", ".stp", ".brep", ".brp")
SCRIPT = (".geo",)
MESH = (".msh",)
# gmsh volume element type -> (meshio name, geometric order, facet name, corner nodes per facet)
VOLUME_TYPES = {4: ("tetra", 1, "triangle", 3), 11: ("tetra10", 2, "triangle", 3), 5: ("hexahedron", 1, "quad", 4)}
FACET_TYPES = {2: 3, 9: 3, 3: 4}  # gmsh facet element type (3-node, 6-node triangle, 4-node quad) -> corners
_GMSH_TO_MESHIO = {11: [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]}  # gmsh numbers the 10-node tet's last two edges the other way
# corner indices of each facet of a volume element (VTK / meshio corner order)
_CELL_FACETS = {
    "tetra": ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)),
    "hexahedron": ((0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)),
}
CURVATURE_ELEMENTS = 12  # elements per 2 pi radians of a curved CAD edge (gmsh Mesh.MeshSizeFromCurvature)
TOUCH_TOLERANCE = 1e-7  # facets closer than this fraction of the model's size are touching (non-conforming check)


def read_geometry(path: str | Path, *, volumes: Mapping[str, object], faces: Sequence[str], size: float,
                  order: int):
    """The mesh (meshio.Mesh) of the file ``path``: its physical volumes ``volumes`` (names -> the scene's part
    settings, only the names are read) as cell sets ``part:NAME`` and its physical surfaces ``faces`` as
    ``face:NAME``. CAD and ``.geo`` files are meshed with tetrahedra of at most ``size`` [m] (refined on curved
    edges, ``CURVATURE_ELEMENTS`` per turn), of geometric ``order`` 1 or 2 ('tetra10', curved). A ``.msh`` file
    is read as it is: one volume element type, 4- or 10-node tetrahedra or 8-node hexahedra (linear tetrahedra
    are made quadratic, straight-sided, for ``order`` 2).

    MeshError when the file is missing or unreadable, a named group is not in it, a volume has no physical
    group (or is in a group that is no part), pieces touch without sharing nodes, or element types are mixed.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if order not in (1, 2):
        raise MeshError(f"mesh.order: an imported geometry is meshed with order 1 or 2, got {order}")
    if suffix not in MESH and not (np.isfinite(size) and size > 0):
        raise MeshError(f"mesh size must be positive and finite, got {size}")
    with _session(path, MeshError):
        check_groups(path.name, volumes, faces)
        if suffix in MESH:
            _prepare_file_mesh(path.name, order)
        else:
            _generate(path.name, size, order)
        mesh = physical_mesh(volumes, faces)
    check_conforming(mesh, path.name)
    return mesh


@contextlib.contextmanager
def _session(path: Path, error: type[Exception]):
    """gmsh initialised with the geometry file ``path`` open (lengths in metres), finalised on leaving; ``error``
    (MeshError or SceneError) when the file is of no known kind or missing, MeshError when gmsh cannot read it."""
    import gmsh

    if path.suffix.lower() not in CAD + SCRIPT + MESH:
        raise error(f"geometry.file: '{path.name}' is not a STEP, BREP, .geo or .msh file")
    if not path.is_file():
        raise error(f"geometry.file: '{path}' does not exist")
    with gmsh_session():
        gmsh.option.setString("Geometry.OCCTargetUnit", "M")
        gmsh.option.setNumber("Geometry.OCCBoundsUseStl", 1)  # OCC's own boxes are widened by its tolerance
        _open(path)
        yield


def _open(path: Path) -> None:
    """``gmsh.open(path)``, MeshError when gmsh cannot read it. A .msh file must start as one ("$MeshFormat", or
    "$NOD" for format 1): gmsh parses anything else as a script. After a failed parse gmsh's script parser stays
    inside the broken statement (gmsh 4.15: every later file of the process fails too), so it is fed a one-line
    script until that parses again."""
    import gmsh

    if path.suffix.lower() in MESH:
        with path.open("rb") as f:
            head = f.read(16).lstrip()
        if not head.startswith((b"$MeshFormat", b"$NOD")):
            raise MeshError(f"geometry.file: '{path.name}' is not a gmsh mesh file (no $MeshFormat header)")
    try:
        gmsh.open(str(path))
    except Exception as exc:  # gmsh raises bare Exception with its last error message
        _recover_parser()
        raise MeshError(f"geometry.file: gmsh cannot read '{path.name}': {exc}") from None


def _recover_parser(attempts: int = 8) -> None:
    """Parse a harmless script until gmsh's parser accepts it (each failed parse consumes the statement left open
    by a syntax error; three suffice after the errors seen)."""
    import tempfile

    import gmsh

    with tempfile.TemporaryDirectory() as folder:
        script = Path(folder) / "recover.geo"
        script.write_text("modalfe_recover = 0;\n")
        for _ in range(attempts):
            try:
                gmsh.open(str(script))
                return
            except Exception:  # the failure is the state being cleared
                continue


def check_groups(source: str, volumes: Mapping[str, object] | Sequence[str], faces: Sequence[str]) -> None:
    """MeshError unless the current gmsh model has a physical volume for every name of ``volumes`` and a physical
    surface for every name of ``faces``, every volume entity lies in exactly one physical volume, and every
    physical volume is one of ``volumes`` (a piece without a part would be dropped, a silently different device)."""
    import gmsh

    groups = {dim: {gmsh.model.getPhysicalName(dim, tag): tag for d, tag in gmsh.model.getPhysicalGroups()
                    if d == dim} for dim in (2, 3)}
    for dim, names, what in ((3, list(volumes), "physical volume"), (2, list(faces), "physical surface")):
        missing = [n for n in names if n not in groups[dim]]
        if missing:
            present = ", ".join(f"'{n}'" for n in sorted(groups[dim])) or "none"
            raise MeshError(f"{source}: no {what} named '{missing[0]}'; the file has {present}")
    foreign = sorted(set(groups[3]) - set(volumes))
    if foreign:
        raise MeshError(f"{source}: physical volume '{foreign[0]}' is no part of the scene; name it in the parts "
                        "or remove it from the file")
    for _, tag in gmsh.model.getEntities(3):
        owners = gmsh.model.getPhysicalGroupsForEntity(3, tag)
        if len(owners) != 1:
            box = ", ".join(f"{v:.4g}" for v in gmsh.model.getBoundingBox(3, tag))
            how = ("belongs to no physical volume (an unnamed piece; STEP and BREP files carry no physical groups: "
                   "name the pieces in a .geo file that Merges it, docs/guide.md)") if len(owners) == 0 else (
                "belongs to several physical volumes: " + ", ".join(
                    f"'{gmsh.model.getPhysicalName(3, int(g))}'" for g in owners))
            raise MeshError(f"{source}: volume {tag} (bounding box {box} m) {how}")


def _generate(source: str, size: float, order: int) -> None:
    """Tetrahedra of at most ``size`` [m], ``order`` 1 or 2 (curved on the CAD surfaces) on the current model."""
    import gmsh

    gmsh.model.mesh.clear()
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.MeshSizeMin", size / 20)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", CURVATURE_ELEMENTS)
    gmsh.option.setNumber("Mesh.ElementOrder", order)
    if order == 2:  # untangle curved elements whose mid-edge nodes, moved onto the surface, fold them
        gmsh.option.setNumber("Mesh.HighOrderOptimize", 2)
    try:
        gmsh.model.mesh.generate(3)
    except Exception as exc:  # gmsh raises bare Exception
        raise MeshError(f"{source}: gmsh failed to mesh the geometry: {exc}") from None


def _prepare_file_mesh(source: str, order: int) -> None:
    """Check a read mesh holds one supported volume element type; linear tetrahedra become quadratic for
    ``order`` 2 (straight-sided: a mesh file carries no CAD surface to curve them onto)."""
    import gmsh

    types = [int(t) for t in gmsh.model.mesh.getElementTypes(3)]
    names = [gmsh.model.mesh.getElementProperties(t)[0] for t in types]
    if not types:
        raise MeshError(f"{source}: the mesh has no volume elements")
    if len(types) > 1:
        raise MeshError(f"{source}: mixed volume element types ({', '.join(names)}); use one type")
    if types[0] not in VOLUME_TYPES:
        raise MeshError(f"{source}: volume elements '{names[0]}' are not supported; use 4- or 10-node "
                        "tetrahedra or 8-node hexahedra")
    _, file_order, _, _ = VOLUME_TYPES[types[0]]
    if types[0] == 4 and order == 2:
        gmsh.model.mesh.setOrder(2)
    elif file_order > order:
        raise MeshError(f"mesh.order: {source} holds quadratic tetrahedra; set the order to 2")


def physical_mesh(volumes: Mapping[str, object] | Sequence[str], faces: Sequence[str]):
    """meshio.Mesh of the current gmsh model's mesh: the elements of the physical volumes ``volumes`` as one
    cell block with cell sets ``part:NAME``, the facets of the physical surfaces ``faces`` (corner nodes) as a
    second block with ``face:NAME``; points are the nodes the volume elements use, element corners first in
    ascending order (scikit-fem's MeshTet2 numbers its vertices so, and keeps the facets' indices valid).
    MeshError for mixed volume element types or a group without elements."""
    import gmsh
    import meshio

    node_tags, coords, _ = gmsh.model.mesh.getNodes()
    index = np.zeros(int(node_tags.max()) + 1, dtype=np.int64)
    index[node_tags.astype(np.int64)] = np.arange(len(node_tags))
    points = coords.reshape(-1, 3)
    groups = {(dim, gmsh.model.getPhysicalName(dim, tag)): tag for dim, tag in gmsh.model.getPhysicalGroups()}
    blocks: dict[int, list[np.ndarray]] = {3: [], 2: []}
    sets: dict[str, tuple[int, np.ndarray]] = {}
    volume_type = None
    for dim, names, prefix in ((3, list(volumes), "part:"), (2, list(faces), "face:")):
        for name in names:
            conn = []
            for entity in gmsh.model.getEntitiesForPhysicalGroup(dim, groups[(dim, name)]):
                for etype, _, enodes in zip(*gmsh.model.mesh.getElements(dim, int(entity))):
                    etype = int(etype)
                    if dim == 3:
                        if etype not in VOLUME_TYPES or volume_type not in (None, etype):
                            raise MeshError(f"part '{name}': mixed or unsupported volume elements "
                                            f"('{gmsh.model.mesh.getElementProperties(etype)[0]}')")
                        volume_type = etype
                        nodes = gmsh.model.mesh.getElementProperties(etype)[3]
                        cells = index[enodes.astype(np.int64)].reshape(-1, nodes)
                        conn.append(cells[:, _GMSH_TO_MESHIO.get(etype, slice(None))])
                    elif etype in FACET_TYPES:
                        nodes = gmsh.model.mesh.getElementProperties(etype)[3]
                        conn.append(index[enodes.astype(np.int64)].reshape(-1, nodes)[:, : FACET_TYPES[etype]])
            if not conn:
                raise MeshError(f"physical group '{name}' got no {'volume' if dim == 3 else 'face'} elements")
            block = blocks[dim]
            start = sum(len(c) for c in block)
            block.append(np.concatenate(conn))
            sets[prefix + name] = (dim, np.arange(start, start + len(block[-1])))
    if volume_type is None:
        raise MeshError("the mesh has no volume elements: name the solids as physical volumes")
    vname, _, fname, facet_corners = VOLUME_TYPES[volume_type]
    if any(b.shape[1] != facet_corners for b in blocks[2]):
        raise MeshError(f"face groups: facets do not match the volume elements '{vname}' ({fname} expected)")
    volume_cells = np.concatenate(blocks[3])
    corners = np.unique(volume_cells[:, : 8 if vname == "hexahedron" else 4])
    used = np.r_[corners, np.setdiff1d(np.unique(volume_cells), corners)]  # nodes no volume uses are dropped
    remap = np.full(len(points), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    volume_cells = remap[volume_cells]
    empty = np.array([], dtype=int)
    cell_blocks = [(vname, volume_cells)]
    if blocks[2]:
        cell_blocks.append((fname, remap[np.concatenate(blocks[2])]))
    width = len(cell_blocks)
    cell_sets = {name: [ids if dim == 3 - k else empty for k in range(width)] for name, (dim, ids) in sets.items()}
    return meshio.Mesh(points[used], cell_blocks, cell_sets=cell_sets)


def check_conforming(mesh, source: str) -> None:
    """MeshError if two pieces touch without sharing nodes: the boundary facets (those of one volume element
    only) of a conforming mesh all lie on its outer skin, so a boundary facet whose centroid lies on another
    boundary facet (within ``TOUCH_TOLERANCE`` of the model's size) marks two volumes meshed apart on a common
    face (CAD solids that were not fragmented: gmsh ``BooleanFragments`` / ``occ.fragment`` makes them share it)."""
    from scipy.spatial import cKDTree

    volume = mesh.cells[0]
    facets_of = _CELL_FACETS["hexahedron" if volume.type == "hexahedron" else "tetra"]
    cells = volume.data
    facets = np.concatenate([cells[:, list(f)] for f in facets_of])  # corner nodes of every facet of every cell
    owner = np.tile(np.arange(len(cells)), len(facets_of))
    _, first, counts = np.unique(np.sort(facets, axis=1), axis=0, return_index=True, return_counts=True)
    outer = first[counts == 1]
    triangles = facets[outer][:, :3]  # a quad's first three corners span its plane and half of it
    points = mesh.points
    corners = points[triangles]  # (m, 3, 3)
    centroids = corners.mean(axis=1)
    reach = np.linalg.norm(corners - centroids[:, None], axis=2).max(axis=1)
    scale = float(np.linalg.norm(np.ptp(points, axis=0)))
    near = cKDTree(centroids).query_ball_point(centroids, reach * (1 + 1e-9))
    first = np.repeat(np.arange(len(near)), [len(n) for n in near])
    second = np.concatenate([np.asarray(n, dtype=np.int64) for n in near])
    pairs = first != second
    first, second = first[pairs], second[pairs]
    hit = np.flatnonzero(_on_triangle(corners[first], centroids[second], TOUCH_TOLERANCE * scale))
    if len(hit):
        i, j = first[hit[0]], second[hit[0]]
        names = sorted({_part_of(mesh, int(owner[outer[k]])) for k in (i, j)})
        x, y, z = centroids[j]
        raise MeshError(f"{source}: pieces touch without sharing nodes near ({x:.4g}, {y:.4g}, {z:.4g}) m (parts "
                        f"{' and '.join(repr(n) for n in names)}): non-conforming; fragment the touching volumes "
                        "(gmsh BooleanFragments) so that they share their common faces")


def _on_triangle(corners: np.ndarray, targets: np.ndarray, tolerance: float) -> np.ndarray:
    """Which ``targets`` (k, 3) lie on their triangles ``corners`` (k, 3, 3): within ``tolerance`` of its plane and
    inside its edges (barycentric coordinates >= 0)."""
    a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
    normal = np.cross(b - a, c - a)
    area2 = np.linalg.norm(normal, axis=1)
    normal = normal / area2[:, None]
    d = targets - a
    close = np.abs(np.sum(d * normal, axis=1)) <= tolerance
    u = np.sum(np.cross(b - a, d) * normal, axis=1) / area2  # barycentric weight of c
    v = np.sum(np.cross(d, c - a) * normal, axis=1) / area2  # of b
    return close & (u >= -1e-9) & (v >= -1e-9) & (u + v <= 1 + 1e-9)


def _part_of(mesh, cell: int) -> str:
    """The part (cell set ``part:NAME``) holding volume element ``cell``."""
    return next((name[5:] for name, blocks in mesh.cell_sets.items()
                 if name.startswith("part:") and cell in blocks[0]), "?")


_INCLUDED = re.compile(r'\b(?:Merge|Include|ShapeFromFile)\s*\(?\s*"([^"]+)"')  # files a .geo script reads


def file_digest(path: str | Path) -> str:
    """SHA-256 (hex, 20 digits) of a geometry file's bytes and, for a ``.geo`` script, of the files it names in
    ``Merge "..."``, ``Include "..."`` and ``ShapeFromFile("...")`` (relative to the script; one level: files
    those merge in turn are not followed). The mesh cache key holds it, so an edited file is meshed again."""
    path = Path(path)
    h = hashlib.sha256()
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise SceneError(f"geometry.file: cannot read '{path}': {exc.strerror or exc}") from None
    h.update(data)
    if path.suffix.lower() in SCRIPT:
        for name in _INCLUDED.findall(data.decode("utf-8", errors="replace")):
            other = path.parent / name
            h.update(name.encode())
            h.update(other.read_bytes() if other.is_file() else b"<missing>")
    return h.hexdigest()[:20]


@dataclass(frozen=True)
class ImportedPart(_Shape):
    """A part read from a geometry file: one physical volume. Its extent is its bounding box ``bounds`` ((lo, hi)
    [m]), ``volume`` [m^3] the file's (CAD) or its mesh's; ``sides`` are the face groups (physical surfaces) on it,
    ``areas`` [m^2] their areas on this part. ``inside`` tests the bounding box only (what the overlap and bond
    checks of ``modalfe.geometry.parts`` read: the file's own conformity is checked when it is meshed). Poling
    along an axis, or radial about ``axis`` through ``centre`` (a point [m]) when both are given."""

    name: str
    region: str
    material: str
    bounds: tuple[tuple[float, float, float], tuple[float, float, float]]
    volume: float
    sides: tuple[str, ...] = ()
    areas: tuple[float, ...] = ()
    poling: int | str = 0
    axis: str = "z"
    centre: tuple[float, float, float] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "poling", normalized_poling(self.name, self.poling,
                                                             radial_allowed=self.centre is not None))

    def _bounds(self):
        return self.bounds

    @property
    def thickness(self) -> float:
        """Smallest extent of the bounding box [m]."""
        return min(self.size)

    def area(self, side: str, window=None) -> float:
        self.face_bounds(side, window) if window is not None else self.face(side)
        return self.areas[self.sides.index(side)]

    def inside(self, points: np.ndarray, tol: float = 0.0) -> np.ndarray:
        """Whether points (n, 3) [m] lie in the bounding box widened by ``tol`` [m]."""
        p = np.asarray(points, dtype=float)
        return np.all((p >= np.array(self.lo) - tol) & (p <= np.array(self.hi) + tol), axis=-1)

    def planar_face(self, side: str):
        """None: a file's faces are compared by name (``modalfe.scene.checks``)."""
        return None

    def face_bounds(self, side: str, window=None):
        """SceneError: what needs a face's rectangle (a face group's centre or mean as an output, antinodes on a
        face, windows) is not known for a file's surface."""
        raise SceneError(f"face '{self.name}.{side}': a geometry file's surface has no rectangle to place points "
                         f"on (a face group's centre or mean, antinodes); give a point output (--point NAME=X,Y,Z)")

    @property
    def poling_faces(self) -> None:
        """None: which of the file's surfaces the poling runs between is not known."""
        return None


@dataclass(frozen=True)
class ImportedAssembly(Assembly):
    """An ``Assembly`` read from the geometry ``file`` (absolute path) whose content hashes to ``digest``."""

    file: str = ""
    digest: str = ""


def imported(*, file: str, digest: str, parts: Sequence[Mapping]) -> ImportedAssembly:
    """The assembly of a geometry file: ``parts`` (``modalfe.scene.part_tables.imported_parts``: group, material,
    region, poling, axis, centre) name its physical volumes; every physical surface is a face group."""
    volumes, surfaces = _summary(str(file), digest)
    names = [str(p["group"]) for p in parts]
    for i, name in enumerate(names):
        if name not in volumes:
            known = ", ".join(f"'{n}'" for n in sorted(volumes)) or "none"
            raise SceneError(f"parts[{i}].group: no physical volume '{name}' in {Path(file).name}; it has {known}")
    foreign = sorted(set(volumes) - set(names))
    if foreign:
        raise SceneError(f"parts: physical volume '{foreign[0]}' of {Path(file).name} is no part; add a [[parts]] "
                         f"table with group = '{foreign[0]}' (a piece left out would change the device)")
    poled = {str(p["group"]) for p in parts if p.get("poling", 0) not in (0, None, "", "0")}
    on: dict[str, dict[str, float]] = {}  # part -> face group -> area
    for group, pieces in surfaces.items():
        for owners, area in pieces:
            owner = next((o for o in owners if o in poled), owners[0])
            on.setdefault(owner, {}).setdefault(group, 0.0)
            on[owner][group] += area
    built = []
    for spec in parts:
        name = str(spec["group"])
        lo, hi, volume = volumes[name]
        sides = on.get(name, {})
        built.append(ImportedPart(name, str(spec.get("region", name)), str(spec["material"]), (lo, hi), volume,
                                  tuple(sides), tuple(sides.values()), spec.get("poling", 0),
                                  str(spec.get("axis", "z")),
                                  None if spec.get("centre") is None else tuple(spec["centre"])))
    faces = {g: tuple(Face(part, g) for part, sides in on.items() if g in sides) for g in surfaces}
    return ImportedAssembly(tuple(built), faces, file=str(file), digest=digest)


@functools.lru_cache(maxsize=16)
def _summary(file: str, digest: str):
    """What the scene reads of a geometry file (cached by its path and ``digest``): physical volume -> (lo, hi,
    volume), physical surface -> [(names of the physical volumes its piece bounds, area), ...]. SceneError naming
    ``geometry.file`` when the file cannot be read or has unnamed pieces."""
    path = Path(file)
    try:
        with _session(path, SceneError):
            return _read_summary(path.name)
    except MeshError as exc:
        raise SceneError(f"geometry.file: {exc}") from None


caches.register("imported geometry summaries", _summary.cache_clear)


def _read_summary(source: str):
    """``_summary`` of the open gmsh model (MeshError for unnamed pieces)."""
    import gmsh

    names = {tag: gmsh.model.getPhysicalName(3, tag) for _, tag in gmsh.model.getPhysicalGroups(3)}
    check_groups(source, list(names.values()), [])
    owner = {int(e): names[int(gmsh.model.getPhysicalGroupsForEntity(3, int(e))[0])]
             for _, e in gmsh.model.getEntities(3)}
    volumes = {}
    for tag, name in names.items():
        entities = [int(e) for e in gmsh.model.getEntitiesForPhysicalGroup(3, tag)]
        boxes = np.array([gmsh.model.getBoundingBox(3, e) for e in entities])
        volumes[name] = (tuple(float(x) for x in boxes[:, :3].min(axis=0)),
                         tuple(float(x) for x in boxes[:, 3:].max(axis=0)),
                         sum(_measure(3, e) for e in entities))
    surfaces = {}
    for _, tag in gmsh.model.getPhysicalGroups(2):
        name = gmsh.model.getPhysicalName(2, tag)
        pieces = []
        for e in gmsh.model.getEntitiesForPhysicalGroup(2, tag):
            owners = tuple(owner[int(v)] for v in gmsh.model.getAdjacencies(2, int(e))[0] if int(v) in owner)
            if not owners:
                raise MeshError(f"{source}: surface {int(e)} of physical surface '{name}' bounds no named volume")
            pieces.append((owners, _measure(2, int(e))))
        surfaces[name] = pieces
    return volumes, surfaces


def _measure(dim: int, tag: int) -> float:
    """Volume (dim 3) or area (dim 2) of a gmsh entity [m^3, m^2]: OpenCASCADE's for CAD shapes, else the sum
    over its mesh elements of the Jacobian determinant times the Gauss weights (a .msh file's discrete entities)."""
    import gmsh

    try:
        return float(gmsh.model.occ.getMass(dim, tag))
    except Exception:  # not an OpenCASCADE entity (gmsh raises bare Exception)
        pass
    total = 0.0
    for etype in gmsh.model.mesh.getElementTypes(dim, tag):
        local, weights = gmsh.model.mesh.getIntegrationPoints(int(etype), "Gauss2")
        _, det, _ = gmsh.model.mesh.getJacobians(int(etype), local, tag=tag)
        total += float(np.sum(np.abs(det).reshape(-1, len(weights)) @ weights))
    return total
