"""Curved-part convergence study (studies/curved_convergence.py): its Richardson step on a known sequence, its
thin-disc theory against the values in docs/studies.md, and a short convergence run of the radially poled ring."""

import math

import pytest

from tests.helpers import load_study

STUDY = load_study("curved_convergence")


def test_richardson_recovers_order_and_limit_of_an_h4_sequence():
    """f = f0 + c h^4 on h = 1, 0.8, 0.64: order 4 and f0 to round-off; a sequence whose differences change sign
    has no order (NaN) and is extrapolated at P2's 4."""
    f = [100.0 + 3.0 * h**4 for h in (1.0, 0.8, 0.64)]
    order, limit = STUDY.richardson3(f)
    assert order == pytest.approx(4.0, rel=1e-9)
    assert limit == pytest.approx(100.0, rel=1e-12)
    order, limit = STUDY.richardson3([100.0, 99.0, 99.5])
    assert math.isnan(order)
    assert limit == pytest.approx(99.5 + 0.5 / (1.25**4 - 1))


def test_thin_disc_theory_of_the_pzt5a_disc():
    """IEEE Std 176-1987 planar mode of the 20 mm PZT-5A disc: 99 478 Hz and 117 397 Hz (docs/studies.md "Curved
    parts", from the same constants through the test of tests/models/test_curved_parts.py); 1 Hz is the rounding."""
    fr, fa = STUDY.thin_disc("PZT-5A", 0.01)
    assert fr == pytest.approx(99478, abs=1)
    assert fa == pytest.approx(117397, abs=1)


@pytest.mark.slow
def test_radially_poled_ring_converges_to_the_thin_ring_breathing_mode():
    """Three levels (elements 0.5, 0.4, 0.32 mm; 13k-50k DOFs, ~40 s): the extrapolated fr and fa lie within 0.1 %
    of the thin-ring fr = sqrt(1 / (rho s11^E)) / (2 pi R) and fa = fr / sqrt(1 - k31^2) (Berlincourt, Curran &
    Jaffe 1964): the formula leaves out the wall's curvature, (t/R)^2 / 12 = 2e-4, and the height's Poisson coupling
    (plane stress on free faces, none to first order); measured +0.02 % (fr) and +0.01 % (fa)."""
    out = STUDY.convergence("pzt_ring", levels=STUDY.LEVELS[:3])
    _, _, quantities = STUDY.cases()["pzt_ring"]
    for label, _, _, theory in quantities:
        _, extrapolated = out[label]
        assert extrapolated == pytest.approx(theory, rel=1e-3), label
