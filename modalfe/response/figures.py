"""What a device does per volt (or per unit of another load) at its working mode: the figures behind
`modalfe forced`, with the peak stress and field at resonance against the materials' limits."""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

from modalfe.errors import SceneError, SolverError
from modalfe.results.coupling import k_eff


@dataclass(frozen=True)
class ForcedFigures:
    """Working-mode figures of one device.

    amplitude_per_volt: output -> 0-peak normal amplitude per volt at resonance [m/V];
    volts_for: target name -> drive voltage [V] reaching that amplitude at the reference output;
    amplitude_at: target name -> our largest output amplitude at the seed's voltage, beside the seed's;
    acceleration: output -> (peak omega^2 A, half-period average 2/pi omega^2 A) per volt [m/s^2/V];
    time_constant [s]; frequency [Hz] / frf [m/V] / admittance [S] curves from the reduced model;
    frf_full [m/V]: the full FE harmonic response at the same frequencies, when asked for.
    For a load other than a voltage (``load_unit`` N, Pa or m/s^2) the same figures are per unit load, there is
    no admittance (None) and no voltage target; ``velocity`` output -> peak omega A per unit load [m/s];
    ``absolute_acceleration`` (base acceleration) output -> |-omega^2 u_rel + a_base| per unit base acceleration;
    ``stress``: peaks per part at resonance (``modalfe.response.stress``) and ``limits`` the load reaching each.
    ``error_estimate``: the stated relative error of the mode's frequency (NaN: not estimated) on the discretization
    ``resolution`` describes (the answer ``modes`` gives for the same question). ``antiresonance`` [Hz]: fa of the
    mode's open-circuit partner on the same model (as ``table`` and ``report`` give it); the BVD's fa is the one-mode
    circuit's approximation of it. ``errors``: name -> (stated relative error, "" or why not estimated) of every
    number ``device_numbers`` lists, from the frequency's own estimate levels (``modalfe.solve.api.derived_errors``).
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
    load_description: str = "voltage on the driven electrodes"
    load_source: str = ""
    load_unit: str = "V"
    velocity: dict[str, float] = field(default_factory=dict)
    absolute_acceleration: dict[str, float] = field(default_factory=dict)
    stress: list | None = None
    limits: list | None = None
    error_estimate: float = float("nan")
    resolution: str = ""
    antiresonance: float | None = None
    errors: dict[str, tuple[float, str]] = field(default_factory=dict)
    capacitance_clamped: float | None = None
    mode: object = field(default=None, repr=False)  # the working mode (bound to its model), for fields beyond outputs
    state: np.ndarray | None = field(default=None, repr=False)

    @property
    def capacitances(self) -> dict[str, float]:
        """The three capacitances [F] by their one name each (docs/capacitance.md): ``free`` (static, the structure
        free to deform: C0 + C1 of the BVD), ``clamped`` (every displacement held at 0) and ``C0`` of the BVD (the
        free one less this mode's share C1). Empty for a load other than a voltage."""
        if not self.rom.is_voltage_driven:
            return {}
        bvd = self.rom.bvd
        return {"free": bvd["C0"] + bvd["C1"], "clamped": self.capacitance_clamped, "C0": bvd["C0"]}

    def error(self, name: str) -> float:
        """The stated relative error of the number ``name`` (``device_numbers``' keys), NaN when not estimated."""
        return self.errors.get(name, (float("nan"), ""))[0]

    def to_json(self) -> dict:
        rom = self.rom
        if self.load_unit != "V":
            return self._load_json()
        return {
            "scene": self.scene, "mode": rom.label, "frequency_hz": rom.frequency,
            "damping": rom.damping_description, "damping_source": self.damping_source,
            "reduced_model": {"reference": rom.reference, "modal_mass_kg": rom.modal_mass,
                              "stiffness_n_per_m": rom.stiffness, "damping_n_s_per_m": rom.damping,
                              "force_factor_n_per_v": rom.force_factor},
            "bvd": rom.bvd, "capacitance_free_F": self.capacitances["free"],
            "capacitance_clamped_F": self.capacitances["clamped"], "bvd_antiresonance_hz": rom.antiresonance,
            "antiresonance_hz": self.antiresonance,
            "k_eff": None if self.antiresonance is None else k_eff(rom.frequency, self.antiresonance),
            "bvd_k_eff": rom.k_eff,
            "amplitude_per_volt_m": self.amplitude_per_volt, "volts_for": self.volts_for,
            "amplitude_at": self.amplitude_at, "peak_amplitude_per_volt_m": self.peak_amplitude_per_volt,
            "acceleration_per_volt": {k: {"peak": v[0], "half_period_average": v[1]}
                                      for k, v in self.acceleration.items()},
            "time_constant_s": self.time_constant, "notes": self.notes,
            "curve": {"frequency_hz": self.frequency.tolist(), "abs_frf_m_per_v": np.abs(self.frf).tolist(),
                      "abs_admittance_s": np.abs(self.admittance).tolist(),
                      "abs_frf_full_m_per_v": None if self.frf_full is None else np.abs(self.frf_full).tolist()},
            **self._extra_json(),
        }

    def _extra_json(self) -> dict:
        """What every load reports: the load, outputs per unit load, and the stress section when asked."""
        unit = self.load_unit
        outputs = {o: {f"displacement_m_per_{unit}": a, f"velocity_m_per_s_per_{unit}": self.velocity[o],
                       f"acceleration_m_per_s2_per_{unit}": self.acceleration[o][0]}
                   for o, a in self.amplitude_per_volt.items()}
        for o, a in self.absolute_acceleration.items():
            outputs[o]["absolute_acceleration_per_unit_base_acceleration"] = a
        extra = {"load": self.load_description, "load_source": self.load_source, "load_unit": unit,
                 "outputs_per_load": outputs, "frequency_error_estimate": _finite(self.error_estimate),
                 "resolution": self.resolution,
                 "stated_errors": {name: _finite(e) for name, (e, _) in self.errors.items()},
                 "errors_not_estimated": {name: why for name, (_, why) in self.errors.items() if why}}
        if self.stress is not None:
            extra["stress_at_resonance_per_load"] = [
                {"part": p.part, "material": p.material,
                 "von_mises_pa": p.von_mises.value, "von_mises_at_m": p.von_mises.point,
                 "max_principal_pa": p.principal.value, "max_principal_at_m": p.principal.point,
                 "field_v_per_m": None if p.field is None else p.field.value,
                 "field_at_m": None if p.field is None else p.field.point} for p in self.stress]
            extra["load_to_limit"] = self.limits
        return extra

    def _load_json(self) -> dict:
        """JSON of a force-, pressure- or base-driven device: no circuit, no voltage targets."""
        rom = self.rom
        unit = self.load_unit
        return {
            "scene": self.scene, "mode": rom.label, "frequency_hz": rom.frequency,
            "damping": rom.damping_description, "damping_source": self.damping_source,
            "reduced_model": {"reference": rom.reference, "modal_mass_kg": rom.modal_mass,
                              "stiffness_n_per_m": rom.stiffness, "damping_n_s_per_m": rom.damping,
                              f"force_factor_n_per_{unit}": rom.force_factor},
            "bvd": None, "antiresonance_hz": None, "k_eff": None,
            "peak_amplitude_per_load_m": self.peak_amplitude_per_volt,
            "time_constant_s": self.time_constant, "notes": self.notes,
            "curve": {"frequency_hz": self.frequency.tolist(), f"abs_frf_m_per_{unit}": np.abs(self.frf).tolist(),
                      f"abs_frf_full_m_per_{unit}": None if self.frf_full is None else np.abs(self.frf_full).tolist()},
            **self._extra_json(),
        }


def forced_figures(scene, *, selector: str | None = None, near: float | None = None, damping=None,
                   outputs=None, span: float = 0.02, points: int = 41, full: bool = False, load=None,
                   stress=None, state: bool = False, **resolution) -> ForcedFigures:
    """Reduce the working mode and derive the device figures; ``full`` adds the direct FE FRF. ``load``
    (``modalfe.response.loads.Load``; default: the scene's ``drive.load``) is checked before any solve; ``stress``:
    True (every part) or part names for the peak stress and field at resonance; ``state``: keep the mode and the
    full response at resonance per unit load (for ``modalfe.report.export.export_forced_vtu``). The mode is the one
    ``modes`` gives for the scene's question about it (``modalfe.solve.api.working_question``), solved at
    ``resolution`` (``solve_modes``' tol, fidelity, error_estimate) on the 3-D solid or, for a body of revolution,
    the axisymmetric model (its mode revolved: ``modalfe.models.axisymmetric``), unless the question needs the solid
    (``solid_only``)."""
    from modalfe.response.admittance import clamped_capacitance
    from modalfe.response.forced import Damping, harmonic_response, open_circuit, reduce, resonant_state
    from modalfe.response.loads import Load, check_forcing, check_outputs
    from modalfe.response.losses import mode_damping, resolve_losses
    from modalfe.response.stress import limit_loads, part_peaks
    from modalfe.results.labels import check_selector
    from modalfe.results.modes import select
    from modalfe.solve.api import REVOLVED, derived_errors, solid_modes, sought_near, working_question

    if load is None:
        load, load_source = scene.drive.load, scene.drive.load_source
    else:
        load, load_source = Load.from_value(load, "load"), "set by the user"
    check_forcing(scene, load)  # before the solve: a tile has no electrode to drive
    voltage = load.kind == "voltage"
    parts = None
    if stress is not None and stress is not False:
        known = {p.name for p in scene.assembly().parts}
        parts = sorted(known) if stress is True else list(stress)
        for name in parts:
            if name not in known:
                raise SceneError(f"stress: no part '{name}'; parts: {sorted(known)}")

    if not scene.working_modes and selector is None:
        raise SolverError("forced: the scene names no working mode; give --mode and --near")
    if near is not None:
        from modalfe.scene.values import number

        number("near", near, unit="Hz", positive=True)
    if selector is not None:
        selector = check_selector(selector, "mode")
    question = working_question(scene, selector, near)
    selector, near = question["mode"], sought_near(scene, selector, near)
    if damping is not None and not (isinstance(damping, Damping) or damping == "material"):
        raise SceneError(f"damping: must be a Damping (Damping.parse('Q=150')) or 'material', got {damping!r}")
    losses = None if isinstance(damping, Damping) else resolve_losses(scene, damping=damping)
    outputs = tuple(outputs or scene.drive.outputs)
    if not outputs:
        raise SolverError("forced: no outputs; give --outputs (face groups) or set drive.outputs")
    check_outputs(scene, outputs)
    why = solid_only(scene, load, stress=parts is not None)
    if why and resolution.get("fidelity") == "axisymmetric":
        raise SolverError(f"{why} (fidelity 'axisymmetric' asked)")
    modes = solid_modes(scene, needs="the forced response" + (f" ({why})" if why else ""),
                        takes=() if why else REVOLVED, **question, **resolution)
    mode = select(modes, selector, near)
    damping, source = (damping, "set by the user") if losses is None else mode_damping(mode, losses)
    rom = reduce(mode, outputs=outputs, damping=damping, load=None if voltage else load)
    fa, notes_fa = None, ""
    if voltage:
        try:
            fa = open_circuit(mode, among=modes, near=question.get("near", mode.frequency)).fa
        except SolverError as exc:
            notes_fa = f"open-circuit fa not found ({exc}); the BVD's one-mode fa stands alone"
    amp = {o: float(abs(rom.frf(rom.frequency, o))) for o in rom.shapes}
    omega = rom.omega
    accel = {o: (omega**2 * a, 2 / np.pi * omega**2 * a) for o, a in amp.items()}
    velocity = {o: omega * a for o, a in amp.items()}
    absolute = {}
    if load.kind == "base-acceleration":  # relative motion plus the base's own, along z (the outputs' normal)
        base = 1.0 if load.axis == "z" else 0.0
        absolute = {o: float(abs(-(omega**2) * rom.frf(rom.frequency, o) + base)) for o in rom.shapes}
    volts_for, amplitude_at = {}, {}
    for t in (scene.drive.targets if voltage else ()):
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
                                     damping=damping, reference_omega=omega, load=None if voltage else load)
        frf_full = response.displacement[rom.reference][:, 2]
    notes = [f"damping {rom.damping_description} ({source})"] + ([notes_fa] if notes_fa else [])
    if not voltage and load.kind == "base-acceleration":
        notes.append("displacement, velocity and acceleration are relative to the base; absolute acceleration "
                     "= relative + base")
    for t in (scene.drive.targets if voltage else ()):
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
    notes.append(f"largest normal amplitude on the top face: {1e9 * peak:.3g} nm/{load.unit} (0-peak) at x = "
                 f"{1e3 * where[0]:.1f} mm, y = {1e3 * where[1]:.1f} mm")
    peaks = limits = None
    resonant = resonant_state(mode, damping=damping, load=None if voltage else load) \
        if parts is not None or state else None
    if parts is not None:
        peaks = part_peaks(mode.model, resonant, parts)
        limits = limit_loads(peaks, scene)
        if scene.symmetry:
            notes.append(f"stress: solved on the part of the device kept by symmetry ({', '.join(scene.symmetry)}); "
                         f"each peak has a mirror image")
    clamped = mode.model.copies * clamped_capacitance(mode.model) if voltage else None
    fine = device_numbers(rom, fa, peaks, clamped)

    def level_fa(m) -> float | None:  # fa of a mode's partner on its level, sought as the answer's is (at the shift
        try:  # the level was solved at: its factorization reused)
            return open_circuit(m, among=modes.estimate.level_holding(m), near=question.get("near", m.frequency)).fa
        except SolverError:
            return None

    def level_numbers(m) -> dict[str, float]:  # the same numbers from a mode's partner on an estimate level
        r = reduce(m, outputs=outputs, damping=damping, reference=rom.reference, load=None if voltage else load)
        at_level = None if not voltage else level_fa(m)
        level_peaks = None if parts is None else part_peaks(
            m.model, resonant_state(m, damping=damping, load=None if voltage else load), parts)
        at_level_clamped = None if not voltage else m.model.copies * clamped_capacitance(m.model)
        return device_numbers(r, at_level, level_peaks, at_level_clamped)

    errors = with_composed_errors(derived_errors(modes, mode, level_numbers, fine, eigenvalues=("fa",)),
                                  mode.error_estimate, voltage)
    if peaks is not None:
        notes += singular_peak_notes(scene, mode.model, peaks)
    return ForcedFigures(scene.name, rom, source, amp, volts_for, accel,
                         rom.envelope_time_constant, f, rom.frf(f), rom.admittance(f) if voltage else None, frf_full,
                         notes, amplitude_at, peak, load.describe() if not voltage else
                         "voltage on the driven electrodes", load_source, load.unit, velocity, absolute, peaks, limits,
                         mode.error_estimate, modes.resolution, fa, errors, clamped, mode,
                         resonant if state else None)


def solid_only(scene, load, *, stress: bool) -> str | None:
    """What of a forced response asked of a body of revolution needs the 3-D solid rather than the axisymmetric
    model (None: nothing, the axisymmetric answer serves): the peak stress (``stress``), a load the model cannot
    project on its harmonics (``modalfe.models.axisymmetric.load_refusal``)."""
    from modalfe.models.axisymmetric import load_refusal, round_parts

    if not round_parts(scene):
        return None
    if stress:
        return "--stress: the peak stress is computed on the 3-D solid"
    return load_refusal(scene, load)


def device_numbers(rom, fa: float | None, peaks=None, clamped: float | None = None) -> dict[str, float]:
    """The numbers ``forced`` estimates on the levels, of a reduced model ``rom`` (``modalfe.response.forced.reduce``),
    by name: the reduced model's mass and force factor, the amplitude per unit load at each output, and for a voltage
    drive C0 of the BVD, the free capacitance (C0 + C1) and the ``clamped`` one, the one-mode circuit's fa and k_eff
    and the open circuit's ``fa`` and k_eff; with ``peaks``
    (``modalfe.response.stress.part_peaks``) each part's peak von Mises and principal stress and field. The numbers
    made of these and the frequency (stiffness, damping, R1, L1, C1) get their errors composed
    (``with_composed_errors``)."""
    numbers = {"modal_mass": rom.modal_mass, "force_factor": abs(rom.force_factor),
               **{f"amplitude:{o}": rom.amplitude_per_volt(o) for o in rom.shapes}}
    if rom.is_voltage_driven:
        numbers.update({"bvd:C0": rom.capacitance, "capacitance:free": rom.capacitance + rom.bvd["C1"]},
                       bvd_fa=rom.antiresonance, bvd_k_eff=rom.k_eff)
        if clamped is not None:
            numbers["capacitance:clamped"] = clamped
        if fa is not None:
            numbers.update(fa=fa, k_eff=k_eff(rom.frequency, fa))
    for p in peaks or ():
        numbers[f"von_mises:{p.part}"] = p.von_mises.value
        numbers[f"principal:{p.part}"] = p.principal.value
        if p.field is not None:
            numbers[f"field:{p.part}"] = p.field.value
    return numbers


def with_composed_errors(errors: dict[str, tuple[float, str]], frequency_error: float,
                         voltage: bool) -> dict[str, tuple[float, str]]:
    """``errors`` (``device_numbers``' names) with those of the numbers made of them and the frequency (error
    ``frequency_error``): stiffness k = m omega^2, damping c = 2 zeta omega m, the time constant 1 / (zeta omega),
    each output's velocity omega A and acceleration omega^2 A, and for a voltage drive the BVD's R1 = c / N^2,
    L1 = m / N^2, C1 = N^2 / k: a product's relative error is at most the sum of its factors' times their powers
    (first order; zeta is given, not computed)."""
    def composed(*terms: tuple[str | None, float]) -> tuple[float, str]:
        parts = [(frequency_error, "") if name is None else errors[name] for name, _ in terms]
        reasons = "; ".join(dict.fromkeys(why for _, why in parts if why))
        return sum(abs(power) * e for (_, power), (e, _) in zip(terms, parts)), reasons

    out = dict(errors)
    out["stiffness"] = composed(("modal_mass", 1), (None, 2))
    out["damping"] = composed(("modal_mass", 1), (None, 1))
    out["time_constant"] = composed((None, 1))
    for name in [n for n in errors if n.startswith("amplitude:")]:
        output = name.split(":", 1)[1]
        out[f"velocity:{output}"] = composed((name, 1), (None, 1))
        out[f"acceleration:{output}"] = composed((name, 1), (None, 2))
    if voltage:
        out["bvd:R1"] = composed(("modal_mass", 1), (None, 1), ("force_factor", 2))
        out["bvd:L1"] = composed(("modal_mass", 1), ("force_factor", 2))
        out["bvd:C1"] = composed(("force_factor", 2), ("modal_mass", 1), (None, 2))
    return out


def singular_peak_notes(scene, model, peaks) -> list[str]:
    """Notes on the peaks (``part_peaks``) that sit within an element of an edge of their part's box where
    ``scene``'s field is singular (``modalfe.solve.estimates.singular_field``: bonded parts, clamps, springs): there
    the stress (and field) grows without bound as the mesh refines, and a stated error does not bound it."""
    from modalfe.geometry.parts import Box
    from modalfe.solve.estimates import singular_field

    why = singular_field(scene)
    if not why:
        return []
    parts = {p.name: p for p in scene.full_assembly().parts}
    mesh = model.mesh.mesh
    at_edges = []
    for peak in peaks:
        part = parts.get(peak.part)
        if not isinstance(part, Box):
            continue  # a curved or imported part: its edges are not its box's
        cells = mesh.t[:, model.mesh.parts[peak.part]]
        h = np.median(mesh.p[:, cells].max(axis=1) - mesh.p[:, cells].min(axis=1), axis=1)  # element extents
        found = [name for name, at in (("von Mises", peak.von_mises), ("principal", peak.principal),
                                       ("field", peak.field)) if at is not None and _near_edge(at.point, part, h)]
        if found:
            at_edges.append(f"{peak.part} ({', '.join(found)})")
    if not at_edges:
        return []
    return [f"peaks at an edge of their part, where {why} make the field singular: {'; '.join(at_edges)}; they grow "
            f"as the mesh refines, and their stated errors do not bound them"]


def _near_edge(point, part, h: np.ndarray) -> bool:
    """Whether ``point`` lies within an element (extents ``h`` per axis) of two of the box ``part``'s faces that meet
    at an edge (two axes)."""
    x = np.asarray(point)
    close = [min(abs(x[a] - part.lo[a]), abs(x[a] - part.hi[a])) <= h[a] for a in range(3)]
    return sum(close) >= 2


def _finite(x: float) -> float | None:
    return float(x) if np.isfinite(x) else None


PEAK_GRID = (50, 200)  # the face's peak: a grid of its size / 50, then / 200 around the strongest maxima
PEAK_CANDIDATES = 4


def _grid_peak(mode, main) -> tuple[float, tuple[float, float]]:
    """(max |w|, where) on the top face of a box main part: the coarse grid's ``PEAK_CANDIDATES`` strongest local
    maxima, each searched again on the fine grid over two coarse spacings around it (the fine grid over the whole
    face read 16x the points: 24,000 on the Cu-Be plate, 0.9 s)."""
    from scipy.ndimage import maximum_filter

    from modalfe.response.placement import face_field

    size = max(main.size[:2])
    xs, ys, W = face_field(mode, part=main.name, side="zmax", spacing=size / PEAK_GRID[0])
    A = np.abs(W)
    rows, cols = np.nonzero(maximum_filter(A, size=3, mode="nearest") == A)
    strongest = np.argsort(-A[rows, cols], kind="stable")[:PEAK_CANDIDATES]
    best = (-1.0, (0.0, 0.0))
    reach = 2 * size / PEAK_GRID[0]
    for i, j in zip(rows[strongest], cols[strongest]):
        window = ((xs[j] - reach, ys[i] - reach), (xs[j] + reach, ys[i] + reach))
        fx, fy, F = face_field(mode, part=main.name, side="zmax", spacing=size / PEAK_GRID[1], window=window)
        k, m = np.unravel_index(np.argmax(np.abs(F)), F.shape)
        if abs(F[k, m]) > best[0]:
            best = (float(abs(F[k, m])), (float(fx[m]), float(fy[k])))
    return best


def _face_peak(mode, rom) -> tuple[float, tuple[float, float]]:
    """Largest 0-peak normal amplitude per volt [m/V] on the top face of the main part, and where:
    modal amplitude at resonance |q| = |theta| / (2 zeta omega^2) times the mass-normalised shape. A main part
    that is not a box (a shape, a geometry file's piece) is read at its mesh vertices on the top plane of its
    bounding box (all its vertices when none lies there)."""

    main = mode.scene.full_assembly().main_part
    theta = abs(rom.force_factor) / np.sqrt(rom.modal_mass)
    q = theta / (2 * rom.zeta * rom.omega**2)
    if "zmax" in main.sides:
        w, at = _grid_peak(mode, main)
        return float(q * w), at
    points, u = mode.model.vertex_field(mode.shape, main.name)
    top = np.abs(points[2] - main.hi[2]) <= 1e-9 * max(main.size)
    if top.any():
        points, u = points[:, top], u[:, top]
    k = int(np.argmax(np.abs(u[2])))
    return float(q * abs(u[2, k])), (float(points[0, k]), float(points[1, k]))
