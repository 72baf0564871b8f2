"""Mesh a box assembly with gmsh, convert it to scikit-fem through meshio, cache it by parameters.

A scene's geometry file (``modalfe.geometry.imported.ImportedAssembly``) is meshed by ``read_geometry``
(curved quadratic tetrahedra); its cache key holds the digest of the file's bytes (and of the files a .geo
merges), so an edited file is meshed again.

Structured hexahedra (transfinite volumes on the tensor grid of the parts' coordinates) when
``element="hex"``, unstructured tetrahedra otherwise. A box assembly's mesh is geometrically linear
(exact for boxes); quadratic fields come from the element chosen in the model (serendipity hex or P2
tet). An assembly with cylinders, rings or extruded outlines is meshed with quadratic, curved
tetrahedra (gmsh ``Mesh.ElementOrder`` 2 -> skfem ``MeshTet2``: the mid-edge nodes of the boundary lie
on the true surface, so a disc's rim is not a polygon).
"""

from __future__ import annotations

import contextlib
import hashlib
import itertools
import logging
import math
import os
import tempfile
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

import modalfe.caches as caches
from modalfe.errors import MeshError
from modalfe.geometry.imported import ImportedAssembly, physical_mesh, read_geometry
from modalfe.geometry.shapes import Ring
from modalfe.models.swept import swept_mesh

log = logging.getLogger(__name__)

MESH_FORMAT_VERSION = 7  # 3: key, element and checksum stored inside the file; 4: nodes numbered by physical_mesh;
# 5: a swept section left with a triangle subdivided at the sizes asked (issue 35); 6: circles on a box grid's
# section meshed as O-grid blocks (``modalfe.models.section_blocks``); 7: their cells reach out to the box edges near
# them (``Block.reaching``)
GRADING_RATIO = 0.4  # size ratio of neighbouring element layers toward a clamped face
# a ring's elements are at most its wall / RING_WALL_ELEMENTS long: quadratic elements on a thin curved wall lock in
# membrane (bending carries spurious stretching, e.g. Stolarski & Belytschko, J. Appl. Mech. 49 (1982) 172). Measured
# on the free steel ring of docs/studies.md (R 20 mm, wall 1 mm, 20-node hexahedra, one layer): n = 2 is 13.6 %,
# 0.57 % and 0.05 % high with elements 4, 2 and 1 mm long
RING_WALL_ELEMENTS = 1.0
# elements across each side of a face carrying an attached mass (hexahedra): a smeared mass has modes of its own
# (bouncing, rocking, twisting on the structure under it) whose shapes span the patch. On the honeycomb tile's 40 mm
# actuator pad 2 quadratic elements across put them 2-33 % high and 4 within 1-2 % of quartic elements; every
# estimate level must resolve them (with 2 across on the coarsest level, x2.25, its twisting mode mixed with the
# pad's and the estimate missed the error), so the scene's mesh gets 4 x 2.25 = 9 and its coarsest level 4
MASS_PATCH_ELEMENTS = 9
_memory_cache: dict[str, DeviceMesh] = {}


def _forget_files() -> None:
    folder = cache_dir()
    for path in (folder / "meshes").glob("*.npz") if folder is not None else ():
        with contextlib.suppress(OSError):
            path.unlink()


caches.register("meshes in memory", _memory_cache.clear)
caches.register("mesh files", _forget_files, disk=True)


@dataclass(frozen=True)
class DeviceMesh:
    """A scikit-fem mesh with its named parts, regions and faces.

    mesh : skfem MeshHex1 (boxes), MeshTet1, or for assemblies with non-box parts MeshTet2 or MeshHex2 (swept,
           ``modalfe.models.swept``), curved (coordinates in m)
    parts : part name -> element indices
    faces : face group name -> facet indices
    key : content hash of the parameters that built it
    seconds : wall time to build it (0 when read from the cache)
    """

    mesh: object
    parts: dict[str, np.ndarray]
    faces: dict[str, np.ndarray]
    element: str
    size: float
    key: str
    seconds: float

    @property
    def nelements(self) -> int:
        return self.mesh.t.shape[1]


CACHE_OFF = ("off", "none", "0", "false", "no")


def cache_dir() -> Path | None:
    """Where meshes are cached: $MODALFE_CACHE, else $XDG_CACHE_HOME/modalfe, else ~/.cache/modalfe;
    None when ``MODALFE_CACHE=off`` (or none, 0, false, no): no disk cache."""
    root = os.environ.get("MODALFE_CACHE")
    if root and root.strip().lower() in CACHE_OFF:
        return None
    if root:
        return Path(root)
    return Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "modalfe"


def divisions(assembly, axis: int, breaks: np.ndarray, sizes: Mapping[str, float],
              min_layers: int = 3, patches: Sequence[tuple[int, float, float, float]] = ()) -> np.ndarray:
    """Elements per grid interval along ``axis``: ceil(length / size), with the size the smallest
    asked for by any part spanning that interval, or by a ``patch`` (axis, lo, hi, size) spanning it; the main
    (largest) part gets at least ``min_layers`` elements across each of its dimensions, so bending through its
    thickness is resolved (one quadratic layer under-estimates shear and rotary effects)."""
    return np.array([max(1, int(np.ceil((b - a) / interval_size(assembly, axis, a, b, sizes, min_layers, patches)
                                        - 1e-9)))
                     for a, b in itertools.pairwise(breaks)])


def interval_size(assembly, axis: int, a: float, b: float, sizes: Mapping[str, float], min_layers: int,
                  patches: Sequence[tuple[int, float, float, float]] = ()) -> float:
    """Element size [m] along ``axis`` on the grid interval [a, b] (``divisions``): the smallest asked for by the
    parts and ``patches`` spanning it, at most the main part's size / ``min_layers``; its length where nothing
    spans it."""
    main = assembly.main_part
    mid = (a + b) / 2
    spanning = [sizes[p.name] for p in assembly.parts if p.lo[axis] <= mid <= p.hi[axis]]
    spanning += [h for k, lo, hi, h in patches if k == axis and lo <= mid <= hi]
    h = min(spanning) if spanning else b - a
    if main.lo[axis] <= mid <= main.hi[axis]:
        h = min(h, main.size[axis] / min_layers)
    return h


def graded_breaks(assembly, breaks: list[np.ndarray], faces: Sequence[str], sizes: Mapping[str, float],
                  layers: int) -> list[np.ndarray]:
    """``breaks`` plus ``layers`` grid planes toward each face of the groups ``faces``, at distances
    h r^k (k = 1..layers, r = GRADING_RATIO, h the face's part's element size) inside its part.

    Where a clamped face meets a free one the stress is singular (Williams 1952, J. Appl. Mech. 19,
    526), which uniform refinement resolves slowly: the ciliary beam's mode 6 converges at order
    ~1.9 in h instead of the ~4 of quadratic elements on smooth fields (docs/benchmark_peer.md).
    Planes closer than a third of their own distance to an existing break are skipped (no slivers).
    """
    out = [b.copy() for b in breaks]
    for group in faces:
        for face in assembly.faces[group]:
            part = assembly.part(face.part)
            axis, plane, _, _ = part.face_bounds(face.side, face.window)
            inward = 1.0 if face.side.endswith("min") else -1.0
            for k in range(1, layers + 1):
                distance = sizes[part.name] * GRADING_RATIO**k
                if distance >= part.size[axis] / 2:
                    continue
                at = plane + inward * distance
                if np.min(np.abs(out[axis] - at)) > distance / 3:
                    out[axis] = np.sort(np.append(out[axis], at))
    return out


def element_sizes(scene) -> dict[str, float]:
    """Target element size per part [m]: the shortest of the bending wavelength of the device's
    main layer stack and the part's shear wavelength at ``scene.max_frequency``, divided by
    ``mesh.elements_per_wavelength`` and clipped to [mesh.min_size, mesh.max_size]."""
    assembly = scene.assembly()
    settings = scene.mesh
    f = scene.max_frequency
    wavelength_bending = bending_wavelength(scene, assembly, f)
    sizes = {}
    for part in assembly.parts:
        mat = scene.material(part.material)
        lam = min(wavelength_bending, mat.wave_speed_shear() / f)
        h = lam / settings.elements_per_wavelength
        if isinstance(part, Ring):  # curved thin wall: elements no longer than it is thick (see RING_WALL_ELEMENTS)
            h = min(h, (part.outer - part.inner) / RING_WALL_ELEMENTS)
        sizes[part.name] = float(np.clip(h, settings.min_size, settings.max_size))
    return sizes


def resolved_frequency(scene) -> float:
    """The highest frequency [Hz] the scene's mesh resolves at ``mesh.elements_per_wavelength``: where the wavelength
    sizes (``element_sizes`` unclipped) fall to the elements' actual sizes, which ``mesh.max_size`` and a part shorter
    than one element (the mesher divides it into one at least) make smaller than ``scene.max_frequency`` asks, and
    ``mesh.min_size`` larger. Bisection in ln f (the sizes fall monotonically with frequency)."""
    settings = scene.mesh
    unclipped = replace(settings, min_size=0.0, max_size=math.inf)
    extents = {part.name: max(part.size) for part in scene.assembly().parts}
    actual = {name: min(h, extents[name]) for name, h in element_sizes(scene).items()}

    def resolved(f: float) -> bool:
        at = replace(scene, mesh=replace(unclipped, max_frequency=f),
                     analysis=replace(scene.analysis, near=f, band=None))
        return all(h >= actual[name] for name, h in element_sizes(at).items())

    lo, hi = scene.max_frequency, scene.max_frequency
    while resolved(hi * 2) and hi < 1e15:
        hi *= 2
    hi *= 2
    while not resolved(lo) and lo > 1e-6:
        lo /= 2
    for _ in range(40):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if resolved(mid) else (lo, mid)
    return lo


def bending_wavelength(scene, assembly, frequency: float) -> float:
    """Flexural wavelength 2 pi (D / (m omega^2))^(1/4) [m] of the layer stack along the device's
    ``thickness_axis`` through the centre of the part with the largest footprint normal to it (classical laminate
    D about the stack's neutral axis)."""
    k = assembly.thickness_axis
    u, v = (k + 1) % 3, (k + 2) % 3
    host = max(assembly.parts, key=lambda p: p.size[u] * p.size[v])
    cu, cv = (host.lo[u] + host.hi[u]) / 2, (host.lo[v] + host.hi[v]) / 2
    stack = [p for p in assembly.parts if p.lo[u] <= cu <= p.hi[u] and p.lo[v] <= cv <= p.hi[v]]
    layers = []
    for p in stack:
        C = scene.material(p.material).C
        layers.append((p.lo[k], p.hi[k], C[0, 0] - C[0, 2] ** 2 / C[2, 2], scene.material(p.material).rho))
    stiffness = sum(E * (z1 - z0) for z0, z1, E, _ in layers)
    neutral = sum(E * (z1 - z0) * (z0 + z1) / 2 for z0, z1, E, _ in layers) / stiffness
    D = sum(E * ((z1 - neutral) ** 3 - (z0 - neutral) ** 3) / 3 for z0, z1, E, _ in layers)
    mass = sum(rho * (z1 - z0) for z0, z1, _, rho in layers)
    omega = 2 * np.pi * frequency
    return float(2 * np.pi * (D / (mass * omega**2)) ** 0.25)


def build_mesh(assembly, *, size: float | Mapping[str, float], element: str = "hex",
               min_layers: int = 3, graded_faces: Sequence[str] = (), grading_layers: int = 0,
               patches: Sequence[tuple[int, float, float, float]] = (), use_cache: bool = True) -> DeviceMesh:
    """Mesh ``assembly`` with target element ``size`` [m] (one value, or one per part name);
    ``element`` is "hex" (structured) or "tet"; hex meshes get ``grading_layers`` geometric layers
    toward the face groups ``graded_faces`` (see ``graded_breaks``) and elements no larger than a ``patch``'s size
    over its span ((axis, lo, hi, size), ``mass_patches``)."""
    if element not in ("hex", "tet"):
        raise MeshError(f"mesh.element must be 'hex' or 'tet', got '{element}'")
    if element == "hex" and assembly.shaped and assembly.sweep_axis is None:
        raise MeshError(f"mesh.element: the cylinders, rings and extrusions stand on different axes (part "
                        f"'{assembly.shaped[0]}'); swept hexahedra need one axis: set mesh.element = 'tet'")
    sizes = size if isinstance(size, Mapping) else {p.name: size for p in assembly.parts}
    for name, h in sizes.items():
        if not (np.isfinite(h) and h > 0):
            raise MeshError(f"mesh size of part '{name}' must be positive and finite, got {h}")
    size = min(sizes.values())
    grading = (tuple(graded_faces), grading_layers) if element == "hex" and graded_faces and grading_layers else None
    for group in graded_faces:
        if group not in assembly.faces:
            raise MeshError(f"graded_faces: no face group named '{group}'")
    patches = tuple(patches) if element == "hex" else ()
    key = hashlib.sha256(
        repr((MESH_FORMAT_VERSION, assembly, sorted(sizes.items()), element, min_layers, grading)
             + ((patches,) if patches else ())).encode()
    ).hexdigest()[:20]
    if use_cache and key in _memory_cache:
        return _memory_cache[key]
    folder = cache_dir() if use_cache else None
    path = folder / "meshes" / f"{key}.npz" if folder is not None else None
    if path is not None and path.exists():
        try:
            result = _load(path, key, element, size)
            _check(result, assembly)
            if set(result.parts) != {p.name for p in assembly.parts} or set(result.faces) != set(assembly.faces):
                raise ValueError("its parts or face groups are not the assembly's")
            _memory_cache[key] = result
            return result
        except Exception as exc:  # any damage (truncated zip, bad CRC, wrong content): rebuild and overwrite
            log.warning("mesh cache: rebuilding damaged or foreign %s (%s: %s)", path, type(exc).__name__, exc)
    start = time.perf_counter()
    if isinstance(assembly, ImportedAssembly):  # curved quadratic tetrahedra on the file's surfaces
        try:
            meshio_mesh = read_geometry(assembly.file, volumes=[p.name for p in assembly.parts],
                                        faces=list(assembly.faces), size=tet_size(assembly, sizes, min_layers),
                                        order=2)
        except MeshError as exc:  # name the scene file's field at fault
            raise MeshError(str(exc) if str(exc).startswith(("geometry.", "mesh.")) else f"geometry.file: {exc}") \
                from None
    elif element == "hex" and assembly.shaped:
        mesh, parts, faces = _swept(assembly, sizes, min_layers, patches)
    else:
        meshio_mesh = _gmsh_mesh(assembly, sizes=sizes, element=element, min_layers=min_layers, grading=grading,
                                 patches=patches)
    if element == "tet" or not assembly.shaped:
        mesh, parts, faces = _to_skfem(meshio_mesh, assembly)
    result = DeviceMesh(mesh, parts, faces, element, float(size), key, time.perf_counter() - start)
    _check(result, assembly)
    if use_cache:
        if path is not None:
            _save(path, result)
        _memory_cache[key] = result
    return result


def mass_patches(scene, size_factor: float = 1.0) -> tuple[tuple[int, float, float, float], ...]:
    """(axis, lo, hi, size) over each in-plane side of every face carrying an attached mass: ``MASS_PATCH_ELEMENTS``
    elements across the whole device's face (a half model's cut face keeps the whole one's elements), times
    ``size_factor`` (an estimate level's elements are as much larger there as elsewhere)."""
    assembly = scene.full_assembly()
    out = []
    for group in scene.masses:
        for face in assembly.faces.get(group, ()):
            rect = assembly.face_rect(face)
            if rect is None:  # a curved wall: no grid interval to size
                continue
            normal, _, lo, hi = rect
            out += [(axis, float(lo[axis]), float(hi[axis]), (hi[axis] - lo[axis]) / MASS_PATCH_ELEMENTS * size_factor)
                    for axis in range(3) if axis != normal and hi[axis] > lo[axis]]
    return tuple(out)


def tet_size(assembly, sizes: Mapping[str, float], min_layers: int) -> float:
    """Largest tetrahedron [m]: the smallest part size, and at most the main part's thickness / ``min_layers``."""
    return min(min(sizes.values()), assembly.main_part.thickness / min_layers)


def _swept(assembly, sizes: Mapping[str, float], min_layers: int, patches=()):
    """``modalfe.models.swept.swept_mesh`` with the structured grid's layers along the sweep axis (``divisions``)."""
    from modalfe.geometry.gmsh_model import grid_breaks

    if any(f.window is not None for faces in assembly.faces.values() for f in faces):
        # the section mesh has no edges along a window's border: its facets would only approximate the window
        raise MeshError("mesh.element: face windows need a scene of boxes only (the structured grid puts element edges "
                        "on their borders); use whole faces with cylinders, rings or extrusions")
    axis = assembly.sweep_axis
    breaks = grid_breaks(assembly)[axis]
    return swept_mesh(assembly, dict(sizes), divisions(assembly, axis, breaks, sizes, min_layers, patches), breaks)


def _gmsh_mesh(assembly, *, sizes: Mapping[str, float], element: str, min_layers: int, grading=None, patches=()):
    """Run gmsh on the assembly; return a meshio.Mesh with cell sets per part and face group."""
    import gmsh

    from modalfe.geometry.gmsh_model import add_grid, add_parts, gmsh_session, grid_breaks

    with gmsh_session():
        if element == "hex":
            breaks = grid_breaks(assembly)
            if grading is not None:
                breaks = graded_breaks(assembly, breaks, grading[0], sizes, grading[1])
            add_grid(assembly, breaks)
            counts = [divisions(assembly, k, b, sizes, min_layers, patches) for k, b in enumerate(breaks)]
            _set_transfinite(breaks, counts)
        else:
            if any(f.window is not None for faces in assembly.faces.values() for f in faces):
                raise MeshError("mesh.element: face windows need a scene of boxes only, on hexahedra (the structured "
                                "grid puts element edges on their borders)")
            add_parts(assembly)
            size = tet_size(assembly, sizes, min_layers)
            gmsh.option.setNumber("Mesh.MeshSizeMax", size)
            gmsh.option.setNumber("Mesh.MeshSizeMin", size / 20)
        curved = bool(assembly.shaped)
        gmsh.option.setNumber("Mesh.ElementOrder", 2 if curved else 1)
        if curved:  # untangle curved elements whose mid-edge nodes, moved onto the surface, fold them
            gmsh.option.setNumber("Mesh.HighOrderOptimize", 2)
        try:
            gmsh.model.mesh.generate(3)
        except Exception as exc:  # gmsh raises bare Exception
            raise MeshError(f"gmsh failed to mesh the assembly: {exc}") from exc
        names = {dim: [gmsh.model.getPhysicalName(dim, tag) for _, tag in gmsh.model.getPhysicalGroups(dim)]
                 for dim in (2, 3)}
        return physical_mesh(names[3], names[2])  # a foot is a part and a face group: part:NAME, face:NAME


def _set_transfinite(breaks: list[np.ndarray], counts: list[np.ndarray]) -> None:
    """Structured divisions: each curve gets the count of the grid interval it spans."""
    import gmsh

    for dim, tag in gmsh.model.getEntities(1):
        x0, y0, z0, x1, y1, z1 = gmsh.model.getBoundingBox(dim, tag)
        span = np.array([x1 - x0, y1 - y0, z1 - z0])
        axis = int(np.argmax(span))
        lo = (x0, y0, z0)[axis]
        i = int(np.argmin(np.abs(breaks[axis] - lo)))
        gmsh.model.mesh.setTransfiniteCurve(tag, int(counts[axis][i]) + 1)
    for _, tag in gmsh.model.getEntities(2):
        gmsh.model.mesh.setTransfiniteSurface(tag)
        gmsh.model.mesh.setRecombine(2, tag)
    for _, tag in gmsh.model.getEntities(3):
        gmsh.model.mesh.setTransfiniteVolume(tag)


def _to_skfem(meshio_mesh, assembly):
    """meshio -> skfem, keeping part subdomains and face-group boundaries."""
    from skfem.io.meshio import from_meshio

    mesh = from_meshio(meshio_mesh, ignore_orientation=True)
    parts = {p.name: np.asarray(mesh.subdomains[f"part:{p.name}"]) for p in assembly.parts}
    faces = {g: np.asarray(mesh.boundaries[f"face:{g}"]) for g in assembly.faces}
    bare = type(mesh)(mesh.p, mesh.t)
    return bare, parts, faces


def _check(result: DeviceMesh, assembly) -> None:
    if result.nelements == 0:
        raise MeshError("the mesh is empty")
    for name, elements in result.parts.items():
        if len(elements) == 0:
            raise MeshError(f"part '{name}' got no elements")
    for name, facets in result.faces.items():
        if len(facets) == 0:
            raise MeshError(f"face group '{name}' got no facets")


_unwritable: set[Path] = set()  # cache folders already warned about (one warning per folder and process)


def _checksum(arrays: Mapping[str, np.ndarray]) -> str:
    """SHA-256 of the arrays' names, dtypes, shapes and bytes, in name order."""
    h = hashlib.sha256()
    for name in sorted(arrays):
        a = np.ascontiguousarray(arrays[name])
        h.update(f"{name}|{a.dtype.str}|{a.shape}|".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def _save(path: Path, result: DeviceMesh) -> None:
    """Write ``result`` to ``path`` atomically (a unique temporary file in the same folder, then os.replace),
    with its key and a checksum of its content inside; a folder that cannot be written is skipped with one
    warning (the run goes on without the cache)."""
    arrays = {"p": result.mesh.p, "t": result.mesh.t}
    arrays.update({f"part:{k}": v for k, v in result.parts.items()})
    arrays.update({f"face:{k}": v for k, v in result.faces.items()})
    meta = {"__key__": np.array(result.key), "__element__": np.array(result.element),
            "__version__": np.array(MESH_FORMAT_VERSION), "__checksum__": np.array(_checksum(arrays))}
    tmp = None
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=".tmp", dir=path.parent)
        with os.fdopen(fd, "wb") as f:
            np.savez(f, **arrays, **meta)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
        tmp = None
    except OSError as exc:
        folder = path.parent
        if folder not in _unwritable:
            _unwritable.add(folder)
            log.warning("mesh cache: cannot write %s (%s); going on without the disk cache", folder, exc)
    finally:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)


def _load(path: Path, key: str, element: str, size: float) -> DeviceMesh:
    """Read a cached mesh; ValueError unless the file holds ``key``, ``element``, this format version and
    content matching its checksum."""
    from skfem import MeshHex1, MeshHex2, MeshTet1, MeshTet2

    with np.load(path, allow_pickle=False) as data:
        files = set(data.files)
        missing = {"__key__", "__element__", "__version__", "__checksum__", "p", "t"} - files
        if missing:
            raise ValueError(f"missing {sorted(missing)}")
        if int(data["__version__"]) != MESH_FORMAT_VERSION:
            raise ValueError(f"format version {int(data['__version__'])}, expected {MESH_FORMAT_VERSION}")
        if str(data["__key__"]) != key or str(data["__element__"]) != element:
            raise ValueError(f"holds mesh {data['__key__']} ({data['__element__']}), expected {key} ({element})")
        arrays = {k: data[k] for k in files if not k.startswith("__")}
        if _checksum(arrays) != str(data["__checksum__"]):
            raise ValueError("checksum mismatch")
    p, t = arrays["p"], arrays["t"]
    if p.ndim != 2 or p.shape[0] != 3 or t.ndim != 2 or t.shape[0] != (8 if element == "hex" else 4):
        raise ValueError(f"arrays of shapes p {p.shape}, t {t.shape} are not a {element} mesh")
    curved = p.shape[1] > t.max() + 1  # MeshTet2, MeshHex2: the higher-order nodes after the vertices
    mesh = {("hex", False): MeshHex1, ("hex", True): MeshHex2, ("tet", False): MeshTet1,
            ("tet", True): MeshTet2}[element, curved](p, t)
    parts = {k[5:]: v for k, v in arrays.items() if k.startswith("part:")}
    faces = {k[5:]: v for k, v in arrays.items() if k.startswith("face:")}
    return DeviceMesh(mesh, parts, faces, element, size, key, 0.0)
