"""What a device does per volt at its working mode: the figures behind `modalfe forced`."""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

from modalfe.errors import SceneError, SolverError


@dataclass(frozen=True)
class ForcedFigures:
    """Working-mode figures of one device.

    amplitude_per_volt: output -> 0-peak normal amplitude per volt at resonance [m/V];
    volts_for: target name -> drive voltage [V] reaching that amplitude at the reference output;
    amplitude_at: target name -> our largest output amplitude at the seed's voltage, beside the seed's;
    acceleration: output -> (peak omega^2 A, half-period average 2/pi omega^2 A) per volt [m/s^2/V];
    time_constant [s]; frequency [Hz] / frf [m/V] / admittance [S] curves from the reduced model;
    frf_full [m/V]: the full FE harmonic response at the same frequencies, when asked for.
    """

    scene: str
    rom: object
    damping_source: str
    amplitude_per_volt: dict[str, float]
    volts_for: dict[str, float]
    acceleration: dict[str, tuple[float, float]]
    time_constant: float
    frequency: np.ndarray
    frf: np.ndarray
    admittance: np.ndarray
    frf_full: np.ndarray | None = None
    notes: list[str] = field(default_factory=list)
    amplitude_at: dict[str, dict] = field(default_factory=dict)
    peak_amplitude_per_volt: float = float("nan")

    def to_json(self) -> dict:
        rom = self.rom
        return {
            "scene": self.scene, "mode": rom.label, "frequency_hz": rom.frequency,
            "damping": rom.damping_description, "damping_source": self.damping_source,
            "reduced_model": {"reference": rom.reference, "modal_mass_kg": rom.modal_mass,
                              "stiffness_n_per_m": rom.stiffness, "damping_n_s_per_m": rom.damping,
                              "force_factor_n_per_v": rom.force_factor},
            "bvd": rom.bvd, "antiresonance_hz": rom.antiresonance, "k_eff": rom.k_eff,
            "amplitude_per_volt_m": self.amplitude_per_volt, "volts_for": self.volts_for,
            "amplitude_at": self.amplitude_at, "peak_amplitude_per_volt_m": self.peak_amplitude_per_volt,
            "acceleration_per_volt": {k: {"peak": v[0], "half_period_average": v[1]}
                                      for k, v in self.acceleration.items()},
            "time_constant_s": self.time_constant, "notes": self.notes,
            "curve": {"frequency_hz": self.frequency.tolist(), "abs_frf_m_per_v": np.abs(self.frf).tolist(),
                      "abs_admittance_s": np.abs(self.admittance).tolist(),
                      "abs_frf_full_m_per_v": None if self.frf_full is None else np.abs(self.frf_full).tolist()},
        }


def forced_figures(scene, *, selector: str | None = None, near: float | None = None, damping=None,
                   outputs=None, span: float = 0.02, points: int = 41, full: bool = False) -> ForcedFigures:
    """Reduce the working mode and derive the device figures; ``full`` adds the direct FE FRF."""
    from modalfe.response.forced import Damping, harmonic_response, reduce
    from modalfe.results.modes import select
    from modalfe.solve.api import solve_modes

    if not scene.working_modes and selector is None:
        raise SolverError("forced: the scene names no working mode; give --mode and --near")
    wm = scene.working_modes[0] if scene.working_modes else None
    if near is not None:
        from modalfe.scene.values import number

        number("near", near, unit="Hz", positive=True)
    if selector is not None and (not isinstance(selector, str) or not selector.strip()):
        raise SceneError(f"mode: must be a label such as '(0,6)' or 'bending-z 6', got {selector!r}")
    selector = selector or wm.selector
    near = near or wm.near
    if damping is not None:
        if not isinstance(damping, Damping):
            raise SceneError(f"damping: must be a Damping (Damping.parse('Q=150')), got {damping!r}")
        source = "set by the user"
    else:
        damping, source = Damping.parse(scene.drive.damping), scene.drive.damping_source
    outputs = tuple(outputs or scene.drive.outputs)
    if not outputs:
        raise SolverError("forced: no outputs; give --outputs (face groups) or set drive.outputs")
    modes = solve_modes(scene, near=near, count=10, error_estimate=False)
    mode = select(modes, selector, near)
    rom = reduce(mode, outputs=outputs, damping=damping)
    amp = {o: float(abs(rom.frf(rom.frequency, o))) for o in rom.shapes}
    omega = rom.omega
    accel = {o: (omega**2 * a, 2 / np.pi * omega**2 * a) for o, a in amp.items()}
    volts_for, amplitude_at = {}, {}
    for t in scene.drive.targets:
        if t.unit != "m":
            continue
        at_khz = re.search(r"_(\d+)kHz$", t.name)
        if at_khz and abs(1e3 * float(at_khz.group(1)) / rom.frequency - 1) > 0.2:
            continue  # a target of another working mode
        at_volts = re.search(r"_(\d+(?:\.\d+)?)V$", t.name)
        if at_volts:  # a seed's amplitude at a stated voltage: compare ours at that voltage
            volts = float(at_volts.group(1))
            ours = volts * max(amp.values())
            amplitude_at[t.name] = {"volts": volts, "ours_m": ours, "seed_m": t.value, "deviation": ours / t.value - 1}
        else:  # an amplitude the device must reach: the voltage it takes (peak-to-peak halved)
            amplitude = t.value / 2 if "pp" in t.name else t.value
            volts_for[t.name] = amplitude / amp[rom.reference]
    f = rom.frequency * np.linspace(1 - span, 1 + span, points)
    frf_full = None
    if full:
        response = harmonic_response(mode.model, f, outputs=[o for o in outputs if o == rom.reference or
                                     (not isinstance(o, str) and o[0] == rom.reference)],
                                     damping=damping, reference_omega=omega)
        frf_full = response.displacement[rom.reference][:, 2]
    notes = [f"damping {rom.damping_description} ({source})"]
    for t in scene.drive.targets:
        at = re.search(r"_(\d+)kHz$", t.name)
        if at and abs(1e3 * float(at.group(1)) / rom.frequency - 1) > 0.2:
            continue  # a target of another working mode
        if t.unit == "s":
            tau = rom.envelope_time_constant
            notes.append(f"amplitude time constant {1e3 * tau:.3g} ms vs {t.name} {1e3 * t.value:.3g} ms "
                         f"({100 * (tau / t.value - 1):+.0f}%; {t.source}); Q = pi f tau would be "
                         f"{np.pi * rom.frequency * t.value:.0f} for the seed's time")
        elif t.unit == "m/s^2":
            average = max(a[1] for a in accel.values()) * 100.0
            notes.append(f"half-period average acceleration at 100 V {average:.4g} m/s^2 vs {t.name} {t.value:.6g} "
                         f"({100 * (average / t.value - 1):+.0f}%; {t.source})")
    peak, where = _face_peak(mode, rom)
    notes.append(f"largest normal amplitude on the top face: {1e9 * peak:.3g} nm/V (0-peak) at x = "
                 f"{1e3 * where[0]:.1f} mm, y = {1e3 * where[1]:.1f} mm")
    return ForcedFigures(scene.name, rom, source, amp, volts_for, accel,
                         rom.envelope_time_constant, f, rom.frf(f), rom.admittance(f), frf_full, notes, amplitude_at,
                         peak)


def _face_peak(mode, rom) -> tuple[float, tuple[float, float]]:
    """Largest 0-peak normal amplitude per volt [m/V] on the top face of the main part, and where:
    modal amplitude at resonance |q| = |theta| / (2 zeta omega^2) times the mass-normalised shape."""
    from modalfe.response.placement import face_field

    main = mode.scene.full_assembly().main_part
    xs, ys, W = face_field(mode, part=main.name, side="zmax", spacing=max(main.size[:2]) / 200)
    i, j = np.unravel_index(np.argmax(np.abs(W)), W.shape)
    theta = abs(rom.force_factor) / np.sqrt(rom.modal_mass)
    q = theta / (2 * rom.zeta * rom.omega**2)
    return float(q * abs(W[i, j])), (float(xs[j]), float(ys[i]))
