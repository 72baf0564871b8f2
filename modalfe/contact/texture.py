"""Notch textures rendered by amplitude control along a track (seed 001, sections 7-9).

The plate is moved by the user at speed V along an 87 mm track (seed 001 section 9).  A grating of
notches fixed in space (Fig. 12) is rendered by switching the vibration amplitude with the plate's
position (the "spatio-temporal conversion", Fig. 13): in a notch ("hole") the plate vibrates and slides
easily, elsewhere it does not.  At speed V a spatial period Lambda becomes a temporal modulation at
V / Lambda (Fig. 14), so the faster the user moves, the faster the amplitude must switch.

The amplitude follows its reference with the plate's step response, taken as first order with the
measured response time, about 1 ms with preload (seed 001 section 7, Fig. 11); the friction follows
the amplitude through the steady-state friction curve of ``modalfe.contact.foot`` (quasi-static: the
foot dynamics settle within a few hundred vibration periods, well under that millisecond).

Two controls:
- ``on_off`` (seed 001 section 8): the amplitude is ``amplitude_on`` in a notch and 0 elsewhere;
- ``proportional``: the notch depth sets a friction reference between the static friction and the
  friction at ``amplitude_on``, and the amplitude is the friction curve's inverse at that reference.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from modalfe.contact.foot import ContactCurve
from modalfe.contact.validation import require
from modalfe.errors import ContactError

TRACK_LENGTH = 87e-3  # m, seed 001 section 9: gratings rendered along 87 mm
RESPONSE_TIME = 1e-3  # s, seed 001 section 7 (Fig. 11): amplitude step response with preload
AMPLITUDE_ON = 0.65e-6  # m, seed 001 section 11: the amplitude felt "strong" (of 1.7 um available)
PROFILES = ("square", "sine")
CONTROLS = ("on_off", "proportional")


@dataclass(frozen=True)
class NotchTexture:
    """A grating of notches along the track (seed 001 Fig. 12).

    period : spatial period Lambda [m]; notch_width : width of each notch [m] (default half the
    period; square profile only); track_length [m]; profile : ``square`` (flat notches) or ``sine``
    (1-D sinusoidal grating, depth 0.5 (1 - cos(2 pi x / Lambda))).
    """

    period: float
    notch_width: float | None = None
    track_length: float = TRACK_LENGTH
    profile: str = "square"

    def __post_init__(self):
        require("period", self.period, positive=True)
        require("track_length", self.track_length, positive=True)
        if self.notch_width is not None:
            w = require("notch_width", self.notch_width, positive=True)
            if w >= self.period:
                raise ContactError(f"notch_width: must be shorter than the period ({self.period:g} m), got {w:g}")
        if self.profile not in PROFILES:
            raise ContactError(f"profile: expected one of {PROFILES}, got {self.profile!r}")

    @property
    def cycles(self) -> float:
        """Notches along the track (what seed 001's participants counted)."""
        return self.track_length / self.period

    def depth(self, x) -> np.ndarray:
        """Notch depth at position x [m]: 1 at the bottom of a notch (sliding), 0 on the plateau;
        notches are centred in each period, so the track starts and ends on a plateau."""
        x = np.asarray(x, float)
        if self.profile == "sine":
            return 0.5 * (1 - np.cos(2 * math.pi * x / self.period))
        width = self.notch_width if self.notch_width is not None else self.period / 2
        return (np.abs(np.mod(x, self.period) - self.period / 2) < width / 2).astype(float)


@dataclass(frozen=True, eq=False)
class TextureRendering:
    """Friction felt along the track.

    position [m]; time [s] (position / speed); reference : commanded amplitude [m, 0-peak];
    amplitude : amplitude reached through the plate's response [m]; friction_force [N];
    speed [m/s]; control : ``on_off`` or ``proportional``; response_time [s].
    """

    texture: NotchTexture
    position: np.ndarray
    time: np.ndarray
    reference: np.ndarray
    amplitude: np.ndarray
    friction_force: np.ndarray
    speed: float
    control: str
    response_time: float

    @property
    def modulation_frequency(self) -> float:
        """Temporal frequency of the amplitude switching, V / Lambda [Hz] (seed 001 Fig. 14)."""
        return self.speed / self.texture.period

    @property
    def contrast(self) -> float:
        """Friction swing along the track after the first notch [N]: max - min."""
        tail = self.position >= self.texture.period
        f = self.friction_force[tail] if tail.any() else self.friction_force
        return float(f.max() - f.min())

    def to_json(self) -> dict:
        t = self.texture
        return {"period_m": t.period, "notch_width_m": t.notch_width, "track_length_m": t.track_length,
                "profile": t.profile, "control": self.control, "speed_m_s": self.speed,
                "response_time_s": self.response_time, "modulation_frequency_hz": self.modulation_frequency,
                "contrast_n": self.contrast, "position_m": self.position.tolist(),
                "reference_m": self.reference.tolist(), "amplitude_m": self.amplitude.tolist(),
                "friction_force_n": self.friction_force.tolist()}


def _inverse_friction(curve: ContactCurve, amplitude_on: float):
    """Amplitude giving a friction between the static value and the friction at ``amplitude_on``:
    the inverse of the curve's non-increasing envelope on [0, amplitude_on]."""
    keep = curve.amplitude <= amplitude_on
    A = np.append(curve.amplitude[keep], amplitude_on)
    F = np.minimum.accumulate(np.append(curve.friction_force[keep], _friction(curve, amplitude_on)))
    strict = np.concatenate([[True], np.diff(F) < 0])  # drop the flat part before the onset
    A, F = A[strict], F[strict]

    def amplitude_for(f_ref):
        return np.interp(-np.asarray(f_ref), -F, A)
    return amplitude_for, F[-1]


def _friction(curve: ContactCurve, amplitude) -> np.ndarray:
    return np.interp(amplitude, curve.amplitude, curve.friction_force)


def render_texture(texture: NotchTexture, curve: ContactCurve, *, amplitude_on: float = AMPLITUDE_ON,
                   control: str = "on_off", response_time: float = RESPONSE_TIME,
                   samples_per_period: int = 200) -> TextureRendering:
    """Friction along the track for a user sliding at the friction curve's speed.

    curve : steady friction against amplitude at the user's preload and speed (``simulate_contact``),
    from 0 up to at least ``amplitude_on`` [m, 0-peak]; control : ``on_off`` or ``proportional``;
    response_time : first-order time constant of the amplitude [s] (seed 001: about 1 ms).
    """
    if control not in CONTROLS:
        raise ContactError(f"control: expected one of {CONTROLS}, got {control!r}")
    a_on = require("amplitude_on", amplitude_on, positive=True)
    tau = require("response_time", response_time, nonnegative=True)
    speed = require("speed", curve.speed, positive=True)
    if curve.amplitude.min() > 0 or curve.amplitude.max() < a_on:
        raise ContactError(f"curve: its amplitudes must span 0 to amplitude_on = {a_on:g} m, got "
                           f"{curve.amplitude.min():g} to {curve.amplitude.max():g} m")
    if int(samples_per_period) < 8:
        raise ContactError(f"samples_per_period: at least 8, got {samples_per_period!r}")
    dx = texture.period / int(samples_per_period)
    if tau > 0:
        dx = min(dx, speed * tau / 20)  # resolve the amplitude's response too
    x = np.linspace(0.0, texture.track_length, math.ceil(texture.track_length / dx) + 1)
    t = x / speed
    depth = texture.depth(x)
    if control == "on_off":
        ref = np.where(depth >= 0.5, a_on, 0.0)
    else:
        amplitude_for, f_on = _inverse_friction(curve, a_on)
        f_ref = curve.static_friction - depth * (curve.static_friction - f_on)
        ref = amplitude_for(f_ref)
    if tau > 0:  # exact first-order response to a reference held over each (uniform) step
        from scipy.signal import lfilter

        decay = math.exp(-(t[1] - t[0]) / tau)
        amp, _ = lfilter([0.0, 1.0 - decay], [1.0, -decay], ref, zi=[ref[0]])
    else:
        amp = ref.copy()
    return TextureRendering(texture=texture, position=x, time=t, reference=ref, amplitude=amp,
                            friction_force=_friction(curve, amp), speed=speed, control=control,
                            response_time=tau)
