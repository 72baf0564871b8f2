"""Notch textures (seed 001 sections 7-9) and the contact figures."""

import numpy as np
import pytest

from modalfe.contact.foot import simulate_contact, steady_state
from modalfe.contact.texture import NotchTexture, render_texture
from modalfe.errors import ContactError
from modalfe.plot import contact as plots
from tests.helpers import assert_one_line_error


@pytest.fixture(scope="module")
def curve():
    return simulate_contact(np.linspace(0.0, 1e-6, 41), preload=3.0, speed=0.02)


def test_square_notches_count_and_width():
    # 10 notches of half a period over seed 001's 87 mm track, centred in their periods; the sampled
    # fraction of the track inside notches is 1/2 to the sampling step.
    tex = NotchTexture(period=8.7e-3)
    x = np.linspace(0, tex.track_length, 87001)
    d = tex.depth(x)
    assert tex.cycles == pytest.approx(10)
    assert np.count_nonzero(np.diff(d) > 0) == 10
    assert d.mean() == pytest.approx(0.5, abs=1e-3)
    assert d[0] == 0 and d[-1] == 0


def test_on_off_control_switches_between_two_frictions(curve):
    # With an instantaneous amplitude (response_time 0) the friction takes exactly two values: the
    # static friction on the plateaus and the steady friction at amplitude_on in the notches.
    r = render_texture(NotchTexture(period=8.7e-3), curve, amplitude_on=0.65e-6, response_time=0.0)
    low = np.interp(0.65e-6, curve.amplitude, curve.friction_force)
    assert set(np.round(r.friction_force, 12)) == {round(low, 12), round(curve.static_friction, 12)}
    assert r.modulation_frequency == pytest.approx(0.02 / 8.7e-3)  # V / Lambda, seed 001 Fig. 14
    assert r.contrast == pytest.approx(curve.static_friction - low)


def test_fast_sliding_blurs_the_notches():
    # Seed 001 Fig. 14: a faster user raises the modulation frequency V / Lambda; with the plate's
    # ~1 ms amplitude response the amplitude no longer reaches its reference.  At 1 cm/s over 2 mm
    # notches (5 Hz) it settles (to e^-100).  At 2 m/s each notch and plateau last h = 0.5 tau, and
    # the periodic first-order response swings between A e^-h / (1 + e^-h) = 0.378 A and
    # A / (1 + e^-h) = 0.622 A: bounds with 1 % margin.
    tex = NotchTexture(period=2e-3, track_length=20e-3)
    amplitudes = np.linspace(0.0, 0.65e-6, 14)
    slow = render_texture(tex, simulate_contact(amplitudes, preload=3.0, speed=0.01), response_time=1e-3)
    fast = render_texture(tex, simulate_contact(amplitudes, preload=3.0, speed=2.0), response_time=1e-3)
    assert slow.amplitude.max() == pytest.approx(0.65e-6, rel=1e-9)
    settled = fast.amplitude[fast.position > 10e-3]
    assert settled.max() < 0.63 * 0.65e-6 and settled.min() > 0.37 * 0.65e-6
    assert fast.contrast < 0.5 * slow.contrast


def test_proportional_control_follows_a_sine_grating(curve):
    # The notch depth sets a friction reference between the static friction and the friction at
    # amplitude_on; with an instantaneous amplitude the friction follows it to the curve's
    # interpolation error (41 points up to 1 um: < 1 mN here).
    tex = NotchTexture(period=8.7e-3, profile="sine")
    r = render_texture(tex, curve, amplitude_on=0.65e-6, control="proportional", response_time=0.0)
    low = np.interp(0.65e-6, curve.amplitude, curve.friction_force)
    target = curve.static_friction - tex.depth(r.position) * (curve.static_friction - low)
    np.testing.assert_allclose(r.friction_force, target, atol=1e-3)
    assert np.all(r.reference <= 0.65e-6 + 1e-15)


@pytest.mark.parametrize("call, field", [
    (lambda c: NotchTexture(period=0.0), "period"),
    (lambda c: NotchTexture(period=1e-3, notch_width=2e-3), "notch_width"),
    (lambda c: NotchTexture(period=1e-3, profile="saw"), "profile"),
    (lambda c: render_texture(NotchTexture(period=1e-3), c, control="pwm"), "control"),
    (lambda c: render_texture(NotchTexture(period=1e-3), c, amplitude_on=2e-6), "curve"),
    (lambda c: render_texture(NotchTexture(period=1e-3), c, response_time=-1.0), "response_time"),
])
def test_bad_input_is_a_one_line_error_naming_the_field(curve, call, field):
    assert_one_line_error(lambda: call(curve), field, ContactError)


def test_figures_are_returned_not_shown(curve):
    from matplotlib.figure import Figure

    from modalfe.contact.finger import simulate_finger

    rendering = render_texture(NotchTexture(period=8.7e-3), curve)
    finger = simulate_finger([0.0, 0.2e-6], 225e3)
    figs = [plots.friction_figure(curve), plots.orbit_figure(steady_state(0.65e-6, preload=3.0)),
            plots.finger_figure([finger]), plots.texture_figure(rendering)]
    for fig in figs:
        assert isinstance(fig, Figure)
        assert all(ax.has_data() for ax in fig.axes)
