"""Amplitude control by tuning the drive frequency above resonance (seed 001, section 6).

At a fixed drive voltage the vibration amplitude falls as the frequency moves above resonance; on
the quasi-linear part of that slope a controller sets the amplitude by moving the frequency. The
plant is the reduced model's slowly varying complex envelope a (x = Re(a e^{i omega t})):

    (2 i omega m + c) da/dt = theta V - (k - m omega^2 + i c omega) a

(from m x'' + c x' + k x = theta V cos omega t with a'' neglected)

whose steady state is the exact harmonic response and whose time constant is 2 m / c = 1 / (zeta omega_r).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from modalfe.errors import SceneError, SolverError


def amplitude_curve(rom, volts: float, frequency) -> np.ndarray:
    """Steady amplitude [m] (0-peak, reference output) at each drive frequency [Hz]."""
    return volts * np.abs(rom.frf(frequency))


@dataclass(frozen=True)
class QuasiLinearRegion:
    """Frequencies [Hz] between which amplitude vs frequency is straight to ``tolerance`` of the peak;
    ``slope`` [m/Hz] and amplitudes [m] at both ends."""

    f_low: float
    f_high: float
    slope: float
    amplitude_high: float
    amplitude_low: float
    tolerance: float


def quasi_linear_region(rom, volts: float, *, tolerance: float = 0.02, points: int = 400) -> QuasiLinearRegion:
    """The widest band above resonance where the curve stays within ``tolerance`` x peak of a line."""
    fr = rom.frequency
    f = np.linspace(fr, fr * (1 + 12 * rom.zeta), points)
    a = amplitude_curve(rom, volts, f)
    peak = a.max()
    start = int(np.argmax(a < 0.9 * peak))  # leave the rounded top of the peak
    best = (start, start + 2)
    for j in range(start + 2, points):
        i = best[0]
        line = np.interp(f[i:j + 1], [f[i], f[j]], [a[i], a[j]])
        if np.max(np.abs(a[i:j + 1] - line)) <= tolerance * peak:
            best = (i, j)
    i, j = best
    return QuasiLinearRegion(float(f[i]), float(f[j]), float((a[j] - a[i]) / (f[j] - f[i])), float(a[i]),
                             float(a[j]), tolerance)


@dataclass(frozen=True)
class ControlRun:
    """Closed-loop step: time [s], amplitude [m], drive frequency [Hz], and the response time [s]
    to come and stay within 5 % of the step."""

    time: np.ndarray
    amplitude: np.ndarray
    frequency: np.ndarray
    reference: np.ndarray
    response_time: float


def track_amplitude(rom, volts: float, *, start: float, target: float, closed_loop_time: float | None = None,
                    duration: float | None = None) -> ControlRun:
    """PI control of the drive frequency from amplitude ``start`` to ``target`` [m] (0-peak).

    PI zero on the envelope pole (Ti = 1 / (zeta omega_r)); gain for a closed-loop time constant
    ``closed_loop_time`` (default: the open-loop envelope time constant, which keeps the first
    proportional kick inside the quasi-linear range for steps of a third of it)."""
    from scipy.integrate import solve_ivp

    region = quasi_linear_region(rom, volts)
    for name, value in (("start", start), ("target", target)):
        if not (region.amplitude_low <= value <= region.amplitude_high):
            raise SceneError(f"{name}: {value:.3g} m is outside the quasi-linear range "
                             f"{region.amplitude_low:.3g}-{region.amplitude_high:.3g} m at {volts:g} V")
    m, c, k, n = rom.modal_mass, rom.damping, rom.stiffness, rom.force_factor
    tau = 2 * m / c
    tau_cl = closed_loop_time or tau
    gain = region.slope / (2 * np.pi)  # d amplitude / d omega  [m s / rad], negative
    kp = tau / (tau_cl * abs(gain))
    ki = kp / tau
    w0 = 2 * np.pi * float(np.interp(start, [region.amplitude_low, region.amplitude_high],
                                     [region.f_high, region.f_low]))
    a0 = n * volts / (k - m * w0**2 + 1j * c * w0)
    duration = duration or 10 * tau

    def omega_of(integral, error):
        return w0 - (kp * error + ki * integral)

    def rhs(t, y):
        a = y[0] + 1j * y[1]
        error = target - abs(a)
        w = omega_of(y[2], error)
        da = (n * volts - (k - m * w**2 + 1j * c * w) * a) / (2j * w * m + c)
        return [da.real, da.imag, error]

    sol = solve_ivp(rhs, (0.0, duration), [a0.real, a0.imag, 0.0], max_step=tau / 50, rtol=1e-8, atol=1e-14)
    if not sol.success:
        raise SolverError(f"amplitude control simulation failed: {sol.message}")
    amplitude = np.hypot(sol.y[0], sol.y[1])
    errors = target - amplitude
    frequency = np.array([omega_of(i, e) for i, e in zip(sol.y[2], errors)]) / (2 * np.pi)
    outside = np.abs(errors) > 0.05 * abs(target - start)
    response = float(sol.t[np.nonzero(outside)[0][-1] + 1]) if outside.any() and outside[-1] == 0 else float("nan")
    return ControlRun(sol.t, amplitude, frequency, np.full_like(sol.t, target), response)
