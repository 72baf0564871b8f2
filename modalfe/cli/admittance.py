"""`modalfe admittance` (broadband Y(f), Z(f) of the driven electrodes) and `modalfe table` (the mode table)."""

from __future__ import annotations

import json

from modalfe.cli.options import (
    _float,
    check_band,
    check_output_path,
    frequency_or_zero,
    parse_overrides,
    positive_int,
    solve_keywords,
    solve_options,
    stated,
)
from modalfe.cli.page import add_html_option, scene_page
from modalfe.errors import SceneError


def register(sub) -> None:
    p = sub.add_parser("admittance", help="electrical admittance and impedance of the driven electrodes over a band")
    p.add_argument("scene", help="built-in scene name or .toml scene file")
    p.add_argument("--band", type=_float, nargs=2, metavar=("F1", "F2"), required=True, help="frequency band [Hz]")
    p.add_argument("--points", type=positive_int, default=400, help="frequencies, evenly spaced (default 400)")
    p.add_argument("--damping", help="Q=Q, zeta=Z, eta=ETA, rayleigh=ALPHA,BETA or material (each material's Qm; "
                                     "default: the scene's drive.damping)")
    p.add_argument("--mode-damping", action="append", metavar="LABEL=SPEC",
                   help="one mode's loss, e.g. '(0,6)=Q=300' (repeatable; modal superposition only)")
    p.add_argument("--tan-delta", type=_float, help="dielectric loss tangent (default: the material table's)")
    p.add_argument("--residual", choices=("centre", "static"), default="centre",
                   help="shift of the residual of the modes left out (default: the band's centre)")
    p.add_argument("--direct", action="store_true", help="direct harmonic FE at every frequency instead")
    p.add_argument("--csv", metavar="FILE", help="write frequency_Hz, Y_real_S, Y_imag_S, abs_Z_ohm, phase_Z_deg")
    p.add_argument("--s1p", metavar="FILE", help="write a Touchstone v1 one-port file (S11 against 50 ohm)")
    p.add_argument("--plot", metavar="FILE", help="write the |Y|, |Z| and phase plot (PNG)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene parameter")
    p.add_argument("--json", action="store_true")
    add_html_option(p)
    solve_options(p)
    p.set_defaults(func=_admittance)

    p = sub.add_parser("table", help="mode table: effective masses, participation, fr/fa, k_eff, force factor")
    p.add_argument("scene", help="built-in scene name or .toml scene file")
    p.add_argument("--near", type=frequency_or_zero, help="target frequency [Hz]")
    p.add_argument("--count", type=positive_int, help="number of modes nearest --near")
    p.add_argument("--band", type=_float, nargs=2, metavar=("F1", "F2"), help="all modes in [F1, F2] Hz")
    p.add_argument("--csv", metavar="FILE", help="write the table as CSV (units in the headers)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene parameter")
    p.add_argument("--json", action="store_true")
    solve_options(p)
    add_html_option(p)
    p.set_defaults(func=_table)


def _mode_damping(items: list[str] | None) -> dict[str, str]:
    """LABEL -> SPEC of ``--mode-damping``, each mode once, its label's form checked before any solve."""
    from modalfe.results.labels import check_selector

    out = {}
    for item in items or []:
        label, sep, spec = item.partition("=")
        if not sep or not label.strip() or not spec.strip():
            raise SceneError(f"--mode-damping: expected LABEL=SPEC such as '(0,6)=Q=300', got '{item}'")
        check_selector(label, "--mode-damping")
        if label.strip() in out:
            raise SceneError(f"--mode-damping: mode '{label.strip()}' given twice ({out[label.strip()]} and "
                             f"{spec.strip()}); give each mode once")
        out[label.strip()] = spec.strip()
    return out


def _admittance(args) -> int:
    from modalfe.response.admittance import MAX_POINTS, UNDRIVEN, admittance
    from modalfe.scene import load_scene

    band = check_band(args.band)
    if band[0] <= 0:
        raise SceneError(f"--band: F1 must be above 0 Hz, got {band[0]:g}")
    if not 2 <= args.points <= MAX_POINTS:
        raise SceneError(f"--points: needs 2 to {MAX_POINTS:,} frequencies, got {args.points:,}")
    for flag, path, suffix in (("--csv", args.csv, ".csv"), ("--s1p", args.s1p, ".s1p"), ("--plot", args.plot, ".png")):
        if path is not None:
            check_output_path(flag, path)
            if not path.lower().endswith(suffix):
                raise SceneError(f"{flag}: '{path}' must end in {suffix}")
    scene = load_scene(args.scene, **parse_overrides(args.set))
    result = admittance(scene, band, args.points, damping=args.damping, tan_delta=args.tan_delta,
                        per_mode=_mode_damping(args.mode_damping), direct=args.direct, residual=args.residual,
                        **solve_keywords(args))
    if args.csv:
        result.write_csv(args.csv)
    if args.s1p:
        result.write_s1p(args.s1p)
    circuits = result.bvd_circuits()
    if args.plot:
        from modalfe.plot.figures import plot_admittance

        fig = plot_admittance(result.frequency, result.Y, impedance=True, circuits=circuits, marks=bvd_marks(circuits),
                              title=f"{scene.name}: {'direct FE' if args.direct else 'modal superposition'}")
        fig.savefig(args.plot, dpi=110)
    scene_page(args, scene)
    if args.json:
        print(json.dumps(result.to_json(), indent=2))
        return 0
    print(f"{scene.name}: admittance over {band[0]:g}-{band[1]:g} Hz, {len(result.frequency)} points; {result.method}")
    for line in result.losses:
        print(f"  loss {line}")
    for note in result.notes:
        print(f"  note: {note}")
    print(f"  clamped capacitance C_S (u = 0) {1e9 * result.capacitance_clamped:.4g} nF "
          f"[{stated(result.capacitance_error)}]; "
          f"|Y| at {band[0]:g} Hz {abs(result.Y[0]):.4g} S")
    ext = result.extrema()
    print("  |Y| maxima (near fr) [Hz]: " + (", ".join(f"{f:.1f}" for f in ext["max_abs_Y_hz"]) or "none"))
    print("  |Y| minima (near fa) [Hz]: " + (", ".join(f"{f:.1f}" for f in ext["min_abs_Y_hz"]) or "none"))
    strong = sorted(result.modes, key=lambda r: -abs(r["theta_N_per_V_sqrtkg"]))[:8]
    if strong:  # modes the drive does not reach (theta at round-off) are not among the strongest, whatever their rank
        floor = UNDRIVEN * abs(strong[0]["theta_N_per_V_sqrtkg"])
        strong = [r for r in strong if abs(r["theta_N_per_V_sqrtkg"]) > floor]
    if strong:
        print("  strongest modes (modal force per volt, loss):")
        for r in sorted(strong, key=lambda r: r["frequency_hz"]):
            print(f"    {r['label']:<13} {r['frequency_hz']:10.1f} Hz  theta {r['theta_N_per_V_sqrtkg']:+.4g} "
                  f"N/(V kg^0.5) [{_stated(r, 'theta')}]  {r['loss']}")
            if "peak_hz" in r:
                dip = f", |Y| min above it {r['dip_hz']:.1f} Hz [{_stated(r, 'dip_hz')}]" if "dip_hz" in r else ""
                print(f"      |Y| max {r['peak_S']:.4g} S [{_stated(r, 'peak_S')}] at {r['peak_hz']:.1f} Hz "
                      f"[{_stated(r, 'peak_hz')}]{dip}")
    if circuits:
        print("  BVD circuit of each resonance (IEEE Std 176-1987; C0 at fr: the rest of Y at fr, the clamped "
              "capacitance and the other modes, docs/capacitance.md):")
        print(f"    {'mode':<13} {'fr [Hz]':>10} {'fa [Hz]':>10} {'k_eff':>7} {'C0 at fr [nF]':>13} {'R1 [ohm]':>10} "
              f"{'L1 [H]':>10} {'C1 [pF]':>10}")
        for c in circuits:
            print(f"    {c['label']:<13} {c['fr_hz']:10.1f} {c['fa_hz']:10.1f} {c['k_eff']:7.4f} "
                  f"{1e9 * c['C0_at_fr_F']:13.4g} {c['R1_ohm']:10.4g} {c['L1_H']:10.4g} {1e12 * c['C1_F']:10.4g}  "
                  f"[fr {_known(c['fr_error'])}, L1 {_known(c['L1_error'])}, C1 {_known(c['C1_error'])}]")
    if result.open_circuit:
        print("  FE open circuit of each resonance (its open-circuit mode of the same shape on the same model; the "
              "fa and k_eff of table, forced and the API):")
        print(f"    {'mode':<13} {'fr [Hz]':>10} {'fa [Hz]':>10} {'k_eff':>7}")
        for c in result.open_circuit:
            print(f"    {c['label']:<13} {c['fr_hz']:10.1f} {c['fa_hz']:10.1f} {c['k_eff']:7.4f}")
    print("  [stated errors in brackets, from the frequencies' estimate levels]")
    for flag, path in (("csv", args.csv), ("s1p", args.s1p), ("plot", args.plot)):
        if path:
            print(f"  wrote {flag}: {path}")
    return 0


def bvd_marks(circuits: list[dict]) -> dict[str, float]:
    """fr and fa of each BVD circuit, named for a plot's dotted lines (the mode's label beside them when several)."""
    one = len(circuits) == 1
    return {f"{name}{'' if one else ' ' + c['label']}": c[f"{name}_hz"] for c in circuits for name in ("fr", "fa")}


def _known(error: float | None) -> str:
    return "n/a" if error is None else stated(error)


def _stated(row: dict, name: str) -> str:
    error = row.get(f"{name}_error")
    return stated(float("inf") if error is None else error) if f"{name}_error" in row else "n/a"


def _table(args) -> int:
    from modalfe.response.mode_table import mode_table
    from modalfe.scene import load_scene

    band = check_band(args.band)
    if band is not None and args.near is not None:
        raise SceneError("--near: give either --near (with --count) or --band, not both")
    if band is not None and args.count is not None:
        raise SceneError("--count: --band returns every mode in the band; --count goes with --near")
    if args.csv is not None:
        check_output_path("--csv", args.csv)
    scene = load_scene(args.scene, **parse_overrides(args.set))
    table = mode_table(scene, near=args.near, count=args.count, band=band, **solve_keywords(args))
    if args.csv:
        table.write_csv(args.csv)
    scene_page(args, scene)
    if args.json:
        print(json.dumps(table.to_json(), indent=2))
        return 0
    print(table.format())
    if args.csv:
        print(f"wrote csv: {args.csv}")
    return 0
