"""A mode picture rendered by a second Python process, started before the solve: it imports VTK and pyvista's
plotting and opens an off-screen render window while the solve runs, then draws the mode it is sent
(``modalfe.plot.render.render_mode``, the same picture). On the 2-core machine the import alone took 1.0-1.5 s and
the first plotter 0.4 s, as long as the ciliary beam's whole solve: drawn after the solve in the same process,
`show` took 2.0x the time of `modes` on that beam.

It makes the plotter the picture is drawn in and renders an empty frame in it (the render window's set-up, 0.1 s of
the picture's first render, done ahead), loads what unpickling and drawing the mode import, and leaves to their
first use the modules pyvista imports but no picture here uses (``DEFERRED``): ``prepared``. Drawing the ciliary
beam's mode then takes 0.25 s from its arrival (0.45-0.55 s before).

The mode is sent pickled without its stiffness and mass matrices (the picture reads the mesh, the shape and the
scene; the Cu-Be plate's quartic model pickles to 36 MB in 0.02 s without them). Any failure of the second process
(it could not start, died, or its drawing failed) is reported as ``RenderProcessError``: the caller then draws in
its own process.
"""

from __future__ import annotations

import importlib
import importlib.util
import os
import pickle
import struct
import subprocess
import sys
import traceback
import types
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

from modalfe.errors import ModalfeError

if TYPE_CHECKING:
    import pyvista

    from modalfe.results.modes import Mode

# loaded while the solve runs too, not once the mode has come: the classes the mode unpickles into (its model, mesh
# and scene: scikit-fem and scipy with them, 0.3 s of one core) and what drawing it imports (VTK's surface and cell
# size filters; Pillow's image plugins, ``prepared``), 0.4 s of the glass plate's 1.0 s from the mode's arrival to its
# picture
WARM_MODULES = ("modalfe.models.solid", "modalfe.models.mesh", "modalfe.models.hex_elements",
                "modalfe.results.modes", "modalfe.scene", "vtkmodules.vtkFiltersGeometry",
                "vtkmodules.vtkFiltersVerdict")
# imported but not used by a picture: matplotlib.pyplot by pyvista's colours and charts, for matplotlib's own colour
# cycle and charts (0.3 s of one core: `import matplotlib.pyplot` against matplotlib's colours and colour maps alone);
# pooch (with requests and tqdm) by pyvista's readers, for files it downloads (0.05 s); numpy.f2py (with
# charset_normalizer) by scipy's array API layer, which copies numpy's every public name (0.04 s)
DEFERRED = ("matplotlib.pyplot", "pooch", "numpy.f2py")


class RenderProcessError(ModalfeError):
    """The second process did not render the picture (its reason in the message)."""


class Deferred(types.ModuleType):
    """A module that an import statement binds without running it: the first name read from it loads it."""

    def __getattr__(self, name: str) -> object:
        del sys.modules[self.__name__]
        loaded = importlib.import_module(self.__name__)
        self.__dict__.update(loaded.__dict__)  # who bound this stand-in reads the module's own names from now on
        return getattr(loaded, name)


def defer(name: str) -> None:
    """Let ``import name`` bind a ``Deferred`` module (importlib's LazyLoader loads on the import statement's own
    look-up of ``__spec__`` on Python 3.11); nothing where it is already loaded or cannot be found."""
    spec = None if name in sys.modules else importlib.util.find_spec(name)  # (its package imported)
    if spec is not None:
        module = Deferred(name)
        module.__spec__, module.__loader__, module.__file__ = spec, spec.loader, spec.origin
        sys.modules[name] = module
        package, _, attribute = name.rpartition(".")
        if package:  # as an import sets it (numpy's own __getattr__ would import it again)
            setattr(sys.modules[package], attribute, module)


class RenderProcess:
    """The rendering process, started at construction (RenderProcessError where it cannot be) for ``view`` (one of
    ``render.VIEWS``: its plotter is made ahead); ``render`` once, then it exits."""

    def __init__(self, view: str = "iso+bottom") -> None:
        # this process' modalfe first on the path, whatever put it on this one's (an editable install of another copy)
        here = str(Path(__file__).resolve().parents[2])
        env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in (here, os.environ.get("PYTHONPATH")) if p)}
        try:
            self._process = subprocess.Popen([sys.executable, "-m", "modalfe.plot.render_process", view],
                                              stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                              stderr=subprocess.DEVNULL, env=env)
        except OSError as exc:
            raise RenderProcessError(f"the rendering process could not start: {exc}") from None

    def render(self, mode, out: str, view: str) -> None:
        """Draw ``mode`` with ``view`` into the PNG ``out`` in the second process; RenderProcessError if it did not."""
        payload = pickle.dumps((sent(mode), out, view), protocol=pickle.HIGHEST_PROTOCOL)
        try:
            reply, _ = self._process.communicate(struct.pack("<Q", len(payload)) + payload, timeout=600)
        except (OSError, subprocess.TimeoutExpired) as exc:
            self.close()
            raise RenderProcessError(f"the rendering process failed: {exc}") from None
        if self._process.returncode != 0 or reply != b"ok":
            raise RenderProcessError(f"the rendering process failed (exit {self._process.returncode}): "
                                     f"{reply.decode(errors='replace').strip()[-500:]}")

    def close(self) -> None:
        """Stop the process if it still runs (the picture was not asked after all)."""
        if self._process.poll() is None:
            self._process.kill()
            self._process.wait()


def sent(mode: Mode) -> Mode:
    """``mode`` as it is sent: without its model's stiffness and mass matrices."""
    return replace(mode, model=replace(mode.model, K=None, M=None))


def prepared(view: str) -> pyvista.Plotter | None:
    """What the second process does before the mode comes (``DEFERRED``, the plotter and its window's first frame,
    ``WARM_MODULES``, Pillow's plugins): the plotter of ``view`` (``render.mode_plotter``; None for a view not in
    ``render.VIEWS``)."""
    for name in DEFERRED:
        defer(name)
    from PIL import Image

    from modalfe.plot.render import VIEWS, mode_plotter

    plotter = mode_plotter(view) if view in VIEWS else None
    if plotter is not None:  # an empty frame: the render window's set-up, 0.1 s of the picture's first render
        plotter.render_window.Render()  # (not plotter.render(): the plotter stays one that has not rendered yet)
    for name in WARM_MODULES:
        importlib.import_module(name)
    Image.preinit()  # the plugins a PNG's writing loads
    return plotter


def _serve(view: str) -> int:
    """The second process: ``prepared(view)`` now, then one mode read from stdin drawn (in that plotter where it
    asks for ``view``); b"ok" or the traceback on stdout."""
    plotter = prepared(view)  # while the solve runs
    from modalfe.plot.render import render_mode

    stdin = sys.stdin.buffer
    header = stdin.read(8)
    if len(header) < 8:  # the caller closed without a picture
        return 0
    mode, out, asked = pickle.loads(stdin.read(struct.unpack("<Q", header)[0]))
    try:
        render_mode(mode, out=out, view=asked, plotter=plotter if asked == view else None).close()
    except Exception:
        sys.stdout.buffer.write(traceback.format_exc().encode())
        return 1
    sys.stdout.buffer.write(b"ok")
    return 0


if __name__ == "__main__":
    status = _serve(sys.argv[1] if len(sys.argv) > 1 else "")
    sys.stdout.flush()
    # the picture is on disk and the reply sent: the interpreter's teardown of VTK, pyvista and matplotlib (0.5-0.7 s
    # on the ciliary beam's picture, while `show` waits for this process to end) is skipped
    os._exit(status)
