"""How long `forced`, `table`, `show` and `admittance` take against `modes` on the same device (issue 34's speed
goal: within 1.5x at the default tolerance, fresh).

Each command runs in a fresh process with no kept answer (the resolved answers' folder emptied before every run)
and a warm mesh cache (one folder for the whole study, filled by a first `modes` run that is not counted), the same
for both sides. A command and `modes` run in turn (A B A B ...), and the ratio is taken pair by pair, so that a
machine whose speed drifts still gives a meaningful ratio; the table prints the median ratio and the median wall
seconds of each side.

    python studies/command_speed.py [--runs 3] [--devices cube_plate glass_plate] [--commands forced show]

The admittance is asked over the working mode's frequency +-5 % (``BANDS``); the honeycomb tile, driven by a force
and without a driven electrode, has no admittance.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

# the admittance's band per device [Hz]: its working mode's frequency at the default tolerance +-5 %
BANDS = {"cube_plate": (37.6e3, 41.6e3), "glass_plate": (64.7e3, 71.5e3), "ciliary_beam": (20.5e3, 22.7e3)}
DEVICES = ("cube_plate", "glass_plate", "honeycomb_tile", "ciliary_beam")
COMMANDS = ("forced", "table", "show", "admittance")


def command_line(command: str, device: str, out: str) -> list[str] | None:
    """The CLI arguments of ``command`` on ``device`` (``show`` writes its picture into ``out``), None where the
    command does not apply (an admittance without a driven electrode)."""
    if command == "show":
        return ["show", device, "--out", os.path.join(out, f"{device}.png")]
    if command == "admittance":
        if device not in BANDS:
            return None
        return ["admittance", device, "--band", *(f"{f:g}" for f in BANDS[device])]
    return [command, device]


def timed(args: list[str], cache: str) -> float:
    """Wall seconds of ``modalfe ARGS`` in a fresh process, with no resolved answer kept in ``cache``."""
    shutil.rmtree(os.path.join(cache, "resolved"), ignore_errors=True)
    env = dict(os.environ, MODALFE_CACHE=cache)
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "modalfe.cli.main", *args], env=env, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def measure(device: str, commands: list[str], runs: int, cache: str, out: str) -> dict[str, tuple[float, float, float]]:
    """{command: (median ratio command / modes, median seconds of the command, of modes)} on ``device``."""
    timed(["modes", device], cache)  # fills the mesh cache: every counted run meshes nothing
    rows = {}
    for command in commands:
        args = command_line(command, device, out)
        if args is None:
            continue
        pairs = [(timed(args, cache), timed(["modes", device], cache)) for _ in range(runs)]
        rows[command] = (statistics.median(a / b for a, b in pairs), statistics.median(a for a, _ in pairs),
                         statistics.median(b for _, b in pairs))
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3, help="pairs per command (default 3)")
    parser.add_argument("--devices", nargs="+", default=list(DEVICES), choices=DEVICES)
    parser.add_argument("--commands", nargs="+", default=list(COMMANDS), choices=COMMANDS)
    args = parser.parse_args(argv)
    print(f"{'device':<16}{'command':<12}{'ratio':>7}{'command s':>11}{'modes s':>9}")
    with tempfile.TemporaryDirectory() as cache, tempfile.TemporaryDirectory() as out:
        for device in args.devices:
            for command, (ratio, seconds, modes) in measure(device, args.commands, args.runs, cache, out).items():
                print(f"{device:<16}{command:<12}{ratio:>7.2f}{seconds:>11.1f}{modes:>9.1f}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
