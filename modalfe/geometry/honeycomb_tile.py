"""Aluminium honeycomb floor tile on four rubber mounts, actuator at the centre (seed 002)."""

from __future__ import annotations

from modalfe.errors import SceneError
from modalfe.geometry.parameters import Length
from modalfe.geometry.parts import Assembly, Box, Face


def honeycomb_tile(
    *,
    length: Length = 0.304,
    width: Length = 0.304,
    thickness: Length = 0.0254,
    facing_thickness: Length = 0.0008,
    facing_material: str = "Al-5052",
    core_material: str = "honeycomb-5052-1/4-.001",
    mount_side: Length = 0.02828,
    mount_inset: Length = 0.02,
    actuator_side: Length = 0.04,
) -> Assembly:
    """Sandwich panel (facing_top, core, facing_bottom) with four mount pads and an actuator pad.

        ==============================   facing_top
        |            core            |   homogenised honeycomb
        ==============================   facing_bottom
          [m1]       [act]       [m2]    faces mount_1..4 and actuator on its underside

    The SBR mounts are elastic elements (springs to ground on the mount faces, stiffnesses set by
    the scene); ``mount_inset`` is the distance from a panel edge to a mount's centre and the pad
    ``mount_side``^2 = 8 cm^2 (seed 002). The actuator acts on a centred square of ``actuator_side``.
    """
    core_t = thickness - 2 * facing_thickness
    if core_t <= 0:
        raise SceneError("facing_thickness: two facings are thicker than the panel")
    if mount_inset < mount_side / 2:
        raise SceneError("mount_inset: the mounts stick out past the panel edge")
    if actuator_side >= min(length, width):
        raise SceneError("actuator_side: larger than the panel")
    parts = (
        Box("facing_bottom", "facing", facing_material, (0, 0, 0), (length, width, facing_thickness)),
        Box("core", "core", core_material, (0, 0, facing_thickness), (length, width, facing_thickness + core_t)),
        Box("facing_top", "facing", facing_material, (0, 0, thickness - facing_thickness), (length, width, thickness)),
    )
    faces = {}
    centres = [(mount_inset, mount_inset), (length - mount_inset, mount_inset),
               (mount_inset, width - mount_inset), (length - mount_inset, width - mount_inset)]
    h = mount_side / 2
    for i, (xc, yc) in enumerate(centres, start=1):
        faces[f"mount_{i}"] = (Face("facing_bottom", "zmin", ((xc - h, yc - h), (xc + h, yc + h))),)
    a = actuator_side / 2
    window = ((length / 2 - a, width / 2 - a), (length / 2 + a, width / 2 + a))
    faces["actuator"] = (Face("facing_bottom", "zmin", window),)
    return Assembly(parts, faces)
