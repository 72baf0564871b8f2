"""`modalfe forced`: the working mode per volt, its reduced model, admittance and circuit."""

from __future__ import annotations

import json

from modalfe.cli.options import frequency, positive_float
from modalfe.errors import SceneError


def register(subparsers) -> None:
    p = subparsers.add_parser("forced", help="forced response per volt of a scene's working mode")
    p.add_argument("scene", help="built-in scene name or .toml scene file")
    p.add_argument("--mode", help="working-mode label or family, e.g. '(0,6)' or 'bending-z 6'")
    p.add_argument("--near", type=frequency, help="frequency [Hz] the mode is sought near")
    p.add_argument("--damping", help="zeta=Z, Q=Q or rayleigh=ALPHA,BETA (default: the scene's)")
    p.add_argument("--outputs", help="comma-separated face groups (default: the scene's)")
    p.add_argument("--volts", type=positive_float, default=1.0, help="drive amplitude [V] for the printed curve")
    p.add_argument("--full", action="store_true", help="also solve the full FE harmonic response")
    p.add_argument("--save-rom", metavar="FILE", help="write the reduced model as JSON")
    p.add_argument("--plot", metavar="FILE", help="write FRF and admittance plots (PNG)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene parameter")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=_forced)


def _forced(args) -> int:
    from modalfe.cli.options import parse_overrides
    from modalfe.response.figures import forced_figures
    from modalfe.response.forced import Damping
    from modalfe.scene import load_scene

    damping = Damping.parse(args.damping) if args.damping is not None else None
    outputs = None
    if args.outputs is not None:
        outputs = [o.strip() for o in args.outputs.split(",")]
        if not all(outputs):
            raise SceneError(f"--outputs: expected face groups separated by commas, got '{args.outputs}'")
    scene = load_scene(args.scene, **parse_overrides(args.set))
    fig = forced_figures(scene, selector=args.mode, near=args.near, damping=damping, outputs=outputs,
                         full=args.full)
    if args.save_rom:
        fig.rom.save(args.save_rom)
    if args.plot:
        _plot(fig, args.plot, args.volts)
    if args.json:
        print(json.dumps(fig.to_json(), indent=2))
        return 0
    rom = fig.rom
    print(f"{scene.name}: mode {rom.label} at {rom.frequency:.1f} Hz, {rom.damping_description} ({fig.damping_source})")
    print(f"  reduced model at {rom.reference}: m {rom.modal_mass:.4g} kg, k {rom.stiffness:.4g} N/m, "
          f"c {rom.damping:.4g} N s/m, force factor {rom.force_factor:.4g} N/V")
    bvd = rom.bvd
    print(f"  BVD: C0 {bvd['C0']:.4g} F, R1 {bvd['R1']:.4g} ohm, L1 {bvd['L1']:.4g} H, C1 {bvd['C1']:.4g} F; "
          f"fa {rom.antiresonance:.1f} Hz, k_eff {rom.k_eff:.4f}")
    print(f"  amplitude build-up time constant {1e3 * fig.time_constant:.3f} ms")
    for o, a in fig.amplitude_per_volt.items():
        peak, avg = fig.acceleration[o]
        print(f"  {o:<14} {1e9 * a:10.3f} nm/V 0-peak   accel {peak:.4g} m/s^2/V peak, {avg:.4g} half-period avg")
    for name, volts in fig.volts_for.items():
        print(f"  volts for {name}: {volts:.2f} V")
    for name, a in fig.amplitude_at.items():
        print(f"  {name}: ours {1e6 * a['ours_m']:.3f} um at {a['volts']:g} V vs seed {1e6 * a['seed_m']:.3f} um "
              f"({100 * a['deviation']:+.0f}%)")
    for note in fig.notes:
        print(f"  note: {note}")
    return 0


def _plot(fig, path: str, volts: float) -> None:
    """FRF (reduced model, and full FE when computed) and admittance, one PNG."""
    from modalfe.plot.figures import plot_admittance, plot_frf

    curves = {"reduced model": volts * fig.frf}
    if fig.frf_full is not None:
        curves["full FE"] = volts * fig.frf_full
    title = f"{fig.scene}: {fig.rom.label}, {fig.rom.damping_description}"
    frf = plot_frf(fig.frequency, curves, ylabel=f"amplitude at {fig.rom.reference} [m] at {volts:g} V", title=title)
    stem, dot, ext = path.rpartition(".")
    frf.savefig(path, dpi=110)
    plot_admittance(fig.frequency, fig.admittance, title=title).savefig(f"{stem}_admittance.{ext}" if dot else
                                                                        f"{path}_admittance", dpi=110)
