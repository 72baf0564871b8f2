"""Device builders: keyword-only parametric factories returning a box ``Assembly``.

``BUILDERS`` registers every device by name; ``builder_parameters`` gives a builder's parameters as
data (name, type, default, unit, constraint) read from its annotated signature, and
``check_parameters`` validates scene parameters against them. ``modalfe.geometry.gmsh_model`` turns
an assembly into a gmsh model (structured grid or OCC parts) with physical groups named by part and
by face role.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from functools import cache
from typing import Any

from modalfe.errors import SceneError
from modalfe.geometry.boxes import boxes
from modalfe.geometry.ciliary_beam import ciliary_beam
from modalfe.geometry.cube_plate import cube_plate
from modalfe.geometry.glass_plate import glass_plate
from modalfe.geometry.honeycomb_tile import honeycomb_tile
from modalfe.geometry.imported import imported
from modalfe.geometry.parameters import AtLeast, NonNegative, Parameter, Positive, Unit, parameters_of
from modalfe.geometry.parts import Assembly, Box, Face
from modalfe.geometry.shapes import shaped

BUILDERS: dict[str, Callable[..., Assembly]] = {
    "cube_plate": cube_plate,
    "glass_plate": glass_plate,
    "honeycomb_tile": honeycomb_tile,
    "ciliary_beam": ciliary_beam,
    "boxes": boxes,
    "shaped": shaped,  # scene files with cylinders, rings or extrusions (``modalfe.geometry.shapes``)
    "imported": imported,  # scene files naming a geometry file (``modalfe.geometry.imported``)
}
SCENE_FILE_DEVICES = ("boxes", "shaped", "imported")  # built from a scene file's part tables, not from parameters


def builder_parameters(name: str) -> dict[str, Parameter]:
    """The parameters of builder ``name`` (name -> Parameter), in signature order."""
    try:
        builder = BUILDERS[name]
    except KeyError:
        raise SceneError(f"device: unknown builder '{name}'; known: {sorted(BUILDERS)}") from None
    return dict(_parameters(builder))


@cache
def _parameters(builder: Callable[..., Assembly]) -> tuple[tuple[str, Parameter], ...]:
    return tuple(parameters_of(builder).items())


def check_parameters(name: str, params: Mapping[str, Any]) -> None:
    """Raise a one-line SceneError naming the first unknown or invalid parameter of builder ``name``."""
    accepted = builder_parameters(name)
    unknown = set(params) - set(accepted)
    if unknown:
        raise SceneError(f"{sorted(unknown)[0]}: not a parameter of {name}; known: {sorted(accepted)}")
    for key, value in params.items():
        accepted[key].check(value)


__all__ = ["BUILDERS", "SCENE_FILE_DEVICES", "Assembly", "AtLeast", "Box", "Face", "NonNegative", "Parameter",
           "Positive", "Unit", "boxes", "builder_parameters", "check_parameters", "ciliary_beam", "cube_plate",
           "glass_plate", "honeycomb_tile", "imported", "shaped"]
