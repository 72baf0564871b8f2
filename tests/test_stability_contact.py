"""Contact stress ranges: stiffness 1e4-1e9 N/m, amplitude 1e-12-1e-4 m, preload 1e-3-1e3 N, speed 0."""

import itertools

import numpy as np
import pytest

from modalfe.contact import simulate_contact
from modalfe.contact.foot import FootParameters

BASE = FootParameters()
CASES = [
    pytest.param(*case, marks=pytest.mark.xfail(strict=True, reason=(
        "no periodic orbit: the 400-period average misses the momentum balance by 5.7 % (open in #10)")))
    if case == (1e9, 1e-8, 1.0) else case
    for case in itertools.product([1e4, 1e6, 1e9], [1e-12, 1e-8, 1e-6, 1e-4], [1e-3, 1.0, 1e3])
]


@pytest.mark.parametrize("kn,amplitude,preload", CASES)
def test_contact_over_extreme_ranges_is_finite_bounded_and_balanced(kn, amplitude, preload):
    params = BASE.with_(kn=kn)
    curve = simulate_contact([amplitude], preload=preload, speed=0.01, parameters=params)
    beta, friction, normal = curve.flight_ratio[0], curve.friction_force[0], curve.normal_mean[0]
    weight = preload + params.mass * params.g
    assert np.isfinite([beta, friction, normal]).all()
    assert 0.0 <= beta <= 100.0
    assert -1e-12 <= friction <= BASE.mu0 * weight * (1 + 1e-8)  # Coulomb bound of eq. (16), to round-off
    # momentum balance over a period: <Rn> = (Fn + m g) / n; exact (1e-6) on a periodic orbit, a
    # 400-period time average (1 %) where the motion has no orbit of up to 8 periods (said in the log)
    tolerance = 1e-6 if curve.periodic[0] else 1e-2
    assert normal == pytest.approx(weight / params.n, rel=tolerance)


def test_zero_sliding_speed_gives_no_sliding_friction():
    curve = simulate_contact([1e-6, 1e-5], preload=3.0, speed=0.0)
    # Coulomb-Orowan (eqs 14-17): the tangential force builds with kt V (t - t_c); at V = 0 it stays ~0
    assert np.all(np.abs(curve.friction_force) < 1e-3 * BASE.mu0 * 3.0)
