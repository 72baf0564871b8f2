"""Device builders: keyword-only parametric factories returning a box ``Assembly``.

``BUILDERS`` registers every device by name; ``geometries.gmsh_model`` turns an assembly into a
gmsh model (structured grid or OCC parts) with physical groups named by part and by face role.
"""

from geometries.boxes import boxes
from geometries.ciliary_beam import ciliary_beam
from geometries.cube_plate import cube_plate
from geometries.glass_plate import glass_plate
from geometries.honeycomb_tile import honeycomb_tile
from geometries.parts import Assembly, Box, Face

BUILDERS = {
    "cube_plate": cube_plate,
    "glass_plate": glass_plate,
    "honeycomb_tile": honeycomb_tile,
    "ciliary_beam": ciliary_beam,
    "boxes": boxes,
}

__all__ = ["BUILDERS", "Assembly", "Box", "Face", "boxes", "ciliary_beam", "cube_plate",
           "glass_plate", "honeycomb_tile"]
