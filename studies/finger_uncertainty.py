"""Does the finger's stated uncertainty cover the scatter of repeated time averages? (issue 35, contact property)

``coverage``: at each amplitude, M time averages of the bed-spring finger (``finger_steady_state`` with its
defaults), each started from the previous one's end state (a chained window: the chaotic motion carries on), and
their scatter (sample std) against the RMS of the uncertainties they state; a ratio stated / observed >= 1 means
the stated uncertainty covers the repeated averages.  Periodic points state 0 and repeat exactly.

    python studies/finger_uncertainty.py coverage --frequency 66e3 --amplitude 0.8e-6,1.2e-6,1.6e-6,2.4e-6,3.2e-6,5e-6
    python studies/finger_uncertainty.py coverage --frequency 225e3 --amplitude 0.5e-6,3e-6

``batches``: one long run (``--periods``, after the steady state's own window), cut into consecutive windows of
B batches of L periods; per (B, L) the plain batch-means standard error (RMS over the windows) against the std of
the windows' averages: how far short the estimate falls for lack of long batches, before the confidence factor
of ``kernel.batch_ratio``; the autocorrelation of the per-period friction.  Then the same run cut into a
sequence of averages as ``finger_steady_state`` cuts them (the window doubling from ``BATCHES`` batches of
``BATCH_DECAY_TIMES`` decay times while its bound exceeds ``AVERAGE_TOL``): the RMS stated uncertainty over the
std of the averages, stating the stopping window's own bound, and the largest of the bounds of the windows tried
(what ``finger_steady_state`` states).

    python studies/finger_uncertainty.py batches --amplitude 3.2e-6 --periods 100000
    python studies/finger_uncertainty.py batches --amplitude 5e-6 --periods 300000

``foot``: the same question for seed 000's foot at its rattling stress case (kn 1e9 N/m, W 10 nm, Fn 1 N, the
open point of docs/contact.md): 16 time averages after marches of 400, 405, ... 475 periods from rest (the
foot has no start state to continue from), their scatter against the RMS stated uncertainty of <Rt>.

    python studies/finger_uncertainty.py foot
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from modalfe.contact.finger import FingerParameters, _FingerDynamics, _sums, advance, finger_steady_state
from modalfe.contact.kernel import batch_ratio, touchdown_times


def coverage(amplitude: float, frequency: float, repeats: int) -> dict:
    """M chained default time averages at one point: their mean, std, RMS stated uncertainty and periods."""
    orbit = finger_steady_state(amplitude, frequency)
    ratios, stated, periods = [], [], []
    start = time.perf_counter()
    for _ in range(repeats):
        orbit = finger_steady_state(amplitude, frequency, guess=orbit.period_one, start=orbit.state)
        ratios.append(orbit.friction_ratio)
        stated.append(orbit.uncertainty)
        periods.append(orbit.periods)
    r, u = np.array(ratios), np.array(stated)
    return {"mean": r.mean(), "observed": r.std(ddof=1), "stated": math.sqrt(np.mean(u ** 2)),
            "periods": float(np.median(periods)), "method": orbit.method.split()[0],
            "seconds": (time.perf_counter() - start) / repeats}


def period_sums(amplitude: float, frequency: float, periods: int, chunk: int = 500) -> tuple[np.ndarray, np.ndarray]:
    """Per drive period: int f_Tsc dt / mu and int f_Nsc dt over ``periods`` periods after the steady state (each
    piece counted in the period it starts in; a contact carried across chunks keeps its touchdown)."""
    orbit = finger_steady_state(amplitude, frequency)
    p = orbit.parameters
    dyn = _FingerDynamics(p, 2 * math.pi * frequency, amplitude / 2)
    T, x, tail = 1 / frequency, orbit.state, []
    num, den = np.zeros(periods), np.zeros(periods)
    for c in range(0, periods, chunk):
        pieces, x, _ = advance(dyn, c * T, (c + chunk) * T, x, sensitivity=False)
        window = tail + pieces
        n_int, t_int, _ = _sums(dyn, window, touchdown_times(window, first=window[0].t0 if tail else -math.inf))
        for q, n, t in zip(pieces, n_int[len(tail):], t_int[len(tail):]):
            i = min(int(q.t0 * frequency + 1e-9), periods - 1)
            num[i] += t / p.mu
            den[i] += n
        landed = [i for i in range(1, len(pieces)) if pieces[i].contact and not pieces[i - 1].contact]
        tail = pieces[landed[-1]:] if landed else []
    return num, den


def batches(num: np.ndarray, den: np.ndarray, count: int, length: int) -> tuple[float, int]:
    """RMS plain batch-means standard error / std of the window averages, over the run cut into windows of
    ``count`` batches of ``length`` periods; and the number of windows."""
    w = count * length
    m = len(num) // w
    n = num[:m * w].reshape(m, count, length).sum(2)
    d = den[:m * w].reshape(m, count, length).sum(2)
    se = (n / d).std(1, ddof=1) / math.sqrt(count)
    return float(math.sqrt(np.mean(se ** 2)) / (n.sum(1) / d.sum(1)).std(ddof=1)), m


def sequence(num: np.ndarray, den: np.ndarray, first: int) -> tuple[float, float, int]:
    """The run cut into consecutive averages as ``finger_steady_state`` cuts them (windows doubling from ``first``
    periods while their bound exceeds AVERAGE_TOL): RMS stated / std of the averages, stating the stopping window's
    bound, then the largest of the tried windows' bounds scaled to the window; and the number of averages."""
    from modalfe.contact.finger import AVERAGE_TOL, BATCHES, MAX_AVERAGE_PERIODS  # (here: coverage runs on older trees)

    pos, ratios, own, largest = 0, [], [], []
    while True:
        window, tried = first, []
        while pos + window <= len(num):
            ratio, bound = batch_ratio(num[pos:pos + window], den[pos:pos + window], BATCHES)
            if bound <= AVERAGE_TOL or window >= MAX_AVERAGE_PERIODS:
                break
            tried.append((bound, window))
            window *= 2
        if pos + window > len(num):
            break
        ratios.append(ratio)
        own.append(bound)
        largest.append(max([bound] + [b * math.sqrt(w / window) for b, w in tried]))
        pos += window
    scatter = float(np.std(ratios, ddof=1))
    return (math.sqrt(np.mean(np.square(own))) / scatter, math.sqrt(np.mean(np.square(largest))) / scatter,
            len(ratios))


def foot_coverage(repeats: int) -> dict:
    """The rattling foot's time averages after marches of 400 + 5 i periods (i < repeats): mean <Rt> [N], their
    std, the RMS stated uncertainty [N] and the windows' lengths [periods]."""
    from modalfe.contact.foot import FootParameters, steady_state

    params = FootParameters().with_(kn=1e9)
    orbits = [steady_state(1e-8, preload=1.0, parameters=params, march_periods=400 + 5 * i) for i in range(repeats)]
    r = np.array([o.friction_mean for o in orbits])
    u = np.array([o.friction_uncertainty * o.friction_mean for o in orbits])
    return {"mean": r.mean(), "observed": r.std(ddof=1), "stated": math.sqrt(np.mean(u ** 2)),
            "periods": sorted(o.periods for o in orbits)}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("what", choices=("coverage", "batches", "foot"))
    parser.add_argument("--frequency", type=float, default=66e3)
    parser.add_argument("--amplitude", default="0.8e-6,1.2e-6,1.6e-6,2.4e-6,3.2e-6,5e-6", help="um pp list [m]")
    parser.add_argument("--repeats", type=int, default=16, help="coverage: chained averages per amplitude")
    parser.add_argument("--periods", type=int, default=100000, help="batches: length of the long run")
    args = parser.parse_args(argv)
    amplitudes = [float(a) for a in args.amplitude.split(",")]
    if args.what == "foot":
        c = foot_coverage(args.repeats)
        print(f"rattling foot (kn 1e9 N/m, 10 nm, 1 N), {args.repeats} averages: <Rt> {c['mean']:.4g} N, observed std "
              f"{c['observed']:.3g} N, stated {c['stated']:.3g} N, stated/observed {c['stated'] / c['observed']:.2f}; "
              f"windows {c['periods']} periods")
        return 0
    if args.what == "coverage":
        print(f"{args.frequency / 1e3:g} kHz, {args.repeats} chained averages per amplitude")
        print(f"{'A [um pp]':>9} {'method':>8} {'mu_US/mu':>9} {'observed':>9} {'stated':>9} {'stated/obs':>10} "
              f"{'periods':>8} {'s/avg':>6}")
        for a in amplitudes:
            c = coverage(a, args.frequency, args.repeats)
            ratio = c["stated"] / c["observed"] if c["observed"] > 0 else math.inf
            print(f"{a * 1e6:9.2f} {c['method']:>8} {c['mean']:9.4f} {c['observed']:9.2e} {c['stated']:9.2e} "
                  f"{ratio:10.2f} {c['periods']:8.0f} {c['seconds']:6.2f}")
        return 0
    from modalfe.contact.finger import BATCH_DECAY_TIMES, BATCHES

    for a in amplitudes:
        num, den = period_sums(a, args.frequency, args.periods)
        shapes = [(10, 15)] + [(BATCHES, n) for n in (71, 142, 284, 568)]  # the former estimate's, then ours
        cells = [(b, ln, *batches(num, den, b, ln)) for b, ln in shapes]
        print(f"{a * 1e6:.2f} um pp, {args.frequency / 1e3:g} kHz, {args.periods} periods: plain standard error / "
              "scatter, B batches x L periods (windows): "
              + ", ".join(f"{b}x{ln}: {r:.2f} ({m})" for b, ln, r, m in cells))
        dyn = _FingerDynamics(FingerParameters(), 2 * math.pi * args.frequency, a / 2)
        first = BATCHES * math.ceil(BATCH_DECAY_TIMES * dyn.slowest_decay_time * args.frequency)
        ratio = num.sum() / den.sum()
        z = (num - ratio * den) / den.mean()  # per period, linearized: the deviation of the ratio it carries
        z -= z.mean()
        print("  autocorrelation at lags 1, 2, 5, 10, 20, 50 periods: "
              + ", ".join(f"{z[:-k] @ z[k:] / (len(z) - k) / z.var():.3f}" for k in (1, 2, 5, 10, 20, 50)))
        own, largest, m = sequence(num, den, first)
        print(f"  {m} averages as finger_steady_state cuts them: stated / scatter {own:.2f} (the stopping window's "
              f"bound), {largest:.2f} (the largest of the windows tried)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
