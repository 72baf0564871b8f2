"""Issue 35, contact: the steady state ``steady_state`` reports is the one the motion from rest reaches (the plate at
rest under its load when the vibration starts, as in seed 000's simulations), checked against an independent
integration from rest (``tests.oracles.contact_brute_force``, RK23 as the seed's ode23) below, at and above the
flight onset, on generated operating points."""

import pytest
from hypothesis import Phase, example, given, settings
from hypothesis import strategies as st

from modalfe.contact.foot import FootParameters, steady_state
from tests.oracles.contact_brute_force import brute_force_steady_state

# Both agree to ~1e-5 where the reference settles (measured at the points below); 0.2 pp (beta) and 0.5 % (<Rt>)
# are the benchmark's targets (studies/benchmark_contact.py), as in test_contact_foot.py: a coexisting orbit
# differs by tens of points (2.04 % against 75.9 % at 1.3 um) and cannot pass.
FLIGHT_PP = 0.2
FRICTION_REL = 5e-3


def assert_reached_from_rest(amplitude: float, preload: float, p: FootParameters, steps_per_period: int) -> None:
    orbit = steady_state(amplitude, preload=preload, parameters=p)
    # a reference that does not settle at one step is tried at half the step count: at 537.6 Hz, dn 10.7 N s/m,
    # Fn 1 N, 0.885 of the onset, RK23 from rest wandered for 3000 periods at T/400 (flight 91.50 % then 91.42 %)
    # and settled in 369 at T/200 on the orbit modalfe reports (91.5344 %): a lightly damped approach, which the
    # step's error keeps stirring, is not a motion without a steady state
    for steps in (steps_per_period, steps_per_period // 2):
        ref = brute_force_steady_state(amplitude, preload=preload, parameters=p, max_step=p.period / steps,
                                       settle=1e-4, max_periods=3000)
        if ref.converged:
            break
    if not ref.converged:  # no steady state within 3000 periods (chaotic rattling: 500 Hz, dn 34 N s/m, Fn 1 N, 3.2 um)
        assert not orbit.periodic, "an orbit where the motion from rest reaches none"
        return
    assert orbit.flight_ratio == pytest.approx(ref.flight_ratio, abs=FLIGHT_PP)
    assert orbit.friction_mean == pytest.approx(ref.friction_mean, rel=FRICTION_REL)


@pytest.mark.parametrize("amplitude, flight", [(1.3e-6, 75.86), (1.4e-6, 76.01)])
def test_above_the_onset_the_orbit_reached_from_rest_is_reported(amplitude, flight):
    # issue 35 at 1.5 kHz, dn 20 N s/m, Fn 10 N (onset 1.295 um): shot from the contact-only state modalfe reported
    # a coexisting period-1 orbit with 2.04 % flight at 1.3 um, and from the quasi-static guess a period-3 orbit with
    # 75.23 % at 1.4 um; the motion from rest (RK23 from rest, max step 1e-6 s, settled to 1e-5) reaches a period-1
    # orbit with 75.861 % and 76.006 % flight (one touchdown a period, multipliers 0.935 at +-124 degrees, so it
    # recurs fastest after three periods). 0.01 pp: the reference's own settling.
    p = FootParameters(frequency=1500.0, dn=20.0)
    assert amplitude > p.onset_amplitude(10.0)
    orbit = steady_state(amplitude, preload=10.0, parameters=p)
    assert orbit.periodic and orbit.periods == 1 and orbit.contacts_per_period == 1
    assert orbit.flight_ratio == pytest.approx(flight, abs=0.01)


def operating_points():
    """Generated (frequency [Hz], dn [N s/m], Fn [N], W / onset): low drive frequencies, where the foot chatters and
    orbits coexist (seed 000's 40.7 kHz is the test file's), amplitudes from half the onset to twice it."""
    return dict(frequency=st.floats(500.0, 3000.0), dn=st.floats(10.0, 200.0), preload=st.floats(1.0, 10.0),
                ratio=st.floats(0.5, 2.0))


# by default the explicit point only (a reference costs 5-30 s on a loaded machine; below the onset see
# test_contact_foot.py); generated ones under -m slow
@settings(deadline=None, phases=(Phase.explicit,))
@given(**operating_points())
@example(frequency=1500.0, dn=20.0, preload=10.0, ratio=1.0)  # issue 35's point, at the onset
def test_the_reported_orbit_is_the_one_reached_from_rest(frequency, dn, preload, ratio):
    p = FootParameters(frequency=frequency, dn=dn)
    # 200 steps a period: RK23 locates the switches as events, the step only bounds its error between them
    assert_reached_from_rest(ratio * p.onset_amplitude(preload), preload, p, 200)


@pytest.mark.slow
@settings(max_examples=12, deadline=None)
@given(**operating_points())
@example(frequency=537.59614388759, dn=10.71043692413177, preload=1.0, ratio=0.8850671462162305)  # see above
def test_the_reported_orbit_is_the_one_reached_from_rest_many(frequency, dn, preload, ratio):
    p = FootParameters(frequency=frequency, dn=dn)
    assert_reached_from_rest(ratio * p.onset_amplitude(preload), preload, p, 400)
