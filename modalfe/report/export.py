"""VTU export for ParaView (and anything that reads VTK): the whole device with every computed mode.

The cells are the solve's own: 20-node quadratic hexahedra (VTK_QUADRATIC_HEXAHEDRON, edge mid-nodes
included) for the serendipity solid, 10-node tetrahedra (VTK_QUADRATIC_TETRA) for P2 (on a curved mesh the
mid-edge nodes are the mesh's own, on the curved surface), linear cells for
order 1 (and, vertices only, for the Gauss-Lobatto orders 3-4). Symmetric models are unfolded to the
whole device. Written:

- point data ``mode_<i>_<label>_<f>Hz displacement [m]`` (the mass-normalised shape, vector at every node)
  and ``mode_<i>_<label>_<f>Hz potential [V]`` (the electric potential over the poled parts, 0 elsewhere);
- cell data, per mode, ``<stem> strain [-]`` and ``<stem> stress [Pa]`` (3 x 3 tensors, row-major, 9 components:
  ParaView reads 9 components as a full tensor, free of any Voigt-order convention), ``<stem> von Mises [Pa]``
  and ``<stem> electric field [V/m]``: each the mean over the cell of the field recovered from the solution
  (``modalfe.response.stress``: S = sym grad u, E = -grad phi, sigma = c^E S - e^T E), so exact for a field
  the cell's interpolation holds and well defined across parts of different materials, where nodal values
  would be double-valued; on a curved or higher-order mesh the mean uses the cells' own (curved) geometry and
  the solve's quadrature. Like the displacement, they are per unit modal coordinate of the mass-normalised
  shape (the modal mass is 1 kg);
- cell data ``part`` (index into the whole device's parts) and one 0/1 array ``part:<name>`` per part,
  so that ParaView lists the parts by name (meshio cannot read a VTU holding a string array);
- field data ``frequency [Hz]``, ``mode index`` and ``error estimate [relative]`` (one value per mode, in the
  point-data order; NaN where the solve made no estimate);
- a sidecar CSV ``<file>_modes.csv`` with the frequency table, units in every header.

The axisymmetric model's answer is written on its revolved body (``AxisymmetricModel.revolved_mesh``: the meridian
mesh's elements cut in ``DISPLAY_SPLIT`` x ``DISPLAY_SPLIT`` and swept round the axis, linear hexahedra), each
mode revolved: displacement and potential at every point, and per cell the same arrays, each the mean over the
cell's meridian part of the harmonics' strain table at the sector's middle angle (``AxisymmetricModel.cell_fields``).

``export_forced_vtu`` writes a forced response at resonance the same way, per unit load (``[m/V]``, ``[Pa/V]``...):
its in-phase and quadrature parts and the von Mises stress's peak over the cycle (docs/export.md).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from modalfe.errors import SolverError
from modalfe.models.axisymmetric import AxisymmetricModel
from modalfe.models.symmetry import VTK_HEX_CORNERS, VTK_HEXAHEDRON, image_signs, mirror_planes, mirrored

# VTK's edge order of the quadratic cells, as pairs of corner positions
_HEX_EDGES = ((0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7))
_TET_EDGES = ((0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3))
# VTK cell type of each (element, quadratic): HEXAHEDRON, QUADRATIC_HEXAHEDRON, TETRA, QUADRATIC_TETRA
VTK_TYPE = {("hex", False): 12, ("hex", True): 25, ("tet", False): 10, ("tet", True): 24}
# the cell-data arrays of a mode, after its point-data displacement and potential (module docstring)
CELL_ARRAYS = ("strain [-]", "stress [Pa]", "von Mises [Pa]", "electric field [V/m]")
CSV_HEADER = ("mode index", "label", "frequency [Hz]", "error estimate [relative]", "circuit",
              "displacement array", "potential array", "strain array", "stress array", "von Mises array",
              "electric field array")
# Voigt component (xx, yy, zz, yz, xz, xy) of each entry of a row-major 3 x 3 tensor, and whether it is a shear
_VOIGT_OF = np.array([0, 5, 4, 5, 1, 3, 4, 3, 2])
_SHEAR = _VOIGT_OF >= 3


def mode_array_name(mode) -> str:
    """The point-data name stem of one mode: ``mode_<index>_<label>_<frequency>Hz``."""
    return f"mode_{mode.index}_{mode.label.replace(' ', '_')}_{mode.frequency:.1f}Hz"


def edge_nodes(mesh) -> np.ndarray:
    """(3, n_edges) mid-edge nodes of ``mesh``'s edges: a curved mesh's own (skfem MeshTet2 and MeshHex2 store
    them right after the vertices, in edge order, on the true surface), else the edges' midpoints."""
    n_v = mesh.nvertices
    if mesh.p.shape[1] > n_v:
        return mesh.p[:, n_v:n_v + mesh.edges.shape[1]]
    return mesh.p[:, mesh.edges].mean(axis=1)


def _corners(model) -> np.ndarray:
    """Corner connectivity (n_cells, 8 or 4) in VTK order of the solved part's mesh."""
    t = model.mesh.mesh.t
    return t[VTK_HEX_CORNERS].T if model.mesh.element == "hex" else t.T


def _edge_lookup(edges: np.ndarray, n_vertices: int):
    """Function mapping vertex pairs (a, b) arrays to the index of the mesh edge joining them."""
    keys = np.sort(edges, axis=0)
    code = keys[0].astype(np.int64) * n_vertices + keys[1]
    order = np.argsort(code)
    sorted_code = code[order]

    def find(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        lo, hi = np.minimum(a, b).astype(np.int64), np.maximum(a, b).astype(np.int64)
        wanted = lo * n_vertices + hi
        at = np.searchsorted(sorted_code, wanted)
        if np.any(at >= len(sorted_code)) or np.any(sorted_code[np.minimum(at, len(sorted_code) - 1)] != wanted):
            raise SolverError("export: a cell edge is not an edge of the mesh")
        return order[at]

    return find


def quadratic_device(model, shapes: list[np.ndarray]):
    """(points (n, 3), cells (n_cells, k) in VTK order, VTK cell type, displacements [(n, 3)] and
    potentials [(n,)] per shape, full-assembly part name of every cell) of the whole device."""
    from skfem import Basis

    from modalfe.models.solid import element_for

    scene, dm = model.scene, model.mesh
    mesh = dm.mesh
    order = scene.mesh.order
    quadratic = order == 2
    kind = dm.element
    n_v = mesh.nvertices
    corners = _corners(model)
    ub = model.u_basis
    scalar = Basis(mesh, element_for(scene.mesh), intorder=1) if model.n_phi else None
    pieces = [mesh.p[:, :n_v].T] + ([edge_nodes(mesh).T] if quadratic else [])
    u_dofs = [ub.nodal_dofs] + ([ub.edge_dofs] if quadratic else [])
    disp = [[x[: model.n_u][d].T for d in u_dofs] for x in shapes]
    pot = []
    for x in shapes:
        if scalar is None:
            pot.append([np.zeros(len(p)) for p in pieces])
            continue
        phi = np.zeros(scalar.N)
        phi[model.phi_dofs] = x[model.n_u:]  # zero outside the poled parts (no potential unknowns there)
        pot.append([phi[scalar.nodal_dofs[0]]] + ([phi[scalar.edge_dofs[0]]] if quadratic else []))
    points = np.vstack(pieces)
    displacements = [np.vstack(d) for d in disp]
    potentials = [np.concatenate(p) for p in pot]
    n_block = len(points)
    find = _edge_lookup(mesh.edges, n_v) if quadratic else None
    pairs = _HEX_EDGES if kind == "hex" else _TET_EDGES
    flip = [1, 0, 3, 2, 5, 4, 7, 6] if kind == "hex" else [1, 0, 2, 3]
    copies = [corners]  # corner connectivity of each copy, in the solved part's vertex numbering
    for (axis, twice), sign in zip(mirror_planes(scene), image_signs(scene)):
        points = np.vstack([points, mirrored(points.T, axis, twice).T])
        # the normal component odd across a plane of symmetry, the others across one of antisymmetry
        displacements = [np.vstack([u, u * sign]) for u in displacements]
        potentials = [np.concatenate([p, p]) for p in potentials]
        copies = copies + [c[:, flip] for c in copies]  # reordered: mirrored cells keep a positive volume
    blocks = []
    for j, c in enumerate(copies):
        block = [c]
        if quadratic:
            block += [(n_v + find(c[:, a], c[:, b]))[:, None] for a, b in pairs]
        blocks.append(np.hstack(block) + j * n_block)
    cells = np.vstack(blocks)
    return points, cells, VTK_TYPE[(kind, quadratic)], displacements, potentials, _part_names(model, points, cells)


def cell_fields(model, shapes: list[np.ndarray]) -> list[dict[str, np.ndarray]]:
    """Per shape, the whole device's cell arrays ``CELL_ARRAYS`` in ``quadratic_device``'s cell order: the mean
    over each cell (its quadrature, ``modalfe.response.stress.part_fields``) of the strain and stress tensors
    (n_cells, 9) row-major (tensor strain: half the engineering shears), the von Mises stress of that mean stress
    (n_cells,) and the electric field (n_cells, 3) (0 where there is no potential). A mirrored cell's tensors
    are ``S T R`` and its field ``R E``, with S the displacement's image signs and R the reflection (the
    potential is copied unchanged, as ``quadratic_device`` copies it)."""
    from modalfe.response.stress import part_fields

    scene = model.scene
    out = []
    for x in shapes:
        if isinstance(model, AxisymmetricModel):  # the revolved body's cells (``AxisymmetricModel.cell_fields``)
            strain, stress, field = model.cell_fields(x)
            out.append(_cell_arrays(strain, stress, field))
            continue
        n = model.mesh.mesh.nelements
        strain, stress, field = np.full((n, 6), np.nan), np.full((n, 6), np.nan), np.zeros((n, 3))
        for part in model.mesh.parts:
            f = part_fields(model, x, part)
            volume = f.weights.sum(axis=-1)
            strain[f.elements] = (np.sum(f.strain * f.weights, axis=-1) / volume).T
            stress[f.elements] = (np.sum(f.stress * f.weights, axis=-1) / volume).T
            if f.field is not None:
                field[f.elements] = (np.sum(f.field * f.weights, axis=-1) / volume).T
        if np.isnan(strain).any():
            raise SolverError("export: a cell belongs to no part of the mesh")
        arrays = _cell_arrays(strain, stress, field)
        for (axis, _), sign in zip(mirror_planes(scene), image_signs(scene)):
            reflection = np.ones(3)
            reflection[axis] = -1.0
            tensor_sign = np.outer(sign, reflection).ravel()
            for name, signs in zip(CELL_ARRAYS, (tensor_sign, tensor_sign, 1.0, reflection), strict=True):
                arrays[name] = np.concatenate([arrays[name], arrays[name] * signs])
        out.append(arrays)
    return out


def _cell_arrays(strain: np.ndarray, stress: np.ndarray, field: np.ndarray) -> dict[str, np.ndarray]:
    """``CELL_ARRAYS`` of cells' Voigt strain (engineering shears) and stress (n, 6) and field (n, 3): the tensors
    (n, 9) row-major (tensor strain: half the engineering shears), the von Mises stress (n,), the field."""
    from modalfe.response.stress import von_mises

    return dict(zip(CELL_ARRAYS, (strain[:, _VOIGT_OF] * np.where(_SHEAR, 0.5, 1.0), stress[:, _VOIGT_OF],
                                  von_mises(stress.T), field), strict=True))


def _part_names(model, points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """The full assembly's part of each cell: the mesh's own part sets for a whole model, else the part whose
    bounding box holds the cell's centroid (mirrored cells get the mirrored part's name)."""
    scene = model.scene
    if not mirror_planes(scene):
        names = np.full(len(cells), "", dtype=object)
        for name, elements in model.mesh.parts.items():
            names[elements] = name
        return names
    assembly = scene.full_assembly()
    corners = cells[:, :8] if cells.shape[1] >= 8 else cells[:, :4]
    centroid = points[corners].mean(axis=1)
    names = np.full(len(cells), "", dtype=object)
    for part in assembly.parts:
        names[part.inside(centroid, 1e-12) & (names == "")] = part.name
    if np.any(names == ""):
        raise SolverError("export: a cell lies outside every part of the device")
    return names


def _unit(name: str, per: str) -> str:
    """An array name with its unit per unit load: ``stress [Pa]`` -> ``stress [Pa/V]``, ``strain [-]`` -> ``[1/V]``."""
    if not per:
        return name
    head, _, unit = name.rpartition(" [")
    unit = unit.rstrip("]")
    return f"{head} [{'1' if unit == '-' else unit}/{per}]"


def device_grid(model, states: list[tuple[str, np.ndarray]], *, per: str = ""):
    """A pyvista grid of the whole device (``quadratic_device``) with, for each (stem, real full DOF vector) of
    ``states``, the point arrays ``<stem> displacement [m]`` and ``<stem> potential [V]`` and the cell arrays
    ``CELL_ARRAYS`` (``cell_fields``), units per unit load ``per`` (e.g. ``V``) where given; and the parts (the
    axisymmetric model's: on its revolved body, module docstring)."""
    import pyvista as pv

    names = [p.name for p in model.scene.full_assembly().parts]
    if isinstance(model, AxisymmetricModel):  # the revolved body: linear hexahedra, point arrays only
        points, cells, probes, potential, part_id = model.revolved_mesh
        cell_type = VTK_HEXAHEDRON
        disp = [np.asarray(probes @ x).reshape(3, -1).T for _, x in states]
        pot = [np.asarray(potential @ x) for _, x in states]
        per_cells = cell_fields(model, [x for _, x in states])
    elif not hasattr(model, "u_basis") or not hasattr(getattr(model, "mesh", None), "mesh"):
        raise SolverError("export: VTU export needs the 3-D solid or the axisymmetric model (--fidelity solid)")
    else:
        shapes = [x for _, x in states]
        points, cells, cell_type, disp, pot, part_of = quadratic_device(model, shapes)
        index = {name: i for i, name in enumerate(names)}
        part_id = np.array([index[n] for n in part_of], dtype=np.int32)
        per_cells = cell_fields(model, shapes)
    grid = pv.UnstructuredGrid(np.hstack([np.full((len(cells), 1), cells.shape[1]), cells]).ravel(),
                               np.full(len(cells), cell_type, dtype=np.uint8), points)
    for (stem, _), u, phi, per_cell in zip(states, disp, pot, per_cells, strict=True):
        grid.point_data[f"{stem} {_unit('displacement [m]', per)}"] = u
        grid.point_data[f"{stem} {_unit('potential [V]', per)}"] = phi
        for name, values in per_cell.items():
            grid.cell_data[f"{stem} {_unit(name, per)}"] = values
    grid.cell_data["part"] = np.asarray(part_id, dtype=np.int32)
    for i, name in enumerate(names):
        grid.cell_data[f"part:{name}"] = (part_id == i).astype(np.uint8)
    return grid


def _save(grid, path: str | Path) -> Path:
    path = Path(path)
    if path.suffix.lower() != ".vtu":
        raise SolverError(f"--vtu: the file name must end in .vtu, got '{path.name}'")
    grid.save(path, binary=True)
    return path


def export_vtu(modes, path: str | Path, *, table: bool = True) -> Path:
    """Write ``modes`` (a solid model's) to ``path`` (.vtu) as described in the module docstring, and with
    ``table`` the sidecar ``<stem>_modes.csv``. Returns the VTU path."""
    mode_list = list(modes)
    grid = device_grid(modes.model, [(mode_array_name(m), m.shape) for m in mode_list])
    grid.field_data["frequency [Hz]"] = np.array([m.frequency for m in mode_list])
    grid.field_data["mode index"] = np.array([m.index for m in mode_list], dtype=np.int32)
    grid.field_data["error estimate [relative]"] = np.array([m.error_estimate for m in mode_list])
    path = _save(grid, path)
    if table:
        write_mode_table(mode_list, table_path(path))
    return path


def export_forced_vtu(mode, state: np.ndarray, path: str | Path, *, unit: str = "V",
                      error_estimate: float = float("nan")) -> Path:
    """Write the forced response ``state`` (full DOF, complex, per unit load ``unit``; x = a + i b varies as
    a cos(wt) - b sin(wt)) at ``mode``'s resonance to ``path`` (.vtu): the arrays of ``device_grid`` for the
    in-phase part a (``resonance_<label>_<f>Hz in phase``) and for -b, a quarter period later (``... quadrature``),
    per unit load, the von Mises stress's peak over the cycle of each cell's mean stress
    (``modalfe.response.stress``: exact, the largest eigenvalue of a 2 x 2 form), and as field data the
    frequency and its stated error."""
    from modalfe.response.stress import von_mises_peak

    stem = f"resonance_{mode.label.replace(' ', '_')}_{mode.frequency:.1f}Hz"
    state = np.asarray(state, dtype=complex)
    grid = device_grid(mode.model, [(f"{stem} in phase", state.real), (f"{stem} quadrature", -state.imag)],
                       per=unit)
    voigt = [0, 4, 8, 5, 2, 1]  # row-major 3 x 3 entries of xx, yy, zz, yz, xz, xy
    a = grid.cell_data[f"{stem} in phase {_unit('stress [Pa]', unit)}"][:, voigt].T
    b = grid.cell_data[f"{stem} quadrature {_unit('stress [Pa]', unit)}"][:, voigt].T
    grid.cell_data[f"{stem} {_unit('von Mises peak over the cycle [Pa]', unit)}"] = von_mises_peak(a, b)
    grid.field_data["frequency [Hz]"] = np.array([mode.frequency])
    grid.field_data["error estimate [relative]"] = np.array([error_estimate])
    return _save(grid, path)


def table_path(vtu: str | Path) -> Path:
    """The sidecar frequency table of a VTU file: ``<stem>_modes.csv`` beside it."""
    vtu = Path(vtu)
    return vtu.with_name(f"{vtu.stem}_modes.csv")


def write_mode_table(modes, path: str | Path) -> Path:
    """CSV of the modes' index, label, frequency [Hz], error estimate and their VTU array names."""
    path = Path(path)
    with path.open("w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(CSV_HEADER)
        for m in modes:
            error = "" if math.isnan(m.error_estimate) else f"{m.error_estimate:.3g}"
            writer.writerow([m.index, m.label, repr(m.frequency), error, m.circuit,  # the float exactly
                             f"{mode_array_name(m)} displacement [m]", f"{mode_array_name(m)} potential [V]",
                             *(f"{mode_array_name(m)} {name}" for name in CELL_ARRAYS)])
    return path
