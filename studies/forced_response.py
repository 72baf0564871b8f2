"""Device figures per volt at the working modes (issue 4): amplitudes, voltages, accelerations,
response times, foot placement and frequency-tuning amplitude control.

    python studies/forced_response.py [--quick]

Every figure is printed beside the seed's, with the difference. Damping is stated with its source.
"""

from __future__ import annotations

import argparse
import math

from modalfe.response.control import quasi_linear_region, track_amplitude
from modalfe.response.figures import forced_figures
from modalfe.response.placement import place_feet
from modalfe.scene import load_scene

KN = 9.7e6  # N/m, foot contact stiffness, seed 000 appendix


def _scene(name: str, quick: bool, **overrides):
    if quick:
        overrides["mesh.elements_per_wavelength"] = 4.0
    return load_scene(name, **overrides)


def rise_time(tau: float) -> float:
    """10-90 % rise time of a first-order envelope with time constant tau [s]."""
    return tau * math.log(9)


def cube_plate(quick: bool) -> None:
    fig = forced_figures(_scene("cube_plate", quick))
    rom = fig.rom
    print(f"Cu-Be plate, mode {rom.label} at {rom.frequency:.0f} Hz, {rom.damping_description} ({fig.damping_source})")
    print(f"  foot amplitude {1e9 * fig.amplitude_per_volt['foot_1']:.1f} nm/V (0-peak)")
    for name, volts in fig.volts_for.items():
        print(f"  {name}: {volts:.1f} V   (seed: 'some ten volts' for the device)")
    print(f"  envelope time constant {1e3 * fig.time_constant:.2f} ms, "
          f"10-90 % rise {1e3 * rise_time(fig.time_constant):.2f} ms"
          f"  (seed 001: ~1 ms; Q that would give tau = 1 ms: {math.pi * rom.frequency * 1e-3:.0f})")
    print(f"  BVD {rom.bvd}, k_eff {rom.k_eff:.3f}")
    volts = 2.0e-6 / fig.amplitude_per_volt["foot_1"]
    region = quasi_linear_region(rom, volts)
    print(f"  frequency tuning at {volts:.1f} V: quasi-linear {region.f_low:.0f}-{region.f_high:.0f} Hz, "
          f"{1e6 * region.amplitude_low:.2f}-{1e6 * region.amplitude_high:.2f} um, "
          f"slope {1e9 * region.slope:.2f} nm/Hz")
    span = region.amplitude_high - region.amplitude_low
    start, target = region.amplitude_low + 0.3 * span, region.amplitude_low + 0.6 * span
    run = track_amplitude(rom, volts, start=start, target=target)
    print(f"  PI frequency controller, step {1e6 * start:.2f} -> {1e6 * target:.2f} um: within 5 % after "
          f"{1e3 * run.response_time:.2f} ms, drive settles at {run.frequency[-1]:.0f} Hz")
    placement = place_feet(_scene("cube_plate", quick), selector="(0,6)", near=40.7e3, contact_stiffness=KN)
    print(f"  feet on antinodes at x = {sorted({round(1e3 * x, 2) for x, _ in placement.feet})} mm "
          f"(moved by <= {1e3 * max(placement.moved_by):.2f} mm); frequency {placement.frequency_without_feet:.0f} Hz "
          f"without feet, {placement.shift_from_feet:+.0f} Hz from the feet, {placement.shift_from_contact:+.0f} Hz "
          f"from kn = {KN:.3g} N/m each")


def ciliary_beam(quick: bool) -> None:
    for material in ("PZT-5A", "piezo-seed003-e31"):
        fig = forced_figures(_scene("ciliary_beam", quick, sheet_material=material))
        rom = fig.rom
        print(f"ciliary beam, sheets {material}: mode {rom.label} at {rom.frequency:.0f} Hz, {rom.damping_description}")
        for name, a in fig.amplitude_at.items():
            print(f"  {name}: {1e6 * a['ours_m']:.3f} um vs seed {1e6 * a['seed_m']:.2f} um "
                  f"({100 * a['deviation']:+.0f}%)")
        peak, average = fig.acceleration["tip"]
        print(f"  tip acceleration at 100 V: peak {100 * peak:.0f} m/s^2, "
              f"half-period average {100 * average:.0f} m/s^2 "
              f"(seed: 69,324; its own 1.44 um at 24.2 kHz gives omega^2 A = "
              f"{(2 * math.pi * 24221) ** 2 * 1.44e-6:.0f} and 2/pi of that = "
              f"{2 / math.pi * (2 * math.pi * 24221) ** 2 * 1.44e-6:.0f})")


def beam_acceleration_profile(quick: bool, volts: float = 100.0) -> None:
    """Half-period average acceleration (2 / pi) omega^2 |w| along the beam's top centre line."""
    import numpy as np

    from modalfe.solve.api import solve_modes

    scene = _scene("ciliary_beam", quick)
    fig = forced_figures(scene)
    rom = fig.rom
    modes = solve_modes(scene, near=rom.frequency, count=4, error_estimate=False)
    mode = modes.labelled(rom.label, near=rom.frequency)
    x = np.linspace(0.0, 0.1, 201)
    points = np.vstack([x, np.full_like(x, 2.5e-3), np.full_like(x, 5e-3)])
    w = (modes.model.displacement_probes(points.T) @ mode.shape)[2 * len(x):]
    q = abs(rom.force_factor) / np.sqrt(rom.modal_mass) / (2 * rom.zeta * rom.omega**2)
    average = 2 / math.pi * rom.omega**2 * q * volts * np.abs(w)
    peaks = [x[i] for i in range(1, len(x) - 1) if average[i] >= average[i - 1] and average[i] > average[i + 1]]
    print(f"  half-period average acceleration along the beam at {volts:g} V: max {average.max():.0f} m/s^2 at "
          f"x = {1e3 * x[np.argmax(average)]:.1f} mm; antinodes at x = {[round(1e3 * float(p), 1) for p in peaks]} mm "
          "(seed 003 Table 3 measured: 13.25, 29.25, 47.25, 74.70, 90.75 mm)")


def glass_plate(quick: bool) -> None:
    scene = _scene("glass_plate", quick)
    for wm, tau_name in zip(scene.working_modes, ("response_time_66kHz", "response_time_225kHz")):
        fig = forced_figures(scene, selector=wm.selector, near=wm.near)
        rom = fig.rom
        seed_tau = next(t.value for t in scene.drive.targets if t.name == tau_name)
        print(f"glass plate, mode {rom.label} at {rom.frequency:.0f} Hz, {rom.damping_description} "
              f"({fig.damping_source})")
        for o, a in fig.amplitude_per_volt.items():
            print(f"  {o}: {1e9 * a:.2f} nm/V 0-peak")
        print(f"  {fig.notes[-1]}")
        print(f"  envelope time constant {1e3 * fig.time_constant:.3f} ms (seed {1e3 * seed_tau:.1f} ms; Q for it: "
              f"{math.pi * rom.frequency * seed_tau:.0f})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="coarse meshes")
    args = parser.parse_args()
    cube_plate(args.quick)
    ciliary_beam(args.quick)
    beam_acceleration_profile(args.quick)
    glass_plate(args.quick)


if __name__ == "__main__":
    main()
