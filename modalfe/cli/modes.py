"""``modalfe report`` and ``modalfe modes``: eigenfrequencies of the seed devices and of any scene."""

from __future__ import annotations

import argparse
import json
import math
import sys

from modalfe.cli.options import (
    _float,
    check_band,
    frequency_or_zero,
    parse_overrides,
    positive_int,
    solve_keywords,
    solve_options,
)
from modalfe.cli.page import add_html_option, scene_page
from modalfe.errors import SceneError
from modalfe.progress import is_shown


def register(sub) -> None:
    p = sub.add_parser("report", help="working modes of every seed device against the seeds' targets")
    p.add_argument("--scene", action="append", help="only this built-in scene (repeatable)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene parameter")
    p.add_argument("--json", action="store_true", help="machine-readable rows")
    p.add_argument("-v", "--verbose", action="store_true", default=argparse.SUPPRESS,
                   help="also how each row was resolved, its notes and the assumptions (and log progress)")
    p.add_argument("--jobs", type=positive_int,
                   help="devices solved at once, one process each (default: one per core)")
    add_html_option(p)
    solve_options(p)
    p.set_defaults(func=_report)

    p = sub.add_parser("modes", help="eigenmodes of a built-in scene or a TOML scene file")
    p.add_argument("scene", help="built-in scene name or path to a .toml scene file")
    p.add_argument("--near", type=frequency_or_zero, help="target frequency [Hz]")
    p.add_argument("--count", type=positive_int, help="number of modes nearest --near")
    p.add_argument("--band", type=_float, nargs=2, metavar=("F1", "F2"), help="all modes in [F1, F2] Hz")
    p.add_argument("--circuit", choices=("short", "open"), help="electrodes grounded or driven one floating")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene parameter")
    p.add_argument("--json", action="store_true")
    add_html_option(p)
    solve_options(p)
    p.set_defaults(func=_modes)


def _report(args) -> int:
    from modalfe.cli.page import write_design_page
    from modalfe.report.report import format_rows, run_report

    overrides = parse_overrides(args.set)
    rows = run_report(args.scene, progress=is_shown(), overrides=overrides, jobs=args.jobs, **solve_keywords(args))
    if args.json:
        print(json.dumps([r.to_json() for r in rows], indent=2))
    else:
        print(format_rows(rows, detail=args.verbose))
    if args.html:
        from modalfe.scene import load_scene

        scenes = [(load_scene(name, **overrides), [r for r in rows if r.scene == name])
                  for name in dict.fromkeys(r.scene for r in rows)]
        page = write_design_page(args.html, scenes, keywords=solve_keywords(args), command=args.command_line)
        print(f"design page: {page}", file=sys.stderr if args.json else sys.stdout)
    return 1 if any(r.mode == "FAILED" for r in rows) else 0


def _modes(args) -> int:
    from modalfe.scene import load_scene
    from modalfe.solve.api import solve_modes

    band = check_band(args.band)
    if band is not None and args.near is not None:
        raise SceneError("--near: give either --near (with --count) or --band, not both")
    if band is not None and args.count is not None:
        raise SceneError("--count: --band returns every mode in the band; --count goes with --near")
    scene = load_scene(args.scene, **parse_overrides(args.set))
    modes = solve_modes(scene, near=args.near, count=args.count, band=band, circuit=args.circuit,
                        **solve_keywords(args))
    rows = [{"index": m.index, "frequency_hz": m.frequency, "label": m.label,
             "error_estimate": None if not math.isfinite(m.error_estimate) else m.error_estimate,
             "error_unresolved": m.error_estimate == float("inf"),
             "model_error": None if not math.isfinite(m.model_error) else m.model_error,
             "wavelength_m": None if m.wavelength != m.wavelength else m.wavelength} for m in modes]
    scene_page(args, scene)
    if args.json:
        print(json.dumps({"scene": scene.name, "circuit": modes.circuit, "fidelity": modes.fidelity,
                          "fidelity_note": modes.fidelity_note, "estimate_method": modes.estimate_method,
                          "dofs": modes.dofs,
                          "mesh_frequency_hz": modes.mesh_frequency, "modes": rows,
                          "timings": {k: v for k, v in modes.timings.items()}}, indent=2))
        return 0
    print(f"{scene.name}: {modes.dofs} DOFs, {modes.circuit} circuit, {modes.fidelity} fidelity, mesh resolves "
          f"up to {modes.mesh_frequency:.6g} Hz (mesh.max_frequency)")
    if modes.fidelity_note:
        print(modes.fidelity_note)
    if modes.estimate_method:
        print(f"error estimates: {modes.estimate_method}")
    print(f"{'#':>3} {'f [Hz]':>12} {'label':<14} {'err est':>8}")
    for r in rows:
        err = ("unresolved" if r["error_unresolved"] else "unknown" if r["error_estimate"] is None
               else f"{100 * r['error_estimate']:.3f}%")
        print(f"{r['index']:>3} {r['frequency_hz']:>12.2f} {r['label']:<14} {err:>8}")
    return 0
