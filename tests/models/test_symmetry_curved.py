"""Symmetry planes through round parts (issue 36 item 3): the half or quarter of a disc, ring or round foot, cut
through its axis, meshed with its curved walls and solved with the mirror conditions on its cut faces, against the
whole device."""

import math

import numpy as np
import pytest
from skfem import Basis, ElementHex1, ElementTetP2, Functional

from modalfe.errors import SceneError
from modalfe.geometry.parts import Assembly, Face
from modalfe.geometry.shapes import Cylinder, Extrusion, Ring
from modalfe.models.mesh import build_mesh
from modalfe.models.solid import face_area
from modalfe.response.admittance import clamped_capacitance, modal_admittance
from modalfe.response.losses import resolve_losses
from modalfe.scene import load_scene
from modalfe.solve.api import OWN_MESH, solve_modes
from tests.helpers import assert_one_line_error

DISC = "examples/pzt5a_disc.toml"  # 20 x 1 mm PZT-5A disc, electrodes on both faces, R1 near 99.4 kHz
RING = "examples/steel_ring.toml"  # steel ring, mean radius 20 mm, wall 1 mm, height 2 mm
_one = Functional(lambda w: 1.0 + 0.0 * w.x[0])


def _even_harmonic(label: str) -> bool:
    """Whether a disc label names a field even about both mid-planes through the axis: n = 0 (R, T, (0,c)) or an
    even n (cos n theta is even about x = 0 and y = 0 for even n only; its sin n theta partner is odd about both)."""
    if label.startswith(("R", "T")):
        return label[0] == "R"  # T (torsion) is odd about every plane through the axis
    if label.startswith("n="):
        return int(label[2:].split()[0]) % 2 == 0
    return int(label.strip("()").split(",")[0]) % 2 == 0


def test_a_quarter_disc_is_a_quarter_of_the_disc_with_its_cut_faces_in_the_mirror_groups():
    scene = load_scene(DISC, symmetry=["x", "y"])
    disc = scene.assembly().part("disc")
    assert disc.cuts == ((0, 0.0), (1, 0.0)) and disc.lo == pytest.approx((-0.01, -0.01, 0.0))
    assert disc.hi == pytest.approx((0.0, 0.0, 1e-3))
    assert disc.volume == pytest.approx(math.pi * 0.01**2 * 1e-3 / 4)
    assert disc.area("cut_x") == pytest.approx(0.01 * 1e-3) and disc.area("top") == pytest.approx(math.pi * 1e-4 / 4)
    faces = scene.assembly().faces
    assert faces["symmetry_x"] == (Face("disc", "cut_x"),) and faces["symmetry_y"] == (Face("disc", "cut_y"),)
    assert faces["electrode_a"] == (Face("disc", "top"),)  # electrodes and poling kept on the quarter
    dm = build_mesh(scene.assembly(), size=2e-3, element="hex", min_layers=2, use_cache=False)
    # curved quadratic walls, exact planes: the volume as exact as the whole disc's (2.2e-6 at 16 arcs per circle,
    # tests/models/test_swept_mesh.py), the cut faces exactly the r x h strips
    volume = _one.assemble(Basis(dm.mesh, ElementHex1(), intorder=4))
    assert volume == pytest.approx(disc.volume, rel=1e-5)
    assert face_area(dm, "symmetry_x") == pytest.approx(1e-5, rel=1e-12)
    assert face_area(dm, "electrode_a") == pytest.approx(disc.area("top"), rel=1e-5)


@pytest.mark.parametrize("scene_file, symmetry", [(DISC, ["x", "y"]), (RING, ["x"])])
def test_curved_tetrahedra_keep_the_cut_parts_exact_volumes_and_faces(scene_file, symmetry):
    assembly = load_scene(scene_file, symmetry=symmetry).assembly()
    dm = build_mesh(assembly, size=2e-3, element="tet", min_layers=1, use_cache=False)
    part = assembly.main_part
    # quadratic tetrahedra with curved faces (OCC intersection of the part with its clipped box): measured 1.1e-7
    # (quarter disc) and 1.1e-8 (half ring) of the volume; the planar cut faces to rounding
    assert _one.assemble(Basis(dm.mesh, ElementTetP2(), intorder=4)) == pytest.approx(part.volume, rel=1e-6)
    for group, faces in assembly.faces.items():
        exact = sum(assembly.part(f.part).area(f.side) for f in faces)
        assert face_area(dm, group) == pytest.approx(exact, rel=1e-6 if group.startswith("electrode") else 1e-12)


def test_a_half_ring_cut_through_its_axis_keeps_two_wall_strips():
    ring = Ring("ring", "ring", "steel", (0.0, 0.0, 0.0), "z", 0.0195, 0.0205, 0.002)
    half, side = ring.cut_below(0, 0.0, 1e-12)
    assert side == "cut_x" and half.sides == ("top", "bottom", "outer", "inner", "cut_x")
    assert half.area("cut_x") == pytest.approx(2 * 0.001 * 0.002)  # the strips on both sides of the bore
    assert half.side_of((0.0, 0.02, 0.001), 1e-9) == "cut_x" and half.side_of((-0.0205, 0.0, 0.001), 1e-9) == "outer"
    assert half.inside(np.array([[-0.02, 0.0, 0.001], [0.02, 0.0, 0.001]])).tolist() == [True, False]
    shorter, top = Cylinder("c", "c", "steel", (0.0, 0.0, 0.0), "z", 0.01, 0.002).cut_below(2, 0.0015, 1e-12)
    assert top == "top" and shorter.height == pytest.approx(0.0015)  # a plane normal to the axis shortens it


def test_a_round_part_that_is_no_mirror_half_is_refused_naming_the_symmetry():
    # a disc off-centre across the plane, no mirror partner: the half would not stand for the whole
    plate = {"name": "plate", "material": "steel", "origin": [0, 0, 0], "size": [40, 30, 2]}
    disc = {"name": "disc", "shape": "cylinder", "material": "steel", "centre": [21, 15, 2], "axis": "z",
            "radius": 5, "height": 1}
    data = {"name": "off", "units": "mm", "kind": "solid", "parts": [plate, disc], "analysis": {"near": 1e4},
            "symmetry": ["x"]}
    from modalfe.scene import scene_from_dict

    assert_one_line_error(lambda: scene_from_dict(data), "symmetry", SceneError)
    # called directly with a plane along its axis but off it, the cut is refused too
    ring = Ring("ring", "ring", "steel", (0.0, 0.0, 0.0), "z", 0.01, 0.02, 0.002)
    with pytest.raises(SceneError, match=r"^symmetry: part 'ring' crosses the x mid-plane off its axis"):
        ring.cut_below(0, 0.001, 1e-9)
    # an extrusion is not cut (its outline's mirror image is not checked)
    square = Extrusion("plate", "plate", "steel", ((-1, -1), (1, -1), (1, 1), (-1, 1)), "z", 0.0, 0.1)
    with pytest.raises(SceneError, match=r"^symmetry: part 'plate' crosses the x mid-plane; only boxes, cylinders"):
        Assembly((square,)).halved(0)


@pytest.fixture(scope="module")
def disc_modes():
    """The whole disc and its quarter, each on its own mesh with its stated error (three grids, no refinement): the
    3-D solid both (auto answers the whole disc with the axisymmetric model)."""
    return {sym: solve_modes(load_scene(DISC, symmetry=list(sym)), near=99e3, count=8, tol=OWN_MESH, fidelity="solid")
            for sym in ((), ("x", "y"))}


def test_the_quarter_disc_gives_the_whole_discs_doubly_symmetric_modes_within_their_stated_errors(disc_modes):
    whole, quarter = disc_modes[()], disc_modes[("x", "y")]
    assert quarter.model.copies == 4 and quarter.dofs < whole.dofs / 2
    assert all(_even_harmonic(m.label) for m in quarter)  # odd n (n=3, (1,2)...) have no quarter of their own
    assert {m.label.split("#")[0] for m in quarter} >= {"R1", "(8,0)", "(4,1)"}
    r1 = quarter.labelled("R1")
    # IEEE Std 176-1987 thin-disc theory 99,478 Hz; 3-D disc (finite thickness) ~0.1 % lower (examples/pzt5a_disc.toml)
    assert r1.frequency == pytest.approx(99.4e3, rel=2e-3)
    _within_stated_errors(quarter, whole, at_least=("R1", "(8,0)", "(4,1)"))


def _within_stated_errors(part, whole, at_least: tuple[str, ...]) -> None:
    """Every mode of the symmetric ``part`` model that the ``whole``'s solve also holds (by label) lies within the
    sum of the two stated errors of its whole partner: two meshes of one device, each stated error covering its own
    distance from the exact frequency (a stated error is a promise: it covers the actual error on every verification
    case), so their sum covers the distance between them; ``at_least`` the labels that must be met."""
    met = []
    for mode in part:
        partners = [m for m in whole if m.label.split("#")[0] == mode.label]
        if not partners:
            continue  # outside the whole's modes nearest its target
        partner = min(partners, key=lambda m: abs(m.frequency - mode.frequency))
        assert abs(partner.frequency - mode.frequency) <= (partner.error_estimate + mode.error_estimate) \
            * mode.frequency, mode.label
        met.append(mode.label)
    assert set(at_least) <= set(met)


def test_the_quarter_discs_capacitance_and_admittance_are_the_whole_discs(disc_modes):
    whole, quarter = disc_modes[()], disc_modes[("x", "y")]
    # the clamped dielectric is uniformly polarised between the two electrodes: any mesh gives eps33S A / h exactly, and
    # four quarters give the whole's to rounding
    c_whole = clamped_capacitance(whole.model)
    assert quarter.model.copies * clamped_capacitance(quarter.model) == pytest.approx(c_whole, rel=1e-9)
    losses = resolve_losses(whole.model.scene)
    f = np.linspace(95e3, 104e3, 10)
    y_whole = modal_admittance(whole, f, losses)
    y_quarter = modal_admittance(quarter, f, losses)
    (b_whole,) = [c for c in y_whole.bvd_circuits() if c["label"] == "R1"]
    (b_quarter,) = [c for c in y_quarter.bvd_circuits() if c["label"] == "R1"]
    # R1's motional branch from two meshes: its stated error (3e-7 and 1e-6 relative) bounds fr, the mode shape's
    # theta^2 moves with it; 1e-4 is ~100x the frequencies' stated errors
    for key in ("fr_hz", "fa_hz", "k_eff", "C1_F", "L1_H"):
        assert b_quarter[key] == pytest.approx(b_whole[key], rel=1e-4), key
    # |Y| over the band: the same modal sum of the driven modes (odd ones carry no charge), residual alike
    assert np.abs(y_quarter.Y) == pytest.approx(np.abs(y_whole.Y), rel=1e-3)
    # theta is the quarter's own (sqrt(4) x smaller than the whole's: its modal mass is a quarter), and the output
    # says so
    (t_whole,) = [r["theta_N_per_V_sqrtkg"] for r in y_whole.modes if r["label"] == "R1"]
    (t_quarter,) = [r["theta_N_per_V_sqrtkg"] for r in y_quarter.modes if r["label"] == "R1"]
    assert abs(t_quarter) * 2 == pytest.approx(abs(t_whole), rel=1e-4)
    assert any("theta is the solved part's" in note for note in y_quarter.notes)
    assert not any("theta is the solved part's" in note for note in y_whole.notes)


def test_a_half_ring_gives_the_whole_rings_modes_symmetric_about_its_cut():
    whole = solve_modes(load_scene(RING, symmetry=[]), near=3e3, count=8, tol=OWN_MESH)
    half = solve_modes(load_scene(RING, symmetry=["x"]), near=3e3, count=8, tol=OWN_MESH)
    elastic = [m for m in half if m.frequency > 100.0]
    assert [m.label for m in elastic][:2] == ["n=2", "(2,0)"]  # one of each whole pair: the even partner
    _within_stated_errors(elastic, whole, at_least=("n=2", "(2,0)"))


@pytest.mark.slow
def test_the_cube_plate_with_round_feet_gives_the_same_working_mode_with_and_without_symmetry():
    # the (0,6) of this scene states no error (its coarse levels pair no mode with it: "inf"), so each model's
    # discretization error is bounded here from two of its own meshes: quadratic elements converge at ~h^4 on a smooth
    # field, so at 9 elements per wavelength the error is ~(6/9)^4 = 0.2 of that at 6, and |f_9 - f_6| (0.8 of the
    # coarse error) bounds the fine one four times over; measured: whole 39,807 -> 39,721 Hz, y half 39,434 -> 39,663,
    # quarter 39,783 -> 39,718
    found = {}
    for symmetry in ([], ["y"], ["x", "y"]):
        f = [solve_modes(load_scene("cube_plate", foot_shape="round", symmetry=symmetry,
                                    **{"mesh.elements_per_wavelength": epw}),
                         near=40.7e3, count=8, error_estimate=False).labelled("(0,6)").frequency for epw in (6.0, 9.0)]
        found[len(symmetry)] = (f[1], abs(f[1] - f[0]))
    whole, bound = found[0]
    for half, half_bound in (found[1], found[2]):
        # the working mode is even about both mid-planes (six nodal lines placed alike about the mid-length): every
        # model finds it, within the sum of the two models' bounds
        assert abs(half - whole) <= half_bound + bound


def test_a_hexahedron_s_corners_in_vtk_order_are_scikit_fem_s_own_mapping():
    # written out so that drawing a mode does not import skfem.io.meshio (meshio's every format): the same corners
    from skfem.io.meshio import HEX_MAPPING

    from modalfe.models.symmetry import VTK_HEX_CORNERS

    assert VTK_HEX_CORNERS.tolist() == HEX_MAPPING[:8]
