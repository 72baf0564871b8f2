"""Resolved answers kept: the modes a question got at a tolerance (frequencies, shapes, labels, stated errors and the
discretization that met the tolerance, ``modalfe.models.build.Level``), in memory and on disk beside the mesh cache,
so that a second command on the same scene, window and tolerance (``forced`` after ``modes``) reads them instead of
solving again, and answers with the very same numbers.

Keyed like the mesh cache (a digest of everything the answer depends on: the scene and its geometry, the question,
the fidelity and tolerance, and modalfe's own source, so that a changed solver never reads an old answer). On a read
the model is rebuilt at the stored level (mesh from the mesh cache, assembly) and must have the stored number of
unknowns, else the entry is ignored and solved again. ``MODALFE_CACHE=off`` turns the disk copy off.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import json
import logging
import os
import tempfile
import time
from collections import OrderedDict
from dataclasses import asdict, replace
from pathlib import Path

import numpy as np

import modalfe.caches as caches
from modalfe.models.build import Level, build_model
from modalfe.models.mesh import MESH_FORMAT_VERSION, cache_dir
from modalfe.results.modes import Mode, Modes
from modalfe.solve.estimates import EstimatePlan

log = logging.getLogger(__name__)

FORMAT_VERSION = 3  # 2: the estimate plan and its levels kept with the answer; 3: with its p-rate floor
KEPT_IN_MEMORY = 4  # answers kept in this process (a report's windows, the command's own question)
KEPT_ON_DISK = 64  # answer files kept in the cache folder, the least recently written dropped first
_MEMORY: OrderedDict[str, Modes] = OrderedDict()


def clear(*, disk: bool = False) -> None:
    """Forget the answers kept in this process and, with ``disk``, their copies on disk too (``modalfe.caches``
    registers both)."""
    _MEMORY.clear()
    where = folder()
    if disk and where is not None and where.is_dir():
        for path in where.glob("*.npz"):
            with contextlib.suppress(OSError):
                path.unlink()


caches.register("resolved answers in memory", clear)
caches.register("resolved answer files", lambda: clear(disk=True), disk=True)


def folder() -> Path | None:
    """Where answers are kept on disk: ``resolved/`` in the mesh cache's folder (None when that is off)."""
    root = cache_dir()
    return None if root is None else root / "resolved"


@functools.cache
def source_digest() -> str:
    """SHA-256 of modalfe's own source files: an answer is only read back by the code that made it."""
    h = hashlib.sha256()
    package = Path(__file__).resolve().parents[1]
    for path in sorted(package.rglob("*.py")):
        h.update(str(path.relative_to(package)).encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def answer_key(scene, analysis, **question) -> str:
    """The digest that names one answer: the scene (with its assembly, which holds an imported file's digest), the
    analysis, the keyword ``question`` (fidelity, tol, check, ...) and modalfe's source."""
    text = repr((FORMAT_VERSION, MESH_FORMAT_VERSION, source_digest(), scene, scene.assembly(), analysis,
                 sorted(question.items())))
    return hashlib.sha256(text.encode()).hexdigest()[:24]


def lookup(key: str, scene) -> Modes | None:
    """The answer kept under ``key`` for ``scene`` (the scene it was solved for), else None."""
    if key in _MEMORY:
        _MEMORY.move_to_end(key)
        return _MEMORY[key]
    where = folder()
    path = where / f"{key}.npz" if where is not None else None
    if path is None or not path.exists():
        return None
    start = time.perf_counter()
    try:
        with np.load(path, allow_pickle=False) as data:
            meta = json.loads(str(data["__meta__"]))
            if meta.get("key") != key:
                raise ValueError(f"holds {meta.get('key')}")
            modes = _restore(meta["answer"], data, "answer", scene)
    except Exception as exc:  # damaged, foreign or no longer rebuildable: solve again (and overwrite)
        log.warning("resolved cache: ignoring %s (%s: %s)", path, type(exc).__name__, exc)
        return None
    modes = replace(modes, timings={**modes.timings, "read from cache": time.perf_counter() - start})
    _remember(key, modes)
    log.info("resolved cache: %s read from %s", scene.name, path)
    return modes


def store(key: str, modes: Modes) -> None:
    """Keep ``modes`` (an answer whose every level carries its ``Level``) under ``key``, in memory and on disk."""
    _remember(key, modes)
    where = folder()
    if where is None or not _storable(modes):
        return
    arrays: dict[str, np.ndarray] = {}
    meta = {"key": key, "answer": _describe(modes, "answer", arrays)}
    tmp = None
    try:
        where.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{key}.", suffix=".tmp", dir=where)
        with os.fdopen(fd, "wb") as f:
            np.savez(f, __meta__=np.array(json.dumps(meta)), **arrays)
        os.replace(tmp, where / f"{key}.npz")
        tmp = None
        _prune(where)
    except OSError as exc:
        log.warning("resolved cache: cannot write %s (%s); going on without it", where, exc)
    finally:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)


def _remember(key: str, modes: Modes) -> None:
    _MEMORY[key] = modes
    _MEMORY.move_to_end(key)
    while len(_MEMORY) > KEPT_IN_MEMORY:
        _MEMORY.popitem(last=False)


def _storable(modes: Modes) -> bool:
    return modes.level is not None and all(_storable(level) for level in (*modes.cross_check, *_estimate_levels(modes)))


def _estimate_levels(modes: Modes) -> tuple[Modes, ...]:
    plan = modes.estimate
    return () if plan is None else (*plan.levels, *([plan.floor] if plan.floor is not None else []))


def _prune(where: Path) -> None:
    files = sorted(where.glob("*.npz"), key=lambda p: p.stat().st_mtime)
    for old in files[:-KEPT_ON_DISK]:
        with contextlib.suppress(OSError):
            old.unlink()


def _describe(modes: Modes, name: str, arrays: dict) -> dict:
    """JSON of ``modes`` with its shapes put in ``arrays`` under ``name``; cross-check levels alike."""
    arrays[f"{name}:shapes"] = np.column_stack([m.shape for m in modes]) if len(modes) else np.zeros((0, 0))
    level = modes.level
    return {
        "level": {"fidelity": level.fidelity, "mesh": asdict(level.mesh), "size_factor": level.size_factor,
                  "min_layers": level.min_layers},
        "modes": [{"index": m.index, "frequency": m.frequency, "label": m.label, "circuit": m.circuit,
                   "error_estimate": m.error_estimate, "wavelength": m.wavelength, "model_error": m.model_error}
                  for m in modes],
        "circuit": modes.circuit, "fidelity": modes.fidelity, "dofs": modes.dofs,
        "timings": {k: v for k, v in modes.timings.items() if isinstance(v, (int, float, str))},
        "fidelity_note": modes.fidelity_note, "mesh_frequency": modes.mesh_frequency,
        "estimate_method": modes.estimate_method,
        "cross_check": [_describe(c, f"{name}.{i}", arrays) for i, c in enumerate(modes.cross_check)],
        "estimate": None if modes.estimate is None else _describe_plan(modes.estimate, f"{name}.estimate", arrays),
    }


def _describe_plan(plan: EstimatePlan, name: str, arrays: dict) -> dict:
    return {"rule": plan.rule, "ratios": list(plan.ratios), "ceiling": plan.ceiling, "method": plan.method,
            "rate": plan.rate,
            "levels": [_describe(level, f"{name}.{i}", arrays) for i, level in enumerate(plan.levels)],
            "floor": None if plan.floor is None else _describe(plan.floor, f"{name}.floor", arrays)}


def _restore_plan(meta: dict, data, name: str, scene) -> EstimatePlan:
    levels = tuple(_restore(level, data, f"{name}.{i}", scene) for i, level in enumerate(meta["levels"]))
    floor = None if meta["floor"] is None else _restore(meta["floor"], data, f"{name}.floor", scene)
    return EstimatePlan(meta["rule"], levels, tuple(meta["ratios"]), meta["ceiling"], floor, meta["method"],
                        meta["rate"])


def _restore(meta: dict, data, name: str, scene) -> Modes:
    """The ``Modes`` that ``_describe`` wrote, bound to its model rebuilt at the stored level."""
    from modalfe.scene.scene import MeshSettings

    stored = meta["level"]
    level = Level(stored["fidelity"], MeshSettings(**stored["mesh"]), stored["size_factor"], stored["min_layers"])
    model, _ = build_model(level.scene_of(scene), level.fidelity, size_factor=level.size_factor,
                           min_layers=level.min_layers)
    shapes = data[f"{name}:shapes"]
    if len(meta["modes"]) and shapes.shape[0] != model.K.shape[0]:
        raise ValueError(f"the rebuilt model has {model.K.shape[0]} unknowns, the stored shapes {shapes.shape[0]}")
    modes = tuple(Mode(m["index"], m["frequency"], m["label"], shapes[:, i].copy(), model, m["circuit"],
                       m["error_estimate"], m["wavelength"], m["model_error"]) for i, m in enumerate(meta["modes"]))
    cross = tuple(_restore(c, data, f"{name}.{i}", scene) for i, c in enumerate(meta["cross_check"]))
    plan = None if meta["estimate"] is None else _restore_plan(meta["estimate"], data, f"{name}.estimate", scene)
    return Modes(modes, model, meta["circuit"], meta["fidelity"], meta["dofs"], dict(meta["timings"]),
                 meta["fidelity_note"], cross, meta["mesh_frequency"], meta["estimate_method"], level, plan)
