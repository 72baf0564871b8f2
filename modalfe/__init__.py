"""modalfe: finite-element and modal design of piezoelectric and vibrotactile haptic actuators.

The Python API mirrors the CLI: ``load_scene``, ``solve_modes``, ``forced_response``, ``reduce``,
``simulate_contact``, ``simulate_finger``, ``sweep``. ``import modalfe`` is light: gmsh, the
assembly, pyvista, matplotlib and dask load inside the functions that need them.
"""

import os

# numpy's OpenBLAS threads spin while they wait; on a small machine shared with MKL PARDISO's threads and other
# processes, the small dense operations here (the labels' interpolation) then ran up to 100x slower (measured:
# the Cu-Be plate's report row 6 s with one BLAS thread, 30-40 s with two under load). modalfe's heavy work is
# sparse (PARDISO has its own threads), so one BLAS thread costs nothing. Takes effect if numpy loads after this.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from modalfe.errors import ContactError, MeshError, ModalfeError, SceneError, SolverError
from modalfe.scene import load_scene

__version__ = "0.1.0"


def solve_modes(scene, **kwargs):
    """Eigenmodes of a scene; see ``modalfe.solve.api.solve_modes``."""
    from modalfe.solve.api import solve_modes as _solve_modes

    return _solve_modes(scene, **kwargs)


def forced_response(scene, **kwargs):
    """Working-mode figures per volt (reduced model, FRF, admittance); see ``modalfe.response.figures``."""
    from modalfe.response.figures import forced_figures

    return forced_figures(scene, **kwargs)


def reduce(scene, mode, modes, **kwargs):
    """Reduced modal model of one mode; see ``modalfe.response.forced.reduce``."""
    from modalfe.response.forced import reduce as _reduce

    return _reduce(scene, mode, modes, **kwargs)


def simulate_contact(*args, **kwargs):
    """Foot contact and friction at periodic steady state; see ``modalfe.contact.foot``."""
    from modalfe.contact import simulate_contact as _simulate

    return _simulate(*args, **kwargs)


def simulate_finger(*args, **kwargs):
    """Finger bed-spring model; see ``modalfe.contact.finger``."""
    from modalfe.contact import simulate_finger as _simulate

    return _simulate(*args, **kwargs)


def sweep(*args, **kwargs):
    """Resumable parameter sweep on dask; see ``modalfe.sweeps.sweep.sweep``."""
    from modalfe.sweeps.sweep import sweep as _sweep

    return _sweep(*args, **kwargs)


__all__ = ["ContactError", "MeshError", "ModalfeError", "SceneError", "SolverError", "forced_response",
           "load_scene", "reduce", "simulate_contact", "simulate_finger", "solve_modes", "sweep"]
