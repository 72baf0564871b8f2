"""Glass plate with two piezo strips on its bottom face (seed 004)."""

from __future__ import annotations

from modalfe.errors import SceneError
from modalfe.geometry.parameters import Length
from modalfe.geometry.parts import Assembly, Box, Face


def glass_plate(
    *,
    length: Length = 60e-3,
    width: Length = 20e-3,
    thickness: Length = 1.9e-3,
    glass_material: str = "soda-lime-glass",
    piezo_length: Length = 18e-3,
    piezo_width: Length = 5e-3,
    piezo_thickness: Length = 0.3e-3,
    piezo_material: str = "PZT-4",
    piezo_inset: Length = 5e-3,
) -> Assembly:
    """Glass plate; two piezos across the width near each short end, on the bottom face.

        ________________________________   glass, z = 0 .. thickness
        |==|                        |==|   piezo_1, piezo_2 (18 mm along y), z < 0
        piezo_inset = distance from a short end to a piezo's centre line

    The seed's in-plane size was lost with its figure: 60 x 20 mm is an assumption
    (docs/assumptions.md, glass plate); the 66 and 225 kHz modes exist at any length of a few wavelengths,
    their wavelengths being set by the glass's dispersion, not by the length.
    """
    if piezo_length > width + 1e-12:
        raise SceneError(f"piezo_length: {piezo_length} m does not fit across the width {width} m")
    glass = Box("glass", "glass", glass_material, (0.0, 0.0, 0.0), (length, width, thickness))
    parts = [glass]
    outer, inner = [], []
    y0 = (width - piezo_length) / 2
    for i, xc in enumerate((piezo_inset, length - piezo_inset), start=1):
        if xc - piezo_width / 2 < -1e-12 or xc + piezo_width / 2 > length + 1e-12:
            raise SceneError("piezo_inset: the piezos lie off the glass")
        name = f"piezo_{i}"
        parts.append(
            Box(name, "piezo", piezo_material,
                (xc - piezo_width / 2, y0, -piezo_thickness), (xc + piezo_width / 2, y0 + piezo_length, 0.0),
                poling=1)
        )
        outer.append(Face(name, "zmin"))
        inner.append(Face(name, "zmax"))
    return Assembly(tuple(parts), {"electrode_outer": tuple(outer), "electrode_inner": tuple(inner)})
