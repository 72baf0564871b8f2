"""A part's material as the solid model assembles it: poled along the part's poling direction and turned by the
model's frame, its tensors constant or, for a radially poled part, one set per quadrature point."""

from __future__ import annotations

import numpy as np


def radially_poled(part) -> bool:
    """Whether ``part`` is poled along its radius: its material tensors vary from point to point
    (``material_of``); every other part's are constant."""
    return bool(part.poling) and part.poling_vector is None


def material_of(scene, part, frame) -> tuple[object, object]:
    """(material, tensors) of one part: the material poled along the part's poling direction (boxes: +z or -z;
    other parts: any axis, ``modalfe.scene.materials.poling_frames``) and turned by ``frame``; ``tensors(basis)``
    gives (c^E, e, eps^S) on a batch basis, constant, or for radial poling one set per quadrature point: the poling
    axis follows the radius at each point, so the only error is the quadrature's (of order h^(2p) like the
    rest of the element integrals), where per-element centroid tensors would add an O(h) error in the direction."""
    from modalfe.scene.materials import poled_tensors, poling_frames

    mat = scene.material(part.material)
    if radially_poled(part):  # varies through the part
        def tensors(basis):
            x = np.asarray(basis.global_coordinates())  # (3, nel, nq), in the rotated frame if any
            if frame is not None:
                x = np.einsum("ji,jeq->ieq", frame, x)
            R = poling_frames(part.poling_directions(x))
            return poled_tensors(mat, R if frame is None else frame @ R)

        return mat, tensors
    if part.poling:
        mat = mat.poled(part.poling) if isinstance(part.poling, int) else mat.rotated(poling_frames(part.poling_vector))
    if frame is not None:
        mat = mat.rotated(frame)
    constant = (mat.C, getattr(mat, "e", None), getattr(mat, "eps_S", None))
    return mat, lambda basis: constant
