"""Tuning to the felt outcome (modalfe/design/tuning.py, ``LeastVoltage``): the least drive voltage for a friction
reduction, V = W_R(f) / A, its derivative against a finite difference, a run that lowers it on the frequency target
and is verified on the resolved model through the chain, and the CLI's one-line refusals of --objective.

The two-patch PZT bar of tests/contact/test_chain.py (30 x 2 x 1 mm, bending-z 4 near 35.5 kHz, ~1 s a solve)
carries the mode, read at a point 1 mm from its end, Q = 100; seed 000's foot at 3 N and 1 cm/s."""

import math

import pytest

from modalfe.cli.main import main
from modalfe.contact.chain import FootContact, amplitude_for
from modalfe.design.outcome import LeastVoltage, ReductionAt, outcome_at
from modalfe.design.tuning import FrequencyTarget, tune
from modalfe.errors import SceneError
from modalfe.response.sensitivity import parameter_value, with_values
from modalfe.solve.api import solve_modes
from tests.oracles.cases import two_patch_bar_scene

LABEL, NEAR = "bending-z 4", 35.45e3
# the patches' length moves the frequency, d31 (both patches: one material) the amplitude; d31 leaves the mesh as it
# is, so a finite difference of re-solved designs has no remeshing in it (a length's has: the 1 mm elements move)
D31 = "materials.PZT-5A.d31"
NAMES = ["parts.right.size.x", D31]
OBJECTIVE = LeastVoltage(0.3, FootContact(preload=3.0, speed=0.01))


def _bar():
    return two_patch_bar_scene(drive={"damping": "Q=100", "outputs": [{"name": "end", "point": [29, 1, 1]}]})


def _at(scene, objective=OBJECTIVE):
    modes = solve_modes(scene, near=NEAR, count=6, fidelity="solid", error_estimate=False)
    o = outcome_at(scene, modes, LABEL, NEAR, NAMES, objective)
    return o.volts, o.amplitude_per_volt, o.output, o.gradient, o.sensitivities


def test_the_voltages_derivative_is_a_finite_differences():
    """d ln V / d ln p = (d ln W_R / d ln f)(d ln f / d ln p) - d ln A / d ln p: the amplitude's from the
    sensitivities, the contact model's frequency slope by a central difference of its steady state (1 %, W_R found to
    1e-10), against a central difference of V over two re-solved designs (d31 +- 0.3 %). Measured: -0.14068 against
    -0.14071, the contact model's term (-0.128) ten times the amplitude's (0.012)."""
    scene = _bar()
    volts, amplitude, output, g, sens = _at(scene)
    row = list(sens.labels).index(LABEL)
    f, dlnf = sens.frequencies[row], sens.relative[row]
    assert output == "end" and volts == pytest.approx(
        amplitude_for(OBJECTIVE.contact.tuned(f, None), 0.3) / amplitude, rel=1e-12)
    w = [amplitude_for(OBJECTIVE.contact.tuned(f * (1 + s * 0.01), None), 0.3, rtol=1e-10) for s in (1, -1)]
    dlnw = math.log(w[0] / w[1]) / math.log(1.01 / 0.99)
    d31 = parameter_value(scene, D31)
    h = 3e-3
    v = [_at(with_values(scene, {D31: d31 * (1 + s * h)}))[0] for s in (1, -1)]
    fd = math.log(v[0] / v[1]) / math.log((1 + h) / (1 - h))
    chain = dlnw * dlnf[1] - g[1]
    # the difference's truncation (h^2 times the third derivative) and W_R's search tolerance (1e-4 / (2 h), 2 %
    # of the slope at most, measured 2e-4): 1 % holds both
    assert fd == pytest.approx(chain, rel=1e-2)
    assert abs(dlnw * dlnf[1]) > 5 * abs(g[1])  # the contact model's term is what is checked here, not noise


def test_tuning_lowers_the_voltage_on_the_target_and_verifies_it_through_the_chain():
    """bending-z 4 held at 36.2 kHz (2 % above the start) while the voltage for 30 % is minimized, |d31| bounded to
    +5 %. Every kept design on the target after the first asks less than the first on it, and the run ends on the
    optimality test (d31 on its bound, the length alone held by the target). The resolved stage re-solves the
    final design without an error estimate (the bar's 1 mm elements leave the estimate levels nothing to say: its
    stated error is inf, the cube_plate run in docs/tuning.md has one), and the chain there (``haptic_chain``) gives
    the voltage and the outcome. Measured: 1488 V at the start, 1464.8 V on the target, 1460.8 V final, 3
    evaluations on the own mesh."""
    scene = _bar()
    d31 = parameter_value(scene, D31)
    target = 36.2e3
    result = tune(scene, [FrequencyTarget(LABEL, target)], NAMES, maximize=OBJECTIVE, tol=5e-3,
                  bounds={D31: (1.05 * d31, d31)}, resolution={"error_estimate": False})
    assert result.converged and "projected gradient" in result.reason, result.reason
    cheap = [it for it in result.iterates if not it.resolved and it.accepted]
    on_target = [it for it in cheap if abs(it.frequencies[0] / target - 1) <= 5e-3]
    assert len(on_target) >= 2 and max(it.volts for it in on_target[1:]) < on_target[0].volts
    assert cheap[-1].values[D31] == pytest.approx(1.05 * d31, rel=1e-9)  # held on its bound
    final = result.final
    assert final.resolved and abs(final.frequencies[0] / target - 1) <= 5e-3
    assert result.verified.output == "end"
    # the outcome at the verified voltage: the required reduction, to the amplitude's search tolerance (a slope of
    # the reduction ~1 per relative amplitude: 1e-4, doubled)
    assert result.outcome.reduction == pytest.approx(0.3, abs=2e-4)
    # the chain's voltage on the same design and mesh as the last own-mesh iterate: the objective's own V = W_R / A,
    # the same numbers (forced's reduced model and the sensitivities' amplitude) to W_R's search tolerance
    assert result.verified.voltage == pytest.approx(cheap[-1].volts, rel=1e-3)


def test_cli_prints_the_iterates_voltages_and_the_verified_outcome(tmp_path, capsys):
    """The same run from the command line, as JSON: each own-mesh iterate's voltage, and the chain's verified voltage
    and outcome at the final design; the text form prints the verified line."""
    import json

    from modalfe.scene.writing import scene_to_toml

    path = tmp_path / "bar.toml"
    path.write_text(scene_to_toml(_bar()))
    d31 = parameter_value(_bar(), D31)
    args = ["tune", str(path), "--vary", ",".join(NAMES), "--target", f"{LABEL}=36.2e3", "--objective",
            "volts-for reduction=30% preload=3 speed=0.01", "--bounds", f"{D31}={1.05 * d31!r}:{d31!r}",
            "--no-error-estimate"]
    assert main([*args, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    volts = [it["volts"] for it in out["iterates"] if not it["resolved"]]
    assert volts[-1] < volts[0] and out["verified"]["output"] == "end"
    # the chain on the final design's solve and the objective's own V on the same design and mesh (test above)
    assert out["verified"]["voltage_v"] == pytest.approx(volts[-1], rel=1e-3)
    assert out["verified"]["outcome"]["friction_reduction"] == pytest.approx(0.3, abs=2e-4)
    assert main(args) == 0
    text = capsys.readouterr().out
    assert "verified on the resolved model: " in text and f"{volts[0]:.4g} V at the start" in text


@pytest.mark.parametrize("objective, message", [
    ("least-volts reduction=0.6", "--objective: expected"),
    ("volts-for preload=3", "--objective: give reduction=R"),
    ("volts-for reduction=1.5", "--objective reduction: expected a fraction"),
    ("volts-for reduction=0.6 preload=abc", "--objective: preload and speed must be numbers"),
    ("volts-for reduction=0.6 preload=-1", "--objective: preload"),
    ("volts-for reduction=0.6 contact=hand", "--objective: contact must be foot or finger"),
    ("volts-for reduction=0.6 voltage=3", "--objective: 'voltage=3' is not one of"),
    ("reduction-at reduction=0.6", "--objective: 'reduction=0.6' is not one of"),
    ("reduction-at volts=-2", "--objective: volts must be a positive finite number"),
    ("reduction-at preload=3", "--objective: give volts=V"),
])
def test_bad_objectives_are_refused_in_one_line(tmp_path, capsys, objective, message):
    assert main(["tune", "cube_plate", "--vary", "length", "--target", "(0,6)=40.7e3", "--objective",
                 objective]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1


def test_objective_refusals_in_the_library():
    with pytest.raises(SceneError, match=r"^objective: the reduction must lie strictly between 0 and 1"):
        tune(_bar(), [FrequencyTarget(LABEL, 36e3)], NAMES, maximize=LeastVoltage(1.2, FootContact()))
    with pytest.raises(SceneError, match=r"^maximize: k_eff or an outcome objective"):
        tune(_bar(), [FrequencyTarget(LABEL, 36e3)], NAMES, maximize="volts")


AT = ReductionAt(1460.0, FootContact(preload=3.0, speed=0.01))  # ~30 % on the bar at the start (measured 29.7 %)


def test_the_reductions_derivative_is_a_finite_difference():
    """d R / d ln p at a fixed voltage = (dR / d ln W)(d ln A / d ln p) + (dR / d ln f)(d ln f / d ln p): the
    objective's gradient holds the first term (the second drops out on the targets, module docstring of
    modalfe.design.tuning), the second from the contact model's 1 % central difference in f; their sum against a
    central difference of R over two re-solved designs (d31 +- 0.3 %)."""
    scene = _bar()
    _, _, output, g, sens = _at(scene, AT)
    row = list(sens.labels).index(LABEL)
    f, dlnf = sens.frequencies[row], sens.relative[row]
    A = _at(scene, AT)[1]
    contact = AT.contact
    dRdlnf = (contact.tuned(f * 1.01, None).state(AT.voltage * A).reduction
              - contact.tuned(f * 0.99, None).state(AT.voltage * A).reduction) / math.log(1.01 / 0.99)
    d31 = parameter_value(scene, D31)
    h = 3e-3
    r = [outcome_at(s, solve_modes(s, near=NEAR, count=6, fidelity="solid", error_estimate=False), LABEL, NEAR,
                    NAMES, AT).reduction for s in (with_values(scene, {D31: d31 * (1 + k * h)}) for k in (1, -1))]
    fd = (r[0] - r[1]) / math.log((1 + h) / (1 - h))
    # the central differences' truncation (h^2, 1e-5 relative) and the contact steady state's own tolerance: 1 %
    assert output == "end" and fd == pytest.approx(g[1] + dRdlnf * dlnf[1], rel=1e-2)
    # d31 moves the frequency too (d ln f / d ln d31 = 0.11): the frequency term is ~10x the gradient's (measured
    # 0.049 and 0.0048), so the 1 % on their sum holds the gradient to ~11 %; it must stay 5x that tolerance at least
    assert abs(g[1]) > 5 * 1e-2 * abs(fd)


@pytest.mark.slow  # 19 s: two stages of solves of the bar
def test_tuning_raises_the_reduction_at_a_voltage_and_verifies_it_through_the_chain():
    """The run of the LeastVoltage test above, maximizing the reduction at 1460 V instead: every kept design on the
    target after the first gives more, d31 ends on its bound, and the chain on the resolved model (the final design
    re-solved without an error estimate) gives the final own-mesh iterate's reduction at that voltage."""
    scene = _bar()
    d31 = parameter_value(scene, D31)
    target = 36.2e3
    result = tune(scene, [FrequencyTarget(LABEL, target)], NAMES, maximize=AT, tol=5e-3,
                  bounds={D31: (1.05 * d31, d31)}, resolution={"error_estimate": False})
    assert result.converged, result.reason
    cheap = [it for it in result.iterates if not it.resolved and it.accepted]
    on_target = [it for it in cheap if abs(it.frequencies[0] / target - 1) <= 5e-3]
    assert len(on_target) >= 2 and min(it.reduction for it in on_target[1:]) > on_target[0].reduction
    assert cheap[-1].values[D31] == pytest.approx(1.05 * d31, rel=1e-9)
    assert result.verified is None and result.outcome.voltage == AT.voltage
    # the same design and mesh as the last own-mesh iterate: forced's reduced model against the sensitivities'
    # amplitude (1e-3 apart at most in A, as the LeastVoltage test), times dR / d ln W < 1
    assert result.outcome.reduction == pytest.approx(cheap[-1].reduction, abs=1e-3)
