"""``modalfe tune`` timed as a user runs it, and its printed design re-solved (issue 34, item 3).

For each case the command runs ``--runs`` times in a fresh process (after one warm-up run that fills the mesh cache),
each with no kept answers (``modalfe.solve.resolved``: its folder emptied before the run) but the meshes cached, as
a user's second design session would; the median wall time is printed with the min and max. Then the printed
``parameters:`` line (the ``--set`` options) is given to ``modalfe modes`` at the tol the design was verified at
(RESOLVED_SHARE x tune's tol: the same frequency and stated error must come back) and at ``--tol 1e-3`` (a finer
model: the target must still lie within tune's tol, its own stated error included).

    python studies/tune_timing.py [--case cube_plate ...] [--runs 3]
"""

from __future__ import annotations

import argparse
import json
import os
import shlex
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from modalfe.design.tuning import RESOLVED_SHARE
from modalfe.solve.api import DEFAULT_TOL

# (target label, target [Hz], parameters varied): the seeds' measured working frequencies
CASES = {
    "cube_plate": ("(0,6)", 40.7e3, "length,ceramic_thickness"),  # seed 001: 40.7 kHz measured
    "ciliary_beam": ("bending-z 6", 23.2e3, "length"),  # seed 003: ~23.2 kHz felt smooth
}
FINER_TOL = 1e-3  # the re-solve on a finer model than the one tune verified on


def modalfe(argv: list[str], cache: Path) -> tuple[str, float]:
    """(stdout, wall seconds) of ``modalfe ARGV`` in a fresh process whose kept answers are emptied first."""
    shutil.rmtree(cache / "resolved", ignore_errors=True)
    env = {**os.environ, "MODALFE_CACHE": str(cache)}
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "modalfe.cli.main", *argv], capture_output=True, text=True, env=env,
                          check=False)
    seconds = time.perf_counter() - start
    if done.returncode not in (0, 1):  # 1: tune did not converge, said on stderr and kept in the output
        raise SystemExit(f"modalfe {shlex.join(argv)}: exit {done.returncode}: {done.stderr.strip()}")
    return done.stdout + done.stderr, seconds


def mode_of(argv: list[str], label: str, cache: Path) -> dict:
    out, _ = modalfe([*argv, "--json"], cache)
    return next(m for m in json.loads(out)["modes"] if m["label"] == label)


def study(name: str, runs: int, cache: Path) -> None:
    label, target, vary = CASES[name]
    argv = ["tune", name, "--target", f"{label}={target}", "--vary", vary]
    modalfe(argv, cache)  # warm-up: the meshes cached
    outputs, times = [], []
    for _ in range(runs):
        out, seconds = modalfe(argv, cache)
        outputs.append(out)
        times.append(seconds)
    print(f"modalfe {shlex.join(argv)}")
    print(f"  wall {statistics.median(times):.1f} s median of {runs} (min {min(times):.1f}, max {max(times):.1f})")
    lines = outputs[-1].splitlines()
    print("  " + next(x for x in lines if x.startswith(("reached", "NOT reached"))))
    sets = shlex.split(next(x for x in lines if x.startswith("parameters: ")).removeprefix("parameters: "))
    for tol in (RESOLVED_SHARE * DEFAULT_TOL, FINER_TOL):
        m = mode_of(["modes", name, *sets, "--tol", repr(tol)], label, cache)
        deviation = m["frequency_hz"] / target - 1
        verdict = "within" if abs(deviation) + m["error_estimate"] <= DEFAULT_TOL else "NOT within"
        print(f"  modes --tol {tol:g}: {label} {m['frequency_hz']:.2f} Hz ({100 * deviation:+.4f} %), stated error "
              f"{100 * m['error_estimate']:.3f} %: {verdict} tune's tol {100 * DEFAULT_TOL:g} %")


def parse(argv: list[str] | None = None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", action="append", choices=sorted(CASES), help="default: every case")
    parser.add_argument("--runs", type=int, default=3, help="timed runs of each tune (default 3)")
    return parser.parse_args(argv)


if __name__ == "__main__":
    args = parse()
    with tempfile.TemporaryDirectory(prefix="modalfe-tune-") as folder:
        for case in args.case or list(CASES):
            study(case, args.runs, Path(folder))
