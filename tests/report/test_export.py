"""VTU export read back with meshio and with pyvista: quadratic cells, part names, the displacement and
potential of a mode at its nodes, the frequency table; the sidecar CSV's headers carry units."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from modalfe.report.export import CSV_HEADER, export_vtu, mode_array_name, table_path
from modalfe.scene import load_scene
from modalfe.solve.api import solve_modes

pv = pytest.importorskip("pyvista")
meshio = pytest.importorskip("meshio")

# a node's exported displacement is the solution's DOF value there, and mode.displacement(point) evaluates the
# same interpolant at that point (nudged 1e-9 x the device's size inward): they agree to rounding, ~1e-9 of the
# peak; 1e-6 leaves room for the nudge across a steep gradient and still catches any wrong node (O(1) errors)
REL = 1e-6


@pytest.fixture(scope="module")
def plate():
    scene = load_scene("cube_plate", **{"mesh.elements_per_wavelength": 4.0})
    return solve_modes(scene, near=40e3, count=4, error_estimate=False)


@pytest.fixture(scope="module")
def written(plate, tmp_path_factory):
    return export_vtu(plate, tmp_path_factory.mktemp("vtu") / "plate.vtu")


def _nodes_to_check(cells: np.ndarray, in_plate: np.ndarray) -> np.ndarray:
    """A corner and an edge mid-node of a plate cell in the solved half and of one in the mirrored half (the
    plate's: ``Mode.displacement`` nudges points toward the device's centre, which leaves a foot at its corner)."""
    plate_cells = np.flatnonzero(in_plate)
    first, last = cells[plate_cells[len(plate_cells) // 4]], cells[plate_cells[-len(plate_cells) // 4]]
    return np.array([first[0], first[8], last[0], last[8]])


def test_meshio_reads_quadratic_hexahedra_part_names_and_fields(plate, written):
    mesh = meshio.read(written)
    assert [c.type for c in mesh.cells] == ["hexahedron20"]  # VTK_QUADRATIC_HEXAHEDRON
    names = sorted(k.split(":", 1)[1] for k in mesh.cell_data if k.startswith("part:"))
    assert names == sorted(p.name for p in plate.model.scene.full_assembly().parts)
    assert {"foot_1", "foot_2", "foot_3", "foot_4", "ceramic_2", "ceramic_10"} <= set(names)  # mirrored half named
    # each cell is in exactly one part, and the index agrees with the per-part arrays
    flags = np.column_stack([mesh.cell_data[f"part:{n}"][0] for n in names])
    assert np.all(flags.sum(axis=1) == 1)
    # the whole 64 x 38 mm plate, unfolded from the half model
    assert np.ptp(mesh.points[:, 1]) == pytest.approx(38e-3, rel=1e-9)
    assert np.ptp(mesh.points[:, 0]) == pytest.approx(64e-3, rel=1e-9)
    np.testing.assert_allclose(mesh.field_data["frequency [Hz]"], plate.frequencies, rtol=1e-12)
    working = plate.labelled("(0,6)")
    u = mesh.point_data[f"{mode_array_name(working)} displacement [m]"]
    cells = mesh.cells[0].data
    nodes = _nodes_to_check(cells, mesh.cell_data["part:plate"][0].astype(bool))
    assert mesh.points[nodes, 1].min() < 19e-3 < mesh.points[nodes, 1].max()  # both halves checked
    expected = working.displacement(mesh.points[nodes])
    peak = np.abs(u).max()
    assert np.abs(expected).max() > 0.05 * peak  # the nodes checked move: a real comparison
    np.testing.assert_allclose(u[nodes], expected, atol=REL * peak)


def test_potential_is_the_modes_over_the_ceramics_and_zero_elsewhere(plate, written):
    mesh = meshio.read(written)
    working = plate.labelled("(0,6)")
    phi = mesh.point_data[f"{mode_array_name(working)} potential [V]"]
    cells = mesh.cells[0].data
    ceramic = np.zeros(len(cells), dtype=bool)
    plate_cells = mesh.cell_data["part:plate"][0].astype(bool) | mesh.cell_data["part:foot_1"][0].astype(bool)
    for key, value in mesh.cell_data.items():
        if key.startswith("part:ceramic"):
            ceramic |= value[0].astype(bool)
    in_ceramic = np.unique(cells[ceramic])
    only_plate = np.setdiff1d(np.unique(cells[plate_cells]), in_ceramic)
    assert np.abs(phi[in_ceramic]).max() > 0  # the coupled mode carries a potential in the ceramics
    assert np.all(phi[only_plate] == 0)
    # at the mid-plane of a ceramic (not an electrode) the exported value is the mode's potential there
    z = mesh.points[in_ceramic, 2]
    inner = in_ceramic[np.abs(z - 0.5 * (z.min() + z.max())) < 1e-9][:6]
    assert len(inner) > 0
    np.testing.assert_allclose(phi[inner], working.potential(mesh.points[inner]), atol=REL * np.abs(phi).max())


def test_pyvista_reads_the_same_file(plate, written):
    grid = pv.read(written)
    assert set(np.unique(grid.celltypes)) == {pv.CellType.QUADRATIC_HEXAHEDRON}
    assert grid.n_cells == 2 * plate.model.mesh.nelements  # the half model, mirrored
    volumes = grid.compute_cell_sizes(length=False, area=False).cell_data["Volume"]
    assert volumes.min() > 0  # every cell (mirrored ones too) is positively oriented
    assert volumes.sum() == pytest.approx(64e-3 * 38e-3 * 3e-3 + 10 * 12e-3 * 12e-3 * 1e-3 + 4 * 3e-3 ** 2 * 4e-3,
                                          rel=1e-9)
    assert "part:foot_3" in grid.cell_data
    working = plate.labelled("(0,6)")
    u = grid.point_data[f"{mode_array_name(working)} displacement [m]"]
    node = int(np.argmax(np.abs(u[:, 2])))
    np.testing.assert_allclose(u[node], working.displacement(grid.points[node])[0], atol=REL * np.abs(u).max())
    np.testing.assert_allclose(grid.field_data["frequency [Hz]"], plate.frequencies, rtol=1e-12)


def test_sidecar_table_has_units_in_its_headers(plate, written):
    with table_path(written).open() as f:
        rows = list(csv.reader(f))
    assert tuple(rows[0]) == CSV_HEADER
    assert "frequency [Hz]" in rows[0]
    assert [float(r[2]) for r in rows[1:]] == pytest.approx(list(plate.frequencies), rel=1e-9)
    assert [r[1] for r in rows[1:]] == [m.label for m in plate]
