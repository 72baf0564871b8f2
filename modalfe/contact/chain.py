"""The chain from a solved working mode to what the user feels (issue 38): drive voltage -> amplitude at a foot or
at any point of a touch surface -> contact and friction -> friction reduction, flight ratio, the voltage for a
required reduction, the current and power drawn and the rise time of the amplitude.

Links, each the library's own:

- amplitude: the one-mode reduced model with every other mode's quasi-static part
  (``modalfe.response.forced.reduce``; at a point of a surface ``resonant_state``, the same state:
  u = phi theta / (2 i zeta omega_r^2) + residual), W = V |u| per volt, 0-peak, at the drive frequency;
- contact: seed 000's foot (``modalfe.contact.foot.steady_state``, Coulomb-Orowan friction, eqs 2-17) or seed 004's
  bed-spring finger (``modalfe.contact.finger.finger_steady_state``, section II), fed that amplitude;
- circuit: the admittance of the one-mode circuit Y = i omega (C0 + N^2 / (k - m omega^2 + i c omega))
  (``ReducedModel.admittance``): current amplitude V |Y|, power drawn V^2 Re(Y) / 2 (the structure's damping;
  the contact's own losses are not in the reduced model);
- rise time: the amplitude's envelope time constant tau = 1 / (zeta omega_r) = Q / (pi f)
  (``ReducedModel.envelope_time_constant``).

Uncertainty carried through the chain: the amplitude's stated relative error e (``forced``'s, from the mode's
estimate levels) gives the reduction at W (1 - e) and W (1 + e); a time-averaged contact state adds its standard
error (``contact_uncertainty``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from modalfe.contact.finger import FingerParameters, finger_steady_state, simulate_finger
from modalfe.contact.foot import FN, SPEED, ContactCurve, FootParameters, simulate_contact, steady_state
from modalfe.contact.validation import require, values
from modalfe.errors import ContactError

if TYPE_CHECKING:
    from modalfe.response.forced import ReducedModel
    from modalfe.results.modes import Mode
    from modalfe.scene.scene import Scene

NO_ERROR = float("nan")  # a number the chain was not given a stated error for
# A required reduction is sought by doubling the amplitude from SEARCH_START until it is reached, at most
# SEARCH_DOUBLINGS times: 1 nm to 1 mm 0-peak covers every device of the seeds (0.1 to 3 um) with room to spare.
SEARCH_START = 1e-9  # m
SEARCH_DOUBLINGS = 20
SEARCH_RTOL = 1e-4  # relative tolerance of the amplitude found (brentq); far below any stated amplitude error


@dataclass(frozen=True)
class ContactState:
    """The contact model's answer at one amplitude: amplitude W [m, 0-peak]; reduction 1 - F / F0 (the friction
    removed by the vibration); flight_ratio [%] (time off the surface per period); uncertainty: upper 95 % bound on
    the standard error of the reduction (a time average; 0 on a periodic orbit)."""

    amplitude: float
    reduction: float
    flight_ratio: float
    uncertainty: float


@dataclass(frozen=True)
class FootContact:
    """Seed 000's foot model (``modalfe.contact.foot``) at ``preload`` Fn [N] and sliding ``speed`` V [m/s]; the
    chain sets its drive frequency and, from the reduced model's foot outputs, how many feet share the load."""

    parameters: FootParameters = field(default_factory=FootParameters)
    preload: float = FN
    speed: float = SPEED

    def __post_init__(self) -> None:
        require("preload", self.preload, nonnegative=True)
        require("speed", self.speed, nonnegative=True)

    def describe(self) -> str:
        p = self.parameters
        return (f"foot (seed 000): Fn {self.preload:g} N, V {self.speed:g} m/s, mu0 {p.mu0:g}, kt {p.kt:g} N/m, "
                f"kn {p.kn:g} N/m, dn {p.dn:g} N s/m, m {p.mass:g} kg, n {p.n}")

    def tuned(self, frequency: float, feet: int | None) -> FootContact:
        """A copy driven at ``frequency`` [Hz], with ``feet`` sharing the load when given."""
        changes = {"frequency": frequency} | ({"n": feet} if feet else {})
        return FootContact(self.parameters.with_(**changes), self.preload, self.speed)

    def state(self, amplitude: float) -> ContactState:
        """Steady state at W [m, 0-peak] (``foot.steady_state``)."""
        o = steady_state(amplitude, preload=self.preload, speed=self.speed, parameters=self.parameters)
        static = self.parameters.mu0 * self.parameters.total_load(self.preload)
        reduction = 1.0 - o.friction_force / static
        return ContactState(float(amplitude), reduction, o.flight_ratio, o.friction_uncertainty * (1 - reduction))

    def states(self, amplitudes) -> list[ContactState]:
        """``state`` at each of ``amplitudes`` [m, 0-peak] (each one independent)."""
        return [self.state(w) for w in amplitudes]

    def table(self, amplitudes: np.ndarray, progress: bool = False) -> list[ContactState]:
        """States at each amplitude (``foot.simulate_contact``: each one independent); ``progress``: a tqdm bar."""
        c = simulate_contact(amplitudes, preload=self.preload, speed=self.speed, parameters=self.parameters,
                             progress=progress)
        return [ContactState(float(w), float(r), float(b), 0.0)
                for w, r, b in zip(c.amplitude, c.friction_reduction, c.flight_ratio)]


@dataclass(frozen=True)
class FingerContact:
    """Seed 004's bed-spring finger (``modalfe.contact.finger``; preload, speed and friction in its parameters) on
    a plate vibrating at the chain's frequency."""

    parameters: FingerParameters = field(default_factory=FingerParameters)
    frequency: float = 0.0  # [Hz], set by the chain

    def describe(self) -> str:
        p = self.parameters
        return (f"finger (seed 004 Table I, {p.reading}): f_p {p.preload:g} N, V_F {p.speed:g} m/s, mu {p.mu:g}, "
                f"K_sc {p.K_sc:g} N/m, K_Tsc {p.K_Tsc:g} N/m, damping ratio {p.damping_ratio:g}")

    def tuned(self, frequency: float, feet: int | None) -> FingerContact:
        """A copy on a plate vibrating at ``frequency`` [Hz] (``feet``: unused, one finger)."""
        return FingerContact(self.parameters, frequency)

    def state(self, amplitude: float) -> ContactState:
        """Steady state at W [m, 0-peak] = A_pp / 2 (``finger.finger_steady_state``): reduction 1 - mu_US / mu,
        flight 100 - contact [%]."""
        o = finger_steady_state(2 * amplitude, self.frequency, parameters=self.parameters)
        return ContactState(float(amplitude), 1.0 - o.friction_ratio, 100.0 - o.contact_ratio, o.uncertainty)

    def states(self, amplitudes) -> list[ContactState]:
        """States at each of ``amplitudes`` [m, 0-peak]: one alone is ``state``'s; several are continued from the
        smallest (``table``: the next one's march starts on its neighbour's attractor, ``finger.WARM_MARCH_PERIODS``
        instead of ``MARCH_PERIODS`` from rest; an outcome's W (1 -+ e) and W)."""
        return [self.state(amplitudes[0])] if len(amplitudes) == 1 else self.table(np.asarray(amplitudes))

    def table(self, amplitudes: np.ndarray, progress: bool = False) -> list[ContactState]:
        """States at each amplitude, each continued from its smaller neighbour (``finger.simulate_finger``);
        ``progress``: a tqdm bar."""
        c = simulate_finger(2 * np.asarray(amplitudes), self.frequency, parameters=self.parameters, progress=progress)
        return [ContactState(float(a / 2), float(1 - r), float(100 - cr), float(u))
                for a, r, cr, u in zip(c.amplitude_pp, c.friction_ratio, c.contact_ratio, c.uncertainty)]


Contact = FootContact | FingerContact


@dataclass(frozen=True)
class Outcome:
    """What the user feels at one drive voltage, and what the drive costs.

    voltage [V]; output: where the contact sits; amplitude W there [m, 0-peak]; amplitude_error: its stated
    relative error (NaN: none stated); reduction: 1 - F / F0 at W; reduction_range: its extremes at W,
    W (1 - amplitude_error) (not below 0) and W (1 + amplitude_error); contact_uncertainty: upper 95 % bound on the
    standard error of the reduction from a time-averaged contact state; flight_ratio [%]; current: amplitude of the
    drive current [A]; power: mean electrical power drawn [W]; rise_time: the amplitude's time constant
    Q / (pi f) [s]; *_error: stated relative errors (NaN: none).
    """

    voltage: float
    output: str
    amplitude: float
    amplitude_error: float
    reduction: float
    reduction_range: tuple[float, float]
    contact_uncertainty: float
    flight_ratio: float
    current: float
    current_error: float
    power: float
    power_error: float
    rise_time: float
    rise_time_error: float

    def to_json(self) -> dict:
        return {"voltage_v": self.voltage, "output": self.output, "amplitude_m": self.amplitude,
                "amplitude_error": _finite(self.amplitude_error), "friction_reduction": self.reduction,
                "friction_reduction_range": list(self.reduction_range),
                "contact_uncertainty": self.contact_uncertainty, "flight_ratio_percent": self.flight_ratio,
                "current_a": self.current, "current_error": _finite(self.current_error), "power_w": self.power,
                "power_error": _finite(self.power_error), "rise_time_s": self.rise_time,
                "rise_time_error": _finite(self.rise_time_error)}


@dataclass(frozen=True)
class VoltageFor:
    """The drive voltage [V] at which the reduction reaches ``reduction`` (``HapticChain.voltage_for``), the
    amplitude [m, 0-peak] it takes and the voltage's stated relative error (the amplitude per volt's; NaN: none
    stated)."""

    reduction: float
    output: str
    voltage: float
    amplitude: float
    voltage_error: float


@dataclass(frozen=True, eq=False)
class HapticChain:
    """A working mode's reduced model joined to a contact model: volts in, felt friction out.

    rom: ``modalfe.response.forced.ReducedModel``; contact: ``FootContact`` or ``FingerContact`` (drive frequency
    and, for feet, their number set from the reduced model by ``haptic_chain``); output: the reduced model's output
    where the contact sits (default its reference); frequency: drive frequency [Hz] (default the resonance);
    errors: name -> stated relative error of ``forced``'s numbers (``ForcedFigures.errors``: ``amplitude:OUTPUT``,
    ``bvd:R1``, ``bvd:C0``, ``time_constant``), empty when none are stated (a reduced model read from a file);
    mode: the solved ``Mode`` (for amplitudes at points of a surface), or None.
    """

    rom: ReducedModel
    contact: Contact
    output: str
    frequency: float
    errors: Mapping[str, float] = field(default_factory=dict)
    mode: Mode | None = None

    def error(self, name: str) -> float:
        return float(self.errors.get(name, NO_ERROR))

    def amplitude_per_volt(self, output: str | None = None) -> float:
        """|u| per volt [m/V, 0-peak] at ``output`` (default the chain's) at the drive frequency
        (``ReducedModel.frf``)."""
        return float(abs(self.rom.frf(self.frequency, output or self.output)))

    def amplitude(self, voltage: float, output: str | None = None) -> float:
        """W [m, 0-peak] at ``output`` for ``voltage`` [V]."""
        return require("voltage", voltage, nonnegative=True) * self.amplitude_per_volt(output)

    def amplitude_per_volt_at(self, points: np.ndarray) -> np.ndarray:
        """|u_z| per volt [m/V, 0-peak] at ``points`` (n, 3) [m] of the device at resonance: the reduced model's
        state, the mode plus every other mode's quasi-static part (``modalfe.response.forced.resonant_state``)."""
        from modalfe.response.forced import Damping, resonant_state

        if self.mode is None:
            raise ContactError("points: the chain has no solved mode (a reduced model alone knows only its outputs)")
        if not math.isclose(self.frequency, self.rom.frequency, rel_tol=1e-12):
            raise ContactError(f"frequency: amplitudes at points are at resonance ({self.rom.frequency:.6g} Hz), "
                               f"not {self.frequency:.6g} Hz")
        p = np.atleast_2d(np.asarray(points, dtype=float))
        if p.ndim != 2 or p.shape[1] != 3:
            raise ContactError(f"points: expected an (n, 3) array [m], got shape {p.shape}")
        state = resonant_state(self.mode, damping=Damping(zeta=self.rom.zeta))
        return np.abs(self.mode.model.displacement_probes(p) @ state)[2 * len(p):]

    def reduction_at(self, amplitude: float) -> ContactState:
        """The contact model's state at W [m, 0-peak]: what the chain feeds it, nothing added."""
        return self.contact.state(require("amplitude", amplitude, nonnegative=True))

    def outcome(self, voltage: float, output: str | None = None) -> Outcome:
        """The felt outcome at ``voltage`` [V] (module docstring), the reduction's range from the amplitude's
        stated error."""
        output = output or self.output
        W = self.amplitude(voltage, output)
        e = self.error(f"amplitude:{output}")
        states = self.contact.states([W] + ([W * max(1 - e, 0.0), W * (1 + e)] if math.isfinite(e) else []))
        here = states[0]
        span = (min(s.reduction for s in states), max(s.reduction for s in states))
        current, current_error, power, power_error = self._drawn(float(voltage))
        return Outcome(float(voltage), output, W, e, here.reduction, span, here.uncertainty, here.flight_ratio,
                       current, current_error, power, power_error, self.rom.envelope_time_constant,
                       self.error("time_constant"))

    def _drawn(self, voltage: float) -> tuple[float, float, float, float]:
        """(current amplitude V |Y| [A], its error, mean power V^2 Re(Y) / 2 [W], its error): Re Y = 1 / R1 at
        resonance carries R1's stated error, |Y| the first-order bound (|G| e_R1 + |B| (e_C0 + e_f)) / |Y|."""
        if not self.rom.is_voltage_driven:
            return NO_ERROR, NO_ERROR, NO_ERROR, NO_ERROR
        Y = complex(self.rom.admittance(self.frequency))
        e_g = self.error("bvd:R1")
        e_b = self.error("bvd:C0") + self.error("time_constant")  # the frequency's error is the time constant's
        return (voltage * abs(Y), (abs(Y.real) * e_g + abs(Y.imag) * e_b) / abs(Y), voltage**2 * Y.real / 2, e_g)

    def voltage_for(self, reduction: float, output: str | None = None) -> VoltageFor:
        """The voltage [V] at which the reduction at ``output`` first reaches ``reduction``: the amplitude
        ``amplitude_for`` finds over this chain's amplitude per volt."""
        output = output or self.output
        W = amplitude_for(self.contact, reduction)
        return VoltageFor(reduction, output, W / self.amplitude_per_volt(output), W,
                          self.error(f"amplitude:{output}"))

    def foot_curve(self, voltage) -> ContactCurve:
        """``foot.simulate_contact`` over ``voltage`` [V] with this chain's amplitude per volt (a foot chain)."""
        if not isinstance(self.contact, FootContact):
            raise ContactError("contact: a friction curve against voltage needs the foot model")
        c = self.contact
        return simulate_contact(voltage=values("voltage", voltage), amplitude_per_volt=self.amplitude_per_volt(),
                                preload=c.preload, speed=c.speed, parameters=c.parameters)


def amplitude_for(contact: Contact, reduction: float, rtol: float = SEARCH_RTOL) -> float:
    """The amplitude W [m, 0-peak] at which ``contact``'s reduction first reaches ``reduction``: W doubled from
    SEARCH_START until the contact model's reduction reaches it, then Brent's method (relative tolerance ``rtol``)
    between the last amplitude below and the first at or above it. That is the first crossing wherever the curve
    rises monotonically within that octave. The finger's curve at 66 kHz dips and recovers near 0.7 um pp, and there
    Brent may return a later crossing of the same octave."""
    from scipy.optimize import brentq

    target = require("reduction", reduction)
    if not 0 < target < 1:
        raise ContactError(f"reduction: a fraction strictly between 0 and 1, got {target:g}")
    low, high = 0.0, SEARCH_START
    for _ in range(SEARCH_DOUBLINGS):
        if contact.state(high).reduction >= target:
            break
        low, high = high, 2 * high
    else:
        raise ContactError(f"reduction: {target:g} is not reached below {high:.3g} m (0-peak)")
    return float(brentq(lambda w: contact.state(w).reduction - target, low, high, rtol=rtol, xtol=1e-15))


def foot_count(rom: ReducedModel) -> int | None:
    """Feet sharing the load according to the reduced model's outputs (``feet_among``)."""
    return feet_among(rom.shapes)


def foot_outputs(outputs) -> list[str]:
    """The named outputs that are feet: ``foot*`` (a point given as (name, (x, y, z)) is none)."""
    return [o for o in outputs if isinstance(o, str) and o.startswith("foot")]


def feet_among(outputs) -> int | None:
    """Feet sharing the load according to output names: the ``foot*`` ones where there are two or more (the Cu-Be
    plate has 4); one foot output alone says nothing of how many there are (None)."""
    feet = foot_outputs(outputs)
    return len(feet) if len(feet) > 1 else None


def chain_from_rom(rom: ReducedModel, contact: Contact, *, output: str | None = None, frequency: float | None = None,
                   feet: int | None = None, errors: Mapping[str, float] | None = None,
                   mode: Mode | None = None) -> HapticChain:
    """The chain of a reduced model ``rom`` and a contact model: drive at ``frequency`` [Hz] (default the
    resonance), the contact at ``output`` (default the reference); a foot model gets the frequency and ``feet``
    (default ``foot_count``)."""
    output = output or rom.reference
    if output not in rom.shapes:
        raise ContactError(f"output: {output!r} is not an output of the reduced model ({', '.join(rom.shapes)})")
    frequency = rom.frequency if frequency is None else require("frequency", frequency, positive=True)
    tuned = contact.tuned(frequency, feet or foot_count(rom))
    return HapticChain(rom, tuned, output, frequency, dict(errors or {}), mode)


def haptic_chain(scene: Scene, contact: Contact, *, output: str | None = None, feet: int | None = None,
                 **question) -> HapticChain:
    """The chain of ``scene``'s working mode (``modalfe.response.figures.forced_figures`` with ``question``: its
    selector, near, damping, outputs and resolution) and ``contact``, with ``forced``'s stated errors."""
    from modalfe.response.figures import forced_figures

    fig = forced_figures(scene, **question)
    errors = {name: e for name, (e, _) in fig.errors.items()}
    return chain_from_rom(fig.rom, contact, output=output, feet=feet, errors=errors, mode=fig.mode)


# ----------------------------------------------------------------------------------------------
# Haptic map
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class HapticMap:
    """The friction reduction over points of a touch surface (or at the feet) at one voltage.

    points (n, 3) [m]; amplitude (n,) [m, 0-peak]; reduction (n,), and reduction_low / reduction_high at the
    amplitude -+ its stated error, widened by the contact states' uncertainty (a chaotic finger's time average);
    flight_ratio (n,) [%]; table: the contact states the map interpolates (linearly in the amplitude); bracket (n,):
    the spread of the two table states around each point, which bounds the interpolation error where the curve is
    monotone between them; weights (n,): each point's share of the area.
    """

    voltage: float
    frequency: float
    points: np.ndarray
    amplitude: np.ndarray
    amplitude_error: float
    reduction: np.ndarray
    reduction_low: np.ndarray
    reduction_high: np.ndarray
    flight_ratio: np.ndarray
    bracket: np.ndarray
    weights: np.ndarray
    table: tuple[ContactState, ...]
    contact: str

    def area_fraction(self, required: float) -> tuple[float, float, float]:
        """(fraction of the area where the reduction reaches ``required``, and that fraction at the reduction's low
        and high ends: the amplitude's stated error and the contact states' uncertainty)."""
        w = self.weights / self.weights.sum()
        return tuple(float(w[r >= required].sum()) for r in (self.reduction, self.reduction_low, self.reduction_high))

    def reduction_slope(self) -> np.ndarray:
        """(n,) dR / dW [1/m] of the map's interpolant at each point's amplitude: the slope of the table segment it
        lies in (the right-hand one at a table amplitude)."""
        grid = np.array([s.amplitude for s in self.table])
        red = np.array([s.reduction for s in self.table])
        i = np.clip(np.searchsorted(grid, self.amplitude, side="right"), 1, len(grid) - 1)
        return (red[i] - red[i - 1]) / (grid[i] - grid[i - 1])

    def write_csv(self, path: str | Path) -> None:
        """x, y, z [m], amplitude [m 0-peak], reduction and its range, flight ratio [%], weight, one row a point."""
        header = "x_m,y_m,z_m,amplitude_m,reduction,reduction_low,reduction_high,flight_ratio_percent,area_weight"
        data = np.column_stack([self.points, self.amplitude, self.reduction, self.reduction_low,
                                self.reduction_high, self.flight_ratio, self.weights])
        np.savetxt(path, data, delimiter=",", header=header, comments="", fmt="%.9g")

    def write_vtu(self, path: str | Path) -> None:
        """A point cloud (VTK vertex cells) with the same fields as the CSV (meshio)."""
        import meshio

        cells = [("vertex", np.arange(len(self.points)).reshape(-1, 1))]
        meshio.write(str(path), meshio.Mesh(self.points, cells, point_data={
            "amplitude_m": self.amplitude, "reduction": self.reduction, "reduction_low": self.reduction_low,
            "reduction_high": self.reduction_high, "flight_ratio_percent": self.flight_ratio}))


def surface_points(scene: Scene, *, part: str | None = None, side: str = "zmax", count: int = 400
                   ) -> tuple[np.ndarray, np.ndarray]:
    """(points (n, 3) [m], area weights (n,)) of a face of ``part`` (default the main part) of the whole device: the
    centres of a grid of about ``count`` equal cells (n >= count)."""
    full = scene.full_assembly()
    box = full.part(part) if part is not None else full.main_part
    axis, c, lo, hi = box.face_bounds(side)
    if count < 1:
        raise ContactError(f"count: at least one point, got {count}")
    a, b = [k for k in range(3) if k != axis]
    la, lb = hi[a] - lo[a], hi[b] - lo[b]
    na = max(1, math.ceil(math.sqrt(count * la / lb)))
    nb = max(1, math.ceil(count / na))
    ua = lo[a] + (np.arange(na) + 0.5) * la / na
    ub = lo[b] + (np.arange(nb) + 0.5) * lb / nb
    A, B = np.meshgrid(ua, ub)
    points = np.zeros((A.size, 3))
    points[:, a], points[:, b], points[:, axis] = A.ravel(), B.ravel(), c
    return points, np.full(A.size, la * lb / A.size)


def haptic_map(chain: HapticChain, points: np.ndarray, voltage: float, *, weights: np.ndarray | None = None,
               amplitude_per_volt: np.ndarray | None = None, table_points: int = 17,
               progress: bool = False) -> HapticMap:
    """The reduction at ``points`` (n, 3) [m] at ``voltage`` [V]: the amplitude at each point
    (``HapticChain.amplitude_per_volt_at``, unless given) and ``contact_map`` with the chain's contact, frequency and
    stated amplitude error; ``weights``: area shares (default equal); ``progress``: a tqdm bar over the table."""
    volts = require("voltage", voltage, nonnegative=True)
    apv = chain.amplitude_per_volt_at(points) if amplitude_per_volt is None else np.asarray(amplitude_per_volt)
    e = chain.error(f"amplitude:{chain.output}")
    return contact_map(chain.contact, chain.frequency, points, volts, volts * apv, e if math.isfinite(e) else 0.0,
                       weights=weights, table_points=table_points, progress=progress)


def contact_map(contact: Contact, frequency: float, points: np.ndarray, voltage: float, amplitude: np.ndarray,
                amplitude_error: float, *, weights: np.ndarray | None = None, table_points: int = 17,
                progress: bool = False) -> HapticMap:
    """The map of ``contact`` (already tuned to ``frequency`` [Hz]) at ``points`` (n, 3) [m] whose amplitudes W (n,)
    [m, 0-peak] at ``voltage`` [V] are given, with a relative ``amplitude_error``: the contact model tabulated at
    ``table_points`` amplitudes from 0 to the largest W (1 + error) and interpolated linearly."""
    if table_points < 2:
        raise ContactError(f"table_points: at least 2, got {table_points}")
    W, e = np.asarray(amplitude, dtype=float), amplitude_error
    top = max(float(W.max()) * (1 + e), SEARCH_START)
    table = tuple(contact.table(np.linspace(0.0, top, table_points), progress))
    grid = np.array([s.amplitude for s in table])
    red = np.array([s.reduction for s in table])

    def at(w: np.ndarray) -> np.ndarray:
        return np.interp(w, grid, red)

    i = np.clip(np.searchsorted(grid, W), 1, len(grid) - 1)
    ends = np.stack([at(W), at(W * max(1 - e, 0.0)), at(W * (1 + e))])
    # a time-averaged state's uncertainty widens the range by the larger of the two table states' around the point
    unc = np.array([s.uncertainty for s in table])
    u = np.maximum(unc[i], unc[i - 1])
    return HapticMap(voltage, frequency, np.atleast_2d(np.asarray(points, dtype=float)), W, e, at(W),
                     ends.min(axis=0) - u, ends.max(axis=0) + u, np.interp(W, grid, [s.flight_ratio for s in table]),
                     np.abs(red[i] - red[i - 1]), np.ones(len(W)) if weights is None else np.asarray(weights),
                     table, contact.describe())


def _finite(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None

