"""modalfe: finite-element and modal design of piezoelectric and vibrotactile haptic actuators.

The Python API mirrors the CLI: ``load_scene`` (``Scene``), ``solve_modes`` (``Modes`` of ``Mode``),
``forced_response`` (``ForcedFigures``), ``reduce`` (``ReducedModel``), ``simulate_contact``,
``simulate_finger``, ``sweep``. Importing it loads nothing: each name loads its module on first use, and gmsh, the
assembly, pyvista, matplotlib and dask load inside the functions that need them; it leaves the process environment
alone.
"""

import importlib

# each public name and the module it lives in: imported on first use (PEP 562), so that a process needing one
# module (the rendering process of ``show``, a contact simulation) does not load the solver stack (~1 s)
_PUBLIC = {
    "simulate_contact": "modalfe.contact", "simulate_finger": "modalfe.contact", "sweep": "modalfe.design.sweep",
    "ContactError": "modalfe.errors", "MeshError": "modalfe.errors", "ModalfeError": "modalfe.errors",
    "SceneError": "modalfe.errors", "SolverError": "modalfe.errors", "ForcedFigures": "modalfe.response.figures",
    "forced_response": "modalfe.response.figures", "Damping": "modalfe.response.forced",
    "ReducedModel": "modalfe.response.forced", "reduce": "modalfe.response.forced", "Mode": "modalfe.results.modes",
    "Modes": "modalfe.results.modes", "Scene": "modalfe.scene", "load_scene": "modalfe.scene",
    "solve_modes": "modalfe.solve.api",
}
_RENAMED = {"forced_response": "forced_figures"}


def __getattr__(name: str):
    """A public name (``_PUBLIC``) or a subpackage (``modalfe.solve``), imported now."""
    if name not in _PUBLIC:
        try:
            return importlib.import_module(f"modalfe.{name}")
        except ModuleNotFoundError as exc:
            if exc.name != f"modalfe.{name}":  # the subpackage exists, a library it needs does not
                raise
            raise AttributeError(f"module 'modalfe' has no attribute '{name}'") from None
    value = getattr(importlib.import_module(_PUBLIC[name]), _RENAMED.get(name, name))
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted([*globals(), *_PUBLIC])


__version__ = "0.1.0"

__all__ = ["ContactError", "Damping", "ForcedFigures", "MeshError", "ModalfeError", "Mode", "Modes", "ReducedModel",
           "Scene", "SceneError", "SolverError", "forced_response", "load_scene", "reduce", "simulate_contact",
           "simulate_finger", "solve_modes", "sweep"]
