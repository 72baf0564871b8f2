"""Every cache modalfe keeps, in one registry with one ``clear``: each module that keeps something registers what it
keeps and how to drop it, so that nothing is forgotten by the one call that resets the process (tests, a long design
study that wants its memory back, a user who changed a file the caches cannot see).

What is kept, and until when (``registered()`` lists them):
- meshes in memory (``modalfe.models.mesh``), and their files on disk (the mesh cache);
- assembled models, the last few per kind (``modalfe.models.build``);
- short-circuit factorizations kept for their open circuit (``modalfe.solve.levels``), while their model lives;
- the open-circuit solves of the partner search (``modalfe.solve.api.open_circuit_partner``), the last few, while
  their model lives;
- resolved answers, a few in memory and the newest on disk (``modalfe.solve.resolved``);
- summaries of imported geometry files, by path and content digest (``modalfe.geometry.imported``);
- per-material stiffness matrices of live models, for the materials' Qm (``modalfe.response.losses``).
- the upper triangles of the last few shifted pencils A - s B, while A and B live (``modalfe.solve.linalg``);
- the point locators of the last few curved hexahedral meshes probed, while the mesh lives (``modalfe.models.probing``).
Only the whereabouts of MKL (``modalfe.solve.linalg``) are not dropped: they do not change while a process runs.
"""

from __future__ import annotations

from collections.abc import Callable

_REGISTRY: dict[str, tuple[Callable[[], None], bool]] = {}


def register(name: str, clear: Callable[[], None], *, disk: bool = False) -> None:
    """Register the cache ``name``, dropped by ``clear()`` (``disk``: files on disk, dropped by ``clear(disk=True)``
    only)."""
    _REGISTRY[name] = (clear, disk)


def clear(*, disk: bool = False) -> list[str]:
    """Drop every cache kept in memory and, with ``disk``, the files on disk too; the names of those dropped."""
    dropped = []
    for name, (drop, on_disk) in _REGISTRY.items():
        if disk or not on_disk:
            drop()
            dropped.append(name)
    return dropped


def registered() -> list[str]:
    """The names of the caches registered (by the modules imported so far)."""
    return list(_REGISTRY)
