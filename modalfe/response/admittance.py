"""Broadband electrical admittance Y(f) and impedance Z(f) of a scene's driven electrodes, by modal
superposition with the residual of the modes left out, or by direct harmonic FE.

Charge per volt on the driven electrodes (short-circuit free unknowns x, ``modalfe.response.forced.drive_vectors``):

    (A - omega^2 B + losses) x = F,   Q / V = C_b + F . x,   Y = i omega Q / V,   Z = 1 / Y

Modal superposition over the mass-normalised short-circuit modes r of a widened band (theta_r = phi_r . f,
the modal force per volt) with the residual of every mode left out taken at a shift sigma (the mode-
acceleration method; Craig & Kurdila, Fundamentals of Structural Dynamics, 2nd ed. 2006, ch. 14 for sigma = 0;
Preumont, Mechatronics, 2006, ch. 4 for the piezoelectric admittance):

    Q / V = C_b + F . x_left + (omega^2 - sigma) x_left . B x_left + (omega^2 - sigma)^2 z . B x_left
            + sum_r theta_r^2 / d_r(omega),   d_r = omega_r^2 - omega^2 + i (2 zeta_r omega_r omega + eta_r omega_r^2)
    x_left = (A - sigma B)^-1 (F - sum_r B phi_r theta_r),   z = (A - sigma B)^-1 B x_left

the residual of the modes left out, their terms taken out of the load before the solve (a kept mode beside sigma
amplifies nothing), as its Taylor series in omega^2 about sigma (d/ds (A - s B)^-1 = (A - s B)^-1 B (A - s B)^-1):
error theta^2 t^3 / (omega_r^2 - omega^2), t = (omega^2 - sigma) / (omega_r^2 - sigma), for a mode left out.

``residual="static"``: sigma = 0 (needs a supported body); ``"centre"`` (default): sigma in the band, the kept eigen
solve's shift where it lies there (two direct solves), else the band's centre (``shifted_solve``): an error smaller
than the static one for every mode above the band and bounded for those below it (a free body's rigid modes).

Losses: mechanical viscous (modal zeta, Q = 1 / 2 zeta, Rayleigh alpha + beta omega_r^2 = 2 zeta_r omega_r) or
hysteretic (loss factor eta, and per material eta_r = sum_m U_m,r / U_r / Qm_m, the modal strain-energy method,
Johnson & Kienholz, AIAA J. 20 (1982) 1284); dielectric: eps^S (1 - i tan delta), so the clamped capacitance
(u = 0) becomes C_S (1 - i tan delta) (exact: it is linear in eps^S). A half or quarter model's charge is
doubled per mirror plane (its modes are the symmetric ones).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import scipy.sparse as sp

from modalfe.errors import SceneError, SolverError
from modalfe.response.losses import (
    Losses,
    fallback_eta,
    loss_spec,
    material_stiffness,
    modal_losses,
    qm_table,
    resolve_losses,
)
from modalfe.results.coupling import k_eff
from modalfe.results.modes import Modes
from modalfe.scene.checks import check_ground
from modalfe.scene.scene import Analysis

WIDEN = 1.25  # modes solved in [f1 / WIDEN, f2 * WIDEN]: the nearest ones outside the band stay dynamic
RIGID_HZ = 1e-3  # modes below this fraction of the band's top are rigid-body modes (no charge): left out
Z0 = 50.0  # Touchstone reference impedance [ohm]
# most frequencies of one curve: 100,000 points resolve a Q = 10^4 peak over a 100x band (its width / 10), and cost
# 100,000 x modes complex numbers; more is a typo in --points (a direct FE solve per point would run for days)
MAX_POINTS = 100_000
CSV_HEADER = "frequency_Hz,Y_real_S,Y_imag_S,abs_Z_ohm,phase_Z_deg"


UNDRIVEN = 1e-6  # a mode whose theta is below this fraction of the strongest's is not driven: no error stated on it
# the band's modes and the resolved answer's, eigenpairs of one model from two Lanczos runs, are the same mode where
# their frequencies agree to this (ARPACK's residual tol 1e-8: eigenvalues to about its square, measured ~1e-10)
SAME_EIGENVALUE = 1e-8
# a resonance gets its BVD circuit where k_eff^2 = C1 / (C0 + C1) exceeds this: a weaker one changes |Y| by less than
# 0.1 % near fr, invisible on the plot and not a working resonance of a transducer
BVD_MIN_COUPLING = 1e-3
REFINE_SAMPLES = 2001  # fewest samples of the model's |Y| in the window of a mode, before Brent


def _grid_extrema(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(indices of the local maxima, of the local minima) of ``a`` inside its ends."""
    inner = np.arange(1, len(a) - 1)
    peaks = inner[(a[inner] > a[inner - 1]) & (a[inner] >= a[inner + 1])]
    dips = inner[(a[inner] < a[inner - 1]) & (a[inner] <= a[inner + 1])]
    return peaks, dips


@dataclass(frozen=True)
class Admittance:
    """Admittance of the driven electrodes (whole device): frequency [Hz], Y [S] complex; method; losses (each with its
    source); capacitance_clamped C_S [F] (the clamped capacitance, u = 0, lossless); modes: per mode used, label,
    frequency_hz, error_estimate (relative, None: not estimated), theta (modal force per volt [N/(V kg^0.5)]) and
    its loss, and where the answer states errors (``with_stated_errors``) the |Y| maximum nearest the mode
    (``peak_hz``, ``peak_S``) and the minimum above it (``dip_hz``) with their stated errors (``*_error``, as
    ``theta_error``); ``capacitance_error``: C_S's stated error; notes; ``open_circuit``: per resonance of the band
    (those with a BVD circuit, ``bvd_circuits``), label, fr_hz and the FE open circuit's fa_hz and k_eff
    (``modalfe.response.forced.open_circuit``: as ``table``, ``forced`` and the API give them; not the BVD's fa)."""

    scene: str
    frequency: np.ndarray
    Y: np.ndarray
    method: str
    losses: tuple[str, ...]
    capacitance_clamped: float
    dofs: int
    modes: tuple[dict, ...] = ()
    notes: tuple[str, ...] = ()
    model_Y: Callable[[np.ndarray], np.ndarray] | None = field(default=None, repr=False, compare=False)
    capacitance_error: float = float("nan")
    copies: int = 1
    open_circuit: tuple[dict, ...] = ()

    @property
    def Z(self) -> np.ndarray:  # noqa: N802 (the impedance's own symbol)
        """Impedance 1 / Y [ohm] (complex)."""
        return 1.0 / self.Y

    def s11(self, z0: float = Z0) -> np.ndarray:
        """Reflection coefficient S11 = (Z - z0) / (Z + z0) against ``z0`` [ohm]."""
        return (self.Z - z0) / (self.Z + z0)

    def extrema(self) -> dict[str, list[float]]:
        """Local maxima (near fr) and minima (near fa) of |Y| [Hz] inside the band: on the frequency grid, or where
        the model can be evaluated anywhere (``model_Y``, modal superposition) on the model itself, sampled around
        each mode in the band finer than its resonance and refined (Brent), so that a coarse grid does not move them
        (issue 35: fr read as 500 Hz for a 545 Hz mode)."""
        f = self.frequency
        if self.model_Y is None:
            peaks, dips = _grid_extrema(np.abs(self.Y))
            return {"max_abs_Y_hz": f[peaks].tolist(), "min_abs_Y_hz": f[dips].tolist()}
        found = {-1.0: [], 1.0: []}
        for x in self._windows():
            peaks, dips = _grid_extrema(np.abs(self.model_Y(x)))
            for sign, indices in ((-1.0, peaks), (1.0, dips)):
                for j in indices:
                    v = self._refine(x, j, sign)
                    if not any(abs(v - u) <= 1e-7 * v for u in found[sign]):  # met again where windows overlap
                        found[sign].append(v)
        return {"max_abs_Y_hz": sorted(found[-1.0]), "min_abs_Y_hz": sorted(found[1.0])}

    def _windows(self) -> list[np.ndarray]:
        """Frequencies at which to look for the extrema: the grid when no mode lies in the band, else one window
        per mode from midway to its neighbours (or the band's ends), overlapping by a fifth of their spacing, with
        16 samples per resonance width (``width_hz``), at least REFINE_SAMPLES and at most MAX_POINTS."""
        f = self.frequency
        inside = sorted((m["frequency_hz"], m["width_hz"]) for m in self.modes if f[0] < m["frequency_hz"] < f[-1])
        if not inside:
            return [f]
        centres = [c for c, _ in inside]
        edges = [f[0], *(0.5 * (a + b) for a, b in itertools.pairwise(centres)), f[-1]]
        out = []
        for k, (_, width) in enumerate(inside):
            lo = max(f[0], edges[k] - 0.2 * (edges[k + 1] - edges[k]))
            hi = min(f[-1], edges[k + 1] + 0.2 * (edges[k + 1] - edges[k]))
            n = MAX_POINTS if not width > 0 else int(np.clip(16 * (hi - lo) / width, REFINE_SAMPLES, MAX_POINTS))
            out.append(np.linspace(lo, hi, n))
        return out

    def _refine(self, x: np.ndarray, j: int, sign: float) -> float:
        """The extremum of |Y| between the samples beside ``x[j]``: a minimum (``sign`` 1) or maximum (-1)."""
        from scipy.optimize import minimize_scalar

        found = minimize_scalar(lambda v: sign * float(np.abs(self.model_Y(v))[0]), bounds=(x[j - 1], x[j + 1]),
                                method="bounded", options={"xatol": 1e-10 * x[j]})
        return float(found.x) if found.fun <= sign * float(np.abs(self.model_Y(x[j]))[0]) else float(x[j])

    def bvd_circuits(self) -> list[dict]:
        """The Butterworth-Van Dyke circuit of each resonance in the band (IEEE Std 176-1987, fig. 3): its motional
        branch is the mode's own term of the modal sum, copies theta^2 / (omega_r^2 - omega^2 + i omega 2 pi width):
        L1 = 1 / (copies theta^2) [H], C1 = copies theta^2 / omega_r^2 [F], R1 = 2 pi width L1 [ohm] (width: the
        half-power width at the mode, ``width_hz``); its shunt, "C0 at fr" [F] (``C0_at_fr_F``: not the forced
        response's C0 of the BVD, the free capacitance less C1), is the rest of the admittance at fr, Im(Y - Y_branch) /
        omega_r (the clamped capacitance and every other mode's share); fa_hz = fr sqrt(1 + C1 / C0), k_eff from fr
        and fa. Stated errors composed to first order from theta's and fr's (L1: 2 theta, C1: 2 theta + 2 fr; none
        for R1 and C0's share of the other modes: the loss is a stated input). Only resonances with k_eff^2 above
        ``BVD_MIN_COUPLING``; none without the modal terms (direct FE)."""
        if self.model_Y is None:
            return []
        out = []
        for row in self.modes:
            fr, theta = row["frequency_hz"], row["theta_N_per_V_sqrtkg"]
            if not (self.frequency[0] <= fr <= self.frequency[-1]) or theta == 0:
                continue
            w = 2 * np.pi * fr
            L1, C1 = 1.0 / (self.copies * theta**2), self.copies * theta**2 / w**2
            R1 = 2 * np.pi * row["width_hz"] * L1
            branch = bvd_admittance({"C0_at_fr_F": 0.0, "R1_ohm": R1, "L1_H": L1, "C1_F": C1}, fr)[0]
            C0 = float((self.model_Y(fr)[0] - branch).imag / w)
            if not C0 > 0 or C1 / (C0 + C1) < BVD_MIN_COUPLING:
                continue
            fa = fr * math.sqrt(1 + C1 / C0)
            err_f, err_t = row["error_estimate"], row.get("theta_error")
            out.append({"label": row["label"], "fr_hz": fr, "fa_hz": fa, "k_eff": k_eff(fr, fa), "C0_at_fr_F": C0,
                        "R1_ohm": R1, "L1_H": L1, "C1_F": C1, "fr_error": err_f,
                        "L1_error": None if err_t is None else 2 * err_t,
                        "C1_error": None if err_t is None or err_f is None else 2 * err_t + 2 * err_f})
        return out

    def to_json(self) -> dict:
        Z = self.Z
        return {
            "scene": self.scene, "method": self.method, "losses": list(self.losses), "dofs": self.dofs,
            "capacitance_clamped_F": self.capacitance_clamped, "modes": list(self.modes), "notes": list(self.notes),
            **self.extrema(), "bvd": self.bvd_circuits(), "open_circuit": list(self.open_circuit),
            "frequency_Hz": self.frequency.tolist(), "Y_real_S": self.Y.real.tolist(), "Y_imag_S": self.Y.imag.tolist(),
            "abs_Z_ohm": np.abs(Z).tolist(), "phase_Z_deg": np.degrees(np.angle(Z)).tolist(),
        }

    def write_csv(self, path: str | Path) -> None:
        """``frequency_Hz, Y_real_S, Y_imag_S, abs_Z_ohm, phase_Z_deg``, one row per frequency."""
        Z = self.Z
        rows = np.column_stack([self.frequency, self.Y.real, self.Y.imag, np.abs(Z), np.degrees(np.angle(Z))])
        np.savetxt(path, rows, delimiter=",", header=CSV_HEADER, comments="", fmt="%.10g")

    def write_s1p(self, path: str | Path, z0: float = Z0) -> None:
        """Touchstone version 1 one-port file: ``# HZ S RI R 50``, S11 = (Z - 50) / (Z + 50)."""
        s = self.s11(z0)
        lines = [f"! modalfe admittance of {self.scene}: {self.method}"]
        lines += [f"! {line}" for line in self.losses]
        lines.append(f"# HZ S RI R {z0:g}")
        lines += [f"{f:.10g} {v.real:.10g} {v.imag:.10g}" for f, v in zip(self.frequency, s)]
        Path(path).write_text("\n".join(lines) + "\n")


def admittance(scene, band: tuple[float, float], points: int, *, damping: str | None = None,
               tan_delta: float | None = None, per_mode: Mapping[str, str] | None = None, direct: bool = False,
               residual: str = "centre", widen: float = WIDEN, **resolution) -> Admittance:
    """Y(f) of ``scene``'s driven electrodes at ``points`` frequencies evenly spaced over ``band`` [Hz]: modal
    superposition (every short-circuit mode in the band widened by ``widen``, residual of the others at
    ``residual``: ``centre`` or ``static``), or the direct damped FE solve (``direct``; its progress shown where
    ``modalfe.progress.shown``), both on the modes of the widened band of the 3-D solid or the axisymmetric model
    (``band_modes``, resolved at ``resolution``: ``solve_modes``' tol, fidelity, error_estimate). Losses from
    ``resolve_losses``."""
    frequency = frequency_grid(band, points)
    losses = resolve_losses(scene, damping=damping, tan_delta=tan_delta, per_mode=per_mode)
    if "drive" not in scene.electrodes.values():
        raise SceneError("electrodes: the scene has no driven electrode; an admittance needs one")
    check_ground(scene, "electrodes")
    if not (math.isfinite(widen) and widen >= 1):
        raise SceneError(f"widen: must be >= 1, got {widen:g}")
    lo, hi = band[0] / widen, band[1] * widen
    try:
        modes = band_modes(scene, (lo, hi), **resolution)
    except SolverError:
        modes = _no_modes(scene, (lo, hi))  # a band without a resonance
        if modes is None:  # modes the band solve failed to find: its own error
            raise
    if direct:
        return direct_admittance(modes.model, frequency, losses)
    result = modal_admittance(modes, frequency, losses, residual=residual,
                              note=f"short-circuit modes in [{lo:.6g}, {hi:.6g}] Hz (the band widened {widen:g}x); "
                                   f"resolved: {modes.resolution}")
    result = with_open_circuit(result, modes)
    if len(modes) and modes.estimate is None:  # no estimate levels kept (the axisymmetric model's p-step, no errors)
        return replace(result, notes=(*result.notes, f"theta, the |Y| extrema and C0: errors not estimated (the answer "
                                                     f"keeps no estimate levels: {modes.estimate_method})"))
    return with_stated_errors(result, modes, losses, residual) if len(modes) else result


def with_open_circuit(result: Admittance, modes) -> Admittance:
    """``result`` with the FE open circuit's fa and k_eff of each resonance that has a BVD circuit: the mode's
    open-circuit partner by shape on its model (``modalfe.response.forced.open_circuit``, the one path of ``table``,
    ``forced`` and the API); a resonance whose partner is not found is left out, with a note."""
    from modalfe.response.forced import open_circuit

    rows, missing = [], []
    for circuit in result.bvd_circuits():
        mode = next(m for m in modes if m.label == circuit["label"] and m.frequency == circuit["fr_hz"])
        try:
            both = open_circuit(mode, among=modes)
        except SolverError:
            missing.append(mode.label)
            continue
        rows.append({"label": both.label, "fr_hz": both.fr, "fa_hz": both.fa, "k_eff": both.k_eff})
    notes = [f"FE open-circuit fa not found for {', '.join(missing)}"] if missing else []
    return replace(result, open_circuit=tuple(rows), notes=(*result.notes, *notes))


def with_stated_errors(result: Admittance, modes, losses: Losses, residual: str) -> Admittance:
    """``result`` (``modal_admittance`` of ``modes``) with the stated errors of what a designer reads off it: each
    mode's theta, the |Y| maximum nearest it (frequency and value) and the minimum above it, and C_S, from the
    same estimate levels as the frequencies (``modalfe.solve.api.derived_errors``): the admittance of each level's
    modes over the same grid, read at the partner of each mode. A mode whose frequency states no error gets none
    either; the extrema only where every mode of the band states one (a band solved on the working mode's answer,
    ``band_modes``, has levels that hold the modes near it only)."""
    from modalfe.solve.api import derived_errors

    curves = {id(modes.model): (result, result.extrema())}
    every = all(r["error_estimate"] is not None for r in result.modes)  # else the levels hold part of the band
    strongest = max(abs(r["theta_N_per_V_sqrtkg"]) for r in result.modes) if result.modes else 0.0

    def numbers(m) -> dict[str, float]:
        if id(m.model) not in curves:
            level = modal_admittance(modes.estimate.level_holding(m), result.frequency, losses, residual=residual)
            curves[id(m.model)] = (level, level.extrema() if every else None)
        curve, ext = curves[id(m.model)]
        out = {"C_S": curve.capacitance_clamped}
        theta = abs(float(m.shape @ m.model.voltage_load(1.0)))
        if theta > UNDRIVEN * strongest:
            out["theta"] = theta
        own = [r["frequency_hz"] for r in curve.modes]
        # the maxima whose nearest mode is this one: merged resonances give their one peak to the nearest mode
        peaks = [f for f in ext["max_abs_Y_hz"] if min(own, key=lambda g: abs(g - f)) == m.frequency] if ext else []
        if peaks:
            peak = min(peaks, key=lambda f: abs(f - m.frequency))
            out.update(peak_hz=peak, peak_S=float(np.abs(curve.model_Y(peak))[0]))
            above = [f for f in ext["min_abs_Y_hz"] if f > peak]
            if above:
                out["dip_hz"] = min(above)
        return out

    rows, c0_error = [], math.nan
    for row in result.modes:
        m = next(m for m in modes if m.frequency == row["frequency_hz"])
        if row["error_estimate"] is None:  # its frequency states no error: neither do its numbers
            rows.append(row)
            continue
        fine = numbers(m)
        errors = derived_errors(modes, m, numbers, fine)
        c0_error = errors["C_S"][0] if math.isnan(c0_error) else max(c0_error, errors["C_S"][0])
        rows.append({**row, **{k: v for k, v in fine.items() if k in ("peak_hz", "peak_S", "dip_hz")},
                     **{f"{k}_error": float(e) if math.isfinite(e) else None for k, (e, _) in errors.items()
                        if k != "C_S"}})
    note = "stated errors of theta, the |Y| extrema and the clamped capacitance: from the frequencies' estimate " \
           "levels (the admittance of each level's modes)"
    if not every:
        note += "; the extrema's not estimated: the band's other modes state no error (solved on the working mode's " \
                "answer only)"
    return replace(result, modes=tuple(rows), capacitance_error=c0_error, notes=(*result.notes, note))


def band_modes(scene, band: tuple[float, float], **resolution) -> Modes:
    """Every short-circuit mode of ``scene``'s 3-D solid (or axisymmetric model, where auto answers with it or it is
    asked: ``REVOLVED``) in ``band`` [Hz], certified by Sturm counts, on the
    discretization that resolves the band's working mode to ``resolution`` (``solve_modes``' tol, fidelity,
    error_estimate) as ``modes`` resolves it. The working modes in the band drive the resolution (one fr in every
    command); in a band without one, the mode nearest the scene's analysis.near where the band holds it, else its
    centre (every mode of a wide band of a disc refined its flexural modes for minutes).

    Where the band holds one working mode and ``modes`` asks about it by its frequency (near and count,
    ``modalfe.solve.api.working_question``), or none but the scene's own frequency (``modes`` without options asks
    about the mode nearest it), that question: its answer (``modes``' own, read back where kept) sets
    the level, and the band is then solved once on that answer's model, not at every estimate level and refinement
    step: its Sturm counts, the answer's modes in it kept and only the others sought, at the answer's own shift and
    factorization (``modalfe.solve.levels.modes_of``'s ``known``). The band's modes the answer holds take its
    frequency and stated error (those ``modes`` gives; the labels are the band solve's, unique in the band); the
    others are solved on the same model but carry no error estimate (NaN: not estimated), which the note says, with
    how many lie above the frequency the mesh resolves (``Scene.max_frequency``: the band question raised it to the
    band's top, and so refined the mesh past the one ``modes`` answers on, which then gave the working mode another
    frequency). Otherwise (none or several working modes in the band, or a scene whose own question is a band) the
    band question itself, every mode estimated."""
    from modalfe.solve.api import NEAREST, REVOLVED, solid_modes, working_question
    from modalfe.solve.levels import modes_of

    lo, hi = band
    a = scene.analysis
    inside = [wm for wm in scene.working_modes if lo <= wm.near <= hi]
    question = working_question(scene, inside[0].selector) if len(inside) == 1 else {}
    if not inside and a.band is None and a.near is not None and lo <= a.near <= hi:
        question = {"near": a.near, "count": a.count}  # no working mode: the scene's own question, as ``modes`` asks
    if question.get("near") is None:  # in a band without a working mode, the mode nearest the scene's own frequency
        near = a.near if a.near is not None and lo <= a.near <= hi else 0.5 * (lo + hi)  # where the band holds it,
        check = tuple((wm.selector, wm.near) for wm in inside) or ((NEAREST, near),)  # else nearest its centre
        return solid_modes(scene, needs="the admittance", band=band, circuit="short", check=check, takes=REVOLVED,
                           **resolution)
    answer = solid_modes(scene, needs="the admittance", circuit="short", takes=REVOLVED, **question, **resolution)
    found = modes_of(answer.model, Analysis(band=band, circuit="short"), fidelity=answer.fidelity, known=answer)
    unmatched = list(answer)
    rows = []
    for mode in found:
        same = next((m for m in unmatched if abs(m.frequency - mode.frequency) <= SAME_EIGENVALUE * m.frequency), None)
        if same is not None:
            unmatched.remove(same)
            mode = replace(mode, frequency=same.frequency, error_estimate=same.error_estimate,
                           model_error=same.model_error)
        rows.append(mode)
    shared = len(answer) - len(unmatched)
    above = sum(m.frequency > answer.mesh_frequency for m in rows)
    note = (f"{answer.fidelity_note}; the band's {len(rows)} modes solved on this mesh: {shared} of them the resolved "
            f"question's (its frequencies and error estimates), the others' errors not estimated"
            + (f" ({above} above the {answer.mesh_frequency:.6g} Hz the mesh resolves, mesh.max_frequency)"
               if above else ""))
    return replace(answer, modes=tuple(rows), fidelity_note=note)


def _no_modes(scene, band: tuple[float, float]):
    """Modes (none) of ``scene``'s solid model when its Sturm counts find no short-circuit mode in ``band`` [Hz] (the
    device is then a capacitor plus the residual of the modes outside), else None."""
    from modalfe.models.build import build_model
    from modalfe.solve.eigen import sturm_count

    model, _ = build_model(scene, "solid")
    T = model.constraints("short").T
    A, B = (T.T @ model.K @ T).tocsr(), (T.T @ model.M @ T).tocsr()
    below = [sturm_count(A, B, (2 * np.pi * f) ** 2) for f in band]
    if below[1] != below[0]:
        return None
    return Modes((), model, "short", "solid", T.shape[1])


def frequency_grid(band, points: int) -> np.ndarray:
    """``points`` frequencies evenly spaced over ``band`` = (F1, F2) [Hz], 0 < F1 < F2."""
    f1, f2 = (float(b) for b in band)
    if not (math.isfinite(f1) and math.isfinite(f2) and 0 < f1 < f2):
        raise SceneError(f"band: needs 0 < F1 < F2 [Hz], got {f1:g} {f2:g}")
    if int(points) != points or not 2 <= points <= MAX_POINTS:
        raise SceneError(f"points: must be an integer from 2 to {MAX_POINTS:,}, got {points}")
    return np.linspace(f1, f2, int(points))


def clamped_capacitance(model) -> float:
    """The clamped capacitance C_S [F] of the solved part: every displacement held at zero (the dielectric alone)."""
    from scipy.sparse.linalg import splu

    from modalfe.response.forced import drive_vectors
    from modalfe.solve.levels import short_circuit_pencil

    T, F, C_b, _ = drive_vectors(model)
    n_uf = model.n_u_free
    if T.shape[1] == n_uf:
        return C_b
    A = short_circuit_pencil(model)[0][n_uf:, n_uf:]
    F_phi = F[n_uf:]
    return float(C_b + F_phi @ splu(A.tocsc()).solve(F_phi))


def bvd_admittance(circuit: Mapping, frequency) -> np.ndarray:
    """Y [S] (complex) at ``frequency`` [Hz] of a Butterworth-Van Dyke circuit (``Admittance.bvd_circuits``): C0 in
    parallel with R1, L1 and C1 in series, Y = i omega C0 + 1 / (R1 + i omega L1 + 1 / (i omega C1))."""
    w = 2 * np.pi * np.atleast_1d(np.asarray(frequency, dtype=float))
    return 1j * w * circuit["C0_at_fr_F"] + 1.0 / (circuit["R1_ohm"] + 1j * w * circuit["L1_H"]
                                             + 1.0 / (1j * w * circuit["C1_F"]))


def modal_admittance(modes, frequency, losses: Losses, *, residual: str = "centre", note: str = "") -> Admittance:
    """Y(f) [S] by modal superposition of ``modes`` (short circuit, one model; none for a band without a resonance:
    the clamped capacitance and the residual) with the residual of the modes left out at ``residual`` (module
    docstring). The result can evaluate the same Y anywhere (``Admittance.model_Y``), so its fr and fa are refined
    between the grid's points."""
    from modalfe.models.constraints import free_values
    from modalfe.response.forced import drive_vectors
    from modalfe.solve.levels import short_circuit_pencil
    from modalfe.solve.linalg import shifted_solve

    if residual not in ("centre", "static"):
        raise SceneError(f"residual: must be 'centre' or 'static', got '{residual}'")
    if modes.circuit != "short":
        raise SolverError(f"modes: the admittance needs short-circuit modes, got {modes.circuit}")
    model = modes.model
    f = np.atleast_1d(np.asarray(frequency, dtype=float))
    w = 2 * np.pi * f
    _, F, C_b, _ = drive_vectors(model)
    load = model.voltage_load(1.0)
    top = max(float(f.max()), max((m.frequency for m in modes), default=0.0))
    used = [m for m in modes if m.frequency > RIGID_HZ * top]
    rigid = len(modes) - len(used)
    omega_r = np.array([m.omega for m in used])
    theta = np.array([float(m.shape @ load) for m in used])
    centre = (0.5 * (w.min() + w.max())) ** 2
    A, B, kept = short_circuit_pencil(model)
    kept = kept if residual == "centre" else None  # GMRES serves beside the eigen shift, not at 0: factorized there
    # in the band, the kept eigen shift: direct solves there (GMRES at the centre: 8 solves a level on the Cu-Be plate)
    sigma = 0.0 if residual == "static" else kept[1] if kept is not None and w.min() ** 2 <= kept[1] <= w.max() ** 2 \
        else centre
    shapes = np.column_stack([m.shape for m in used]) if used else np.zeros((model.K.shape[0], 0))
    # the load on the modes left out (module docstring): a kept mode beside sigma is not in it (GMRES then converges)
    F_left = F - B @ (free_values(model.constraints("short").T, shapes) @ theta)

    def residual_solves(shift: float) -> tuple[np.ndarray, np.ndarray, float]:  # x, B x, x B (A - shift B)^-1 B x
        solve = shifted_solve(A, B, shift, kept)  # one solve function for both (it factorizes at most once)
        return (x := solve(F_left)), B @ x, float((B @ x) @ solve(B @ x))

    try:
        x_left, B_x, q_res2 = residual_solves(sigma)
    except SolverError as exc:
        if sigma == 0:
            raise SolverError(f"residual: the static solve failed ({exc}); a free body (no clamps or springs) needs "
                              f"residual='centre'") from None
        sigma = _shift_clear_of_modes(w, omega_r)  # the band's centre lies on a resonance: any shift in it serves
        try:
            x_left, B_x, q_res2 = residual_solves(sigma)
        except SolverError as again:
            raise SolverError(f"residual: the solve at {np.sqrt(sigma) / 2 / np.pi:.6g} Hz, beside the band's "
                              f"centre on a resonance, failed ({again})") from None
    c, h, text = modal_losses(used, model, losses)
    q_res0, q_res1 = C_b + float(F @ x_left), float(x_left @ B_x)
    C_S = clamped_capacitance(model)
    factor = model.copies

    def model_Y(frequency) -> np.ndarray:  # noqa: N802 (the admittance's own symbol)
        wf = 2 * np.pi * np.atleast_1d(np.asarray(frequency, dtype=float))
        d = omega_r[None, :] ** 2 - wf[:, None] ** 2 + 1j * (c[None, :] * wf[:, None] + h[None, :])
        ds = wf**2 - sigma
        q = q_res0 + ds * (q_res1 + ds * q_res2) + (theta[None, :] ** 2 / d).sum(axis=1) - 1j * losses.tan_delta * C_S
        return 1j * wf * factor * q

    notes = [note] if note else []
    if not used:
        notes.append("no resonance in the band: the device is a capacitor, the clamped capacitance and the residual "
                     "of the modes outside")
    if rigid:
        notes.append(f"{rigid} rigid-body modes (no charge) left to the residual")
    if factor > 1:
        notes.append(f"solved on 1/{factor} of the device (symmetry); charge and capacitance scaled by {factor}; theta "
                     f"is the solved part's (the whole device's: sqrt({factor}) times it)")
    where = "zero frequency (static)" if sigma == 0 else "the band's centre" if sigma == centre else \
        f"{np.sqrt(sigma) / 2 / np.pi:.6g} Hz (the eigen solve's shift)" if kept is not None and sigma == kept[1] \
        else f"{np.sqrt(sigma) / 2 / np.pi:.6g} Hz (the band's centre lies on a resonance)"
    method = (f"modal superposition of {len(used)} short-circuit modes, residual of the others at {where} "
              f"(mode-acceleration), {modes.dofs} DOFs")
    widths = (c + h / omega_r) / (2 * np.pi)  # half-power: 2 zeta f_r or eta f_r
    rows = tuple({"label": m.label, "frequency_hz": m.frequency,
                  "error_estimate": m.error_estimate if math.isfinite(m.error_estimate) else None,
                  "theta_N_per_V_sqrtkg": float(t), "loss": s, "width_hz": float(b)}
                 for m, t, s, b in zip(used, theta, text, widths))
    notes += _coarse_grid_notes(f, rows)
    return Admittance(model.scene.name, f, model_Y(f), method, tuple(losses.describe()), factor * C_S,
                      modes.dofs, rows, tuple(notes), model_Y, copies=factor)


# a shift moved off a resonance keeps this relative distance (in omega^2) from every mode kept where it can: on a
# resonance A - sigma B is singular, and 0.2 % from one PARDISO's residual is still 2e-6 (bimorph, 545 Hz)
SHIFT_GAP = 0.05


def _shift_clear_of_modes(w: np.ndarray, omega_r: np.ndarray) -> float:
    """sigma in the band (omega^2) for a centre that lies on a mode kept: the one nearest the centre at least
    SHIFT_GAP from every mode, else the one farthest from them (the modes kept are exact at any shift; the residual's
    error grows with the distance from the shift, so it stays as near the centre as it can)."""
    centre = (0.5 * (w.min() + w.max())) ** 2
    candidates = np.linspace(w.min() ** 2, w.max() ** 2, 401)
    gap = np.min(np.abs(omega_r[None, :] ** 2 - candidates[:, None]), axis=1, initial=np.inf) / candidates
    clear = np.flatnonzero(gap >= SHIFT_GAP)
    if len(clear):
        return float(candidates[clear[np.argmin(np.abs(candidates[clear] - centre))]])
    return float(candidates[np.argmax(gap)])


def _coarse_grid_notes(f: np.ndarray, rows) -> list[str]:
    """A note for each mode in the band narrower than the grid's spacing: the curve may miss or misplace its peak
    (the fr and fa listed are the model's, ``Admittance.extrema``)."""
    spacing = float(np.max(np.diff(f)))
    return [f"the grid's spacing {spacing:.4g} Hz is wider than the resonance of mode {r['label']} at "
            f"{r['frequency_hz']:.6g} Hz ({r['width_hz']:.3g} Hz wide): the curve can miss or misplace its peak; fr "
            f"and fa are found on the model, raise --points to draw it"
            for r in rows if f[0] <= r["frequency_hz"] <= f[-1] and spacing > r["width_hz"]]


def direct_admittance(model, frequency, losses: Losses) -> Admittance:
    """Y(f) [S] by the direct damped FE solve at each frequency (one complex sparse LU each)."""
    from modalfe.response.forced import drive_vectors
    from modalfe.solve.linalg import solve_complex

    if losses.per_mode:
        raise SceneError("--mode-damping: per-mode losses have no direct FE equivalent; drop --direct")
    f = np.atleast_1d(np.asarray(frequency, dtype=float))
    w = 2 * np.pi * f
    n_u = model.n_u
    T, _, _, x_v = drive_vectors(model)
    K = model.K.astype(complex)
    K_mech = model.mechanical_stiffness()
    notes = []
    kind, v = loss_spec("--damping", losses.mechanical)
    C = sp.csr_matrix(K.shape)
    w_c = 0.5 * (w.min() + w.max())
    if kind == "zeta":
        C = (2 * v[0] / w_c) * K_mech
        notes.append(f"modal zeta {v[0]:.3g} as stiffness-proportional Rayleigh beta = {2 * v[0] / w_c:.3g} s "
                     f"(gives it at the band's centre, {w_c / 2 / np.pi:.0f} Hz)")
    elif kind == "rayleigh":
        C = v[0] * model.M + v[1] * K_mech
    elif kind == "eta":
        K = K + 1j * v[0] * K_mech
    else:
        qm = qm_table(model)
        stiff = material_stiffness(model, set(qm))
        rest = model.K[:n_u, :n_u] - sum(stiff.values(), sp.csr_matrix((n_u, n_u)))
        eta_rest = float(fallback_eta(losses.fallback, np.array([w_c]))[0])
        lossy = eta_rest * rest + sum((K_m / qm[name] for name, K_m in stiff.items()), sp.csr_matrix((n_u, n_u)))
        K = K + 1j * sp.block_diag([lossy, sp.csr_matrix((model.n_phi, model.n_phi))], format="csr")
    if losses.tan_delta and model.n_phi:
        K_pp = sp.block_diag([sp.csr_matrix((n_u, n_u)), K[n_u:, n_u:]], format="csr")
        K = K - 1j * losses.tan_delta * K_pp  # the phi-phi block (eps^S) times (1 - i tan delta)
    load = -(K @ x_v)
    F = T.T @ load
    C_b = complex(x_v @ load)
    A = (T.T @ K @ T).tocsc()
    B = (T.T @ model.M @ T).tocsc()
    Cf = (T.T @ C @ T).tocsc()
    Y = np.zeros(len(f), dtype=complex)
    from modalfe.progress import counted

    for i in counted(range(len(f)), "direct harmonic FE", unit="frequency"):
        x = solve_complex((A - w[i] ** 2 * B + 1j * w[i] * Cf).tocsr(), F)
        if not np.all(np.isfinite(x)):
            raise SolverError(f"harmonic solve at {f[i]:g} Hz returned NaN")
        Y[i] = 1j * w[i] * (F @ x + C_b)
    factor = model.copies
    if factor > 1:
        notes.append(f"solved on 1/{factor} of the device (symmetry); charge scaled by {factor}")
    dofs = T.shape[1]
    return Admittance(model.scene.name, f, factor * Y, f"direct harmonic FE, {dofs} DOFs", tuple(losses.describe()),
                      factor * clamped_capacitance(model), dofs, (), tuple(notes))
