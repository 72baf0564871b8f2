"""Ciliary beam forced-response study (seed 003): the bimorph-driven responses of bending modes 3-6
along the beam (Fig. 6) and in frequency (Fig. 8), their trends with voltage, sheet thickness, beam
modulus, e31 and damping (Figs. 7, 9), the half-period average acceleration along x (Fig. 11d) and the
antinodes against the measured Table 3, at beam (1-D) or solid (3-D) fidelity.

Every seed number used here is copied below with its place in the paper; nothing is read from
outside the project.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from modalfe.errors import SceneError, SolverError
from modalfe.solve.api import OWN_MESH

if TYPE_CHECKING:
    from modalfe.results.modes import Mode, Modes
    from modalfe.scene import Scene

# ---------------------------------------------------------------------------------------------
# seed 003 numbers, each with its place in the paper

BRASS_NU = 0.34  # Poisson ratio of brass-seed003 (modalfe.scene.materials: ASM Handbook vol. 2), kept in the E trend
SEED_VOLTS = 100.0  # V peak, sec. 4.1 and sec. 5
SEED_ZETA = 0.025  # sec. 4.1
SEED_F6 = 24221.0  # Hz, sec. 4.2: 6th-order natural frequency (Euler-Bernoulli theory)
SEED_F6_MEASURED = 23200.0  # Hz, sec. 5: the prototype felt smooth at ~23,200 Hz
SEED_AMPLITUDE_6 = 1.44e-6  # m, sec. 4.1: mode-6 amplitude at 100 V (Fig. 6d)
SEED_ACCELERATION_6 = 69324.0  # m/s^2, sec. 4.3: largest half-period average acceleration (Fig. 11)
SEED_TABLE3 = (0.01325, 0.02925, 0.04725, 0.07470, 0.09075)  # m, Table 3: measured large-amplitude points
SEED_TABLE3_AMPLITUDE = 1.24e-6  # m, Table 3 (about 1.23-1.25e-6 at all five points)
SEED_THEORY_OFFSET = 8e-3  # m, sec. 5: the seed's theory misses the measured peaks by up to 8 mm at 100 V
SEED_INVESTIGATION_X = 0.02  # m, sec. 4.1: "the position on the beam x = 0.02 m is chosen"
SEED_PIEZO = "piezo-seed003-e31"  # Table 2 sheet: E 76.5 GPa, rho 7500, e31 2.0 C/m^2 (modalfe.scene.materials)
WORKING_MODES = (3, 4, 5, 6)  # sec. 4.1: modes 3-6 form at least one full wave
# seed 003 sec. 4.1 and 4.2: each parameter at three values; (values, direction the seed reports for the
# mode-6 amplitude as the value grows: +1 larger, -1 smaller)
SEED_TRENDS = {
    "volts": ((100.0, 150.0, 200.0), +1),  # Fig. 7a, 9b [V]
    "sheet_thickness": ((0.3e-3, 0.4e-3, 0.5e-3), -1),  # Fig. 7b [m]
    "beam_modulus": ((105e9, 150e9, 200e9), -1),  # Fig. 7c, 9c [Pa]; see BEAM_MODULI_SOURCE
    "e31": ((2.0, 2.5, 3.0), +1),  # Fig. 7d, 9a [C/m^2]
    "zeta": ((0.0125, 0.025, 0.05), -1),  # Fig. 9d; the seed does not print its three values
}
BEAM_MODULI_SOURCE = ("seed 003 compares brass, phosphor bronze and spring steel without printing their moduli; "
                      "here E alone is varied (rho kept at 8500 kg/m^3) from the seed's 105 GPa to ~200 GPa, "
                      "a steel's (ASM Handbook vol. 1, 1990)")
ZETA_VALUES_SOURCE = "assumption: half and twice the seed's zeta = 0.025 (Fig. 9d's values are not in the text)"

_TOP_Y, _TOP_Z = 2.5e-3, 5e-3  # m, the beam's top centre line (seed 003 Table 1: 5 x 5 mm section)


def line_points(length: float = 0.1, samples: int = 401) -> np.ndarray:
    """(3, samples) points [m] on the top centre line of the beam, x from 0 to ``length``."""
    x = np.linspace(0.0, length, samples)
    return np.vstack([x, np.full_like(x, _TOP_Y), np.full_like(x, _TOP_Z)])


def bending_modes(modes: Modes, orders: tuple[int, ...] = WORKING_MODES) -> dict[int, Mode]:
    """Order -> mode of the bending modes in the driven (x, z) plane, found by label (``bending-z n``):
    the seed's planar theory counts only these (its 'mode 6' is our ``bending-z 6``)."""
    found = {}
    for n in orders:
        try:
            found[n] = modes.labelled(f"bending-z {n}")
        except SolverError:
            raise SolverError(f"modes: no 'bending-z {n}' among {[m.label for m in modes]}; widen the band") from None
    return found


@dataclass(frozen=True, eq=False)
class LineResponse:
    """Normal displacement along the top centre line at one drive frequency.

    frequency [Hz]; x (n,) [m]; w (n,) complex [m] 0-peak at ``volts`` [V]; zeta [-] modal damping;
    average_acceleration (n,) [m/s^2]: the half-period average (2 / pi) omega^2 |w| (seed 003 sec. 4.3).
    """

    frequency: float
    x: np.ndarray
    w: np.ndarray
    volts: float
    zeta: float

    @property
    def amplitude(self) -> np.ndarray:
        return np.abs(self.w)

    @property
    def average_acceleration(self) -> np.ndarray:
        return half_period_average_acceleration(self.frequency, self.amplitude)

    @property
    def peak_amplitude(self) -> float:
        return float(self.amplitude.max())

    def antinodes(self, *, relative: float = 0.2) -> np.ndarray:
        """x [m] of the interior local maxima of |w| above ``relative`` x the largest, refined by a parabola
        through the three samples around each (the clamp end excluded; the free tip included)."""
        return amplitude_peaks(self.x, self.amplitude, relative=relative)


def half_period_average_acceleration(frequency: float, amplitude) -> np.ndarray:
    """a_c = (2 / T) int_0^{T/2} |w''| dt = (2 / pi) omega^2 |w| [m/s^2] for harmonic motion of 0-peak
    ``amplitude`` [m] at ``frequency`` [Hz], seed 003 sec. 4.3 (the average over the half period)."""
    omega = 2 * math.pi * frequency
    return 2 / math.pi * omega**2 * np.asarray(amplitude)


def amplitude_peaks(x: np.ndarray, amplitude: np.ndarray, *, relative: float = 0.2) -> np.ndarray:
    """x [m] of the local maxima of ``amplitude`` above ``relative`` x its largest (interior ones refined
    by a parabola; a maximum at the last sample, the free tip, kept as it is)."""
    a = np.asarray(amplitude, dtype=float)
    floor = relative * a.max()
    out = []
    for i in range(1, len(a) - 1):
        if a[i] >= a[i - 1] and a[i] > a[i + 1] and a[i] > floor:
            denominator = a[i - 1] - 2 * a[i] + a[i + 1]
            shift = 0.5 * (a[i - 1] - a[i + 1]) / denominator if denominator else 0.0
            out.append(x[i] + shift * (x[i + 1] - x[i]))
    if a[-1] > a[-2] and a[-1] > floor:
        out.append(x[-1])
    return np.array(out)


def line_response(modes: Modes, frequency: float, *, volts: float = SEED_VOLTS, zeta: float = SEED_ZETA,
                  samples: int = 401, static: np.ndarray | None = None) -> LineResponse:
    """Normal displacement along the top centre line driven by ``volts`` [V] at ``frequency`` [Hz], by
    modal superposition of every mode in ``modes`` plus the static residual (seed 003 eq. (21), with the
    bimorph's distributed moment in place of the seed's point force at x0). ``static``: the static
    response to ``volts`` from ``static_drive`` (computed here when None)."""
    from modalfe.response.superposition import modal_receptance

    model = modes.model
    length = float(model.scene.full_assembly().bounds[1][0])
    points = line_points(length, samples)
    P = model.displacement_probes(points.T)[2 * samples:]
    w = modal_receptance(modes, model.voltage_load(volts), P, [frequency], zeta, static=static)[0]
    return LineResponse(float(frequency), points[0], w, volts, zeta)


def frequency_response(modes: Modes, frequency, x: float, *, volts: float = SEED_VOLTS,
                       zeta: float = SEED_ZETA, static: np.ndarray | None = None) -> np.ndarray:
    """Complex normal displacement [m] at ``x`` [m] on the top centre line for each drive frequency [Hz]
    (seed 003 eq. (22), Fig. 8), by modal superposition with the static residual (``static`` as in
    ``line_response``)."""
    from modalfe.response.superposition import modal_receptance

    P = modes.model.displacement_probes(np.array([[x, _TOP_Y, _TOP_Z]]))[2:]
    return modal_receptance(modes, modes.model.voltage_load(volts), P, frequency, zeta, static=static)[:, 0]


def static_drive(modes: Modes, volts: float = SEED_VOLTS) -> np.ndarray:
    """Full DOF static response K_c^-1 f to ``volts`` [V] on ``modes.model``: pass it as ``static`` to
    ``line_response`` and ``frequency_response`` at the same ``volts`` to factorize K_c once."""
    from modalfe.response.superposition import static_response

    return static_response(modes.model, modes.model.voltage_load(volts))


# ---------------------------------------------------------------------------------------------
# scenes and solves


def study_scene(*, coarse: bool = False, **overrides) -> Scene:
    """The ``ciliary_beam`` scene with seed 003's Table 2 sheet material (E 76.5 GPa, e31 2.0 C/m^2),
    ``coarse``: 4 elements per wavelength (the tests' resolution)."""
    from modalfe.scene import load_scene

    settings = {"sheet_material": SEED_PIEZO}
    if coarse:
        settings["mesh.elements_per_wavelength"] = 4.0
    settings.update(overrides)
    return load_scene("ciliary_beam", **settings)


def sheet_material_with_e31(e31: float) -> dict:
    """Scene material table (``materials.NAME`` keys) of seed 003's sheet with e31 = e32 = ``e31`` [C/m^2]."""
    from modalfe.scene.materials import material

    if not (math.isfinite(e31) and e31 > 0):
        raise SceneError(f"e31: must be a positive piezoelectric constant [C/m^2], got {e31}")
    base = material(SEED_PIEZO)
    e = np.array(base.e, dtype=float)
    e[2, 0] = e[2, 1] = e31
    return {"C": base.C.tolist(), "rho": base.rho, "e": e.tolist(), "eps_S": np.asarray(base.eps_S).tolist(),
            "source": f"{base.source}; e31 = e32 set to {e31:g} C/m^2 for the trend"}


def variant_scene(parameter: str, value: float, *, coarse: bool = False, settings: dict | None = None) -> Scene:
    """The study scene (with ``settings``, e.g. mesh overrides) with one seed 003 trend parameter
    changed (``volts`` and ``zeta`` change no scene)."""
    from modalfe.scene.materials import material

    settings = dict(settings or {})
    if parameter in ("volts", "zeta"):
        pass
    elif parameter == "sheet_thickness":
        settings["sheet_thickness"] = value
    elif parameter == "beam_modulus":
        brass = material("brass-seed003")
        settings.update({"beam_material": "beam", "materials.beam.E": value, "materials.beam.nu": BRASS_NU,
                         "materials.beam.rho": brass.rho,
                         "materials.beam.source": f"{brass.source}; E set to {value:g} Pa for the trend"})
    elif parameter == "e31":
        settings["sheet_material"] = "sheet"
        settings.update({f"materials.sheet.{k}": v for k, v in sheet_material_with_e31(value).items()})
    else:
        raise SceneError(f"parameter: must be one of {sorted(SEED_TRENDS)}, got '{parameter}'")
    return study_scene(coarse=coarse, **settings)


def solve(scene: Scene, *, fidelity: str = "beam", top: float = 45e3, error_estimate: bool = False) -> Modes:
    """All modes from 1 Hz to ``top`` [Hz] (mode 6 near 22-24 kHz and the next two above it) at
    ``fidelity`` (``beam`` or ``solid``), with a Richardson discretization estimate if asked."""
    from modalfe.solve.api import solve_modes

    return solve_modes(scene, band=(1.0, top), fidelity=fidelity, error_estimate=error_estimate, tol=OWN_MESH)


@dataclass(frozen=True)
class TrendPoint:
    """One value of one trend parameter: mode-6 frequency [Hz] and 0-peak amplitude [m] (largest along the
    top line) at resonance, at 100 V unless the parameter is the voltage."""

    parameter: str
    value: float
    frequency: float
    amplitude: float


def changes_scene(parameter: str, value: float, settings: dict | None = None) -> bool:
    """False when ``variant_scene(parameter, value, settings=settings)`` is the study scene with
    ``settings`` itself: ``volts`` and ``zeta`` (no scene), or the study scene's own sheet thickness
    (the ``ciliary_beam`` geometry's default), beam modulus (``brass-seed003``: the same elastic
    constants and density) or e31 = e32 (``SEED_PIEZO``'s) with ``settings`` not replacing that part."""
    from modalfe.geometry import BUILDERS
    from modalfe.scene.materials import isotropic, material

    settings = settings or {}
    if parameter in ("volts", "zeta"):
        return False
    if parameter == "sheet_thickness":
        import inspect

        default = inspect.signature(BUILDERS["ciliary_beam"]).parameters["sheet_thickness"].default
        return value != settings.get("sheet_thickness", default)
    if parameter == "beam_modulus":
        brass = material("brass-seed003")
        same = np.array_equal(isotropic("beam", E=value, nu=BRASS_NU, rho=brass.rho, source="").C, brass.C)
        return not (same and settings.get("beam_material", "brass-seed003") == "brass-seed003")
    if parameter == "e31":
        e = np.asarray(material(SEED_PIEZO).e)
        return not (value == e[2, 0] == e[2, 1] and settings.get("sheet_material", SEED_PIEZO) == SEED_PIEZO)
    raise SceneError(f"parameter: must be one of {sorted(SEED_TRENDS)}, got '{parameter}'")


def trend(parameter: str, values=None, *, coarse: bool = False, fidelity: str = "beam",
          settings: dict | None = None, base: Modes | None = None) -> list[TrendPoint]:
    """Mode-6 amplitude at resonance for each value of a seed 003 trend parameter (Figs. 7, 9), at
    ``fidelity`` (``beam`` or ``solid``) with the scene ``settings`` of ``variant_scene``.

    ``base``: the modes of ``study_scene(coarse=coarse, **settings)`` at ``fidelity`` if already solved;
    every value that does not change the scene (``changes_scene``) uses them instead of a new solve
    (without ``base`` such values share one solve)."""
    if parameter not in SEED_TRENDS:
        raise SceneError(f"parameter: must be one of {sorted(SEED_TRENDS)}, got '{parameter}'")
    values = SEED_TRENDS[parameter][0] if values is None else values
    shared = base  # the study scene's modes serve every value that changes no scene
    out = []
    for v in values:
        if not changes_scene(parameter, v, settings):
            shared = shared or solve(variant_scene(parameter, v, coarse=coarse, settings=settings), fidelity=fidelity)
            modes = shared
        else:
            modes = solve(variant_scene(parameter, v, coarse=coarse, settings=settings), fidelity=fidelity)
        mode = bending_modes(modes, (6,))[6]
        volts = v if parameter == "volts" else SEED_VOLTS
        zeta = v if parameter == "zeta" else SEED_ZETA
        response = line_response(modes, mode.frequency, volts=volts, zeta=zeta)
        out.append(TrendPoint(parameter, float(v), mode.frequency, response.peak_amplitude))
    return out


def direction(points: list[TrendPoint]) -> int:
    """+1 if the amplitude grows strictly with the parameter, -1 if it falls strictly, 0 otherwise."""
    a = np.array([p.amplitude for p in points])
    if np.all(np.diff(a) > 0):
        return 1
    if np.all(np.diff(a) < 0):
        return -1
    return 0


def match_antinodes(antinodes: np.ndarray, measured=SEED_TABLE3) -> list[tuple[float, float, float]]:
    """(measured x, our nearest antinode x, ours - measured) [m] for each measured point of Table 3."""
    antinodes = np.asarray(antinodes, dtype=float)
    if antinodes.size == 0:
        raise SolverError("antinodes: the response has no antinode to match")
    out = []
    for xm in measured:
        xa = float(antinodes[np.argmin(np.abs(antinodes - xm))])
        out.append((float(xm), xa, xa - float(xm)))
    return out
