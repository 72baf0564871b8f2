"""A sweep's outcome columns (``modalfe sweep --outcome``, ``modalfe.design.sweep.OutcomeColumns``): each point's
columns are the chain's outcome for that point's scene (``haptic_chain``, as ``friction SCENE`` gives it; the bar is
solved without an error estimate, its 1 mm elements leave the estimate levels nothing to say, so no range here); a
bad --outcome is refused in one line.

The two-patch PZT bar of tests/contact/test_chain.py (30 x 2 x 1 mm, ~1 s a solve), read
at a point 1 mm from its end, Q = 100; seed 000's foot at 3 N and 1 cm/s."""

import json

import pytest

from modalfe.cli.main import main
from modalfe.contact.chain import FootContact, haptic_chain
from modalfe.scene import load_scene
from modalfe.scene.writing import scene_to_toml
from tests.oracles.cases import two_patch_bar_scene

LABEL, NEAR, VOLTS = "bending-z 6", 31.6e3, 1000.0


def test_sweep_reports_the_chains_outcome_as_columns(tmp_path, capsys):
    scene = two_patch_bar_scene(drive={"damping": "Q=100", "outputs": [{"name": "end", "point": [29, 1, 1]}]})
    path = tmp_path / "bar.toml"
    path.write_text(scene_to_toml(scene))
    # 1 and 3 ug spread over one patch's top: the mode is labelled bending-z 6 near 31.6 kHz with a mass group
    args = ["sweep", str(path), "--param", "masses.top_right=1e-9:3e-9:2", "--out", str(tmp_path / "s.csv"),
            "--scheduler", "inline", "--mode", LABEL, "--near", str(NEAR), "--no-error-estimate", "--outcome",
            f"reduction volts={VOLTS} preload=3 speed=0.01"]
    assert main([*args, "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert len(rows) == 2 and all(r["status"] == "ok" for r in rows), [r["status"] for r in rows]
    reductions = []
    for r in rows:
        scene = load_scene(str(path), **r["params"])
        expected = haptic_chain(scene, FootContact(preload=3.0, speed=0.01), selector=LABEL, near=NEAR,
                                error_estimate=False).outcome(VOLTS).to_json()
        got = r["extra"]
        # the same question solved again and the same chain: equal to the solves' accuracy, not to rounding. PARDISO
        # on two threads sums in an order that varies (8e-15 apart between two factorizations of one matrix), which
        # the Lanczos vectors (ARPACK tol 1e-8) and the orbit's Newton (scaled residual 1e-11) carry to ~1e-9:
        # measured 8e-10 on the amplitude, 3.8e-9 on the reduction; a wrong point or chain differs by percents
        assert got["friction_reduction"] == pytest.approx(expected["friction_reduction"], rel=1e-7)
        assert got["friction_reduction_range"] == pytest.approx(expected["friction_reduction_range"], rel=1e-7)
        assert got["amplitude_error"] == pytest.approx(expected["amplitude_error"], rel=1e-7, nan_ok=True)
        reductions.append(got["friction_reduction"])
    assert min(reductions) > 0.05 and reductions[0] != reductions[1]  # on the curve's rise, and the design moves it
    assert main(args) == 0  # resumed: the table already holds both points
    text = capsys.readouterr().out
    assert "reduction [%] (range)" in text and f"{100 * reductions[0]:.2f}" in text


def test_a_bad_outcome_is_refused_in_one_line_before_any_solve(tmp_path, capsys):
    # the parser is tune --objective's (modalfe.cli.options.parse_outcome; its cases: test_tuning_outcome.py)
    assert main(["sweep", "cube_plate", "--param", "length=0.06:0.064:2", "--out", str(tmp_path / "s.csv"),
                 "--outcome", "reduction volts=0"]) == 2
    assert capsys.readouterr().err.strip() == ("modalfe: error: --outcome: volts must be a positive finite number, "
                                               "got '0'")
