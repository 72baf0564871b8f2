"""Cu-Be plate with PZT ceramics on top and feet below (seeds 000, 001)."""

from __future__ import annotations

from modalfe.errors import SceneError
from modalfe.geometry.parameters import Count, Gap, Length
from modalfe.geometry.parts import Assembly, Box, Face
from modalfe.geometry.shapes import Cylinder

# Feet at the in-phase antinode pair x = 32 -+ 11.65 mm of the (0,6) mode (free-free beam mode
# with six nodes: interior antinode pitch ~ L / 5.5), rows y = 6 and 32 mm (docs/assumptions.md, Cu-Be plate).
DEFAULT_FEET = ((20.35e-3, 6e-3), (43.65e-3, 6e-3), (20.35e-3, 32e-3), (43.65e-3, 32e-3))


def cube_plate(
    *,
    length: Length = 64e-3,
    width: Length = 38e-3,
    thickness: Length = 3e-3,
    plate_material: str = "CuBe",
    ceramic_length: Length = 12e-3,
    ceramic_width: Length = 12e-3,
    ceramic_thickness: Length = 1e-3,
    ceramic_material: str = "PZT-4",
    ceramic_columns: Count = 5,
    ceramic_pitch: Gap = 12.4e-3,
    ceramic_rows: tuple[float, ...] = (12.5e-3, 25.5e-3),
    polarity: tuple[int, ...] = (1, -1, 1, -1, 1),
    feet: tuple[tuple[float, float], ...] = DEFAULT_FEET,
    foot_size: Length = 3e-3,
    foot_height: Length = 4e-3,
    foot_material: str = "CuBe",
    foot_shape: str = "square",
    sensor: tuple[float, float] | None = None,
    sensor_size: Length = 5e-3,
    sensor_shape: str = "square",
    bond_thickness: Gap = 0.0,
    bond_material: str = "epoxy",
    poled: bool = True,
) -> Assembly:
    """Cu-Be plate, PZT ceramics glued on top, square feet below; lengths in metres.

        [+][-][+][-][+]    ceramic_1..10 (electrode_top driven, electrode_bottom on the plate)
        [+][-][+][-][+]    poled through thickness, polarity alternating along x
        ===============    plate (plate_material), z = 0 .. thickness
           |       |       foot_1..foot_n, tips (faces foot_1..) at z = -foot_height

    ``polarity`` gives the poling sign of each column, so the +V/-V pattern drives the (0,6) mode
    with one drive electrode. ``bond_thickness`` > 0 puts a glue layer (bond_1..) under each
    ceramic; the seed's FE had none. ``poled=False`` leaves the ceramics unpoled (for an
    isotropic stand-in material). ``feet`` are foot centres (x, y); ``sensor`` an optional small ceramic
    centred at (x, y) with its own electrode ``sensor_top``. ``foot_shape`` and ``sensor_shape``: ``square``
    (boxes of side ``foot_size``, ``sensor_size``) or ``round`` (cylinders of that diameter, meshed with curved
    tetrahedra: the scene needs mesh.element = "tet" and is solved by the solid model only).
    """
    for field, shape in (("foot_shape", foot_shape), ("sensor_shape", sensor_shape)):
        if shape not in ("square", "round"):
            raise SceneError(f"{field}: must be 'square' or 'round', got {shape!r}")
    if len(polarity) != ceramic_columns:
        raise SceneError(f"polarity: needs one sign per column ({ceramic_columns}), got {len(polarity)}")
    if any(p not in (-1, 1) for p in polarity):
        raise SceneError("polarity: each sign must be +1 or -1")
    plate = Box("plate", "plate", plate_material, (0.0, 0.0, 0.0), (length, width, thickness))
    parts = [plate]
    top, bottom, feet_faces = [], [], {}
    if bond_thickness < 0:
        raise SceneError(f"bond_thickness: must be >= 0, got {bond_thickness}")
    z0, z1 = thickness + bond_thickness, thickness + bond_thickness + ceramic_thickness
    index = 0
    for column in range(ceramic_columns):
        xc = length / 2 + (column - (ceramic_columns - 1) / 2) * ceramic_pitch
        for yc in ceramic_rows:
            index += 1
            name = f"ceramic_{index}"
            box = Box(
                name, "piezo", ceramic_material,
                (xc - ceramic_length / 2, yc - ceramic_width / 2, z0),
                (xc + ceramic_length / 2, yc + ceramic_width / 2, z1),
                poling=polarity[column] if poled else 0,
            )
            _inside_plate(box, plate, f"ceramic '{name}'")
            parts.append(box)
            if bond_thickness > 0:
                parts.append(Box(f"bond_{index}", "bond", bond_material, (box.lo[0], box.lo[1], thickness),
                                 (box.hi[0], box.hi[1], z0)))
            top.append(Face(name, "zmax"))
            bottom.append(Face(name, "zmin"))
    faces = {"electrode_top": tuple(top), "electrode_bottom": tuple(bottom)} if top else {}
    for i, (xc, yc) in enumerate(feet, start=1):
        name = f"foot_{i}"
        if foot_shape == "round":
            box = Cylinder(name, "foot", foot_material, (xc, yc, -foot_height), "z", foot_size / 2, foot_height)
        else:
            box = Box(
                name, "foot", foot_material,
                (xc - foot_size / 2, yc - foot_size / 2, -foot_height),
                (xc + foot_size / 2, yc + foot_size / 2, 0.0),
            )
        _inside_plate(box, plate, f"feet[{i - 1}]")
        parts.append(box)
        feet_faces[name] = (Face(name, "bottom" if foot_shape == "round" else "zmin"),)
    faces.update(feet_faces)
    if sensor is not None:
        xc, yc = sensor
        if sensor_shape == "round":
            box = Cylinder("sensor", "piezo", ceramic_material, (xc, yc, z0), "z", sensor_size / 2, z1 - z0, poling=1)
        else:
            box = Box(
                "sensor", "piezo", ceramic_material,
                (xc - sensor_size / 2, yc - sensor_size / 2, z0),
                (xc + sensor_size / 2, yc + sensor_size / 2, z1),
                poling=1,
            )
        _inside_plate(box, plate, "sensor")
        parts.append(box)
        top_side, bottom_side = ("top", "bottom") if sensor_shape == "round" else ("zmax", "zmin")
        faces["sensor_top"] = (Face("sensor", top_side),)
        faces["electrode_bottom"] = (*faces.get("electrode_bottom", ()), Face("sensor", bottom_side))
    return Assembly(tuple(parts), faces)


def _inside_plate(box, plate: Box, field: str) -> None:
    for k in (0, 1):
        if box.lo[k] < plate.lo[k] - 1e-12 or box.hi[k] > plate.hi[k] + 1e-12:
            raise SceneError(f"{field}: lies off the plate along {'xy'[k]}")
