"""The ``modalfe friction``, ``modalfe finger`` and ``modalfe texture`` subcommands.

A thin layer over ``modalfe.contact``: parse, call, print.  ``register(subparsers)`` adds the
subcommands to the ``modalfe`` parser; each handler returns the exit status.
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np

from modalfe.cli import haptics
from modalfe.errors import ContactError
from modalfe.progress import is_shown

RANGE_HELP = "a number, a list a,b,c or start:stop:count (linspace)"


def parse_values(text: str, name: str) -> np.ndarray:
    """``start:stop:count`` (inclusive linspace), ``a,b,c`` or one number; ContactError naming ``name``."""
    try:
        if ":" in text:
            start, stop, count = text.split(":")
            n = int(count)
            if n < 1:
                raise ValueError
            return np.linspace(float(start), float(stop), n)
        return np.array([float(v) for v in text.split(",")])
    except ValueError:
        raise ContactError(f"{name}: expected {RANGE_HELP}, got {text!r}") from None


def _overrides(pairs: list[str] | None) -> dict:
    from modalfe.cli.options import parse_overrides

    return parse_overrides(pairs)


def _save_plot(fig, path: str | None) -> None:
    if path:
        fig.savefig(path, dpi=120)
        print(f"figure written to {path}")


def _load_rom(path: str):
    """A reduced modal model saved by ``modalfe forced --save-rom``."""
    from modalfe.errors import ModalfeError
    from modalfe.response.forced import ReducedModel

    try:
        return ReducedModel.load(path)
    except (OSError, ValueError, TypeError, ModalfeError) as exc:
        raise ContactError(f"--rom: cannot read a reduced model from {path!r} ({exc})") from None


def _refuse_with_scene(args, *names: str) -> None:
    """A one-line error for a flag given beside a SCENE, whose working mode sets what the flag would."""
    for name in names:
        if getattr(args, name) is not None:
            raise ContactError(f"--{name.replace('_', '-')}: not with a SCENE (its working mode sets the amplitude and "
                               "frequency; --map --map-dir DIR draws the map)")


def _volts(args) -> np.ndarray | None:
    """``--voltage`` parsed, None when not given."""
    return None if args.voltage is None else parse_values(args.voltage, "--voltage")


def _friction(args) -> int:
    from modalfe.contact.chain import FootContact, chain_from_rom
    from modalfe.contact.foot import FootParameters, simulate_contact

    p = FootParameters().with_(**_overrides(args.set))
    from_rom = []
    if args.kt is not None:
        p = p.with_(kt=args.kt)
    if args.feet is not None:
        p = p.with_(n=args.feet)
    if args.scene is not None:
        from modalfe.cli.haptics import run

        _refuse_with_scene(args, "frequency", "rom", "amplitude", "amplitude_per_volt", "plot")
        p = p.on(args.substrate) if args.substrate else p
        return run(args, FootContact(p, args.preload, args.speed), _volts(args), feet_map=True)
    if args.frequency is not None:
        p = p.with_(frequency=args.frequency)
    if args.voltage is not None and args.rom:
        if args.amplitude_per_volt is not None:
            raise ContactError("--amplitude-per-volt: give it or --rom, not both")
        p = p.on(args.substrate) if args.substrate else p
        rom = _load_rom(args.rom)
        if "mass" not in _overrides(args.set) and math.isfinite(rom.device_mass):
            p = p.with_(mass=rom.device_mass)  # the device the feet carry, from its own model
            from_rom.append(f"m = {rom.device_mass:.4g} kg (the device's mass)")
        try:
            chain = chain_from_rom(rom, FootContact(p, args.preload, args.speed),
                                   output=args.rom_output, frequency=args.frequency, feet=args.feet)
        except ContactError as exc:  # the library names its field, the CLI its flag
            if not str(exc).startswith("output:"):
                raise
            raise ContactError(f"--rom-output{str(exc)[len('output'):]}") from None
        curve = chain.foot_curve(parse_values(args.voltage, "--voltage"))
        if args.feet is None:
            from_rom.append(f"n = {curve.parameters.n} feet (its foot outputs)")
    elif args.voltage is not None:
        curve = simulate_contact(voltage=parse_values(args.voltage, "--voltage"),
                                 amplitude_per_volt=args.amplitude_per_volt, preload=args.preload,
                                 speed=args.speed, substrate=args.substrate, parameters=p, progress=is_shown())
    else:
        curve = simulate_contact(parse_values(args.amplitude, "--amplitude"), preload=args.preload,
                                 speed=args.speed, substrate=args.substrate, parameters=p, progress=is_shown())
    if args.json:
        print(json.dumps(curve.to_json(), indent=2))
    else:
        q = curve.parameters
        print(f"foot contact: Fn = {curve.preload:g} N, V = {curve.speed:g} m/s, mu0 = {q.mu0:g}, kt = {q.kt:g} N/m, "
              f"kn = {q.kn:g} N/m, dn = {q.dn:g} N s/m, m = {q.mass:g} kg, n = {q.n}, f = {q.frequency:g} Hz")
        if from_rom:
            print(f"from the reduced model {args.rom}: {', '.join(from_rom)}; kn and dn: seed 000 appendix "
                  f"(the reduced model carries no contact stiffness)")
        print(f"friction without vibration mu0 (Fn + m g) = {curve.static_friction:.4f} N; "
              f"flight from W = {q.onset_amplitude(curve.preload) * 1e6:.4f} um")
        if curve.speed == 0:
            print("speed 0 (the limit V -> 0+): after a touchdown the foot sticks with no tangential force; "
                  "without flight it slides with mu0 Rn, so the friction is mu0 (Fn + m g) up to the onset and 0 above")
        volts = curve.voltage is not None
        print(("  V [V] " if volts else "") + f"{'W [um]':>8} {'beta [%]':>9} {'F [N]':>8} {'reduction':>10} "
              f"{'contacts':>8}")
        for i, w in enumerate(curve.amplitude):
            lead = f"{curve.voltage[i]:7.2f} " if volts else ""
            note = "" if curve.periodic[i] else "  (time average)"
            # rounded to what is printed, + 0.0: a rounding residue never shows as -0.0000 or -0.00 %
            force = round(curve.friction_force[i], 4) + 0.0
            reduction = round(100 * curve.friction_reduction[i], 2) + 0.0
            print(f"{lead}{w * 1e6:8.4f} {curve.flight_ratio[i]:9.3f} {force:8.4f} "
                  f"{reduction:9.2f}% {curve.contacts_per_period[i]:8.3g}{note}")
    if args.plot:
        from modalfe.plot.contact import friction_figure

        _save_plot(friction_figure(curve), args.plot)
    return 0


def _finger_amplitudes(args, frequencies: list[float]) -> list[np.ndarray]:
    from modalfe.contact.validation import require

    frequencies = [require("frequency", f, positive=True) for f in frequencies]
    if not args.amplitude:
        # Table I: mu_US / mu reaches about 0.7 near 3.2 um pp at 66 kHz and 0.3 um pp at 225 kHz
        return [np.linspace(0, 3.2e-6 * (66e3 / f) ** 1.5, 25) for f in frequencies]
    if len(args.amplitude) not in (1, len(frequencies)):
        raise ContactError("--amplitude: give it once for all frequencies or once per --frequency")
    ranges = [parse_values(a, "--amplitude") for a in args.amplitude]
    return ranges * len(frequencies) if len(ranges) == 1 else ranges


def _finger(args) -> int:
    from modalfe.contact.finger import FREQUENCIES, FingerParameters, equal_friction, simulate_finger

    p = FingerParameters().with_(**_overrides(args.set))
    if args.reading is not None:
        p = p.with_(reading=args.reading)
    if args.scene is not None:
        from modalfe.cli.haptics import run
        from modalfe.contact.chain import FingerContact

        _refuse_with_scene(args, "frequency", "amplitude", "plot")
        return run(args, FingerContact(p), _volts(args), feet_map=False)
    if args.voltage is not None:
        raise ContactError("--voltage: needs a SCENE (the amplitude per volt comes from its working mode)")
    frequencies = args.frequency or list(FREQUENCIES)
    curves = [simulate_finger(a, f, parameters=p, progress=is_shown())
              for f, a in zip(frequencies, _finger_amplitudes(args, frequencies))]
    equal, skipped = None, []
    if len(curves) == 2:
        levels = parse_values(args.levels, "--levels")
        inside = [x for x in levels if all(c.friction_ratio.min() <= x < c.friction_ratio[0] for c in curves)]
        skipped = [x for x in levels if x not in inside]
        low, high = sorted(curves, key=lambda c: c.frequency)
        equal = equal_friction(low, high, inside) if inside else None
    if args.json:
        print(json.dumps({"parameters": {k: getattr(p, k) for k in p.__dataclass_fields__},
                          "curves": [c.to_json() for c in curves],
                          "equal_friction": None if equal is None else equal.to_json()}, indent=2))
    else:
        print(f"bed-spring finger (seed 004 Table I, {p.reading} reading): f_p = {p.preload:g} N, "
              f"V_F = {p.speed:g} m/s, mu = {p.mu:g}, damping ratio {p.damping_ratio:g}")
        for c in curves:
            print(f"{c.frequency / 1e3:g} kHz:  {'A [um pp]':>10} {'mu_US/mu':>9} {'+-':>8} {'contact [%]':>11}"
                  "  method")
            for a, r, u, cr, m in zip(c.amplitude_pp, c.friction_ratio, c.uncertainty, c.contact_ratio, c.method):
                print(f"{'':10}{a * 1e6:10.4f} {r:9.4f} {u:8.1e} {cr:11.2f}  {m}")
        if equal is not None:
            lf, hf = (f / 1e3 for f in equal.frequencies)
            print(f"equal friction: amplitude at {hf:g} kHz / amplitude at {lf:g} kHz "
                  f"(equal velocity {equal.velocity_ratio:.3f}, equal acceleration {equal.acceleration_ratio:.3f})")
            print(f"{'mu_US/mu':>9} {'A_low [um]':>11} {'A_high [um]':>12} {'ratio':>7} {'+-':>7}")
            for x, lo, hi, r, u in zip(equal.level, equal.amplitude_low, equal.amplitude_high, equal.ratio,
                                       equal.ratio_uncertainty):
                print(f"{x:9.3f} {lo * 1e6:11.4f} {hi * 1e6:12.4f} {r:7.4f} {u:7.4f}")
        if skipped:
            print(f"levels outside the curves (widen --amplitude): {', '.join(f'{x:g}' for x in skipped)}")
    if args.plot:
        from modalfe.plot.contact import finger_figure

        _save_plot(finger_figure(curves, equal), args.plot)
    return 0


def _texture(args) -> int:
    from modalfe.contact.foot import FootParameters, simulate_contact
    from modalfe.contact.texture import NotchTexture, render_texture
    from modalfe.contact.validation import require

    texture = NotchTexture(period=args.period, notch_width=args.notch_width, track_length=args.track_length,
                           profile=args.profile)
    p = FootParameters().with_(**_overrides(args.set))
    a_on = require("amplitude_on", args.amplitude_on, positive=True)
    curve = simulate_contact(np.linspace(0.0, a_on, 41), preload=args.preload, speed=args.speed,
                             substrate=args.substrate, parameters=p, progress=is_shown())
    r = render_texture(texture, curve, amplitude_on=args.amplitude_on, control=args.control,
                       response_time=args.response_time)
    if args.json:
        print(json.dumps(r.to_json()))
    else:
        print(f"{texture.profile} notches, period {texture.period * 1e3:g} mm over {texture.track_length * 1e3:g} mm "
              f"({texture.cycles:g} cycles), {r.control} control at {args.amplitude_on * 1e6:g} um")
        print(f"speed {r.speed:g} m/s -> modulation {r.modulation_frequency:.2f} Hz; amplitude time constant "
              f"{r.response_time * 1e3:g} ms")
        print(f"friction {r.friction_force.min():.4f} to {r.friction_force.max():.4f} N "
              f"(static {curve.static_friction:.4f} N), contrast {r.contrast:.4f} N")
    if args.plot:
        from modalfe.plot.contact import texture_figure

        _save_plot(texture_figure(r), args.plot)
    return 0


def _common(p: argparse.ArgumentParser) -> None:
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a model parameter")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.add_argument("--plot", metavar="FILE", help="write a figure (png, pdf, svg)")


def register(subparsers) -> None:
    """Add ``friction``, ``finger`` and ``texture`` to the ``modalfe`` subcommands."""
    p = subparsers.add_parser(
        "friction", help="foot contact friction against vibration amplitude (seeds 000, 001)",
        description="Steady-state flight ratio and friction force of a plate on vibrating feet (seed 000 "
                    "eqs 2-17, Coulomb-Orowan friction), against amplitude or drive voltage. Parameters: "
                    "seed 000 appendix (kn, dn, m, h, n=3) with kt identified from seed 001; --set kn=...")
    p.add_argument("scene", nargs="?", help="built-in scene or .toml file: the chain from its working mode "
                                            "(outcomes per --voltage, --reduction, --map; docs/haptics.md)")
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--amplitude", help=f"vibration amplitude at the feet [m, 0-peak]: {RANGE_HELP}")
    src.add_argument("--voltage", help=f"drive voltage [V] (needs --amplitude-per-volt, --rom or a SCENE): "
                                       f"{RANGE_HELP}")
    p.add_argument("--amplitude-per-volt", type=float, metavar="M_PER_V",
                   help="amplitude at the feet per volt [m/V] (from the forced response)")
    p.add_argument("--rom", metavar="FILE", help="reduced model JSON (modalfe forced --save-rom) giving the "
                                                 "amplitude per volt |FRF| at the drive frequency (default: "
                                                 "its resonance), the number of feet (its foot outputs) and the "
                                                 "moving mass m (the device's mass); kn and dn stay seed 000's")
    p.add_argument("--rom-output", metavar="NAME", help="output of the reduced model (default: its reference)")
    p.add_argument("--preload", type=float, default=10.0, help="preload Fn [N] (default 10, seed 000 appendix)")
    p.add_argument("--speed", type=float, default=0.01, help="sliding speed [m/s] (default 0.01)")
    p.add_argument("--substrate", choices=("steel", "glass"), help="sets mu0: steel 0.2, glass 0.08 (default steel)")
    p.add_argument("--frequency", type=float, help="drive frequency [Hz] (default 40.7 kHz, seed 001)")
    p.add_argument("--kt", type=float, help="tangential contact stiffness [N/m] (default: identified)")
    p.add_argument("--feet", type=int, help="number of feet sharing the load (default: the --rom's or SCENE's foot "
                                            "outputs where it has two or more, else 3, seed 000 appendix)")
    _common(p)
    haptics.add_options(p)
    p.set_defaults(func=_friction)

    p = subparsers.add_parser(
        "finger", help="bed-spring fingertip friction against amplitude at two frequencies (seed 004)",
        description="mu_US/mu against peak-to-peak amplitude per frequency (seed 004 Table I, Kelvin-Voigt "
                    "layers, critical damping per layer) and the amplitude ratio giving equal friction.")
    p.add_argument("--frequency", type=float, action="append", help="drive frequency [Hz], repeatable "
                                                                       "(default 66e3 and 225e3)")
    p.add_argument("--amplitude", action="append", help=f"peak-to-peak amplitude [m]: {RANGE_HELP}; once, or "
                                                        "once per --frequency (default: a range per frequency)")
    p.add_argument("--levels", default="0.95,0.9,0.85,0.8,0.75", help="friction levels mu_US/mu for the ratio")
    p.add_argument("--reading", choices=("kelvin-voigt", "literal"), help="reading of seed 004 eq. (1)")
    p.add_argument("scene", nargs="?", help="built-in scene or .toml file: the finger on its working mode "
                                            "(outcomes per --voltage, --reduction, --map; docs/haptics.md)")
    p.add_argument("--voltage", help=f"drive voltage [V] with a SCENE: {RANGE_HELP}")
    _common(p)
    haptics.add_options(p)
    p.set_defaults(func=_finger)

    p = subparsers.add_parser(
        "texture", help="notch texture rendered by amplitude control along a track (seed 001)",
        description="Friction against position for a grating of notches rendered by on/off or proportional "
                    "amplitude control, with the plate's ~1 ms amplitude response (seed 001 sections 7-9).")
    p.add_argument("--period", type=float, required=True, help="spatial period of the notches [m]")
    p.add_argument("--notch-width", type=float, help="notch width [m] (default half the period)")
    p.add_argument("--profile", choices=("square", "sine"), default="square")
    p.add_argument("--control", choices=("on_off", "proportional"), default="on_off")
    p.add_argument("--track-length", type=float, default=87e-3, help="[m] (default 87 mm, seed 001)")
    p.add_argument("--amplitude-on", type=float, default=0.65e-6, help="amplitude in a notch [m, 0-peak]")
    p.add_argument("--response-time", type=float, default=1e-3, help="amplitude time constant [s]")
    p.add_argument("--preload", type=float, default=3.0, help="preload Fn [N] (default 3)")
    p.add_argument("--speed", type=float, default=0.02, help="user's speed [m/s] (default 0.02)")
    p.add_argument("--substrate", choices=("steel", "glass"))
    _common(p)
    p.set_defaults(func=_texture)
