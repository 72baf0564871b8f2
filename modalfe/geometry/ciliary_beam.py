"""Segmented piezoelectric ciliary-like cantilever beam (seed 003)."""

from __future__ import annotations

from modalfe.errors import SceneError
from modalfe.geometry.parameters import Length
from modalfe.geometry.parts import Assembly, Box, Face


def ciliary_beam(
    *,
    length: Length = 0.1,
    height: Length = 5e-3,
    width: Length = 5e-3,
    beam_material: str = "brass-seed003",
    sheet_length: Length = 10e-3,
    sheet_thickness: Length = 0.3e-3,
    sheet_material: str = "PZT-5A",
    x0: Length = 68e-3,
) -> Assembly:
    """Cantilever clamped at x = 0 with a bimorph pair of sheets centred at ``x0``.

        clamp|  beam_1 (l1)  [sheet_top]   beam_3 (l3)   |
             |===============|  beam_2 |=================|   z = 0 .. height
                             [sheet_bottom]
        l1 = x0 - sheet_length/2, l2 = sheet_length, l3 = length - l1 - l2

    Both sheets poled +z; outer faces driven (electrode_outer), inner faces on the beam
    (electrode_inner, grounded): the two sheets strain in opposition and bend the beam.
    """
    l1 = x0 - sheet_length / 2
    l3 = length - x0 - sheet_length / 2
    if l1 <= 0 or l3 <= 0:
        raise SceneError(f"x0: the sheets ({sheet_length} m long at x0 = {x0} m) stick out of the beam")
    x1, x2 = l1, l1 + sheet_length
    parts = (
        Box("beam_1", "beam", beam_material, (0.0, 0.0, 0.0), (x1, width, height)),
        Box("beam_2", "beam", beam_material, (x1, 0.0, 0.0), (x2, width, height)),
        Box("beam_3", "beam", beam_material, (x2, 0.0, 0.0), (length, width, height)),
        Box("sheet_top", "piezo", sheet_material, (x1, 0.0, height), (x2, width, height + sheet_thickness), poling=1),
        Box("sheet_bottom", "piezo", sheet_material, (x1, 0.0, -sheet_thickness), (x2, width, 0.0), poling=1),
    )
    faces = {
        "clamp": (Face("beam_1", "xmin"),),
        "electrode_outer": (Face("sheet_top", "zmax"), Face("sheet_bottom", "zmin")),
        "electrode_inner": (Face("sheet_top", "zmin"), Face("sheet_bottom", "zmax")),
    }
    return Assembly(parts, faces)
