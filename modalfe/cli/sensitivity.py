"""``modalfe sensitivity``: how each mode's frequency (and k_eff) moves with scene parameters (3-D solid)."""

from __future__ import annotations

import json
import math

from modalfe.cli.options import frequency_or_zero, parse_overrides, positive_int
from modalfe.errors import SceneError


def register(sub) -> None:
    p = sub.add_parser("sensitivity", help="df/dp of each mode for scene parameters (3-D solid, no new eigen solve)")
    p.add_argument("scene", help="built-in scene name or path to a .toml scene file")
    p.add_argument("--vary", required=True, metavar="P1,P2,...",
                   help="parameters: builder parameters (length, x0), materials.NAME.KEY of a material the scene "
                        "defines, springs.GROUP[.x|y|z], masses.GROUP, parts.NAME.origin|size.x|y|z (box scenes)")
    p.add_argument("--near", type=frequency_or_zero, help="target frequency [Hz]")
    p.add_argument("--count", type=positive_int, help="number of modes nearest --near")
    p.add_argument("--k-eff", action="store_true", help="also dk_eff/dp (solves the open circuit too)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene parameter")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=_sensitivity)


def _sensitivity(args) -> int:
    from modalfe.response.sensitivity import check_parameters, frequency_sensitivities
    from modalfe.scene import load_scene
    from modalfe.solve.api import solve_modes

    names = [name.strip() for name in args.vary.split(",") if name.strip()]
    if not names or len(set(names)) != len(names):
        raise SceneError(f"--vary: give distinct parameter names separated by commas, got '{args.vary}'")
    scene = load_scene(args.scene, **parse_overrides(args.set))
    check_parameters(scene, names)  # before any solve
    options = {"near": args.near, "count": args.count, "fidelity": "solid", "error_estimate": False}
    modes = solve_modes(scene, **options)
    open_modes = solve_modes(scene, circuit="open", **options) if args.k_eff else None
    found = frequency_sensitivities(modes, names, open_modes=open_modes)
    rows = [{"index": mode.index, "frequency_hz": mode.frequency, "label": mode.label,
             "k_eff": _number(found.k_eff[i]),
             "parameters": {name: {"df_dp": _number(found.dfrequency[i, j]), "dlnf_dlnp": _number(found.relative[i, j]),
                                   "dk_eff_dp": _number(found.dk_eff[i, j])} for j, name in enumerate(names)}}
            for i, mode in enumerate(modes)]
    if args.json:
        print(json.dumps({"scene": scene.name, "dofs": modes.dofs, "circuit": modes.circuit,
                          "values": dict(zip(names, found.values.tolist())),
                          "steps": dict(zip(names, found.steps.tolist())), "modes": rows}, indent=2))
        return 0
    print(f"{scene.name}: {modes.dofs} DOFs, 3-D solid, {modes.circuit} circuit; d ln f / d ln p and (df/dp [Hz per "
          f"unit of p]) from central differences of the assembled matrices")
    for name, value, step in zip(names, found.values, found.steps):
        print(f"  {name} = {value:g} (step {step:.3g})")
    header = f"{'#':>3} {'f [Hz]':>12} {'label':<14}"
    print(header + "".join(f" {name[-24:]:>26}" for name in names))
    for row in rows:
        cells = "".join(f" {_cell(row['parameters'][name]):>26}" for name in names)
        print(f"{row['index']:>3} {row['frequency_hz']:>12.2f} {row['label']:<14}{cells}")
    if args.k_eff:
        print(f"\nk_eff (open-circuit partner by shape) and dk_eff/dp [per unit of p]\n{header} {'k_eff':>8}"
              + "".join(f" {name[-24:]:>26}" for name in names))
        for row in rows:
            k = "-" if row["k_eff"] is None else f"{row['k_eff']:.4f}"
            cells = "".join(f" {_signed(row['parameters'][name]['dk_eff_dp']):>26}" for name in names)
            print(f"{row['index']:>3} {row['frequency_hz']:>12.2f} {row['label']:<14} {k:>8}{cells}")
    return 0


def _number(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def _signed(x: float | None) -> str:
    return "-" if x is None else f"{x:+.3e}"


def _cell(entry: dict) -> str:
    """``+0.500 (1.2e+03)``: d ln f / d ln p and df/dp; ``-`` where undefined (a mode at 0 Hz)."""
    if entry["df_dp"] is None:
        return "-"
    relative = "n/a" if entry["dlnf_dlnp"] is None else f"{entry['dlnf_dlnp']:+.4f}"
    return f"{relative} ({entry['df_dp']:+.3e})"
