"""A mode picture rendered by a second Python process, started before the solve: it imports VTK and pyvista's
plotting and opens an off-screen render window while the solve runs, then draws the mode it is sent
(``modalfe.plot.render.render_mode``, the same picture). On the 2-core machine the import alone took 1.0-1.5 s and
the first plotter 0.4 s, as long as the ciliary beam's whole solve: drawn after the solve in the same process,
`show` took 2.0x the time of `modes` on that beam.

The mode is sent pickled without its stiffness and mass matrices (the picture reads the mesh, the shape and the
scene; the Cu-Be plate's quartic model pickles to 36 MB in 0.02 s without them). Any failure of the second process
(it could not start, died, or its drawing failed) is reported as ``RenderProcessError``: the caller then draws in
its own process.
"""

from __future__ import annotations

import os
import pickle
import struct
import subprocess
import sys
import traceback
from dataclasses import replace
from pathlib import Path

from modalfe.errors import ModalfeError

# loaded while the solve runs too, not once the mode has come: the classes the mode unpickles into (its model and
# scene: scipy.sparse and scikit-fem with them) and what drawing it imports (skfem's meshio reader of the mesh,
# Pillow's PNG writer), 0.4 s of the glass plate's 1.0 s from the mode's arrival to its picture
WARM_MODULES = ("modalfe.models.solid", "modalfe.results.modes", "modalfe.scene", "skfem.io.meshio", "PIL.Image")


class RenderProcessError(ModalfeError):
    """The second process did not render the picture (its reason in the message)."""


class RenderProcess:
    """The rendering process, started at construction (RenderProcessError where it cannot be); ``render`` once, then
    it exits."""

    def __init__(self) -> None:
        # this process' modalfe first on the path, whatever put it on this one's (an editable install of another copy)
        here = str(Path(__file__).resolve().parents[2])
        env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in (here, os.environ.get("PYTHONPATH")) if p)}
        try:
            self._process = subprocess.Popen([sys.executable, "-m", "modalfe.plot.render_process"],
                                              stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                              stderr=subprocess.DEVNULL, env=env)
        except OSError as exc:
            raise RenderProcessError(f"the rendering process could not start: {exc}") from None

    def render(self, mode, out: str, view: str) -> None:
        """Draw ``mode`` with ``view`` into the PNG ``out`` in the second process; RenderProcessError if it did not."""
        light = replace(mode, model=replace(mode.model, K=None, M=None))
        payload = pickle.dumps((light, out, view), protocol=pickle.HIGHEST_PROTOCOL)
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


def _serve() -> int:
    """The second process: imports and a first plotter now, then one mode read from stdin drawn; b"ok" or the
    traceback on stdout."""
    import importlib

    import pyvista as pv

    from modalfe.plot.render import quiet_vtk, render_mode

    quiet_vtk()
    pv.Plotter(off_screen=True).close()  # the render window's first set-up, while the solve runs
    for name in WARM_MODULES:
        importlib.import_module(name)
    stdin = sys.stdin.buffer
    header = stdin.read(8)
    if len(header) < 8:  # the caller closed without a picture
        return 0
    mode, out, view = pickle.loads(stdin.read(struct.unpack("<Q", header)[0]))
    try:
        render_mode(mode, out=out, view=view, off_screen=True).close()
    except Exception:
        sys.stdout.buffer.write(traceback.format_exc().encode())
        return 1
    sys.stdout.buffer.write(b"ok")
    return 0


if __name__ == "__main__":
    status = _serve()
    sys.stdout.flush()
    # the picture is on disk and the reply sent: the interpreter's teardown of VTK, pyvista and matplotlib (0.5-0.7 s
    # on the ciliary beam's picture, while `show` waits for this process to end) is skipped
    os._exit(status)
