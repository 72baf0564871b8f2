"""One answer per question, shown: the working mode of each seed device (and the PZT-5A disc's R1) as every command
that solves modes prints it at default settings, beside ``modalfe modes`` and the Python API.

Each command runs in this process as a user would type it (``modalfe.cli.main.main``, JSON output); the answers are
kept between commands (``modalfe.solve.resolved``), as they are between a user's commands. ``--fresh`` forgets
them before every command, so that each command solves its question itself: the same numbers must come out.

    python studies/one_answer.py [--scene cube_plate ...] [--fresh]
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import io
import json
import tempfile
import time
from pathlib import Path

import modalfe
from modalfe.cli.main import main
from modalfe.solve import resolved

DISC = str(Path(__file__).resolve().parents[1] / "examples" / "pzt5a_disc.toml")
# (scene, mode, the frequency it is sought near, the commands' extra arguments: a band around it for admittance)
CASES = {
    "cube_plate": ("(0,6)", None, ["--band", "38e3", "41e3"]),
    "glass_plate": ("(0,8)", None, ["--band", "60e3", "70e3"]),
    # heave, the working mode its centre actuator drives: the (1,1) mode has nodal lines through the centre, where the
    # scene's force sits, and ``forced`` refuses a load that does not drive the mode (issue 35)
    "honeycomb_tile": ("heave", None, None),
    "ciliary_beam": ("bending-z 6", None, ["--band", "20e3", "23e3"]),
    "disc": ("R1", 99e3, ["--band", "95e3", "105e3"]),
}


def run(argv: list[str]) -> tuple[dict | None, float]:
    """(the command's JSON, or None for one that prints none; wall seconds)."""
    out = io.StringIO()
    start = time.perf_counter()
    with contextlib.redirect_stdout(out):
        status = main(argv)
    seconds = time.perf_counter() - start
    if status != 0:
        raise SystemExit(f"{' '.join(argv)}: exit {status}")
    text = out.getvalue()
    return (json.loads(text) if text.lstrip().startswith(("{", "[")) else None), seconds


def answers(name: str, fresh: bool, folder: Path) -> list[tuple[str, float, float | None, float]]:
    """(command, frequency [Hz], stated error, seconds) of the case's working mode in every command."""
    label, near, band = CASES[name]
    scene = DISC if name == "disc" else name
    at = ["--mode", label] + (["--near", str(near)] if near else [])  # the case's mode, not the first working one
    rows = []

    def ask(command: str, argv: list[str], pick) -> None:
        if fresh:
            resolved.clear(disk=True)
        document, seconds = run(argv)
        f, err = pick(document)
        rows.append((command, f, err, seconds))

    def of(modes: list[dict], key: str = "frequency_hz", error: str = "error_estimate"):
        mode = next(m for m in modes if m["label"] == label)
        return mode[key], mode.get(error)

    ask("modes", ["modes", scene, "--json"] + (["--near", str(near)] if near else []), lambda d: of(d["modes"]))
    ask("table", ["table", scene, "--json"] + (["--near", str(near)] if near else []),
        lambda d: of(d["modes"], "frequency_Hz", "error_estimate_rel"))
    outputs = ["--outputs", "electrode_a"] if name == "disc" else []  # a scene file without drive.outputs
    ask("forced", ["forced", scene, "--json", *at, *outputs],
        lambda d: (d["frequency_hz"], d["frequency_error_estimate"]))
    if name != "disc":  # a built-in material of a scene file is not a sensitivity parameter
        ask("sensitivity", ["sensitivity", scene, "--vary", _parameter(name), "--json"], lambda d: of(d["modes"]))
    vtu = folder / f"{name}.vtu"

    def exported(_):
        with open(folder / f"{name}_modes.csv") as fh:
            row = next(r for r in csv.DictReader(fh) if r["label"] == label)
        return float(row["frequency [Hz]"]), float(row["error estimate [relative]"] or "nan")

    ask("export", ["export", scene, "--vtu", str(vtu)] + (["--near", str(near)] if near else []), exported)
    if band is not None:
        ask("admittance", ["admittance", scene, *band, "--points", "50", "--json"], lambda d: of(d["modes"]))
    ask("sweep", ["sweep", scene, "--param", f"{_parameter(name)}={_value(name)}:{_value(name)}:1", "--out",
                  str(folder / f"{name}.csv"), "--scheduler", "inline", "--json", *at],
        lambda d: (d[0]["frequency_hz"], d[0]["error_estimate"]))
    start = time.perf_counter()
    if fresh:
        resolved.clear(disk=True)
    api = modalfe.solve_modes(modalfe.load_scene(scene), **({"near": near} if near else {}))
    mode = api.labelled(label)
    rows.append(("python api", mode.frequency, mode.error_estimate, time.perf_counter() - start))
    return rows


def _parameter(name: str) -> str:
    return {"cube_plate": "ceramic_thickness", "glass_plate": "thickness", "honeycomb_tile": "facing_thickness",
            "ciliary_beam": "x0", "disc": "analysis.near"}[name]


def _value(name: str) -> float:
    """The parameter's own value, so that the sweep's one point is the device itself."""
    from modalfe.response.sensitivity import parameter_value

    scene = modalfe.load_scene(DISC if name == "disc" else name)
    return scene.analysis.near if name == "disc" else parameter_value(scene, _parameter(name))


def main_() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scene", action="append", choices=list(CASES))
    p.add_argument("--fresh", action="store_true", help="forget the kept answers before every command")
    args = p.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.scene or list(CASES):
            rows = answers(name, args.fresh, Path(tmp))
            reference = rows[0][1]
            print(f"\n{name}: {CASES[name][0]}")
            print(f"  {'command':<12} {'f [Hz]':>16} {'stated':>9} {'vs modes':>10} {'s':>7}")
            for command, f, err, seconds in rows:
                stated = "unknown" if err is None or err != err else f"{100 * err:.3f}%"
                print(f"  {command:<12} {f:16.6f} {stated:>9} {f / reference - 1:+10.1e} {seconds:7.1f}")


if __name__ == "__main__":
    main_()
