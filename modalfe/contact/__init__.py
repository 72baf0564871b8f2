"""Contact and friction simulators: feet on a substrate (seeds 000, 001), a fingertip on a plate
(seed 004), notch textures (seed 001), and the chain from a working mode to the felt outcome (``chain``).
Figures are in ``modalfe.plot.contact``."""

from modalfe.contact.chain import (
    FingerContact,
    FootContact,
    HapticChain,
    HapticMap,
    Outcome,
    chain_from_rom,
    haptic_chain,
    haptic_map,
    surface_points,
)
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
    "ContactCurve",
    "ContactOrbit",
    "EqualFriction",
    "FingerContact",
    "FingerCurve",
    "FingerOrbit",
    "FingerParameters",
    "FootContact",
    "FootParameters",
    "HapticChain",
    "HapticMap",
    "NotchTexture",
    "Outcome",
    "TextureRendering",
    "chain_from_rom",
    "equal_friction",
    "finger_steady_state",
    "haptic_chain",
    "haptic_map",
    "render_texture",
    "simulate_contact",
    "simulate_finger",
    "steady_state",
    "surface_points",
]
