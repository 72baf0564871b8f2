"""Device builders: keyword-only parametric factories returning a box ``Assembly``.

``BUILDERS`` registers every device by name; ``modalfe.geometry.gmsh_model`` turns an assembly into a
gmsh model (structured grid or OCC parts) with physical groups named by part and by face role.
"""

from modalfe.geometry.boxes import boxes
from modalfe.geometry.ciliary_beam import ciliary_beam
from modalfe.geometry.cube_plate import cube_plate
from modalfe.geometry.glass_plate import glass_plate
from modalfe.geometry.honeycomb_tile import honeycomb_tile
from modalfe.geometry.parts import Assembly, Box, Face

BUILDERS = {
    "cube_plate": cube_plate,
    "glass_plate": glass_plate,
    "honeycomb_tile": honeycomb_tile,
    "ciliary_beam": ciliary_beam,
    "boxes": boxes,
}

__all__ = ["BUILDERS", "Assembly", "Box", "Face", "boxes", "ciliary_beam", "cube_plate",
           "glass_plate", "honeycomb_tile"]
