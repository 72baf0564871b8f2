"""``auto`` and the axisymmetric rung (issue 36 item 1): a body of revolution is answered by the axisymmetric model,
its model error checked against the 3-D solid's estimate levels as the plate's where they measure one (else not
measured: the model is exact for a body of revolution); a round scene the model cannot take
is refused with the field at fault in the note, a scene with a box part is not tried, and a model error past tol
falls back to the solid."""

import math
import re

import pytest

from modalfe.errors import SceneError
from modalfe.scene import load_scene, scene_from_dict
from modalfe.solve import fidelity
from modalfe.solve.api import DEFAULT_TOL, solve_modes
from modalfe.solve.fidelity import reduced_fidelities
from tests.oracles.discs import EXAMPLES, PZT5A_DISC, SOLID_FR, SOLID_FR_ERROR

DISC = PZT5A_DISC  # a free 20 x 1 mm disc


def _al_disc(**extra):
    """A free 20 x 2 mm aluminium disc asked near 30 kHz: a coarse mesh, a solid solved in about a second."""
    part = {"name": "disc", "shape": "cylinder", "material": "Al-5052", "centre": [0, 0, 0], "axis": "z",
            "radius": 10, "height": 2}
    return scene_from_dict({"units": "mm", "parts": [part], "analysis": {"near": 30e3, "count": 4}, **extra})


def test_auto_answers_a_free_disc_with_the_axisymmetric_model_where_the_cross_check_cannot_measure():
    """A free aluminium disc is a body of revolution: auto answers with the axisymmetric model. The solid's coarse
    levels of this coarse mesh do not coarsen the disc between them (``cross_check_gap``: ratio 1.00), so they cannot
    measure a model error (extrapolated, they read the (2,0) 0.88 % off, the solid's own error: its answer here,
    25,217.7 Hz, is 0.7 % off). The model is exact for a body of revolution: its discretization's estimate stands,
    the model error is NaN (not measured) and the note says why. Its (2,0) lies within that estimate of an
    independent quartic solid (10,395 DOFs, 1.5 s; 25,041.82 Hz against the axisymmetric 25,041.92: 4e-6 apart)."""
    scene = _al_disc()
    assert reduced_fidelities(scene) == ["axisymmetric"]
    modes = solve_modes(scene)
    assert modes.fidelity == "axisymmetric"
    assert modes.fidelity_note.startswith("auto: axisymmetric answered")
    assert "model error not measured: the 3-D cross-check's levels" in modes.fidelity_note
    mode = modes.labelled("(2,0)")
    assert math.isnan(mode.model_error) and 0 < mode.error_estimate <= DEFAULT_TOL
    reference = solve_modes(_al_disc(mesh={"order": 4, "max_size": 1.5, "min_layers": 2}), fidelity="solid",
                            error_estimate=False).nearest(mode.frequency)
    assert abs(mode.frequency / reference.frequency - 1) <= mode.error_estimate


def test_levels_that_cannot_measure_a_model_error_are_not_solved(monkeypatch):
    """The aluminium disc's cross-check levels cannot measure a model error (``cross_check_gap``, judged on their
    meshes): auto answers with the axisymmetric model without solving them (a 100 mm steel tube's cost 90 s of a
    92 s answer whose own solve took 2 s) and keeps no cross-check."""
    def unsolvable(rung, analysis):
        raise AssertionError("the solid's cross-check levels were solved")

    monkeypatch.setattr(fidelity, "solid_levels", unsolvable)
    modes = solve_modes(_al_disc())
    assert modes.fidelity == "axisymmetric"
    assert "model error not measured: the 3-D cross-check's levels" in modes.fidelity_note
    assert modes.cross_check == ()


def test_levels_that_cannot_be_solved_leave_the_axisymmetric_answer(monkeypatch):
    """Where the solid's cross-check levels would measure but cannot be solved (the 20 x 1 mm disc's thickness mode
    near 1.95 MHz: its levels' ~1e6 DOFs exceed the machine, which ended the whole answer with that refusal), the
    axisymmetric model answers on its discretization's estimate, the note saying why the model error is not
    measured."""
    def too_large(rung, analysis):
        raise SceneError("mesh: too large for this machine")

    monkeypatch.setattr(fidelity, "cross_check_gap", lambda meshes, scene, orders: "")  # as where they measure
    monkeypatch.setattr(fidelity, "solid_levels", too_large)
    modes = solve_modes(_al_disc())
    assert modes.fidelity == "axisymmetric"
    assert "model error not measured: the 3-D cross-check's levels cannot be solved (mesh: too large" in \
        modes.fidelity_note
    assert all(math.isnan(m.model_error) for m in modes)


def test_auto_states_the_model_error_where_the_cross_check_measures_it():
    """The aluminium disc with a PZT-5A disc bonded by a 50 um epoxy film (examples/disc_stack.toml): the solid's
    levels coarsen every part by 1.71 at least, so the model error is measured (0.18 % on T2) and added to the
    discretization's estimate."""
    modes = solve_modes(load_scene(EXAMPLES / "disc_stack.toml"))
    assert modes.fidelity == "axisymmetric"
    assert "from a 3-D solid cross-check, plus discretization" in modes.fidelity_note
    t2 = modes.labelled("T2")
    assert 0 < t2.model_error < t2.error_estimate <= DEFAULT_TOL


@pytest.mark.slow  # 21 s from a fresh cache: the disc's solid cross-check levels
def test_auto_answers_the_pzt5a_disc_with_the_axisymmetric_model_checked_against_the_solid():
    """The disc's default question: R1 answered by the axisymmetric model, its model error from the solid's estimate
    levels finite and within tol, its frequency within the stated errors of the 3-D solid's (tests/oracles/discs.py,
    plus 0.5 Hz of rounding); the harmonics raised till the top one holds no mode (the window holds (8,0))."""
    modes = solve_modes(DISC)
    assert modes.fidelity == "axisymmetric"
    assert modes.fidelity_note.startswith("auto: axisymmetric answered")
    assert len(modes.cross_check) == 2  # the solid's two estimate levels, kept for k_eff and the report
    r1 = modes.labelled("R1")
    assert 0 < r1.model_error <= r1.error_estimate <= DEFAULT_TOL
    assert abs(r1.frequency / SOLID_FR - 1) <= r1.error_estimate + SOLID_FR_ERROR + 0.5 / SOLID_FR
    harmonics = {modes.model.harmonic_of(m.shape) for m in modes}
    assert 8 in harmonics and max(modes.model.harmonics) not in harmonics


def test_a_round_scene_the_model_cannot_take_is_refused_in_the_note():
    """A clamped disc is round but no free body: the solid answers, the note naming the field (clamps)."""
    scene = _al_disc(faces={"base": ["disc.bottom"]}, clamps={"base": "xyz"})
    assert reduced_fidelities(scene) == ["axisymmetric"]
    modes = solve_modes(scene)
    assert modes.fidelity == "solid"
    assert "axisymmetric model not applicable: clamps:" in modes.fidelity_note


def test_a_scene_with_a_box_part_is_not_tried():
    assert reduced_fidelities(load_scene("cube_plate")) == ["plate"]


def test_a_model_error_past_tol_falls_back_to_the_solid(monkeypatch):
    """Where the cross-check states a model error past tol, the solid answers and the note says why (the model
    error made 20 against tol 10, so that only the decision is tested: no refinement at that tol)."""
    monkeypatch.setattr(fidelity, "model_errors", lambda reduced, levels, scene, orders: {m.index: 20.0
                                                                                       for m in reduced})
    monkeypatch.setattr(fidelity, "cross_check_gap", lambda meshes, scene, orders: "")  # as where it measures
    modes = solve_modes(_al_disc(), tol=10.0)
    assert modes.fidelity == "solid"
    assert re.search(r"\(axisymmetric model: model error 2000\.\d\d% on .* > tol 1000\.00%\)", modes.fidelity_note)
    assert math.isnan(modes[0].model_error)


def test_rigid_body_modes_state_no_relative_error():
    """A free disc's rigid-body modes (round-off frequencies, 1e-2 Hz) state no error (NaN, printed "unknown", as the
    solid's Richardson leaves them), not a relative step of round-off over round-off (1.5e6 on the buzzer's yaw);
    the elastic modes theirs."""
    modes = solve_modes(_al_disc(analysis={"near": 1, "count": 6}), fidelity="axisymmetric")
    top = max(m.frequency for m in modes)
    rigid = [m for m in modes if m.frequency < 1e-6 * top]
    assert rigid and all(math.isnan(m.error_estimate) for m in rigid)
    assert all(0 <= m.error_estimate < 1 for m in modes if m not in rigid)


def test_the_note_says_where_harmonics_above_the_top_may_hold_modes_of_the_window():
    """A free 40 x 1 mm PZT-5A disc round R1 (49.7 kHz): the harmonics rule stops at n = 8, which holds no mode of the
    window, yet n = 8 has one below the window's top, and the higher harmonics' lowest modes lie in it ((10,0) at
    42.4 kHz, an n = 11 mode at 50.4 kHz: order 4, n = 0..24): the note says modes may be missing. The 20 x 2 mm
    aluminium disc's window (n = 0..4) has no such mode: no such note."""
    part = {"name": "disc", "shape": "cylinder", "material": "PZT-5A", "centre": [0, 0, 0], "axis": "z",
            "radius": 20, "height": 1, "poling": 1}
    thin = scene_from_dict({"units": "mm", "parts": [part], "analysis": {"near": 49.7e3, "count": 6}})
    modes = solve_modes(thin, fidelity="axisymmetric")
    assert max(modes.model.harmonics) == 8
    assert "harmonics above n = 8 (not solved) may hold modes of the window: n = 8 has 1 mode(s)" in \
        modes.fidelity_note
    assert "harmonics above" not in solve_modes(_al_disc(), fidelity="axisymmetric").fidelity_note
