"""p-refinement error estimates (``mesh.order`` 4: orders 2, 3, 4 on one grid): the stated error covers the actual
error on order-4 verification cases (studies/verification_errors.py ``--order 4``), and at order 3 with the order
2-3 step as a floor under the h-estimate (``--order 3``), and the rate and tail of
``p_rate`` / ``p_extrapolation`` on synthetic sequences."""

import math
from types import SimpleNamespace

import pytest

from modalfe.results.modes import Mode, Modes
from modalfe.solve import estimates
from modalfe.solve.estimates import MIN_P_RATE, p_extrapolation, p_rate

# fast order-4 cases of the study (2-10 s each). References: the exact 3-D (Rayleigh-Lamb) frequency of the SS
# plates, solved to 1e-14 (tests/oracles/analytic.py), so no tolerance beyond the stated error itself; the k31
# bar's 1-D fr with Rayleigh's lateral-inertia correction, within 3e-5 of the 3-D limit (its next order, see
# test_verification.py), which ``Row.covered`` adds to the stated error (``reference_uncertainty``); the clamped
# thin plate's order-2 solid of 0.83 mm elements (12-24x finer), its own stated error added to the actual error
# The clamped roots (a singular field) on coarse grids are the hard cases: the 3-D solid's error there is provably
# larger than a rate observed through orders 2-3-4 (4-6) would state (the cantilever's 3-D limit lies 0.31-0.44 %
# above Timoshenko; the clamped bar's elastic reference bounds the exact frequency from above), which is why the
# estimate keeps the floor rate MIN_P_RATE (modalfe/solve/estimates.py).
FAST = ("thick SS plate, solid", "thick SS plate, solid, coarse", "thin SS plate, solid",
        "thin SS plate, solid, coarse", "k31 bar, solid, coarse", "cantilever, solid, coarse")
# on demand: 10 s and more each (the clamped bar's coarse order-4 case 39 s on a quiet 2-core machine)
SLOW = ("clamped thin plate, solid", "clamped thin plate, solid, coarse", "piezo cube, solid",
        "clamped bar, solid, coarse")


def _params():
    return [pytest.param(name) for name in FAST] + [pytest.param(name, marks=pytest.mark.slow) for name in SLOW]


@pytest.mark.parametrize("case", _params())
def test_order_4_stated_error_covers_the_actual_error(case):
    from tests.helpers import load_study

    rows = load_study("verification_errors").order_cases(4)[case]()
    assert rows, case
    assert all(r.method.startswith("p-refinement") for r in rows), {r.method for r in rows}
    assert all(r.covered for r in rows), [(r.case, r.mode, r.actual, r.stated, r.rate) for r in rows if not r.covered]


# order-3 Lagrange cases of the same study, the coarse clamped ones where the h-estimate alone was short (the 25 mm
# cantilever's bending 3: stated 0.95 % against 1.78 %) and a smooth one; with the order 2-3 step as a floor,
# ``python studies/verification_errors.py --order 3``: 81 of 82 covered, the other (a beam-model row) undecided
# (the clamped bar's reference, 73k DOFs to bound its own error by a nested step, takes ~40 s: slow)
ORDER_3 = ("cantilever, solid, coarse", "thick SS plate, solid, coarse")


@pytest.mark.parametrize("case", [*ORDER_3, pytest.param("clamped bar, solid, coarse", marks=pytest.mark.slow)])
def test_order_3_stated_error_covers_the_actual_error(case):
    from tests.helpers import load_study

    rows = load_study("verification_errors").order_cases(3)[case]()
    assert rows, case
    assert all("at least the order 2-3 step" in r.method for r in rows), {r.method for r in rows}
    assert all(r.covered for r in rows), [(r.case, r.mode, r.actual, r.stated) for r in rows if not r.covered]


# ---------------------------------------------------------------------------------------------
# synthetic sequences: f_k = f + e_k at orders k = 2, 3, 4


def _steps(errors):
    e2, e3, e4 = errors
    return e2 - e3, e3 - e4  # f_(p-2) - f_(p-1), f_(p-1) - f_p


@pytest.mark.parametrize("q", [MIN_P_RATE, 3.0, 4.5, 6.0, 8.0])
def test_p_rate_recovers_an_algebraic_rate_and_the_exact_tail(q):
    errors = [3.0 * k**-q for k in (2, 3, 4)]
    d_low, d_high = _steps(errors)
    assert p_rate(4, d_low, d_high) == pytest.approx(q, rel=1e-9)
    # |f_4 - f_3| / ((4/3)^q - 1) is e_4 exactly: C 3^-q - C 4^-q = C 4^-q ((4/3)^q - 1)
    assert d_high / ((4 / 3) ** q - 1) == pytest.approx(errors[2], rel=1e-9)
    # the sign does not matter (frequencies from above or below)
    assert p_rate(4, -d_low, -d_high) == pytest.approx(q, rel=1e-9)


def test_p_rate_refuses_steps_of_opposite_sign_or_zero():
    assert p_rate(4, 1.0, -0.1) is None
    assert p_rate(4, 0.0, 0.1) is None
    assert p_rate(4, 0.1, 0.0) is None


def _modes(frequencies, order):
    model = SimpleNamespace(scene=SimpleNamespace(mesh=SimpleNamespace(order=order)))
    modes = tuple(Mode(i, f, f"mode {i}", None, model) for i, f in enumerate(frequencies))
    return Modes(modes, model, "short", "solid", 0)


@pytest.fixture
def paired_by_index(monkeypatch):
    """Shapes paired by index (the synthetic modes have no shapes)."""
    monkeypatch.setattr(estimates, "shape_partners",
                        lambda fine, coarse, *_: {m.index: (c, c.frequency, 1.0) for m, c in zip(fine, coarse)})


def test_p_extrapolation_covers_every_power_law_and_is_exact_at_the_floor_rate(paired_by_index):
    exact = [1000.0, 2000.0, 3000.0, 4000.0]
    q = [2.0, 5.0, 1.0, 11.0]  # the floor, faster, slower (observed and used), much faster
    levels = [_modes([f * (1 + 0.2 * k**-r) for f, r in zip(exact, q)], k) for k in (4, 3, 2)]
    stated, rates = p_extrapolation(*levels)
    assert rates == pytest.approx(q, rel=1e-6)
    for i, f in enumerate(levels[0].frequencies):
        actual = abs(f / exact[i] - 1) * exact[i] / f  # the estimate is relative to f_p
        if q[i] <= MIN_P_RATE:  # at the floor, or slower and observed: the exact tail
            assert stated[i] == pytest.approx(actual, rel=1e-6)
        else:  # faster than the floor: the floor's tail, larger
            assert stated[i] > actual


@pytest.mark.parametrize("r", [0.02, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8])
def test_p_extrapolation_over_states_a_geometric_sequence(paired_by_index, r):
    # p-FEM on smooth fields converges geometrically, e_k = C r^k: the floor rate's tail over-states e_4 where the
    # errors fall faster than (4/3)^MIN_P_RATE = 1.78 per order; slower sequences show a rate below the floor
    # through the three orders, which is then used (a power law's tail is longer than a geometric one's)
    levels = [_modes([1000.0 * (1 + 0.5 * r**k)], k) for k in (4, 3, 2)]
    stated, _ = p_extrapolation(*levels)
    f4 = levels[0].frequencies[0]
    assert stated[0] >= abs(f4 / 1000.0 - 1) * 1000.0 / f4
    assert math.isfinite(stated[0])


def test_p_extrapolation_without_the_lowest_order_assumes_the_lowest_rate(paired_by_index):
    fine, lower = _modes([1000.0 * (1 + 0.2 * 4**-3.0)], 4), _modes([1000.0 * (1 + 0.2 * 3**-3.0)], 3)
    stated, rates = p_extrapolation(fine, lower)
    assert rates == []
    f4, f3 = fine.frequencies[0], lower.frequencies[0]
    assert stated[0] == pytest.approx((f3 - f4) / ((4 / 3) ** MIN_P_RATE - 1) / f4, rel=1e-12)
