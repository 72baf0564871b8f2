"""Contact and friction simulators: feet on a substrate (seeds 000, 001), a fingertip on a plate
(seed 004), notch textures (seed 001).  Figures are in ``modalfe.plot.contact``."""

from modalfe.contact.finger import (
    EqualFriction,
    FingerCurve,
    FingerOrbit,
    FingerParameters,
    equal_friction,
    finger_steady_state,
    simulate_finger,
)
from modalfe.contact.foot import (
    ContactCurve,
    ContactOrbit,
    FootParameters,
    simulate_contact,
    steady_state,
)
from modalfe.contact.texture import NotchTexture, TextureRendering, render_texture

__all__ = [
    "ContactCurve", "ContactOrbit", "EqualFriction", "FingerCurve", "FingerOrbit", "FingerParameters",
    "FootParameters", "NotchTexture", "TextureRendering", "equal_friction",
    "finger_steady_state", "render_texture", "simulate_contact", "simulate_finger", "steady_state",
]
