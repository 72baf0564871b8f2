"""``modalfe sensitivity``: how each mode's frequency (and k_eff), and the working mode's amplitude per volt at
resonance, move with scene parameters (3-D solid)."""

from __future__ import annotations

import json
import math

from modalfe.cli.options import (
    frequency_or_zero,
    parse_names,
    parse_overrides,
    positive_int,
    scene_options,
    solve_keywords,
    solve_options,
)
from modalfe.cli.page import add_html_option, scene_page
from modalfe.errors import SceneError


def register(sub) -> None:
    p = sub.add_parser("sensitivity", help="df/dp of each mode for scene parameters (3-D solid, no new eigen solve)")
    p.add_argument("scene", help="built-in scene name or path to a .toml scene file")
    p.add_argument("--vary", required=True, metavar="P1,P2,...",
                   help="parameters: builder parameters (length, x0), materials.NAME.KEY of a material the scene "
                        "defines, materials.NAME.d31|d33|d15|e31|e33|e15 of a piezo material (e.g. "
                        "materials.PZT-4.d31), springs.GROUP[.x|y|z], masses.GROUP, parts.NAME.origin|size.x|y|z "
                        "(box scenes)")
    p.add_argument("--near", type=frequency_or_zero, help="target frequency [Hz]")
    p.add_argument("--count", type=positive_int, help="number of modes nearest --near")
    p.add_argument("--k-eff", action="store_true", help="also dk_eff/dp (solves the open circuit too)")
    p.add_argument("--amplitude", action="store_true",
                   help="also d ln A / d ln p of the working mode's amplitude per volt at resonance at its outputs")
    p.add_argument("--mode", help="with --amplitude: working-mode label or family (default: the scene's)")
    p.add_argument("--damping", help="with --amplitude: zeta=Z, Q=Q, eta=ETA, rayleigh=ALPHA,BETA or material "
                                     "(default: the scene's, material: each material's Qm)")
    p.add_argument("--outputs", help="with --amplitude: comma-separated face groups or mean:GROUP (default: the "
                   "scene's)")
    solve_options(p)
    add_html_option(p)
    scene_options(p, _sensitivity)


def _sensitivity(args) -> int:
    from modalfe.response.losses import mode_damping
    from modalfe.response.sensitivity import amplitude_sensitivities, check_parameters, frequency_sensitivities
    from modalfe.results.modes import select
    from modalfe.scene import load_scene
    from modalfe.solve.api import open_circuit_modes, solid_modes, working_question

    names = parse_names(args.vary)
    scene = load_scene(args.scene, **parse_overrides(args.set))
    check_parameters(scene, names)  # before any solve
    for flag in ("mode", "damping", "outputs"):
        if getattr(args, flag) is not None and not args.amplitude:
            raise SceneError(f"--{flag}: applies to --amplitude only")
    working = _working(scene, args) if args.amplitude else None
    question = ({"near": args.near, "count": args.count} if working is None else
                working_question(scene, working[0], args.near))
    modes = solid_modes(scene, needs="sensitivity", **question, **solve_keywords(args))
    open_modes = open_circuit_modes(modes, near=modes.nearest(question.get("near") or modes[0].frequency).frequency,
                                    count=len(modes)) if args.k_eff else None
    amplitude = None
    if working is None:
        found = frequency_sensitivities(modes, names, open_modes=open_modes)
    else:
        selector, near, losses, outputs = working
        mode = select(modes, selector, near)
        amplitude = amplitude_sensitivities(modes, names, mode=mode, outputs=outputs,
                                            damping=mode_damping(mode, losses)[0], open_modes=open_modes)
        found = amplitude.modal
    rows = [{"index": mode.index, "frequency_hz": mode.frequency, "label": mode.label,
             "error_estimate": _number(mode.error_estimate),
             "k_eff": _number(found.k_eff[i]),
             "parameters": {name: {"df_dp": _number(found.dfrequency[i, j]), "dlnf_dlnp": _number(found.relative[i, j]),
                                   "dk_eff_dp": _number(found.dk_eff[i, j])} for j, name in enumerate(names)}}
            for i, mode in enumerate(modes)]
    scene_page(args, scene)
    if args.json:
        print(json.dumps({"scene": scene.name, "dofs": modes.dofs, "circuit": modes.circuit,
                          "values": dict(zip(names, found.values.tolist())),
                          "steps": dict(zip(names, found.steps.tolist())), "modes": rows,
                          **({} if amplitude is None else {"amplitude": _amplitude_json(amplitude)})}, indent=2))
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
    if amplitude is not None:
        _print_amplitude(amplitude)
    return 0


def _working(scene, args) -> tuple:
    """(selector, near [Hz], Losses, outputs) of the mode whose amplitude is differentiated, checked before any
    solve: the options given, else the scene's working mode and drive."""
    from modalfe.response.loads import check_outputs
    from modalfe.response.losses import resolve_losses
    from modalfe.results.labels import check_selector
    from modalfe.solve.api import seek

    if not scene.working_modes and (args.mode is None or args.near is None):
        raise SceneError("--amplitude: the scene names no working mode; give --mode and --near")
    selector = None if args.mode is None else check_selector(args.mode, "--mode")
    losses = resolve_losses(scene, damping=args.damping)
    if args.outputs is not None:
        outputs = tuple(o.strip() for o in args.outputs.split(","))
        if not all(outputs):
            raise SceneError(f"--outputs: expected face groups separated by commas, got '{args.outputs}'")
    else:
        outputs = tuple(scene.drive.outputs)
    if not outputs:
        raise SceneError("--amplitude: no outputs; give --outputs (face groups) or set drive.outputs")
    check_outputs(scene, outputs)  # every face group known, every name once
    return (*seek(scene, selector, args.near), losses, outputs)


def _amplitude_json(found) -> dict:
    return {"mode": found.label, "frequency_hz": found.frequency, "damping": found.damping,
            "dfrequency_dp": dict(zip(found.modal.parameters, found.dfrequency.tolist())),
            "outputs": {name: {"amplitude_m_per_v": float(found.amplitude[i]),
                               "parameters": {p: {"dA_dp": _number(found.damplitude[i, j]),
                                                  "dlnA_dlnp": _number(found.relative[i, j])}
                                              for j, p in enumerate(found.modal.parameters)}}
                        for i, name in enumerate(found.outputs)}}


def _print_amplitude(found) -> None:
    names = found.modal.parameters
    print(f"\nmode {found.label} at {found.frequency:.2f} Hz, {found.damping}: amplitude per volt at resonance "
          f"(0-peak, normal) and d ln A / d ln p (dA/dp [m/V per unit of p]), no new eigen solve")
    print(f"{'output':<16} {'A [nm/V]':>10}" + "".join(f" {name[-24:]:>26}" for name in names))
    for i, output in enumerate(found.outputs):
        cells = "".join(f" {found.relative[i, j]:+.4f} ({found.damplitude[i, j]:+.3e})".rjust(27)
                        for j in range(len(names)))
        print(f"{output[-16:]:<16} {1e9 * found.amplitude[i]:>10.4g}{cells}")


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
