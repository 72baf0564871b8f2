"""Exactness and speed of the foot contact simulator against a brute-force integration.

modalfe.contact.foot.steady_state (event-driven closed-form arcs + Newton shooting on the period
map) against brute_force_steady_state: scipy solve_ivp with Bogacki-Shampine RK23 (the seed's ode23),
max step 1e-7 s (seed 000 section 4.3.1.2), terminal events at the contact switches, started from
rest and run until beta, <Rn> and <Rt> settle (spread < 1e-5 over 20 periods).  Seed 000 appendix
parameters, identified kt, steel, 1 cm/s.

Prints, per operating point: the flight ratio and <Rt> of both, their differences, the median
times of several repeats and the speed ratio; then the time for a whole 50-amplitude curve.  The
ratios are measured in this one run (these machines are noisy; do not compare across runs).

Run:  python studies/benchmark_contact.py          (full: 9 points, 3 brute-force repeats)
      python studies/benchmark_contact.py --quick  (2 points, 1 brute-force repeat)
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from modalfe.contact.foot import FootParameters, simulate_contact, steady_state

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root: tests.oracles
from tests.oracles.contact_brute_force import brute_force_steady_state

FULL = [(3.0, w) for w in (0.2e-6, 0.4e-6, 0.65e-6, 1.0e-6, 1.5e-6, 2.0e-6)] + \
       [(10.0, w) for w in (0.6e-6, 1.2e-6, 2.0e-6)]
QUICK = [(3.0, 0.4e-6), (10.0, 1.2e-6)]
SEED_HORIZON = 0.5  # s, seed 000: ode23 over [0, 0.5] s
SPEED = 0.01  # m/s


def median_time(fun, repeats: int) -> tuple[float, object]:
    times, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fun()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="2 points, 1 brute-force repeat")
    args = parser.parse_args(argv)
    points = QUICK if args.quick else FULL
    fast_repeats, brute_repeats = (5, 1) if args.quick else (9, 3)
    p = FootParameters()
    print(f"foot contact benchmark: kn={p.kn:g} N/m dn={p.dn:g} N s/m m={p.mass:g} kg n={p.n} "
          f"f={p.frequency:g} Hz mu0={p.mu0:g} kt={p.kt:g} N/m, V={SPEED} m/s")
    print(f"brute force: solve_ivp RK23, max step 1e-7 s, from rest until settled; medians of "
          f"{brute_repeats} (brute) and {fast_repeats} (modalfe) repeats")
    head = (f"{'Fn':>4} {'W[um]':>6} {'beta mf':>8} {'beta bf':>8} {'dbeta[pp]':>10} {'Rt mf[N]':>9} "
            f"{'dRt[%]':>8} {'dRn[%]':>8} {'periods':>7} {'t mf[ms]':>9} {'t bf[s]':>8} {'ratio':>7} "
            f"{'0.5s ratio':>10}")
    print(head)
    worst_beta = worst_rt = 0.0
    ratios, seed_ratios = [], []
    for fn, w in points:
        t_fast, orbit = median_time(lambda fn=fn, w=w: steady_state(w, preload=fn, speed=SPEED, parameters=p),
                                    fast_repeats)
        t_brute, ref = median_time(lambda fn=fn, w=w: brute_force_steady_state(w, preload=fn, speed=SPEED,
                                                                                parameters=p), brute_repeats)
        d_beta = orbit.flight_ratio - ref.flight_ratio
        d_rt = 100 * (orbit.friction_mean - ref.friction_mean) / ref.friction_mean
        d_rn = 100 * (orbit.normal_mean - ref.normal_mean) / ref.normal_mean
        ratio = t_brute / t_fast
        seed_ratio = t_brute / ref.periods * SEED_HORIZON * p.frequency / t_fast
        worst_beta, worst_rt = max(worst_beta, abs(d_beta)), max(worst_rt, abs(d_rt))
        ratios.append(ratio)
        seed_ratios.append(seed_ratio)
        flag = "" if ref.converged else "  (brute force did not settle)"
        print(f"{fn:4.0f} {w * 1e6:6.2f} {orbit.flight_ratio:8.3f} {ref.flight_ratio:8.3f} {d_beta:10.2e} "
              f"{orbit.friction_mean:9.5f} {d_rt:8.1e} {d_rn:8.1e} {ref.periods:7d} {t_fast * 1e3:9.2f} "
              f"{t_brute:8.2f} {ratio:7.0f} {seed_ratio:10.0f}{flag}")
    print(f"worst |beta difference| = {worst_beta:.2e} percentage points (target < 0.2)")
    print(f"worst |<Rt> difference| = {worst_rt:.2e} % (target < 0.5)")
    print(f"speed ratio brute/modalfe: median {statistics.median(ratios):.0f}, min {min(ratios):.0f} "
          f"(target >= 1000); against the seed's fixed 0.5 s horizon: median {statistics.median(seed_ratios):.0f}")
    amplitudes = np.linspace(0, 2e-6, 50)
    t_curve, curve = median_time(lambda: simulate_contact(amplitudes, preload=3.0, speed=SPEED, parameters=p),
                                 3 if args.quick else 7)
    print(f"50-amplitude curve (0-2 um, 3 N): {t_curve * 1e3:.0f} ms median (target < 1000 ms); "
          f"all periodic: {bool(curve.periodic.all())}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
