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
    # the answer's frequencies exactly (a fixed 6 decimals gave a 47 Hz mode 8e-9 off the other commands' answer)
    assert [float(r[2]) for r in rows[1:]] == list(plate.frequencies)
    assert [r[1] for r in rows[1:]] == [m.label for m in plate]


def _linear_field_modes(modes, a: float, gamma: float):
    """``modes``' first with its shape replaced by the linear field u = (a x + gamma y, 0, 0) (no potential), which
    the quadratic cells hold exactly."""
    import dataclasses

    model = modes.model
    ub = model.u_basis
    x = np.zeros_like(modes[0].shape)
    for dofs in (ub.nodal_dofs[0], ub.edge_dofs[0]):
        where = ub.doflocs[:, dofs]
        x[dofs] = a * where[0] + gamma * where[1]
    return [dataclasses.replace(modes[0], shape=x)]


def test_strain_stress_von_mises_of_a_linear_field_are_hookes_law_in_the_plate(plate, tmp_path):
    # u = (a x + gamma y, 0, 0): strain xx = a and xy = gamma / 2 everywhere; in the isotropic Cu-Be plate
    # (E = 123 GPa, nu = 0.30, modalfe.scene.materials) Hooke's law gives sigma_xx = (lambda + 2 mu) a,
    # sigma_yy = sigma_zz = lambda a, sigma_xy = mu gamma. The half model is mirrored about y = 19 mm (a plane
    # of symmetry): the image field is (a x - gamma y', ...) up to a constant, so the mirrored cells carry -gamma.
    a, gamma = 1e-4, 4e-5
    modes = _linear_field_modes(plate, a, gamma)
    path = export_vtu(type(plate)(tuple(modes), plate.model, plate.circuit, plate.fidelity, plate.dofs),
                      tmp_path / "linear.vtu", table=False)
    mesh = meshio.read(path)
    stem = mode_array_name(modes[0])
    in_plate = mesh.cell_data["part:plate"][0].astype(bool)
    cells = mesh.cells[0].data
    solved = mesh.points[cells[:, 0], 1] < 19e-3  # corner 0's side of the plane y = 19 mm
    E, nu = 123e9, 0.30
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    strain = mesh.cell_data[f"{stem} strain [-]"][0].reshape(-1, 3, 3)
    stress = mesh.cell_data[f"{stem} stress [Pa]"][0].reshape(-1, 3, 3)
    mises = mesh.cell_data[f"{stem} von Mises [Pa]"][0]
    assert strain.shape == stress.shape == (len(cells), 3, 3) and mises.shape == (len(cells),)
    assert solved.any() and (~solved).any()
    for side, g in ((solved, gamma), (~solved, -gamma)):
        cells_here = in_plate & side
        s_xx, s_yy, s_xy = lam * a + 2 * mu * a, lam * a, mu * g
        expected = np.array([[s_xx, s_xy, 0], [s_xy, s_yy, 0], [0, 0, s_yy]])
        # exact up to rounding of the quadrature sums and the mesh coordinates: 1e-9 of the largest entry
        np.testing.assert_allclose(stress[cells_here], np.broadcast_to(expected, stress[cells_here].shape),
                                   atol=1e-9 * s_xx)
        np.testing.assert_allclose(strain[cells_here][:, 0, 1], g / 2, rtol=1e-9)
        np.testing.assert_allclose(strain[cells_here][:, 0, 0], a, rtol=1e-9)
        vm = np.sqrt(0.5 * ((s_xx - s_yy) ** 2 + (s_yy - s_yy) ** 2 + (s_yy - s_xx) ** 2) + 3 * s_xy**2)
        np.testing.assert_allclose(mises[cells_here], vm, rtol=1e-9)
    # no potential in this shape: no field anywhere
    assert np.all(mesh.cell_data[f"{stem} electric field [V/m]"][0] == 0)


# VTK_QUADRATIC_HEXAHEDRON's three pairs of opposite faces, each face as (corners, mid-side nodes)
_OPPOSITE_FACES = ((([0, 1, 2, 3], [8, 9, 10, 11]), ([4, 5, 6, 7], [12, 13, 14, 15])),
                   (([0, 1, 5, 4], [8, 17, 12, 16]), ([3, 2, 6, 7], [10, 18, 14, 19])),
                   (([1, 2, 6, 5], [9, 18, 13, 17]), ([0, 3, 7, 4], [11, 19, 15, 16])))


def test_mode_stress_and_field_agree_with_the_stress_module_and_errors_are_stated(plate, written):
    # the working mode's cell arrays read back with pyvista. (1) In a ceramic's box cells the cell mean of E_x is
    # -(mean potential on the face x = x1 - on the face x = x0) / (x1 - x0) (divergence theorem; E_y and E_z
    # likewise; E_z's is 0 in short circuit, both electrodes grounded), the face means taken
    # from the exported point data with the 8-node serendipity face weights (corners -1/12, mid-sides 1/3): an
    # independent route from nodes to field, exact up to rounding (1e-9 of the largest component). (2) Von Mises is
    # convex, so a cell's von Mises of the mean stress cannot exceed the pointwise peak modalfe.response.stress
    # finds over the same quadrature points (1e-12 relative for rounding).
    from modalfe.response.stress import part_peaks

    grid = pv.read(written)
    working = plate.labelled("(0,6)")
    stem = mode_array_name(working)
    for name in ("stress [Pa]", "strain [-]"):
        assert grid.cell_data[f"{stem} {name}"].shape == (grid.n_cells, 9)
    field = grid.cell_data[f"{stem} electric field [V/m]"]
    assert field.shape == (grid.n_cells, 3)
    phi = grid.point_data[f"{stem} potential [V]"]
    cells = grid.cells.reshape(-1, 21)[:, 1:]
    ceramic = np.flatnonzero(grid.cell_data["part:ceramic_1"].astype(bool))
    expected = np.zeros((len(ceramic), 3))
    for row, c in enumerate(cells[ceramic]):
        for axis in range(3):
            x = grid.points[:, axis]
            high, low = next(pair for pair in _OPPOSITE_FACES  # the pair of faces each at one x[axis]
                             if all(np.ptp(x[c[face[0]]]) < 1e-12 for face in pair))
            mean = [-phi[c[corners]].sum() / 12 + phi[c[mids]].sum() / 3 for corners, mids in (high, low)]
            expected[row, axis] = -(mean[0] - mean[1]) / (x[c[high[0][0]]] - x[c[low[0][0]]])
    assert np.abs(expected).max() > 0
    np.testing.assert_allclose(field[ceramic], expected, atol=1e-9 * np.abs(expected).max())
    peak = part_peaks(plate.model, working.shape, parts=["plate"])[0].von_mises.value
    mises = grid.cell_data[f"{stem} von Mises [Pa]"][grid.cell_data["part:plate"].astype(bool)]
    assert 0 < mises.max() <= peak * (1 + 1e-12)
    np.testing.assert_array_equal(grid.field_data["error estimate [relative]"],
                                  [m.error_estimate for m in plate])


def test_curved_quadratic_tetrahedra_carry_exact_cell_fields(tmp_path):
    # a steel cylinder (E 200 GPa, nu 0.3, given here) meshed with curved 10-node tetrahedra: their mid-edge nodes
    # lie on the cylinder, and the isoparametric P2 space holds u = (a x, 0, 0) exactly there too, so every cell's
    # mean stress is Hooke's: sigma_xx = (lambda + 2 mu) a, sigma_yy = sigma_zz = lambda a, no shear (1e-9 for the
    # quadrature's rounding); mid-edge nodes sit on the curved surface (radius 4 mm to rounding, 1e-9)
    from modalfe.scene.loading import scene_from_dict

    E, nu = 200e9, 0.3
    scene = scene_from_dict({
        "units": "mm", "materials": {"steel": {"E": E, "nu": nu, "rho": 7850.0}},
        "parts": [{"name": "rod", "shape": "cylinder", "material": "steel", "centre": [0, 0, 0], "axis": "z",
                   "radius": 4, "height": 3}],
        "analysis": {"near": 1.0, "count": 1}, "mesh": {"element": "tet", "order": 2, "min_layers": 1}})
    modes = solve_modes(scene, near=1.0, count=1, error_estimate=False)
    a = 1e-4
    linear = _linear_field_modes(modes, a, 0.0)
    path = export_vtu(type(modes)(tuple(linear), modes.model, modes.circuit, modes.fidelity, modes.dofs),
                      tmp_path / "rod.vtu", table=False)
    grid = pv.read(path)
    assert set(np.unique(grid.celltypes)) == {pv.CellType.QUADRATIC_TETRA}
    mid_edge = np.unique(grid.cells.reshape(-1, 11)[:, 5:])  # VTK_QUADRATIC_TETRA: 4 corners, then 6 mid-edge nodes
    radius = np.hypot(grid.points[mid_edge, 0], grid.points[mid_edge, 1])
    assert radius.max() < 4e-3 * (1 + 1e-9) and np.sum(np.abs(radius - 4e-3) < 4e-12) > 10
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    stress = grid.cell_data[f"{mode_array_name(linear[0])} stress [Pa]"].reshape(-1, 3, 3)
    expected = np.diag([lam * a + 2 * mu * a, lam * a, lam * a])
    np.testing.assert_allclose(stress, np.broadcast_to(expected, stress.shape), atol=1e-9 * expected[0, 0])


def test_forced_response_per_volt_written_by_forced_vtu(tmp_path):
    # `modalfe forced BIMORPH --vtu`: the response at resonance per volt, in phase (a) and in quadrature (-b) of
    # x = a + i b. Read back with meshio: every array per volt; at the node that moves most the file's values are
    # the state's own (probed at that node, rounding 1e-9); each cell's von Mises peak over the cycle lies between
    # the larger of its two phases' (t = 0 and a quarter period later are in the cycle) and their sum (von Mises is
    # a norm), 1e-9 for rounding
    from modalfe.cli.main import main
    from modalfe.response.figures import forced_figures
    from tests.hostile.cases import BIMORPH

    path = tmp_path / "bimorph.toml"
    path.write_text(BIMORPH)
    vtu = tmp_path / "forced.vtu"
    assert main(["forced", str(path), "--outputs", "tip", "--fidelity", "solid", "--no-error-estimate",
                 "--vtu", str(vtu)]) == 0
    mesh = meshio.read(vtu)
    fig = forced_figures(load_scene(str(path)), outputs=["tip"], fidelity="solid", error_estimate=False, state=True)
    stem = f"resonance_{fig.mode.label.replace(' ', '_')}_{fig.mode.frequency:.1f}Hz"
    for phase in ("in phase", "quadrature"):
        for name in ("displacement [m/V]", "potential [V/V]"):
            assert mesh.point_data[f"{stem} {phase} {name}"].shape[0] == len(mesh.points)
        for name, width in (("strain [1/V]", 9), ("stress [Pa/V]", 9), ("electric field [V/m/V]", 3)):
            assert mesh.cell_data[f"{stem} {phase} {name}"][0].shape[1] == width
    a = mesh.point_data[f"{stem} in phase displacement [m/V]"]
    b = -mesh.point_data[f"{stem} quadrature displacement [m/V]"]
    node = int(np.argmax(np.hypot(a[:, 2], b[:, 2])))
    probe = np.asarray(fig.mode.model.displacement_probes(mesh.points[node:node + 1]) @ fig.state).reshape(3)
    np.testing.assert_allclose(a[node] + 1j * b[node], probe, rtol=1e-9)
    peak = mesh.cell_data[f"{stem} von Mises peak over the cycle [Pa/V]"][0]
    phases = [mesh.cell_data[f"{stem} {p} von Mises [Pa/V]"][0] for p in ("in phase", "quadrature")]
    assert np.all(peak >= np.maximum(*phases) * (1 - 1e-9)) and np.all(peak <= (phases[0] + phases[1]) * (1 + 1e-9))
    assert peak.max() > 0
    assert mesh.field_data["frequency [Hz]"][0] == pytest.approx(fig.mode.frequency, rel=1e-12)


def test_the_axisymmetric_answer_is_exported_on_its_revolved_body(tmp_path):
    """Issue 36 item 1: the axisymmetric model's modes go through the same export, on the meridian mesh swept round
    the axis (linear hexahedra, positive volumes summing to the inscribed polygonal disc's), each mode's displacement
    and potential at the points the revolved fields the point probes read there (two routes: the elements' basis at
    the points' reference coordinates turned by the harmonic's cos / sin, and a point search in the meridian mesh),
    the frequencies as field data, the cell arrays present."""
    from modalfe.models.revolved import DISPLAY_SPLIT, REVOLVED_ANGLES
    from tests.oracles.discs import PZT5A_DISC

    modes = solve_modes(PZT5A_DISC, fidelity="axisymmetric", harmonics=3, error_estimate=False)
    path = export_vtu(modes, tmp_path / "disc.vtu")
    grid = pv.read(path)
    volumes = grid.compute_cell_sizes(length=False, area=False).cell_data["Volume"]
    k = REVOLVED_ANGLES
    polygon = k / 2 * np.sin(2 * np.pi / k) * 10e-3**2 * 1e-3  # the disc's 20 x 1 mm, inscribed polygon
    assert grid.n_cells == k * DISPLAY_SPLIT**2 * modes.model.mesh.t.shape[1]
    assert volumes.min() > 0 and volumes.sum() == pytest.approx(polygon, rel=1e-9)  # round-off only
    np.testing.assert_allclose(grid.field_data["frequency [Hz]"], modes.frequencies, rtol=0)
    for mode in modes:
        u = grid.point_data[f"{mode_array_name(mode)} displacement [m]"]
        peak = np.abs(u).max()
        np.testing.assert_allclose(u, mode.displacement(grid.points), rtol=0, atol=REL * peak)
        phi = grid.point_data[f"{mode_array_name(mode)} potential [V]"]
        np.testing.assert_allclose(phi, mode.potential(grid.points), rtol=0, atol=REL * np.abs(phi).max())
    with open(table_path(path)) as fh:
        rows = list(csv.DictReader(fh))
    assert [r["label"] for r in rows] == [m.label for m in modes]
    assert all(f"{r['stress array']}" in grid.cell_data for r in rows)


def test_the_revolved_cells_strain_stress_and_field_are_exact_for_uniform_fields():
    """The axisymmetric cell arrays on fields they hold exactly: a uniform expansion (n = 0: U_r = a r, U_z = a z),
    the in-plane pure shear u = b (x, -y, 0) (n = 2: U_r = b r, U_t = -b r), a uniform axial field E0 (n = 0:
    Phi = -E0 z), plus a rigid radial translation (n = 1) and a rigid twist (n = 0: U_t = r), which strain nothing:
    every cell reads the strain (a + b, a - b, a), the field (0, 0, E0) and T = c^E S - e^T E in xyz (PZT-5A poled
    along the axis is transversely isotropic about it: its tensors are the same in every turned frame), to 1e-7 of
    the values (the means of constants, the 1 / r terms of polynomials the elements hold; the fields' projection on
    the basis, a mass-matrix solve, leaves up to 5e-9 of them: a wrong term would be of the values' size)."""
    from modalfe.models.axisymmetric import assemble_axisymmetric
    from modalfe.scene.materials import material
    from tests.oracles.discs import PZT5A_DISC

    model = assemble_axisymmetric(load_scene(PZT5A_DISC), harmonics=(0, 1, 2), order=2)
    a, b, E0 = 1e-4, 3e-5, 2e5
    nodes = np.arange(model.basis.N)
    x = model.rigid_translations()[0].copy()
    for n, c, f in ((0, 0, lambda p: a * p[0]), (0, 2, lambda p: a * p[1]), (2, 0, lambda p: b * p[0]),
                    (2, 1, lambda p: -b * p[0]), (0, 1, lambda p: p[0])):
        x[model.u_dof(model.harmonics.index(n), nodes, c)] += model.basis.project(f)
    phi = model.basis.project(lambda p: -E0 * p[1])
    x[model.phi_dof(0, np.arange(len(model.phi_nodes)))] = phi[model.phi_nodes]
    strain, stress, field = model.cell_fields(x)
    S = np.array([a + b, a - b, a, 0, 0, 0])
    pzt = material("PZT-5A")
    E = np.array([0, 0, E0])
    np.testing.assert_allclose(strain, np.tile(S, (len(strain), 1)), rtol=0, atol=1e-7 * a)
    np.testing.assert_allclose(field, np.tile(E, (len(field), 1)), rtol=0, atol=1e-7 * E0)
    T = pzt.C @ S - pzt.e.T @ E
    np.testing.assert_allclose(stress, np.tile(T, (len(stress), 1)), rtol=0, atol=1e-7 * np.abs(T).max())
