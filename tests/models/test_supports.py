"""Edge (line) supports and guided faces (``Scene.edges``, ``Scene.guides``; docs/supports.md): the multi-point
constraint in the T map, a guided beam against Euler-Bernoulli, NAFEMS FV52 on its line supports, and bad input."""

import math

import numpy as np
import pytest

from modalfe.errors import SceneError
from modalfe.models.build import build_model
from modalfe.scene.loading import load_scene, scene_from_dict
from modalfe.solve.api import solve_modes
from modalfe.solve.estimates import singular_field
from tests.helpers import assert_one_line_error
from tests.oracles.cases import EXAMPLES

E, NU, RHO = 200e9, 0.3, 7850.0
L, H = 0.1, 0.004  # a 100 x 4 x 4 mm steel bar: slenderness L / H = 25


def bar(**tables) -> dict:
    """The scene-file tables of the steel bar along x, clamped at x = 0, with ``tables`` added."""
    return {"name": "bar", "kind": "beam", "materials": {"steel": {"E": E, "nu": NU, "rho": RHO}},
            "parts": [{"name": "bar", "material": "steel", "origin": [0, 0, 0], "size": [L, H, H]}],
            "faces": {"root": ["bar.xmin"], "tip": ["bar.xmax"], "bottom": ["bar.zmin"], "top": ["bar.zmax"]},
            "clamps": {"root": "xyz"}, "analysis": {"near": 2000.0, "count": 4}, **tables}


def clamped_guided() -> float:
    """First bending frequency [Hz] of a clamped-guided Euler-Bernoulli beam: tan(bL) + tanh(bL) = 0, bL = 2.3650
    (Blevins 1979, Table 8-1, clamped-sliding), f = (bL)^2 / (2 pi L^2) sqrt(E I / (rho A))."""
    return 2.36502 ** 2 / (2 * math.pi * L**2) * math.sqrt(E * H**2 / 12 / RHO)


@pytest.mark.parametrize("fidelity", ["solid", "beam"])
def test_a_guided_tip_gives_the_clamped_guided_beam(fidelity):
    # the tip's axial displacement held uniform: its section stays normal to the axis (no tilt), free to translate.
    # Against Euler-Bernoulli: the Timoshenko shear and rotary-inertia correction is about
    # -(bL)^2 (r / L)^2 (1 + E / (kappa G)) / 2 = -0.15 % at L / H = 25 (r^2 = H^2 / 12, kappa = 0.85), the root's
    # Poisson restraint on the solid a few 0.1 % stiffer; 1 % holds both and the solve's 0.5 % tolerance
    modes = solve_modes(scene_from_dict(bar(guides={"tip": "x"})), fidelity=fidelity, near=2000.0, count=4)
    first = min(m.frequency for m in modes)
    assert first == pytest.approx(clamped_guided(), rel=0.01), (first, clamped_guided())
    # without the guide the tip is free: the cantilever's bL = 1.8751, a lower mode; the guide must have acted
    free = min(m.frequency for m in solve_modes(scene_from_dict(bar()), fidelity=fidelity, near=1000.0, count=2))
    assert free == pytest.approx(clamped_guided() * (1.87510 / 2.36502) ** 2, rel=0.01)


def test_a_guided_face_moves_as_one_unknown_per_component():
    # every tip node's u_x is one column of T (the multi-point constraint), the tip's u_y and u_z stay free, and a
    # guided group touching a clamped line is clamped whole (its common value is zero)
    scene = scene_from_dict(bar(guides={"tip": "x"}, kind="solid"))
    model = build_model(scene, "solid")[0]
    [group] = model.guided
    T = model.constraints("short").T.tocsr()
    column = T.tocsc()[:, T[group[0]].indices[0]]
    assert set(column.indices) == set(group) and np.all(column.data == 1.0)
    assert model.n_u_free == T.shape[1] - (model.ndofs - model.n_u)
    touching = build_model(scene.with_overrides(**{"guides.root": "z", "clamps": {}, "edges.line": {
        "faces": ["root", "bottom"], "fix": "z"}}), "solid")[0]
    root_z = model.u_basis.get_dofs(model.mesh.faces["root"]).all("u^3")
    assert len(touching.guided) == 1 and set(root_z) <= set(touching.clamped)


def test_an_edge_holds_the_nodes_two_face_groups_share():
    # the line x = 0, z = 0 of a quadratic mesh: its vertices and the mid-edge nodes between them, each held in z
    scene = scene_from_dict(bar(clamps={}, edges={"line": {"faces": ["root", "bottom"], "fix": "z"}}, kind="solid"))
    model = build_model(scene, "solid")[0]
    at = model.u_basis.doflocs[:, model.clamped]
    assert len(model.clamped) >= 3 and np.allclose(at[[0, 2]], 0.0)
    assert np.all(model.clamped % 3 == 2)  # z components only (scikit-fem numbers vector DOFs 3 s + c)
    assert "line supports" in singular_field(scene)
    # two windows side by side in one face meet on their common border: a knife edge across the bar at x = L / 2
    halves = {"a": [{"face": "bar.zmin", "window": [[0, 0], [L / 2, H]]}],
              "b": [{"face": "bar.zmin", "window": [[L / 2, 0], [L, H]]}]}
    knife = scene_from_dict(bar(clamps={}, faces={**bar()["faces"], **halves}, kind="solid",
                                edges={"knife": {"faces": ["a", "b"], "fix": "z"}}))
    model = build_model(knife, "solid")[0]
    at = model.u_basis.doflocs[:, model.clamped]
    assert len(model.clamped) >= 3 and np.allclose(at[0], L / 2) and np.allclose(at[2], 0.0)


def test_nafems_fv52_line_supports():
    # NAFEMS R0015 test FV52: 10 x 10 x 1 m steel plate, uz = 0 on the four bottom edges. The in-plane modes (193.59,
    # 206.19 Hz) do not load the supports and converge: 0.1 % (measured 0.00 % and -0.05 %). The bending modes sit on
    # a line load, whose field has no mesh-independent limit in 3-D (a line has zero capacity): they fall as the
    # mesh refines (docs/supports.md: 43.52, 43.33, 43.14 Hz on elements x1, x0.67, x0.44 against 45.897), so they
    # are checked to fall on the finer grid and to lie below NAFEMS's values; 10 % bounds how far below on the
    # example's own mesh (measured 4.3-6.6 %), not a convergence to them
    scene = load_scene(EXAMPLES / "nafems_fv52.toml")
    answers = [solve_modes(scene, fidelity="solid", error_estimate=False, size_factor=f) for f in (1.0, 0.67)]
    assert "line supports, a singular line load" in answers[0].fidelity_note  # the caveat is part of the answer
    coarse, fine = (sorted(m.frequency for m in modes) for modes in answers)
    for f in (coarse, fine):
        in_plane = [x for x in f if abs(x / 193.59 - 1) < 0.002 or abs(x / 206.19 - 1) < 0.002]
        assert in_plane == pytest.approx([193.59, 206.19, 206.19], rel=1e-3), f
    bending = [np.array(f[:4]) for f in (coarse, fine)]
    assert np.all(bending[1] < bending[0]), bending
    ratios = bending[0] / np.array([45.897, 109.44, 109.44, 167.89])
    assert np.all((ratios < 1.0) & (ratios > 0.9)), ratios


@pytest.mark.parametrize(("tables", "field"), [
    ({"edges": {"e": {"faces": ["root", "nowhere"], "fix": "z"}}}, "edges.e.faces[1]"),
    ({"edges": {"e": {"faces": ["root", "tip"], "fix": "z"}}}, "edges.e.faces"),  # parallel: no common line
    ({"edges": {"e": {"faces": ["top", "top"], "fix": "z"}}}, "edges.e.faces"),
    ({"edges": {"e": {"faces": ["root", "top"], "fix": "w"}}}, "edges.e.fix"),
    ({"edges": {"e": {"faces": ["root"], "fix": "z"}}}, "edges.e.faces"),
    ({"edges": {"e": {"faces": ["root", "top"]}}}, "edges.e"),
    ({"edges": {"e": {"faces": ["root", "top"], "fix": "z", "at": 1}}}, "edges.e.at"),
    ({"guides": {"nowhere": "x"}}, "guides.nowhere"),
    ({"guides": {"tip": "xx"}}, "guides.tip"),
    ({"guides": {"tip": "r"}}, "guides.tip"),
])
def test_bad_supports_name_their_field(tables, field):
    assert_one_line_error(lambda: scene_from_dict(bar(**tables)), field, SceneError)


def test_reduced_models_refuse_what_they_cannot_hold():
    # the plate's mid-surface and the beam's axis have no line at a face's height: the solid answers (auto says why)
    edge = bar(edges={"e": {"faces": ["root", "top"], "fix": "z"}})
    assert_one_line_error(lambda: build_model(scene_from_dict(edge), "beam"), "edges.e", SceneError)
    plate = {**edge, "kind": "plate", "parts": [{**edge["parts"][0], "size": [L, 0.05, H]}]}
    assert_one_line_error(lambda: build_model(scene_from_dict(plate), "plate"), "edges.e", SceneError)
    side = bar(guides={"top": "x"})  # the beam's guides are on its end faces only
    assert_one_line_error(lambda: build_model(scene_from_dict(side), "beam"), "guides.top", SceneError)
    mirrored = bar(edges={"e": {"faces": ["root", "top"], "fix": "z"}}, symmetry=["y"])
    assert_one_line_error(lambda: scene_from_dict(mirrored), "symmetry", SceneError)


def test_edges_and_guides_are_written_and_read_back(tmp_path):
    from modalfe.scene.writing import scene_to_toml

    scene = scene_from_dict(bar(guides={"tip": "x"}, edges={"e": {"faces": ["root", "top"], "fix": "yz"}}))
    (tmp_path / "bar.toml").write_text(scene_to_toml(scene))
    again = load_scene(tmp_path / "bar.toml")
    assert again.edges == scene.edges and again.guides == scene.guides and again.edges["e"]["fix"] == "yz"
    changed = scene.with_overrides(**{"guides.tip": "xz", "edges.e": {"faces": ["root", "bottom"], "fix": "z"}})
    assert changed.guides["tip"] == "xz" and changed.edges["e"]["faces"] == ("root", "bottom")


def test_a_static_tip_force_on_the_guided_bar():
    # the same T map serves the static and forced solves: a 1 N transverse force on the guided tip deflects it by
    # P L^3 / (12 E I) (Euler-Bernoulli, clamped-sliding) plus the shear term P L / (kappa G A), kappa = 10(1+nu) /
    # (12+11nu) (Cowper 1966): 0.5 % of the bending term at L / H = 25. The 3-D root clamp and the guide's held
    # section stiffen it (measured -0.48 % on a grid twice finer), this quartic grid by 0.3 % more (measured -0.76 %):
    # 1.5 % holds both. The tip's axial displacement is one unknown (the guide): no tilt of its section, where the
    # free cantilever's tilts by its slope (~3 w / (2 L)) times the height
    from modalfe.response.loads import load_vector
    from modalfe.response.superposition import static_response
    from modalfe.scene.loads import Load

    scene = scene_from_dict(bar(guides={"tip": "x"}, mesh={"order": 4}))  # quartic: the grid is set for 2 kHz
    model = build_model(scene, "solid")[0]
    f, _ = load_vector(model, Load(kind="force", group="tip", value=(0.0, 0.0, 1.0)))
    x = static_response(model, f)
    kappa, G = 10 * (1 + NU) / (12 + 11 * NU), E / (2 * (1 + NU))
    expected = L**3 / (12 * E * H**4 / 12) + L / (kappa * G * H**2)
    P = model.displacement_probes(np.array([[L, y, z] for y in (0.0, H / 2, H) for z in (0.0, H)]))
    u, _, w = (P @ x).reshape(3, -1)
    assert w == pytest.approx(np.full(len(w), expected), rel=0.015), (w, expected)
    assert np.ptp(u) < 1e-6 * expected, u


def test_a_guided_plate_strip_lies_between_beam_and_cylindrical_bending():
    # the plate model holds a guided side face by its rotation (beta_x) and one shared u along the edge: a strip
    # 100 x 20 x 2 mm clamped at x = 0, guided at x = L bends between the beam (E I) and cylindrical bending
    # (E I / (1 - nu^2)) of the clamped-guided beam; 1 % either side for shear and the plate's discretization
    strip = bar(guides={"tip": "x"}, kind="plate")
    strip["parts"] = [{**strip["parts"][0], "size": [L, 0.02, 0.002]}]
    modes = solve_modes(scene_from_dict(strip), fidelity="plate", near=300.0, count=3, error_estimate=False)
    first = min(m.frequency for m in modes)
    beam = clamped_guided() / 2  # f ~ H at equal length: the 4 mm bar's value halved
    assert 0.99 * beam < first < 1.01 * beam / math.sqrt(1 - NU**2), (first, beam)
