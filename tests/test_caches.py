"""One registry of every cache with one ``clear`` (``modalfe.caches``): after a solve each cache holds something,
``clear()`` empties every one kept in memory and leaves the files on disk, ``clear(disk=True)`` removes those too."""

import importlib

import modalfe.caches as caches
from modalfe import solve_modes
from modalfe.models import build, mesh
from modalfe.scene import load_scene
from modalfe.solve import levels, resolved

imported = importlib.import_module("modalfe.geometry.imported")  # the package's name ``imported`` is its function


def _files() -> int:
    return sum(1 for _ in mesh.cache_dir().rglob("*.npz"))


def test_one_clear_empties_every_cache_in_memory_and_on_disk_when_asked():
    solve_modes(load_scene("ciliary_beam"), near=21.7e3, count=4, fidelity="solid", error_estimate=False)
    assert {"meshes in memory", "mesh files", "assembled models", "short-circuit factorizations",
            "resolved answers in memory", "resolved answer files", "imported geometry summaries"} \
        <= set(caches.registered())
    assert mesh._memory_cache and build._MODELS and levels._SHORT_SOLVES and resolved._MEMORY and _files() >= 2
    dropped = caches.clear()
    assert "mesh files" not in dropped and "resolved answer files" not in dropped
    assert not (mesh._memory_cache or build._MODELS or levels._SHORT_SOLVES or resolved._MEMORY)
    assert imported._summary.cache_info().currsize == 0 and _files() >= 2
    caches.clear(disk=True)
    assert _files() == 0
