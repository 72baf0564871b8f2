"""modalfe: finite-element and modal design of piezoelectric and vibrotactile haptic actuators.

``import modalfe`` is light: gmsh, scikit-fem assembly and plotting load inside the functions
that need them.
"""

from modalfe.errors import ContactError, MeshError, ModalfeError, SceneError, SolverError
from modalfe.scene import load_scene

__version__ = "0.1.0"


def solve_modes(scene, **kwargs):
    """Eigenmodes of a scene; see ``modalfe.solvers.solve_modes``."""
    from modalfe.solvers import solve_modes as _solve_modes

    return _solve_modes(scene, **kwargs)


__all__ = ["ContactError", "MeshError", "ModalfeError", "SceneError", "SolverError", "load_scene",
           "solve_modes"]
