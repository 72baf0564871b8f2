"""The chain from a working mode to the felt outcome (modalfe.contact.chain), link by link against the stand-alone
pieces: forced's amplitude per volt, the foot and finger simulators, the reduced model's circuit, and the map
against the single-point outcome. A two-patch PZT bar (30 x 2 x 1 mm, 1 s to solve) carries the mode."""

import math

import numpy as np
import pytest

from modalfe.contact.chain import (
    FingerContact,
    FootContact,
    chain_from_rom,
    haptic_map,
    surface_points,
)
from modalfe.contact.finger import finger_steady_state
from modalfe.contact.foot import FootParameters, steady_state
from modalfe.errors import ContactError
from modalfe.response.forced import Damping
from modalfe.response.loads import output_points
from tests.oracles.cases import two_patch_bar_scene

OUTPUTS = (("end", (0.03, 0.001, 0.001)), ("mid", (0.0075, 0.001, 0.001)))
Q = 100.0


@pytest.fixture(scope="module")
def bar():
    from modalfe.response.figures import forced_figures

    scene = two_patch_bar_scene()
    fig = forced_figures(scene, selector="bending-z 4", near=35e3, outputs=OUTPUTS, damping=Damping(Q=Q),
                         error_estimate=False)
    return scene, fig


def foot_chain(fig, **errors):
    return chain_from_rom(fig.rom, FootContact(preload=3.0, speed=0.01), output="end", errors=errors, mode=fig.mode)


def test_amplitude_per_volt_is_forceds_at_outputs_and_points(bar):
    scene, fig = bar
    chain = foot_chain(fig)
    points = np.array(list(output_points(scene, OUTPUTS).values()))
    at_points = chain.amplitude_per_volt_at(points)
    for i, (name, _) in enumerate(OUTPUTS):
        # the same reduced model at the same frequency: equal to rounding
        assert chain.amplitude_per_volt(name) == pytest.approx(fig.amplitude_per_volt[name], rel=1e-12)
        # the state at resonance read at the point (resonant_state) and the reduced model's algebra at that output
        # are one expression in two orders of operations: rounding apart
        assert at_points[i] == pytest.approx(fig.amplitude_per_volt[name], rel=1e-9)
    assert chain.amplitude(7.0) == pytest.approx(7.0 * fig.amplitude_per_volt["end"], rel=1e-12)


def test_foot_outcome_is_the_simulators_at_the_chains_amplitude(bar):
    _, fig = bar
    chain = foot_chain(fig)
    volts = 0.5e-6 / fig.amplitude_per_volt["end"]
    outcome = chain.outcome(volts)
    # the simulator called by hand: the foot driven at the mode's resonance, seed 000's 3 feet (no foot outputs)
    p = FootParameters(frequency=fig.rom.frequency)
    orbit = steady_state(volts * fig.amplitude_per_volt["end"], preload=3.0, speed=0.01, parameters=p)
    expected = 1 - orbit.friction_force / (p.mu0 * p.total_load(3.0))
    assert 0.05 < expected < 0.95  # a point on the curve's rise, not a trivial end
    assert outcome.reduction == pytest.approx(expected, rel=1e-12)
    assert outcome.flight_ratio == pytest.approx(orbit.flight_ratio, rel=1e-12)
    assert math.isnan(outcome.amplitude_error) and outcome.reduction_range == (outcome.reduction,) * 2


def test_finger_outcome_is_the_simulators_at_the_chains_amplitude(bar):
    _, fig = bar
    chain = chain_from_rom(fig.rom, FingerContact(), output="end")
    volts = 0.5e-6 / fig.amplitude_per_volt["end"]  # 1 um pp: a periodic orbit with 4 % reduction at 35 kHz
    outcome = chain.outcome(volts)
    orbit = finger_steady_state(2 * volts * fig.amplitude_per_volt["end"], fig.rom.frequency)
    assert orbit.friction_ratio < 0.99
    assert outcome.reduction == pytest.approx(1 - orbit.friction_ratio, rel=1e-12)
    assert outcome.flight_ratio == pytest.approx(100 - orbit.contact_ratio, rel=1e-12)


def test_finger_outcome_with_an_error_is_the_simulators_curve_at_its_three_amplitudes(bar):
    """With a stated error the finger's three states (W, W (1 -+ e)) are solved as ``simulate_finger`` solves a
    curve, each continued from its smaller neighbour (``FingerContact.states``): the outcome is that curve's."""
    from modalfe.contact.finger import simulate_finger

    _, fig = bar
    e = 0.1
    chain = chain_from_rom(fig.rom, FingerContact(), output="end", errors={"amplitude:end": e})
    volts = 0.5e-6 / fig.amplitude_per_volt["end"]
    outcome = chain.outcome(volts)
    W = volts * fig.amplitude_per_volt["end"]
    curve = simulate_finger(2 * W * np.array([1.0, 1 - e, 1 + e]), fig.rom.frequency)
    # the same calls in the same order: equal to rounding
    assert outcome.reduction == pytest.approx(1 - curve.friction_ratio[0], rel=1e-12)
    assert outcome.reduction_range == pytest.approx((1 - curve.friction_ratio.max(), 1 - curve.friction_ratio.min()),
                                                    rel=1e-12)
    assert outcome.reduction_range[0] < outcome.reduction < outcome.reduction_range[1]  # the curve rises there


def test_circuit_and_rise_time_are_the_reduced_models(bar):
    _, fig = bar
    outcome = foot_chain(fig).outcome(10.0)
    bvd = fig.rom.bvd
    # at resonance the motional branch is N^2 / c = 1 / R1 exactly, so the mean power is V^2 / (2 R1)
    assert outcome.power == pytest.approx(10.0**2 / (2 * bvd["R1"]), rel=1e-9)
    # |Y| = |1 / R1 + i omega C0| at resonance
    assert outcome.current == pytest.approx(10.0 * abs(1 / bvd["R1"] + 1j * fig.rom.omega * bvd["C0"]), rel=1e-9)
    assert outcome.rise_time == pytest.approx(Q / (math.pi * fig.rom.frequency), rel=1e-12)


def test_the_amplitudes_stated_error_spans_the_reduction(bar):
    _, fig = bar
    chain = foot_chain(fig, **{"amplitude:end": 0.1})
    volts = 0.5e-6 / fig.amplitude_per_volt["end"]
    outcome = chain.outcome(volts)
    low = chain.reduction_at(0.9 * outcome.amplitude).reduction
    high = chain.reduction_at(1.1 * outcome.amplitude).reduction
    # the foot's reduction rises with the amplitude here, so the range is the two ends' exactly
    assert low < outcome.reduction < high
    assert outcome.reduction_range == pytest.approx((low, high), rel=1e-12)


def test_voltage_for_a_reduction_inverts_the_outcome(bar):
    _, fig = bar
    chain = foot_chain(fig)
    found = chain.voltage_for(0.3)
    # Brent stops at rtol 1e-4 in the amplitude; the reduction's slope dR/dW * W is below 3 on the foot's rise, so
    # the reduction there is within 1e-3 of the target
    assert chain.outcome(found.voltage).reduction == pytest.approx(0.3, abs=1e-3)
    assert chain.outcome(0.9 * found.voltage).reduction < 0.3  # the first crossing: below it, less
    with pytest.raises(ContactError, match=r"^reduction:"):
        chain.voltage_for(1.5)


def test_map_at_a_point_is_the_single_point_outcome(bar):
    scene, fig = bar
    chain = foot_chain(fig)
    points, weights = surface_points(scene, part="left", side="zmax", count=40)
    assert len(points) >= 40 and weights.sum() == pytest.approx(15e-3 * 2e-3, rel=1e-12)
    end = np.array(list(output_points(scene, OUTPUTS[:1]).values()))
    volts = 0.5e-6 / fig.amplitude_per_volt["end"]
    hmap = haptic_map(chain, np.vstack([points, end]), volts, weights=np.append(weights, 0.0))
    assert hmap.amplitude[-1] == pytest.approx(chain.amplitude(volts, "end"), rel=1e-9)
    exact = chain.outcome(volts).reduction
    # linear interpolation between two table states on a monotone stretch stays between them: within the bracket
    table = np.array([s.reduction for s in hmap.table])
    assert np.all(np.diff(table) >= -1e-12)  # flat below the onset up to the rounding of 1 - F / F0 (1e-16)
    assert abs(hmap.reduction[-1] - exact) <= hmap.bracket[-1]
    # every point reaches no reduction at all, none a complete one; the end point has no area
    assert hmap.area_fraction(-1.0) == pytest.approx((1.0, 1.0, 1.0), rel=1e-12)
    assert hmap.area_fraction(1.0) == (0.0, 0.0, 0.0)
    middle = float(np.median(hmap.reduction[:-1]))
    share = weights[hmap.reduction[:-1] >= middle].sum() / weights.sum()
    assert hmap.area_fraction(middle)[0] == pytest.approx(share, rel=1e-12)


def test_chain_refuses_bad_input_naming_the_field(bar):
    _, fig = bar
    with pytest.raises(ContactError, match=r"^output:"):
        chain_from_rom(fig.rom, FootContact(), output="nowhere")
    with pytest.raises(ContactError, match=r"^points:"):
        chain_from_rom(fig.rom, FootContact()).amplitude_per_volt_at(np.zeros((1, 3)))
    with pytest.raises(ContactError, match=r"^preload:"):
        FootContact(preload=-1.0)
    with pytest.raises(ContactError, match=r"^voltage:"):
        foot_chain(fig).outcome(-1.0)


def test_cli_scene_forms_print_the_chains_outcome_and_write_the_map(bar, tmp_path, capsys):
    import json

    from modalfe.cli.main import main
    from modalfe.scene.writing import scene_to_toml

    _, fig = bar
    scene = two_patch_bar_scene(drive={"damping": f"Q={Q:g}", "outputs": [{"name": "end", "point": [30, 1, 1]}]})
    path = tmp_path / "bar.toml"
    path.write_text(scene_to_toml(scene), encoding="utf-8")
    volts = 0.5e-6 / fig.amplitude_per_volt["end"]
    common = [str(path), "--mode", "bending-z 4", "--near", "35e3", "--voltage", f"{volts!r}", "--no-error-estimate",
              "--json"]
    assert main(["friction", *common, "--preload", "3", "--reduction", "0.3"]) == 0
    out = json.loads(capsys.readouterr().out)
    expected = foot_chain(fig).outcome(volts)
    # the same mode solved again from the same file: its amplitude per volt agrees to the eigen solver's rounding
    assert out["outcomes"][0]["friction_reduction"] == pytest.approx(expected.reduction, rel=1e-6)
    assert out["voltage_for"]["voltage_v"] == pytest.approx(foot_chain(fig).voltage_for(0.3).voltage, rel=1e-3)
    assert main(["finger", *common, "--map", "--points", "30", "--map-dir", str(tmp_path / "map")]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["map"]["points"] >= 30 and len(out["map"]["files"]) == 3
    rows = np.loadtxt(out["map"]["files"][0], delimiter=",", skiprows=1)
    assert rows.shape == (out["map"]["points"], 9)
    assert main(["finger", *common[:-4], "--voltage", "1,2", "--map", "--json"]) == 1
    assert capsys.readouterr().err.strip() == "modalfe: error: --voltage: --map takes one voltage"
    # refused before any solve: what the scene's mode sets, and a voltage with no mode to turn it into amplitude
    assert main(["finger", str(path), "--voltage", "1", "--plot", str(tmp_path / "x.png")]) == 1
    assert capsys.readouterr().err.startswith("modalfe: error: --plot: not with a SCENE")
    assert main(["finger", "--voltage", "1"]) == 1
    assert capsys.readouterr().err.startswith("modalfe: error: --voltage: needs a SCENE")


def test_a_maps_range_carries_the_contact_states_uncertainty():
    """A time-averaged contact state (a chaotic finger) has a stated uncertainty: a point's reduction range and the
    area fraction's range include it, the larger of the two table states around the point."""
    from modalfe.contact.chain import ContactState, contact_map

    class Stated:  # a stand-in contact model: reduction 0.1 per um, every state uncertain by 1 % but the first
        def table(self, amplitudes, progress=False):
            return [ContactState(float(a), 1e5 * a, 50.0, 0.0 if a == 0 else 0.01) for a in amplitudes]

        def describe(self):
            return "stand-in"

    W = np.array([0.5e-6, 2e-6])
    hmap = contact_map(Stated(), 66e3, np.zeros((2, 3)), 1.0, W, 0.0, table_points=5)
    np.testing.assert_allclose(hmap.reduction, 1e5 * W, rtol=1e-12)
    np.testing.assert_allclose(hmap.reduction_high - hmap.reduction, 0.01, rtol=1e-12)
    np.testing.assert_allclose(hmap.reduction - hmap.reduction_low, 0.01, rtol=1e-12)
    # the second point reads 0.2 (0.19-0.21), the first 0.05 (0.04-0.06)
    assert hmap.area_fraction(0.15) == (0.5, 0.5, 0.5)
    assert hmap.area_fraction(0.195) == (0.5, 0.0, 0.5)
    assert hmap.area_fraction(0.205) == (0.0, 0.0, 0.5)
