"""Bed-spring finger model (seed 004): momentum balance, trends, the equal-friction amplitude ratio,
the literal reading of eq. (1), a brute-force reference, bad input."""

import math

import numpy as np
import pytest

from modalfe.contact.finger import (
    FingerParameters,
    _advance,
    _FingerDynamics,
    equal_friction,
    finger_steady_state,
    simulate_finger,
)
from modalfe.errors import ContactError
from tests.helpers import assert_one_line_error

F_P = FingerParameters().preload


def test_zero_amplitude_is_plain_coulomb_sliding():
    # No vibration: permanent contact and sliding, f_T = mu f_N = mu f_p; only rounding differs.
    orbit = finger_steady_state(0.0, 66e3)
    assert orbit.contact_ratio == 100.0
    assert orbit.friction_ratio == pytest.approx(1.0, rel=1e-12)
    assert orbit.normal_mean == pytest.approx(F_P, rel=1e-12)


@pytest.mark.parametrize("amplitude, frequency", [(0.5e-6, 66e3), (0.2e-6, 225e3), (0.4e-6, 225e3)])
def test_mean_contact_force_equals_preload(amplitude, frequency):
    # Seed 004 eq. (2) summed over the three masses and averaged over a period: <f_Nsc> = f_p exactly
    # on a periodic orbit; shooting tolerance and quadrature leave < 1e-9, so 1e-6 is safe.
    orbit = finger_steady_state(amplitude, frequency)
    assert orbit.periodic and orbit.contact_ratio < 100
    assert orbit.normal_mean == pytest.approx(F_P, rel=1e-6)


def test_friction_falls_with_amplitude_and_falls_faster_at_high_frequency():
    # Seed 004 section II.C, Fig. 6: friction reduction grows with amplitude and, at equal amplitude,
    # with frequency.
    high = simulate_finger(np.linspace(0.1e-6, 0.4e-6, 7), 225e3)
    assert np.all(np.diff(high.friction_ratio) < 0)
    low = finger_steady_state(0.3e-6, 66e3)
    assert high.friction_ratio[4] < low.friction_ratio < 1  # both at 0.3 um pp


def test_equal_friction_ratio_lies_between_velocity_and_acceleration():
    # Seed 004 Fig. 7: the model gives A(225 kHz) = 0.12 A(66 kHz) for equal friction, between equal
    # velocity (0.29) and equal acceleration (0.086).  Here at mu_US/mu = 0.8.  The 66 kHz points are
    # time averages (the finger bounces irregularly there) with ~0.3 % noise in mu_US/mu, about 1 % in
    # amplitude.  0.12 is the slope of a line through the seed's figure and our contact-release
    # reading is ours, so the test asks for 25 % around it and for the order between the invariants.
    low = simulate_finger([1.7e-6, 1.9e-6, 2.1e-6], 66e3)
    high = simulate_finger([0.18e-6, 0.2e-6, 0.22e-6], 225e3)
    eq = equal_friction(low, high, [0.8])
    assert eq.acceleration_ratio < eq.ratio[0] < eq.velocity_ratio
    assert eq.ratio[0] == pytest.approx(0.12, rel=0.25)


@pytest.mark.parametrize("amplitude", [1e-6, 3e-6])
def test_literal_reading_gives_no_friction_reduction(amplitude):
    # Eq. (1) as printed (dampers on absolute velocities): the finger does leave the plate, but its
    # contact force restarts from zero at each landing and grows slower than K_Tsc V_F / mu, so the
    # pulp slides from the first instant and <f_T> = mu <f_N> = mu f_p: no reduction (rounding only).
    orbit = finger_steady_state(amplitude, 66e3, parameters=FingerParameters(reading="literal"))
    assert orbit.periodic and orbit.contact_ratio < 80
    assert orbit.friction_ratio == pytest.approx(1.0, abs=1e-9)


@pytest.mark.parametrize("reading", ["kelvin-voigt", "literal"])
def test_monodromy_matches_finite_differences(reading):
    # Transition matrices (modal, and the free finger's centre of mass) and saltation at landing;
    # central differences agree to ~1e-7 of the largest entry, 1e-5 catches any missing term.
    dyn = _FingerDynamics(FingerParameters(reading=reading), 2 * math.pi * 66e3, 1e-6)
    x0 = np.array([2e-7, 0, 0, -0.05, 0, 0, 0.2 * dyn.q_rest])
    T = 1 / 66e3
    _, _, Phi = _advance(dyn, 0.0, T, x0)
    J = np.empty((7, 7))
    for j in range(7):
        e = np.zeros(7)
        e[j] = 1e-13 if j < 3 or j == 6 else 1e-8
        J[:, j] = (_advance(dyn, 0.0, T, x0 + e)[1] - _advance(dyn, 0.0, T, x0 - e)[1]) / (2 * e[j])
    assert np.max(np.abs(J - Phi)) < 1e-5 * np.max(np.abs(Phi))


@pytest.mark.parametrize("call, field", [
    (lambda: FingerParameters(K_sc=-1.0), "K_sc"),
    (lambda: FingerParameters(M_st=0.0), "M_st"),
    (lambda: FingerParameters(damping_ratio=math.nan), "damping_ratio"),
    (lambda: FingerParameters(reading="verbatim"), "reading"),
    (lambda: finger_steady_state(1e-7, 0.0), "frequency"),
    (lambda: finger_steady_state(math.nan, 66e3), "amplitude"),
    (lambda: simulate_finger([0.0, -1e-7], 66e3), "amplitude[1]"),
])
def test_bad_input_is_a_one_line_error_naming_the_field(call, field):
    assert_one_line_error(call, field, ContactError)


def test_equal_friction_needs_a_level_inside_the_curves():
    curve = simulate_finger([0.0, 0.1e-6], 225e3)
    with pytest.raises(ContactError, match=r"^level:"):
        equal_friction(curve, curve, [0.5])


def brute_force_friction_ratio(amplitude_pp, frequency, periods):
    """Seed 004's own manner: a variable-step integrator (here RK45, rtol 1e-9) with the state machine
    as terminal events, Kelvin-Voigt reading; mu_US / mu averaged over the second half."""
    from scipy.integrate import solve_ivp

    p = FingerParameters()
    K, D, M = p.stiffness, p.damping, p.mass
    fp, w_, a = p.preload, 2 * math.pi * frequency, amplitude_pp / 2
    q0, T = fp / K[0], 1 / frequency

    def forces(t, y, contact):
        w, wd = a * math.sin(w_ * t), a * w_ * math.cos(w_ * t)
        fe = fp + K[1] * (y[0] - y[1]) + D[1] * (y[3] - y[4])
        fst = fp + K[2] * (y[1] - y[2]) + D[2] * (y[4] - y[5])
        fsc = fp + K[0] * (w - y[0]) + D[0] * (wd - y[3]) if contact else 0.0
        return fsc, fe, fst, wd

    def rhs(contact):
        def f(t, y):
            fsc, fe, fst, wd = forces(t, y, contact)
            qd = wd - y[3] if contact else -K[0] / D[0] * y[6]
            return [y[3], y[4], y[5], (fsc - fe) / M[0], (fe - fst) / M[1], (fst - fp) / M[2], qd]
        return f

    def separation(t, y):
        return forces(t, y, True)[0]

    def landing(t, y):
        return q0 + a * math.sin(w_ * t) - y[0] - y[6]

    separation.terminal, separation.direction = True, -1
    landing.terminal, landing.direction = True, 1
    y, t, contact, tc = np.array([0, 0, 0, 0, 0, 0, q0], float), 0.0, True, None
    t_end, t_avg = periods * T, periods * T / 2
    int_t = int_n = 0.0
    while t < t_end:
        sol = solve_ivp(rhs(contact), (t, t_end), y, method="RK45", max_step=T / 200, rtol=1e-9, atol=1e-16,
                        events=separation if contact else landing, dense_output=True)
        if contact and sol.t[-1] > t_avg:
            ts = np.linspace(max(t, t_avg), sol.t[-1], 400)
            fn = np.array([forces(ti, sol.sol(ti), True)[0] for ti in ts])
            stick = p.K_Tsc * p.speed * (ts - tc) if tc is not None else np.full_like(ts, np.inf)
            sliding = np.maximum.accumulate(stick >= p.mu * fn)
            int_t += np.trapezoid(np.where(sliding, p.mu * fn, stick), ts)
            int_n += np.trapezoid(fn, ts)
        t, y = sol.t[-1], sol.y[:, -1].copy()
        if sol.status == 1:
            t, y = sol.t_events[0][0], sol.y_events[0][0].copy()
            contact = not contact
            if contact:
                tc, y[6] = t, q0 + a * math.sin(w_ * t) - y[0]
    return int_t / (p.mu * int_n)


@pytest.mark.slow
def test_matches_brute_force():
    # 400 periods from rest, averaged over the last 200: the transient (slowest layer, critically
    # damped at 460 Hz) has decayed by e^-6 there; the 400-point trapezoid per contact adds ~1e-4.
    ref = brute_force_friction_ratio(0.2e-6, 225e3, 400)
    assert finger_steady_state(0.2e-6, 225e3).friction_ratio == pytest.approx(ref, rel=2e-3)
