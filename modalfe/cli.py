"""The ``modalfe`` command: a thin layer over the library that parses, calls and prints."""

from __future__ import annotations

import argparse
import json
import logging
import math
import sys

from modalfe.errors import ModalfeError, SceneError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


def parse_overrides(pairs: list[str] | None) -> dict:
    """``key=value`` pairs; values are read as TOML literals (numbers, arrays, strings)."""
    out = {}
    for pair in pairs or []:
        key, sep, value = pair.partition("=")
        if not sep or not key:
            raise SceneError(f"--set: expected key=value, got '{pair}'")
        try:
            out[key.strip()] = tomllib.loads(f"v = {value}")["v"]
        except tomllib.TOMLDecodeError:
            out[key.strip()] = value
    return out


def _report(args) -> int:
    from modalfe.report import format_rows, run_report

    rows = run_report(args.scene, progress=not args.json, error_estimate=not args.no_error_estimate,
                      overrides=parse_overrides(args.set), fidelity=args.fidelity, tol=args.tol, jobs=args.jobs)
    if args.json:
        print(json.dumps([r.to_json() for r in rows], indent=2))
    else:
        print(format_rows(rows))
    return 1 if any(r.mode == "FAILED" for r in rows) else 0


def _modes(args) -> int:
    from modalfe.scene import load_scene
    from modalfe.solvers import solve_modes

    scene = load_scene(args.scene, **parse_overrides(args.set))
    band = tuple(args.band) if args.band else None
    modes = solve_modes(scene, near=args.near, count=args.count, band=band, circuit=args.circuit,
                        error_estimate=not args.no_error_estimate, fidelity=args.fidelity, tol=args.tol)
    rows = [{"index": m.index, "frequency_hz": m.frequency, "label": m.label,
             "error_estimate": None if not math.isfinite(m.error_estimate) else m.error_estimate,
             "error_unresolved": m.error_estimate == float("inf"),
             "model_error": None if not math.isfinite(m.model_error) else m.model_error,
             "wavelength_m": None if m.wavelength != m.wavelength else m.wavelength} for m in modes]
    if args.json:
        print(json.dumps({"scene": scene.name, "circuit": modes.circuit, "fidelity": modes.fidelity,
                          "fidelity_note": modes.fidelity_note, "dofs": modes.dofs, "modes": rows,
                          "timings": {k: v for k, v in modes.timings.items()}}, indent=2))
        return 0
    print(f"{scene.name}: {modes.dofs} DOFs, {modes.circuit} circuit, {modes.fidelity} fidelity")
    if modes.fidelity_note:
        print(modes.fidelity_note)
    print(f"{'#':>3} {'f [Hz]':>12} {'label':<14} {'err est':>8}")
    for r in rows:
        err = ("unresolved" if r["error_unresolved"] else "n/a" if r["error_estimate"] is None
               else f"{100 * r['error_estimate']:.3f}%")
        print(f"{r['index']:>3} {r['frequency_hz']:>12.2f} {r['label']:<14} {err:>8}")
    return 0


def _positive_int(text: str) -> int:
    """argparse type: an integer >= 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a positive integer, got '{text}'") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be a positive integer, got {value}")
    return value


def _fidelity_options(p: argparse.ArgumentParser) -> None:
    from modalfe.solvers import DEFAULT_TOL, FIDELITIES

    p.add_argument("--fidelity", choices=FIDELITIES, default="auto",
                   help="model: 1-D beam, 2-D plate, 3-D solid, or auto: the cheapest meeting --tol (default)")
    p.add_argument("--tol", type=float, default=DEFAULT_TOL,
                   help=f"relative frequency error asked of --fidelity auto (default {DEFAULT_TOL:g})")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="modalfe", description=__doc__)
    parser.add_argument("-v", "--verbose", action="store_true", help="log progress to stderr")
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("report", help="working modes of every seed device against the seeds' targets")
    p.add_argument("--scene", action="append", help="only this built-in scene (repeatable)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene parameter")
    p.add_argument("--json", action="store_true", help="machine-readable rows")
    p.add_argument("--no-error-estimate", action="store_true",
                   help="skip the coarse-mesh solve (solid and reduced fidelities; auto always estimates)")
    p.add_argument("--jobs", type=_positive_int,
                   help="devices solved at once, one process each (default: one per core)")
    _fidelity_options(p)
    p.set_defaults(func=_report)

    p = sub.add_parser("modes", help="eigenmodes of a built-in scene or a TOML scene file")
    p.add_argument("scene", help="built-in scene name or path to a .toml scene file")
    p.add_argument("--near", type=float, help="target frequency [Hz]")
    p.add_argument("--count", type=int, help="number of modes nearest --near")
    p.add_argument("--band", type=float, nargs=2, metavar=("F1", "F2"), help="all modes in [F1, F2] Hz")
    p.add_argument("--circuit", choices=("short", "open"), help="electrodes grounded or driven one floating")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene parameter")
    p.add_argument("--json", action="store_true")
    p.add_argument("--no-error-estimate", action="store_true",
                   help="skip the coarse-mesh solve (solid and reduced fidelities; auto always estimates)")
    _fidelity_options(p)
    p.set_defaults(func=_modes)

    from modalfe import cli_forced

    cli_forced.register(sub)
    for module in ("cli_contact", "cli_view", "cli_sweep"):
        try:
            extra = __import__(f"modalfe.{module}", fromlist=["register"])
        except ImportError:
            continue
        extra.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING,
                        format="%(levelname)s %(name)s: %(message)s")
    try:
        return args.func(args)
    except SceneError as exc:
        print(f"modalfe: error: {exc}", file=sys.stderr)
        return 2
    except ModalfeError as exc:
        print(f"modalfe: error: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
