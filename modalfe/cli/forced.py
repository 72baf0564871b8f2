"""`modalfe forced`: the working mode per volt (or per unit force, pressure or base acceleration), its reduced
model, admittance and circuit, and the peak stress and field at resonance against the materials' limits."""

from __future__ import annotations

import json

from modalfe.cli.options import frequency, positive_float, solve_keywords, solve_options, stated
from modalfe.cli.page import add_html_option, scene_page
from modalfe.errors import SceneError


def register(subparsers) -> None:
    p = subparsers.add_parser("forced", help="forced response per volt of a scene's working mode")
    p.add_argument("scene", help="built-in scene name or .toml scene file")
    p.add_argument("--mode", help="working-mode label or family, e.g. '(0,6)' or 'bending-z 6'")
    p.add_argument("--near", type=frequency, help="frequency [Hz] the mode is sought near")
    p.add_argument("--damping", help="zeta=Z, Q=Q, rayleigh=ALPHA,BETA or material (default: the scene's; "
                                     "material: each material's Qm weighted by the mode's strain energy)")
    p.add_argument("--outputs", help="comma-separated face groups, mean:GROUP for the mean over a face group "
                   "(default: the scene's)")
    p.add_argument("--point", action="append", metavar="NAME=X,Y,Z", help="an output point [m] (repeatable)")
    loads = p.add_mutually_exclusive_group()
    loads.add_argument("--voltage", action="store_true", help="drive the electrodes by a voltage (per volt)")
    loads.add_argument("--force", metavar="GROUP=FX,FY,FZ", help="total force [N] on a face group, spread by area")
    loads.add_argument("--pressure", metavar="GROUP=P", help="normal pressure [Pa] on a face group")
    loads.add_argument("--base-acceleration", choices=("x", "y", "z"),
                       help="supports move with 1 m/s^2 along the axis (response relative to the base)")
    p.add_argument("--stress", nargs="?", const="", metavar="PARTS",
                   help="peak stress and field at resonance in every part, or the comma-separated PARTS")
    p.add_argument("--volts", type=positive_float,
                   help="drive amplitude [V] of the --plot curve (default 1; a voltage drive only)")
    p.add_argument("--full", action="store_true", help="also solve the full FE harmonic response")
    p.add_argument("--save-rom", metavar="FILE", help="write the reduced model as JSON")
    p.add_argument("--vtu", metavar="FILE", help="write the response at resonance per unit load (in phase and "
                   "quadrature: displacement, potential, strain, stress, electric field; von Mises peak) to a VTU")
    p.add_argument("--plot", metavar="FILE", help="write FRF and admittance plots (PNG)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene parameter")
    p.add_argument("--json", action="store_true")
    add_html_option(p)
    solve_options(p)
    p.set_defaults(func=_forced)


def _forced(args) -> int:
    from modalfe.cli.options import parse_overrides
    from modalfe.response.figures import forced_figures
    from modalfe.response.forced import Damping
    from modalfe.response.loads import Load, check_outputs
    from modalfe.results.coupling import k_eff
    from modalfe.results.labels import check_selector
    from modalfe.scene import load_scene

    if args.mode is not None:
        check_selector(args.mode, "--mode")
    damping = args.damping if args.damping in (None, "material") else Damping.parse(args.damping)
    outputs = None
    if args.outputs is not None:
        outputs = [o.strip() for o in args.outputs.split(",")]
        if not all(outputs):
            raise SceneError(f"--outputs: expected face groups separated by commas, got '{args.outputs}'")
    for text in args.point or ():
        name, eq, coords = text.partition("=")
        try:
            point = tuple(float(c) for c in coords.split(","))
        except ValueError:
            point = ()
        if not (eq and name.strip() and len(point) == 3):
            raise SceneError(f"--point: expected NAME=X,Y,Z in metres, got '{text}'")
        outputs = (outputs or []) + [(name.strip(), point)]
    load = None
    if args.voltage:
        load = Load()
    elif args.force is not None:
        load = Load.parse(f"force {args.force}", "--force")
    elif args.pressure is not None:
        load = Load.parse(f"pressure {args.pressure}", "--pressure")
    elif args.base_acceleration is not None:
        load = Load(kind="base-acceleration", axis=args.base_acceleration)
    stress = None
    if args.stress is not None:
        stress = [s.strip() for s in args.stress.split(",")] if args.stress.strip() else True
        if stress is not True and not all(stress):
            raise SceneError(f"--stress: expected part names separated by commas, got '{args.stress}'")
    scene = load_scene(args.scene, **parse_overrides(args.set))
    if outputs is not None:
        check_outputs(scene, outputs, point_field="--point")
    if args.volts is not None:
        _check_volts(args, load or scene.drive.load)
    fig = forced_figures(scene, selector=args.mode, near=args.near, damping=damping, outputs=outputs,
                         full=args.full, load=load, stress=stress, state=bool(args.vtu), **solve_keywords(args))
    if args.save_rom:
        fig.rom.save(args.save_rom)
    if args.vtu:
        from modalfe.report.export import export_forced_vtu

        export_forced_vtu(fig.mode, fig.state, args.vtu, unit=fig.load_unit, error_estimate=fig.error_estimate)
        if not args.json:
            print(f"response at resonance per {fig.load_unit} (in phase and quadrature; von Mises peak over the "
                  f"cycle) -> {args.vtu}")
    if args.plot:
        from modalfe.plot.figures import write_forced_plots

        write_forced_plots(fig, args.plot, args.volts or 1.0)
    scene_page(args, scene)
    if args.json:
        print(json.dumps(fig.to_json(), indent=2))
        return 0
    rom = fig.rom
    print(f"{scene.name}: mode {rom.label} at {rom.frequency:.2f} Hz (stated error {stated(fig.error_estimate)}), "
          f"{rom.damping_description} ({fig.damping_source})")
    print(f"  {fig.resolution}")
    unit = fig.load_unit

    def pm(name: str) -> str:  # the stated error of a number, as every figure is printed
        return f" [{stated(fig.error(name))}]"

    print(f"  reduced model at {rom.reference}: m {rom.modal_mass:.4g} kg{pm('modal_mass')}, k {rom.stiffness:.4g} "
          f"N/m{pm('stiffness')}, c {rom.damping:.4g} N s/m{pm('damping')}, force factor {rom.force_factor:.4g} "
          f"N/{unit}{pm('force_factor')}")
    print("  [stated errors in brackets, from the frequency's estimate levels]")
    if unit != "V":
        _print_load(fig, pm)
        _print_stress(fig, pm)
        return 0
    bvd = rom.bvd
    print(f"  BVD: C0 {bvd['C0']:.4g} F{pm('bvd:C0')}, R1 {bvd['R1']:.4g} ohm{pm('bvd:R1')}, L1 {bvd['L1']:.4g} "
          f"H{pm('bvd:L1')}, C1 {bvd['C1']:.4g} F{pm('bvd:C1')}; one-mode fa {rom.antiresonance:.1f} "
          f"Hz{pm('bvd_fa')}, k_eff {rom.k_eff:.4f}{pm('bvd_k_eff')}")
    cap = fig.capacitances
    print(f"  capacitance: free {1e9 * cap['free']:.4g} nF{pm('capacitance:free')} (static, the structure free), "
          f"clamped {1e9 * cap['clamped']:.4g} nF{pm('capacitance:clamped')} (u = 0), C0 of the BVD "
          f"{1e9 * cap['C0']:.4g} nF{pm('bvd:C0')} (the free one less this mode's C1)")
    if fig.antiresonance is not None:
        print(f"  open circuit (same model): fa {fig.antiresonance:.2f} Hz{pm('fa')}, "
              f"k_eff {k_eff(rom.frequency, fig.antiresonance):.4f}{pm('k_eff')}")
    print(f"  amplitude build-up time constant {1e3 * fig.time_constant:.3f} ms{pm('time_constant')}")
    for o, a in fig.amplitude_per_volt.items():
        peak, avg = fig.acceleration[o]
        print(f"  {o:<14} {1e9 * a:10.3f} nm/V 0-peak{pm(f'amplitude:{o}')}   accel {peak:.4g} m/s^2/V peak"
              f"{pm(f'acceleration:{o}')}, "
              f"{avg:.4g} half-period avg")
    for name, volts in fig.volts_for.items():
        print(f"  volts for {name}: {volts:.2f} V{pm(f'amplitude:{rom.reference}')}")
    for name, a in fig.amplitude_at.items():
        print(f"  {name}: ours {1e6 * a['ours_m']:.3f} um at {a['volts']:g} V vs seed {1e6 * a['seed_m']:.3f} um "
              f"({100 * a['deviation']:+.0f}%)")
    for note in fig.notes:
        print(f"  note: {note}")
    _print_stress(fig, pm)
    return 0


def _check_volts(args, load) -> None:
    """``--volts`` scales the --plot curve of a voltage drive; refused where it would be ignored."""
    if load.kind != "voltage":
        raise SceneError(f"--volts: the load is a {load.describe()}, not a voltage; the results are per "
                         f"{load.unit} (drop --volts)")
    if not args.plot:
        raise SceneError("--volts: scales only the --plot curve (the printed figures are per volt); give --plot FILE")


def _print_load(fig, pm) -> None:
    """Outputs per unit of a force, pressure or base acceleration at resonance."""
    unit = fig.load_unit
    print(f"  load: {fig.load_description} ({fig.load_source})")
    print(f"  amplitude build-up time constant {1e3 * fig.time_constant:.3f} ms{pm('time_constant')}")
    for o, a in fig.amplitude_per_volt.items():
        line = (f"  {o:<16} {1e9 * a:10.4g} nm/{unit} 0-peak{pm(f'amplitude:{o}')}   "
                f"velocity {1e3 * fig.velocity[o]:.4g} mm/s/{unit}{pm(f'velocity:{o}')}   "
                f"accel {fig.acceleration[o][0]:.4g} m/s^2/{unit} peak{pm(f'acceleration:{o}')}")
        if o in fig.absolute_acceleration:
            line += f" (relative; absolute {fig.absolute_acceleration[o]:.4g} per m/s^2 of base)"
        print(line)
    for note in fig.notes:
        print(f"  note: {note}")


def _print_stress(fig, pm) -> None:
    """Peak stress and field per unit load at resonance, and the load that reaches each material limit."""
    if fig.stress is None:
        return
    unit = fig.load_unit
    print(f"  stress and field at resonance per {unit} (peaks over the cycle; point in mm):")

    def at(p) -> str:
        return "(" + ", ".join(f"{1e3 * c:.2f}" for c in p.point) + ")"

    for p in fig.stress:
        line = (f"    {p.part:<12} {p.material:<10} von Mises {p.von_mises.value / 1e6:.4g} MPa/{unit}"
                f"{pm(f'von_mises:{p.part}')} at {at(p.von_mises)}   max principal {p.principal.value / 1e6:.4g} "
                f"MPa/{unit}{pm(f'principal:{p.part}')} at {at(p.principal)}")
        if p.field is not None:
            line += f"   |E| {p.field.value / 1e3:.4g} V/mm per {unit}{pm(f'field:{p.part}')} at {at(p.field)}"
        print(line)
    for row in fig.limits:
        what = "depolarising field" if row["limit"] == "depolarising_field" else "tensile strength"
        if row["limit_value"] is None:
            print(f"    {row['part']:<12} {what}: no limit in the table for {row['material']}")
            continue
        shown = (f"{row['limit_value'] / 1e6:.4g} V/um" if row["limit"] == "depolarising_field" else
                 f"{row['limit_value'] / 1e6:.4g} MPa")
        shown = shown.replace("V/um", "kV/mm")
        print(f"    {row['part']:<12} {what} {shown}: reached at {row['load_to_limit']:.4g} {unit}")
    for source in dict.fromkeys(r["source"] for r in fig.limits if r["source"]):
        print(f"    limits: {source}")
