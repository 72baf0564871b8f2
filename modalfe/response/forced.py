"""Forced response to a drive voltage: damping, full FE harmonic solves, the reduced modal model,
admittance and the Butterworth-Van Dyke circuit of the working mode.

Full FE harmonic response (free unknowns x, drive V on the driven electrodes):

    (A - omega^2 B + i omega C) x = F V,   F = -T^T K x_1V,   Q = F^T x + C_b V

with C = alpha M + beta K_uu (Rayleigh). A modal damping ratio zeta (or Q = 1 / 2 zeta) is applied
to the full model as the stiffness-proportional beta = 2 zeta / omega_r that gives zeta at the
working mode, and said so in the output.

Reduced model of one mode r (mass-normalised shape v, theta = v^T F): the modal coordinate obeys
q'' + 2 zeta omega_r q' + omega_r^2 q = theta V; outputs u_j = phi_j q + D_j V, with D_j the quasi-
static contribution of every other mode, taken from one undamped full solve beside resonance
(residual flexibility); charge Q / V = C_0 + theta^2 / (omega_r^2 - omega^2 + 2 i zeta omega_r omega).
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from modalfe.errors import SceneError, SolverError
from modalfe.models.constraints import free_values
from modalfe.response.loads import load_vector, output_operators
from modalfe.results.coupling import k_eff
from modalfe.results.modes import Mode
from modalfe.scene.scene import check_underdamped

# outputs whose normal motion is within this fraction of the largest count as equal when the reference is
# chosen: symmetric outputs differ by the solver's rounding (~1e-10), real differences are >1e-3
REFERENCE_TIE = 1e-6
# a reference whose normal motion is below this share of the outputs' largest motion sits on a node: the Lanczos
# vectors meet a relative 1e-8 on the eigenvalue (``modalfe.solve.eigen``'s tolerance), which leaves a vector's error
# at about that over the relative gap to the next mode (~1e-2 between a device's modes), so a smaller component is
# rounding (a symmetric cantilever's sideways bending at its upper face: 1e-12 in one run, 3e-9 in another) and the
# reduced model would divide by it
NODE_BELOW = 1e-6
# the reduced model's JSON: /2 adds device_mass (issue 37); a /1 file reads with device_mass unknown (NaN)
ROM_FORMAT = "modalfe.ReducedModel/2"
ROM_FORMATS_READ = ("modalfe.ReducedModel/1", ROM_FORMAT)


@dataclass(frozen=True)
class Damping:
    """Damping as a modal ratio ``zeta``, a quality factor ``Q`` (zeta = 1 / 2Q), or Rayleigh
    ``alpha`` [1/s] and ``beta`` [s] (C = alpha M + beta K)."""

    zeta: float | None = None
    Q: float | None = None
    alpha: float = 0.0
    beta: float = 0.0

    def __post_init__(self) -> None:
        given = sum(x is not None for x in (self.zeta, self.Q)) + (self.alpha != 0 or self.beta != 0)
        if given != 1:
            raise SceneError("damping: give exactly one of zeta, Q, or Rayleigh alpha/beta")
        for name in ("zeta", "Q", "alpha", "beta"):
            v = getattr(self, name)
            if v is not None and not (math.isfinite(v) and v >= 0):
                raise SceneError(f"damping.{name}: must be finite and >= 0, got {v}")
        if self.Q is not None and self.Q == 0:
            raise SceneError("damping.Q: must be positive")
        if self.zeta is not None or self.Q is not None:
            check_underdamped(f"damping.{'zeta' if self.zeta is not None else 'Q'}", self.ratio(1.0))

    @classmethod
    def parse(cls, text: str) -> Damping:
        """``zeta=0.025``, ``Q=150`` or ``rayleigh=ALPHA,BETA``."""
        key, _, value = str(text).partition("=")
        try:
            numbers = [float(v) for v in value.split(",")]
        except ValueError:
            numbers = []
        if key == "zeta" and len(numbers) == 1:
            return cls(zeta=numbers[0])
        if key == "Q" and len(numbers) == 1:
            return cls(Q=numbers[0])
        if key == "rayleigh" and len(numbers) == 2:
            return cls(alpha=numbers[0], beta=numbers[1])
        raise SceneError(f"damping: expected zeta=Z, Q=Q or rayleigh=ALPHA,BETA, got '{text}'")

    def ratio(self, omega: float) -> float:
        """Modal damping ratio at angular frequency ``omega`` [rad/s]."""
        if self.zeta is not None:
            return self.zeta
        if self.Q is not None:
            return 1.0 / (2.0 * self.Q)
        return self.alpha / (2.0 * omega) + self.beta * omega / 2.0

    def rayleigh_at(self, omega: float) -> tuple[float, float]:
        """(alpha, beta) for the full model: as given, or beta = 2 zeta / omega_r."""
        if self.zeta is None and self.Q is None:
            return self.alpha, self.beta
        return 0.0, 2.0 * self.ratio(omega) / omega

    def describe(self) -> str:
        if self.zeta is not None:
            return f"modal zeta = {self.zeta:g}"
        if self.Q is not None:
            return f"quality factor Q = {self.Q:.4g} (zeta = {1 / (2 * self.Q):.3g})"
        return f"Rayleigh alpha = {self.alpha:g} 1/s, beta = {self.beta:g} s"


@dataclass(frozen=True)
class ReducedModel:
    """Single-mode reduced model of a working mode, for the friction simulators and controllers.

    frequency [Hz], zeta [-], reference output name; at the reference output: modal_mass [kg],
    stiffness [N/m], damping [N s/m], force_factor [N/V]; shapes: output -> (ux, uy, uz) of the
    mode relative to the reference's normal (z) value; feedthrough: output -> (3,) [m/V] quasi-static
    response of all other modes; capacitance: C0 of the BVD [F] (the free capacitance less this mode's share,
    docs/capacitance.md) and theta [C/(m)] =
    charge per unit reference displacement. ``drive_load`` and ``load_unit``: what the model is driven by (a voltage
    unless said otherwise; then the force factor is N per ``load_unit`` and there is no circuit, C0 = 0).
    ``device_mass`` [kg]: the whole device's mass (its rigid translation's, r^T M r; NaN where the model cannot
    translate its unknowns rigidly), the mass the feet carry in the contact models.
    """

    label: str
    frequency: float
    zeta: float
    damping_description: str
    reference: str
    modal_mass: float
    stiffness: float
    damping: float
    force_factor: float
    capacitance: float
    shapes: dict[str, list[float]] = field(default_factory=dict)
    feedthrough: dict[str, list[float]] = field(default_factory=dict)
    drive_load: str = "voltage on the driven electrodes"
    load_unit: str = "V"
    device_mass: float = float("nan")

    @property
    def is_voltage_driven(self) -> bool:
        return self.load_unit == "V"

    def _circuit(self, what: str) -> None:
        if not self.is_voltage_driven:
            raise SolverError(f"{what}: the reduced model is driven by a {self.drive_load}, not a voltage: no circuit")

    @property
    def omega(self) -> float:
        return 2 * math.pi * self.frequency

    def frf(self, frequency, output: str | None = None, component: int = 2) -> np.ndarray:
        """Displacement per volt [m/V] (complex) at ``output`` (default: the reference)."""
        output = output or self.reference
        w = 2 * np.pi * np.asarray(frequency, dtype=float)
        modal = self.force_factor / (self.stiffness - self.modal_mass * w**2 + 1j * self.damping * w)
        return modal * self.shapes[output][component] + self.feedthrough[output][component]

    def admittance(self, frequency) -> np.ndarray:
        """Electrical admittance Y = i omega Q / V [S] (complex)."""
        self._circuit("admittance")
        w = 2 * np.pi * np.asarray(frequency, dtype=float)
        motional = self.force_factor**2 / (self.stiffness - self.modal_mass * w**2 + 1j * self.damping * w)
        return 1j * w * (self.capacitance + motional)

    def impedance(self, frequency) -> np.ndarray:
        """Electrical impedance Z = 1 / Y [ohm] (complex)."""
        return 1.0 / self.admittance(frequency)

    @property
    def bvd(self) -> dict[str, float]:
        """Butterworth-Van Dyke circuit: C0 [F], R1 [ohm], L1 [H], C1 [F] (IEEE Std 176-1987)."""
        self._circuit("bvd")
        n = self.force_factor
        return {"C0": self.capacitance, "R1": self.damping / n**2, "L1": self.modal_mass / n**2,
                "C1": n**2 / self.stiffness}

    @property
    def antiresonance(self) -> float:
        """fa [Hz] of the circuit: fr sqrt(1 + C1 / C0)."""
        return self.frequency * math.sqrt(1 + self.bvd["C1"] / self.capacitance)

    @property
    def k_eff(self) -> float:
        """Effective coupling factor of the circuit from its fr and fa (``modalfe.results.coupling.k_eff``)."""
        return k_eff(self.frequency, self.antiresonance)

    @property
    def envelope_time_constant(self) -> float:
        """Amplitude build-up time constant tau = 1 / (zeta omega_r) = Q / (pi f) [s]."""
        return 1.0 / (self.zeta * self.omega)

    def amplitude_per_volt(self, output: str | None = None) -> float:
        """Peak normal amplitude per volt at resonance [m/V] (0-peak)."""
        return float(abs(self.frf(self.frequency, output)))

    def state_space(self, outputs: list[str] | None = None):
        """(A, B, C, D): state (x, x') of the reference, input V, outputs the normal displacement."""
        outputs = outputs or list(self.shapes)
        m, k, c, n = self.modal_mass, self.stiffness, self.damping, self.force_factor
        A = np.array([[0.0, 1.0], [-k / m, -c / m]])
        B = np.array([[0.0], [n / m]])
        C = np.array([[self.shapes[o][2], 0.0] for o in outputs])
        D = np.array([[self.feedthrough[o][2]] for o in outputs])
        return A, B, C, D

    def to_json(self) -> str:
        return json.dumps({"format": ROM_FORMAT, **asdict(self)}, indent=2)

    @classmethod
    def from_json(cls, text: str) -> ReducedModel:
        data = json.loads(text)
        if data.pop("format", None) not in ROM_FORMATS_READ:
            raise SceneError(f"reduced model: not a {' or '.join(ROM_FORMATS_READ)} JSON document")
        return cls(**data)

    def save(self, path: str | Path) -> None:
        Path(path).write_text(self.to_json())

    @classmethod
    def load(cls, path: str | Path) -> ReducedModel:
        return cls.from_json(Path(path).read_text())


def drive_vectors(model, load=None):
    """(T, F, C_b, x_p): constraints, the load on the free unknowns, the part of the charge that does not depend
    on them (voltage drive; zero for other loads) and the prescribed response (driven electrodes at 1 V)."""
    T = model.constraints("short").T
    if load is None or load.kind == "voltage":
        load_full = model.voltage_load(1.0)
        x_v = model.prescribed_potential(1.0)
        return T, T.T @ load_full, float(x_v @ load_full), x_v
    load_full, x_p = load_vector(model, load)
    return T, T.T @ load_full, 0.0, x_p


_BESIDE: dict = {}  # the last mode's solve beside resonance, shared by ``reduce`` and ``resonant_state``


def beside_resonance(mode: Mode, load=None):
    """(T, F, C_b, x_p, x_d, omega_d): one undamped full solve at 0.97 omega_r, for the quasi-static
    contribution of every other mode (residual flexibility). It reuses the pencil and the factorization the mode's
    eigen solve kept (``modalfe.solve.levels.short_circuit_pencil``), solving at omega_d from the factorization at
    the eigen solve's shift (``modalfe.solve.linalg.shifted_solve``: as accurate as a new factorization)."""
    from modalfe.solve.levels import short_circuit_pencil
    from modalfe.solve.linalg import shifted_solve

    if _BESIDE.get("mode") is mode and _BESIDE.get("load") == load:
        return _BESIDE["result"]
    model = mode.model
    T, F, C_b, x_v = drive_vectors(model, load)
    A, B, factor = short_circuit_pencil(model, factorized=True)
    omega_d = 0.97 * mode.omega
    result = (T, F, C_b, x_v, shifted_solve(A, B, omega_d**2, factor)(F), omega_d)
    _BESIDE.clear()
    _BESIDE.update(mode=mode, load=load, result=result)
    return result


def _charge(mode: Mode, load=None) -> tuple[float, float, float]:
    """(theta: the mode's modal force per unit load, its residual modal displacement at 0.97 omega_r, C0 [F]: the
    charge per volt of everything but the mode) of the drive, from one full solve beside resonance."""
    T, F, C_b, _, x_d, omega_d = beside_resonance(mode, load)
    theta = float(free_values(T, mode.shape) @ F)
    modal_d = theta / (mode.omega**2 - omega_d**2)
    return theta, modal_d, float(F @ x_d + C_b - theta * modal_d)


def one_mode_antiresonance(mode: Mode) -> float:
    """fa [Hz] of ``mode``'s one-mode circuit driven by voltage (``ReducedModel.antiresonance``: fr sqrt(1 + C1 /
    C0), C1 / C0 = theta^2 / (omega_r^2 C0) whatever the output that carries the modal mass)."""
    theta, _, capacitance = _charge(mode)
    return mode.frequency * math.sqrt(1 + theta**2 / (mode.omega**2 * capacitance))


@dataclass(frozen=True)
class OpenCircuit:
    """A mode in both circuits, from the FE open circuit of its own model: ``label`` (the short-circuit mode's: a mode
    keeps its label in both circuits), ``fr`` [Hz] (short circuit), ``fa`` [Hz] (its open-circuit partner by shape,
    ``modalfe.results.coupling.antiresonance``) and ``k_eff`` = sqrt((fa^2 - fr^2) / fa^2) (IEEE Std 176-1987,
    eq. 100). Not the one-mode circuit's fa (``ReducedModel.antiresonance``, the BVD's)."""

    label: str
    fr: float
    fa: float

    @property
    def k_eff(self) -> float:
        """Effective coupling factor from fr and fa (``modalfe.results.coupling.k_eff``)."""
        return k_eff(self.fr, self.fa)


def open_circuit(mode: Mode, *, among=None, near: float | None = None) -> OpenCircuit:
    """``mode`` (short circuit) in open circuit: the one path by which ``table``, ``forced``, ``admittance``,
    ``report`` and the Python API (``sweep``'s ``coupling_extra``) give a mode's fa and k_eff. Its open-circuit
    partner by shape on the same model (``modalfe.solve.api.open_circuit_partner``; ``among``: the short-circuit
    ``Modes`` holding ``mode``, to size the solve), sought at ``near`` [Hz] (default: the shift of its model's kept
    short-circuit solve, ``modalfe.solve.levels.short_circuit_pencil``: that factorization reused) and else where the
    one-mode circuit puts it (a strongly coupled mode's fa lies past other modes: a disc's R1). Whichever shift finds
    it, the partner is the one mode of that shape. SolverError where neither holds it."""
    from modalfe.solve.api import open_circuit_partner
    from modalfe.solve.levels import short_circuit_pencil

    if near is None:
        kept = short_circuit_pencil(mode.model, factorized=True)[2]
        near = None if kept is None else math.sqrt(max(kept[1], 0.0)) / (2 * math.pi)
    if near:
        try:
            return OpenCircuit(mode.label, mode.frequency, open_circuit_partner(mode, among=among, near=near).frequency)
        except SolverError:
            pass
    fa = open_circuit_partner(mode, among=among, near=one_mode_antiresonance(mode)).frequency
    return OpenCircuit(mode.label, mode.frequency, fa)


def _check_driven(mode: Mode, load, theta: float) -> None:
    """SolverError where ``load``'s modal force on ``mode`` is rounding: below ``NODE_BELOW`` of what the same load
    would give applied where the mode moves most, along its motion (the load's size times the shape's largest
    displacement): a sideways force on a symmetric plate's bending mode, a pressure on a twisting one. Its figures
    per unit load would be rounding too. (The sum of the load's own terms is no scale: a sideways force meets only
    the mode's sideways rounding, 1e-11 N/N on the bimorph's bending-z 1.)"""
    F = beside_resonance(mode, load)[1]
    displacement = mode.shape[: getattr(mode.model, "n_u", len(mode.shape))]
    scale = float(np.abs(F).sum()) * float(np.abs(displacement).max())
    if abs(theta) < NODE_BELOW * scale:
        raise SolverError(f"load: the {load.describe()} does not drive mode {mode.label} (its modal force is "
                          f"{abs(theta) / scale:.0e} of the same load's along the mode's largest motion: rounding, the "
                          f"load is orthogonal to the mode)")


def reduce(mode: Mode, *, outputs, damping: Damping, reference: str | None = None, load=None) -> ReducedModel:
    """Reduced model of ``mode`` (short circuit, bound to its model) at the named ``outputs``; the
    ``reference`` output (default: the one with the largest normal motion) carries the modal mass.
    ``load`` (``modalfe.response.loads.Load``, default: 1 V on the driven electrodes) sets what the force
    factor is per: N/V for a voltage, N/N for a force, N/Pa for a pressure, N/(m/s^2) for a base acceleration."""
    if mode.circuit != "short":
        raise SolverError(f"mode: the reduced model needs a short-circuit mode, got {mode.circuit}")
    model = mode.model
    T, _, _, x_v, x_d, _ = beside_resonance(mode, load)
    probes = output_operators(model, outputs)
    theta, modal_d, capacitance = _charge(mode, load)  # residual of the other modes: one solve beside resonance
    if load is not None and load.kind != "voltage":
        _check_driven(mode, load, theta)
    omega_r = mode.omega
    phi = {name: P @ mode.shape for name, P in probes.items()}
    if reference is None:  # the output that moves most; among equals (symmetric feet) the first listed, so the
        # choice does not depend on the eigen solver's rounding (it changed between runs before)
        largest = max(abs(phi[name][2]) for name in phi)
        reference = next(name for name in phi if abs(phi[name][2]) >= (1 - REFERENCE_TIE) * largest)
    elif reference not in phi:
        raise SceneError(f"reference: no output '{reference}'; outputs: {sorted(phi)}")
    full_d = {name: P @ (T @ x_d + x_v) for name, P in probes.items()}
    feed = {name: (full_d[name] - phi[name] * modal_d) for name in probes}
    voltage = load is None or load.kind == "voltage"
    capacitance = capacitance if voltage else 0.0
    ref = phi[reference][2]
    if abs(ref) < NODE_BELOW * max(np.abs(np.concatenate(list(phi.values())))):
        raise SolverError(f"outputs: the reference '{reference}' sits on a node of mode {mode.label}")
    zeta = damping.ratio(omega_r)
    check_underdamped("damping", zeta, f" at {mode.frequency:.6g} Hz")
    copies = model.copies  # a half (quarter) model: the whole device's masses, forces and charges
    m_eff = copies / ref**2
    return ReducedModel(
        label=mode.label, frequency=mode.frequency, zeta=zeta, damping_description=damping.describe(),
        reference=reference, modal_mass=m_eff, stiffness=m_eff * omega_r**2, damping=2 * zeta * omega_r * m_eff,
        force_factor=copies * theta / ref, capacitance=copies * capacitance,
        shapes={n: list(map(float, phi[n] / ref)) for n in phi},
        feedthrough={n: list(map(float, feed[n])) for n in feed}, device_mass=_device_mass(model),
        **({} if voltage else {"drive_load": load.describe(), "load_unit": load.unit}),
    )


def _device_mass(model) -> float:
    """The whole device's mass [kg], r^T M r for the unit rigid translation r along z (solid model; the
    axisymmetric model's along its axis), else NaN."""
    from modalfe.response.loads import rigid_translations

    if not (hasattr(model, "rigid_translations") or hasattr(model, "u_basis")):
        return float("nan")
    r = rigid_translations(model)[2, : model.n_u]
    return float(model.copies * (r @ (model.M[: model.n_u, : model.n_u] @ r)))


def resonant_state(mode: Mode, *, damping: Damping, load=None) -> np.ndarray:
    """Full DOF response (complex) per unit load at the mode's resonance, as the reduced model has it: the mode
    at theta / (2 i zeta omega_r^2) plus the quasi-static contribution of every other mode (the residual of the
    solve beside resonance) and the prescribed potential."""
    T, _, _, x_p, x_d, _ = beside_resonance(mode, load)
    omega_r = mode.omega
    theta, modal_d, _ = _charge(mode, load)
    residual = T @ x_d + x_p - mode.shape * modal_d
    zeta = damping.ratio(omega_r)
    return mode.shape * (theta / (2j * zeta * omega_r**2)) + residual


@dataclass(frozen=True)
class HarmonicResponse:
    """Full FE response per volt: frequency [Hz]; displacement: output -> (n_f, 3) complex [m/V];
    admittance (n_f,) complex [S]; damping stated."""

    frequency: np.ndarray
    displacement: dict[str, np.ndarray]
    admittance: np.ndarray
    damping_description: str
    dissipated: np.ndarray | None = None  # time-averaged power lost in the damping per volt^2 [W/V^2]

    def velocity(self, output: str) -> np.ndarray:
        return 2j * np.pi * self.frequency[:, None] * self.displacement[output]

    def acceleration(self, output: str) -> np.ndarray:
        return -((2 * np.pi * self.frequency[:, None]) ** 2) * self.displacement[output]

    @property
    def impedance(self) -> np.ndarray:
        """Electrical impedance Z = 1 / Y [ohm] (complex)."""
        return 1.0 / self.admittance


def harmonic_response(model, frequency, *, outputs, damping: Damping, reference_omega: float,
                      load=None) -> HarmonicResponse:
    """Direct damped solve at each frequency [Hz] (one complex factorization each), per unit ``load``
    (default 1 V on the driven electrodes; the admittance is zero for other loads)."""
    from modalfe.solve.linalg import solve_complex

    T, F, C_b, x_v = drive_vectors(model, load)
    A = (T.T @ model.K @ T).tocsc()
    B = (T.T @ model.M @ T).tocsc()
    alpha, beta = damping.rayleigh_at(reference_omega)
    C = (T.T @ model.rayleigh_damping(alpha, beta) @ T).tocsc()
    probes = output_operators(model, outputs)
    voltage = load is None or load.kind == "voltage"
    freqs = np.atleast_1d(np.asarray(frequency, dtype=float))
    disp = {name: np.zeros((len(freqs), 3), dtype=complex) for name in probes}
    Y = np.zeros(len(freqs), dtype=complex)
    dissipated = np.zeros(len(freqs))
    from modalfe.progress import counted

    for i, f in enumerate(counted(freqs, f"direct harmonic FE ({A.shape[0]} unknowns)", unit="frequency")):
        w = 2 * np.pi * f
        x = solve_complex((A - w**2 * B + 1j * w * C).tocsr(), F)
        if not np.all(np.isfinite(x)):
            raise SolverError(f"harmonic solve at {f:g} Hz returned NaN")
        full = T @ x + x_v
        for name, P in probes.items():
            disp[name][i] = P @ full
        Y[i] = 1j * w * model.copies * (F @ x + C_b) if voltage else 0.0  # the whole device's charge
        dissipated[i] = 0.5 * w**2 * model.copies * float(np.real(np.conj(x) @ (C @ x)))  # the whole device
    description = damping.describe()
    if damping.zeta is not None or damping.Q is not None:
        description += f"; full model: Rayleigh beta = {beta:.3g} s (gives it at {reference_omega / 2 / np.pi:.0f} Hz)"
    return HarmonicResponse(freqs, disp, Y, description, dissipated)
