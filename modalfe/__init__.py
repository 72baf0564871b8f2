"""modalfe: finite-element and modal design of piezoelectric and vibrotactile haptic actuators.

The Python API mirrors the CLI: ``load_scene`` (``Scene``), ``solve_modes`` (``Modes`` of ``Mode``),
``forced_response`` (``ForcedFigures``), ``reduce`` (``ReducedModel``), ``simulate_contact``,
``simulate_finger``, ``sweep``. Importing it loads numpy and scipy only: gmsh, the assembly, pyvista,
matplotlib and dask load inside the functions that need them; it leaves the process environment alone.
"""

from modalfe.contact import simulate_contact, simulate_finger
from modalfe.design.sweep import sweep
from modalfe.errors import ContactError, MeshError, ModalfeError, SceneError, SolverError
from modalfe.response.figures import ForcedFigures
from modalfe.response.figures import forced_figures as forced_response
from modalfe.response.forced import Damping, ReducedModel, reduce
from modalfe.results.modes import Mode, Modes
from modalfe.scene import Scene, load_scene
from modalfe.solve.api import solve_modes

__version__ = "0.1.0"

__all__ = ["ContactError", "Damping", "ForcedFigures", "MeshError", "ModalfeError", "Mode", "Modes", "ReducedModel",
           "Scene", "SceneError", "SolverError", "forced_response", "load_scene", "reduce", "simulate_contact",
           "simulate_finger", "solve_modes", "sweep"]
