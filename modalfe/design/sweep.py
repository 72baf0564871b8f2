"""Parameter sweeps on dask.distributed, written point by point to a CSV table and resumable.

Each row is keyed on everything that defines it: the scene (its name, or the SHA-256 of a scene file's
content), the fixed overrides (``--set``), the point's parameters, the working-mode selector, ``near``,
``count`` and the extra quantity computed. A rerun reuses only rows of the same key and computes the rest;
rows of other sweeps in the same table are kept, never reused. Workers return the working mode chosen by
label and its nearest candidates with their shapes sampled on a grid fixed relative to the device, so that
the working mode is tracked by the modal assurance criterion (MAC) from point to point; where the
best-matching candidate is not the labelled one, matches poorly, or the label is not found at a point (the
mode left the search window), the row says so (a crossing) instead of swapping silently or aborting.

The table (see ``COLUMNS``): one column per swept parameter, the tracking columns, the row's definition and
the raw candidates (for the tracking of a resumed sweep). While a sweep runs, finished points are appended
(flushed and synced) in completion order; at the end the table is rewritten atomically, the sweep's rows
in grid order first, then any other rows as they were. A sidecar ``<table>.lock`` (``fcntl.flock``) keeps a
second sweep from writing the same table at the same time; a torn last line (a killed writer) is dropped
before anything is appended.
"""

from __future__ import annotations

import contextlib
import csv
import hashlib
import io
import itertools
import json
import logging
import os
import tempfile
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from modalfe.design.multistart import INLINE, check_workers, dask_client, submit_all
from modalfe.errors import ModalfeError, SceneError
from modalfe.solve.api import DEFAULT_TOL

log = logging.getLogger(__name__)

DEFAULT_RESOLUTION = {"fidelity": "auto", "tol": DEFAULT_TOL, "error_estimate": True}  # ``solve_modes``' own
MAC_CROSSING = 0.8  # below this the tracked mode is not the same shape any more (Allemang 2003: MAC > 0.9 consistent)
GRID = (12, 6)  # samples of the normal displacement over the main part's top face (relative coordinates)
# the table's fixed columns; the swept parameters' columns go between DEFINITION and RESULT
DEFINITION = ["point", "point_id", "scene", "scene_sha256", "overrides", "selector", "near_hz", "count", "extra_fn",
              "resolution"]
RESULT = ["status", "label", "frequency_hz", "error_estimate", "tracked_label", "tracked_frequency_hz",
          "mac_previous", "crossing", "dofs", "seconds", "extra", "candidates"]
COLUMNS = DEFINITION + RESULT
_JSON = ("overrides", "extra", "candidates", "resolution")


def grid_values(spec: str) -> list[float]:
    """``START:STOP:COUNT`` -> evenly spaced values (COUNT >= 1)."""
    try:
        start, stop, count = spec.split(":")
        count = int(count)
        values = np.linspace(float(start), float(stop), count)
    except ValueError:
        raise SceneError(f"--param: expected NAME=START:STOP:COUNT, got '{spec}'") from None
    if count < 1:
        raise SceneError(f"--param: COUNT must be at least 1, got {count}")
    if not np.all(np.isfinite(values)):
        raise SceneError(f"--param: START and STOP must be finite numbers, got '{spec}'")
    return [float(v) for v in values]


def scene_identity(scene_ref, scene=None) -> tuple[str, str]:
    """(the scene as named, SHA-256 of its file's content, and of the geometry file the loaded ``scene`` names (its
    digest, with the files that one merges: ``modalfe.geometry.imported.file_digest``), or "" for a built-in
    scene): a table resumes only for the same device."""
    path = Path(scene_ref)
    if str(scene_ref).lower().endswith(".toml") and path.is_file():
        digest = hashlib.sha256(path.read_bytes())
        if scene is not None and scene.device == "imported":
            digest.update(scene.params["digest"].encode())
        return str(scene_ref), digest.hexdigest()
    return str(scene_ref), ""


def _canonical(value) -> str:
    return json.dumps(value, sort_keys=True, default=lambda v: list(v) if isinstance(v, (tuple, set)) else str(v))


def definition(scene_ref, base: Mapping | None, selector: str, near: float, count: int,
               extra: Callable | None = None, scene=None, resolution: Mapping | None = None) -> dict:
    """What defines every row of a sweep besides its point's parameters (``scene``: the loaded scene, whose
    geometry file counts too; ``resolution``: ``solve_modes``' tol, fidelity, error_estimate)."""
    name, digest = scene_identity(scene_ref, scene)
    return {"scene": name, "scene_sha256": digest, "overrides": json.loads(_canonical(dict(base or {}))),
            "selector": str(selector), "near_hz": float(near), "count": int(count),
            "extra_fn": _extra_name(extra),
            "resolution": json.loads(_canonical(dict(resolution or {})))}


def _extra_name(extra: Callable | None) -> str:
    """What names an extra computation in a sweep's definition: a function's module and name, or a callable
    object's ``key`` (its parameters included: another voltage is another sweep)."""
    if extra is None:
        return ""
    return getattr(extra, "key", None) or f"{extra.__module__}.{extra.__qualname__}"


def point_id(params: Mapping, context: Mapping | None = None) -> str:
    """Key of a row: a hash of the point's parameters and the sweep's ``definition`` (everything that
    defines the computation: scene content, overrides, selector, near, count, extra)."""
    context = dict(context or {})
    if context.get("scene_sha256"):
        del context["scene"]  # a scene file is its content, wherever it lies
    return hashlib.sha256(_canonical({"params": dict(params), **context}).encode()).hexdigest()[:16]


def mac(a: np.ndarray, b: np.ndarray) -> float:
    """Modal assurance criterion |a.b|^2 / (|a|^2 |b|^2) (Allemang & Brown 1982)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    den = float(a @ a) * float(b @ b)
    return float((a @ b) ** 2 / den) if den > 0 else 0.0


def evaluate_point(scene_ref: str, params: dict, base: dict, selector: str, near: float, count: int = 6,
                   extra: Callable | None = None, resolution: Mapping | None = None) -> dict:
    """Solve one point: the labelled working mode and its ``count`` nearest candidates (shapes sampled), the answer
    ``modes`` gives for that question at ``resolution`` (``solve_modes``' tol, fidelity, error_estimate), with the
    working mode's stated error.

    Never raises a modalfe error: a working mode not found among the candidates gives status ``not found``
    (the tracking then follows the shape), a failed point status ``error`` with the one-line reason."""
    from modalfe.errors import SolverError
    from modalfe.results.modes import select
    from modalfe.scene import load_scene
    from modalfe.solve.api import REVOLVED, solid_modes, working_question

    start = time.perf_counter()
    row = {"params": params, "status": "ok", "label": "", "frequency_hz": None, "error_estimate": None,
           "candidates": [], "dofs": 0, "extra": {}}
    try:
        scene = load_scene(scene_ref, **{**base, **params})
        # sought where the scene's working mode of that selector is: the scene's own question about it, as ``modes``
        # and ``forced`` ask it (one answer); elsewhere the window of ``count`` modes around ``near``
        own = asks_own_question(scene, selector, near)
        question = working_question(scene, selector) if own else {"near": near, "count": count, "mode": selector}
        modes = solid_modes(scene, needs="the sweep", takes=REVOLVED, **question, **(resolution or {}))
        full = scene.full_assembly()
        main = full.main_part
        lo, hi = full.bounds
        U, V = np.meshgrid(np.linspace(0.02, 0.98, GRID[0]), np.linspace(0.05, 0.95, GRID[1]))
        points = np.vstack([lo[0] + U.ravel() * (hi[0] - lo[0]), lo[1] + V.ravel() * (hi[1] - lo[1]),
                            np.full(U.size, main.hi[2])])  # a grid fixed relative to the device
        # a round or holed main part leaves some of the grid outside: those samples stay 0 (no motion to compare),
        # so every point's shapes keep one length
        inside = main.inside(points.T, tol=full.tolerance)
        P = modes.model.displacement_probes(points[:, inside].T)[2 * int(inside.sum()):]

        def sampled(shape: np.ndarray) -> list[float]:
            values = np.zeros(U.size)
            values[inside] = P @ shape
            return _sampled(values)

        row["candidates"] = [{"index": m.index, "label": m.label, "frequency_hz": m.frequency,
                              "shape": sampled(m.shape)} for m in modes]
        row["dofs"] = modes.dofs
        try:
            working = select(modes, selector, near)
        except SolverError as exc:
            row["status"] = f"not found: {_one_line(exc)}"
        else:
            row["label"], row["frequency_hz"] = working.label, working.frequency
            row["error_estimate"] = working.error_estimate if np.isfinite(working.error_estimate) else None
            row["extra"] = extra(working) if extra is not None else {}
    except ModalfeError as exc:
        row["status"] = f"error: {type(exc).__name__}: {_one_line(exc)}"
    row["seconds"] = time.perf_counter() - start
    return row


def asks_own_question(scene, selector: str, near: float) -> bool:
    """Whether a sweep point asks the scene's own question about its working mode ``selector`` sought ``near`` [Hz]
    (as ``modes`` and ``forced`` ask it), rather than a window of modes around ``near``."""
    from modalfe.solve.api import sought_near

    return selector in {wm.selector for wm in scene.working_modes} and near == sought_near(scene, selector)


def _sampled(values: np.ndarray) -> list[float]:
    peak = float(np.abs(values).max()) if values.size else 0.0
    return [round(float(x), 6) for x in (values / peak if peak > 0 else values)]


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split())


# ---- the table ---------------------------------------------------------------------------------------------

def _cell(key: str, value) -> str:
    if value is None:
        return ""
    if key in _JSON:
        return json.dumps(value)
    return str(value)


# units of the swept settings that are not builder parameters (those carry their own, modalfe.geometry)
_SETTING_UNITS = {"analysis.near": "Hz", "mesh.max_frequency": "Hz", "mesh.max_size": "m", "mesh.min_size": "m",
                  "mesh.elements_per_wavelength": "-", "mesh.min_layers": "-", "mesh.clamp_grading": "-",
                  "springs": "N/m", "masses": "kg", "E": "Pa", "rho": "kg/m^3", "nu": "-"}


def parameter_column(scene, name: str) -> str:
    """The table column of a swept parameter: its name and SI unit, e.g. ``ceramic_thickness [m]``."""
    from modalfe.geometry import BUILDERS, builder_parameters

    unit = ""
    if scene.device in BUILDERS and name in builder_parameters(scene.device):
        unit = builder_parameters(scene.device)[name].unit
    unit = unit or _SETTING_UNITS.get(name) or _SETTING_UNITS.get(name.split(".")[0]) \
        or _SETTING_UNITS.get(name.rsplit(".", 1)[-1]) or "SI"
    return f"{name} [{unit}]"


def _parameter(column: str) -> str:
    """The parameter named by a table column (its unit dropped)."""
    return column.split(" [", 1)[0]


def _encode(row: Mapping, columns: Sequence[str]) -> dict[str, str]:
    out = {k: _cell(k, row.get(k)) for k in COLUMNS}
    for c in columns:
        out[c] = json.dumps(row["params"][_parameter(c)]) if _parameter(c) in row["params"] else ""
    return out


def _decode(raw: Mapping[str, str], names: Sequence[str]) -> dict:
    """A parsed row (ValueError, KeyError, TypeError if it cannot be read)."""

    def number(text: str, kind=float):
        return kind(text) if text not in ("", None) else None

    row = {"params": {_parameter(n): json.loads(raw[n]) for n in names if raw.get(n) not in ("", None)},
           "point": number(raw["point"], int), "point_id": raw["point_id"], "scene": raw["scene"],
           "scene_sha256": raw["scene_sha256"], "overrides": json.loads(raw["overrides"] or "{}"),
           "selector": raw["selector"], "near_hz": number(raw["near_hz"]), "count": number(raw["count"], int),
           "extra_fn": raw["extra_fn"], "status": raw["status"], "label": raw["label"],
           "frequency_hz": number(raw["frequency_hz"]), "error_estimate": number(raw.get("error_estimate")),
           "resolution": json.loads(raw.get("resolution") or "{}"), "tracked_label": raw["tracked_label"],
           "tracked_frequency_hz": number(raw["tracked_frequency_hz"]), "mac_previous": number(raw["mac_previous"]),
           "crossing": {"True": True, "False": False}.get(raw["crossing"]), "dofs": number(raw["dofs"], int),
           "seconds": number(raw["seconds"]), "extra": json.loads(raw["extra"] or "{}"),
           "candidates": json.loads(raw["candidates"] or "[]")}
    if not row["point_id"] or not row["status"]:
        raise ValueError("no point id or status")
    return row


def _repair_tail(path: Path) -> None:
    """Drop a torn last line (a writer killed mid-line): truncate after the last newline."""
    if not path.exists():
        return
    with open(path, "rb+") as f:
        data = f.read()
        if not data or data.endswith(b"\n"):
            return
        keep = data.rfind(b"\n") + 1
        f.truncate(keep)
    log.warning("%s: dropped a torn last line (%d bytes) left by an interrupted writer", path, len(data) - keep)


def _read_raw(path: Path) -> tuple[list[str], list[dict[str, str]]]:
    """(header, rows as strings) of a table; SceneError if the file is not a sweep table of this format."""
    if not path.exists() or path.stat().st_size == 0:
        return [], []
    try:
        with open(path, newline="", encoding="utf-8") as f:
            reader = csv.DictReader(f)
            header = list(reader.fieldnames or [])
            rows = list(reader)
    except (UnicodeDecodeError, csv.Error) as exc:
        raise SceneError(f"--out: {path} is not a sweep table ({_one_line(exc)}); choose another file") from None
    missing = [c for c in COLUMNS if c not in header]
    if missing:
        raise SceneError(f"--out: {path} is not a sweep table of this format (no column {missing[0]!r}); "
                         f"choose another file")
    return header, rows


def read_table(path: str | Path) -> dict[str, dict]:
    """Finished points of a results table, by point id (unreadable rows and a torn last line are ignored)."""
    path = Path(path)
    if not path.exists():
        return {}
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError:
        return {}
    if data and not data.endswith(b"\n"):
        data = data[: data.rfind(b"\n") + 1]  # a line being written or torn
    reader = csv.DictReader(io.StringIO(data.decode("utf-8", errors="replace"), newline=""))
    names = [c for c in (reader.fieldnames or []) if c not in COLUMNS]
    rows = {}
    for raw in reader:
        try:
            row = _decode(raw, names)
        except (KeyError, TypeError, ValueError):
            log.warning("ignoring an unreadable row in %s", path)
            continue
        rows[row["point_id"]] = row
    return rows


def _write_atomic(path: Path, header: Sequence[str], rows: Sequence[Mapping[str, str]]) -> None:
    """Replace ``path`` by a table of ``rows`` (strings) in one step (unique temporary file, os.replace)."""
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w", newline="", encoding="utf-8") as f:
            writer = csv.DictWriter(f, fieldnames=list(header), restval="", extrasaction="ignore", lineterminator="\n")
            writer.writeheader()
            writer.writerows(rows)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


@contextlib.contextmanager
def table_lock(path: Path) -> Iterator[None]:
    """Hold the sidecar lock ``<path>.lock`` (exclusive ``fcntl.flock``) for the duration; SceneError at once if
    another sweep holds it. The lock is released by the kernel when its holder dies."""
    try:
        import fcntl
    except ImportError:  # not POSIX: no protection against a second writer
        yield
        return
    lock = path.with_name(path.name + ".lock")
    with open(lock, "a+") as f:
        try:
            fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise SceneError(f"--out: {path} is being written by another sweep (lock {lock.name} held); wait for it "
                             f"to finish or choose another file") from None
        try:
            yield
        finally:
            fcntl.flock(f.fileno(), fcntl.LOCK_UN)


# ---- the sweep -----------------------------------------------------------------------------------------------

def sweep(scene_ref: str, params: Mapping[str, Sequence], *, out: str | Path, selector: str, near: float,
          base: Mapping | None = None, scheduler: str | None = None, workers: int = 2, count: int | None = None,
          extra: Callable | None = None, progress: bool = True, resolution: Mapping | None = None) -> list[dict]:
    """Run (or resume) a sweep over the Cartesian product of ``params``; returns tracked rows in grid order
    (see the module docstring for the table). ``scheduler``: address of an existing dask scheduler, ``"inline"``
    to compute in this process, else a LocalCluster of ``workers`` single-threaded processes. Each point is the
    answer ``modes`` gives at ``resolution`` (``solve_modes``' tol, fidelity, error_estimate; default its own), with
    ``count`` modes (default the scene's ``analysis.count``, as ``modes`` asks)."""
    out = Path(out)
    check_workers(workers)
    if count is not None and (isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count < 1):
        raise SceneError(f"count: must be an integer >= 1, got {count!r}")
    if not (isinstance(near, (int, float)) and np.isfinite(near) and near > 0):
        raise SceneError(f"--near: must be a positive frequency [Hz], got {near!r}")
    names = list(params)
    clash = [n for n in names if n in COLUMNS]
    if clash:
        raise SceneError(f"--param: '{clash[0]}' is also a column of the table; rename the parameter")
    points = [dict(zip(names, combo)) for combo in itertools.product(*(params[n] for n in names))]
    if not points:
        raise SceneError("--param: the sweep has no points")
    if out.is_dir():
        raise SceneError(f"--out: {out} is a folder; give a .csv file")
    from modalfe.scene import load_scene

    base = dict(base or {})
    for p in (points[0], points[-1]):  # bad parameter names or values fail here, in one line
        scene = load_scene(scene_ref, **{**base, **p})
    columns = [parameter_column(scene, n) for n in names]
    count = scene.analysis.count if count is None else count
    resolution = {**DEFAULT_RESOLUTION, **(resolution or {})}
    context = definition(scene_ref, base, selector, near, count, extra, scene, resolution)
    keys = [point_id(p, context) for p in points]
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise SceneError(f"--out: cannot create the folder {out.parent} ({_one_line(exc)})") from None
    with table_lock(out):
        _repair_tail(out)
        header, existing = _read_raw(out)
        stored_names = [c for c in header if c not in COLUMNS]
        stored_names += [c for c in columns if _parameter(c) not in {_parameter(s) for s in stored_names}]
        header = DEFINITION + stored_names + RESULT
        _write_atomic(out, header, existing)  # the union header, the torn tail gone
        done: dict[str, dict] = {}
        for raw in existing:
            with contextlib.suppress(KeyError, TypeError, ValueError):
                row = _decode(raw, stored_names)
                if not row["status"].startswith("error"):
                    done[row["point_id"]] = row
        todo = [(i, p) for i, (p, k) in enumerate(zip(points, keys)) if k not in done]
        log.info("%d points, %d already finished, %d to compute", len(points), len(points) - len(todo), len(todo))

        def finish(i: int, row: dict) -> None:
            row = {**row, **context, "point": i, "point_id": keys[i], "params": points[i]}
            with open(out, "a", newline="", encoding="utf-8") as f:
                writer = csv.DictWriter(f, fieldnames=header, restval="", lineterminator="\n")
                writer.writerow(_encode(row, stored_names))
                f.flush()
                os.fsync(f.fileno())
            done[keys[i]] = row

        if todo:
            question = (scene_ref, base, selector, near, count, extra, resolution)
            _compute(todo, question, scheduler, workers, finish, len(points) if progress else 0)
        rows = track([{**done[k], "point": i} for i, k in enumerate(keys)], selector)
        grid = set(keys)
        others, seen = [], set()
        for raw in reversed(existing):  # other sweeps' rows, and points no longer in the grid: kept, last copy
            if raw.get("point_id") not in grid and raw.get("point_id") not in seen:
                seen.add(raw.get("point_id"))
                others.append(raw)
        _write_atomic(out, header, [_encode(r, stored_names) for r in rows] + others[::-1])
    return rows


def _compute(todo, question: tuple, scheduler, workers, finish, total) -> None:
    """Evaluate the ``todo`` points (index, params), calling ``finish(index, row)`` as each ends; ``question``: the
    arguments of ``evaluate_point`` (scene_ref, base, selector, near, count, extra, resolution) but the point's."""
    scene_ref, base, *rest = question
    bar = None
    if total:
        from tqdm import tqdm

        bar = tqdm(total=total, initial=total - len(todo), desc="sweep", unit="point")
    try:
        if scheduler == INLINE:
            for i, p in todo:
                finish(i, evaluate_point(scene_ref, p, base, *rest))
                if bar is not None:
                    bar.update()
            return
        from dask.distributed import as_completed

        with dask_client(scheduler, workers) as client:
            futures = submit_all(client, evaluate_point,
                                 [(i, (scene_ref, p, base, *rest)) for i, p in todo])
            for future in as_completed(futures):
                finish(futures[future], future.result())
                if bar is not None:
                    bar.update()
    finally:
        if bar is not None:
            bar.close()


def track(rows: list[dict], selector: str) -> list[dict]:
    """Follow the working mode by MAC along the rows' order; flag crossings.

    At the first point the tracked mode is the labelled one (MAC 1 by convention); after it, the candidate
    whose shape best matches the previously tracked one. ``crossing`` is True where that candidate is not the
    labelled mode, the MAC is below ``MAC_CROSSING``, or the label was not found (the mode left the search
    window: the row is still tracked by shape, or marked when there is nothing to follow)."""
    out = []
    previous = None
    for row in rows:
        candidates = row.get("candidates") or []
        labelled = None
        if row.get("label") and row.get("frequency_hz") is not None:
            labelled = next((c for c in candidates if c["label"] == row["label"]
                             and abs(c["frequency_hz"] - row["frequency_hz"]) <= 1e-9 * abs(row["frequency_hz"])),
                            None)
        if previous is None or not candidates:
            tracked, value = labelled, (1.0 if labelled is not None else None)
        else:
            tracked = max(candidates, key=lambda c: mac(c["shape"], previous["shape"]))
            value = mac(tracked["shape"], previous["shape"])
        crossing = tracked is None or tracked is not labelled or value < MAC_CROSSING
        out.append({**row, "tracked_label": tracked["label"] if tracked is not None else "",
                    "tracked_frequency_hz": tracked["frequency_hz"] if tracked is not None else None,
                    "mac_previous": value, "crossing": crossing})
        if tracked is not None:
            previous = tracked
    return out


def coupling_extra(working) -> dict:
    """fa [Hz] and k_eff of the working mode from the open circuit of its model, its partner by shape
    (``modalfe.response.forced.open_circuit``: the one path of ``table``, ``forced`` and ``admittance``)."""
    from modalfe.response.forced import open_circuit

    both = open_circuit(working)
    return {"fa_hz": both.fa, "k_eff": both.k_eff}


def friction_extra(working, *, volts: float = 10.0, preload: float = 3.0, speed: float = 0.01) -> dict:
    """The felt outcome at ``volts`` [V], preload [N] and sliding speed [m/s] (seed 001's 3 N, 1 cm/s) as columns:
    the chain (``modalfe.contact.chain``) of the working mode's reduced model at the feet (the scene's damping; the
    foot model driven at the mode's frequency, its feet sharing the load) and seed 000's foot: the amplitude per
    volt, the friction reduction, the flight ratio, the current and power drawn and the amplitude's rise time."""
    from modalfe.contact.chain import FootContact, chain_from_rom
    from modalfe.response.forced import reduce
    from modalfe.response.losses import mode_damping, resolve_losses

    scene = working.scene
    feet = [g for g in scene.full_assembly().faces if g.startswith("foot_")]
    rom = reduce(working, outputs=feet, damping=mode_damping(working, resolve_losses(scene))[0])
    chain = chain_from_rom(rom, FootContact(preload=preload, speed=speed), mode=working)
    o = chain.outcome(volts)
    return {"amplitude_per_volt_m": chain.amplitude_per_volt(), "friction_reduction": o.reduction,
            "flight_ratio_percent": o.flight_ratio, "current_a": o.current, "power_w": o.power,
            "rise_time_s": o.rise_time, "volts": volts}


@dataclass(frozen=True)
class OutcomeColumns:
    """A sweep's extra columns: the felt outcome at ``voltage`` [V] through ``contact`` (``FootContact`` or
    ``FingerContact``), as ``friction`` and ``finger`` give it for a scene: the chain of ``forced``'s reduced model
    of the working mode (``modalfe.contact.chain.haptic_chain``: the selector and near of the sweep, at its
    ``resolution``, the point's solve read back) with the amplitude's stated error, so the reduction comes with its
    range (``Outcome.to_json``'s columns)."""

    voltage: float
    contact: object
    selector: str
    near: float
    resolution: tuple = ()  # (name, value) pairs of ``solve_modes``' keywords

    @property
    def key(self) -> str:
        return f"{__name__}.OutcomeColumns({self.voltage!r} V, {self.contact.describe()})"

    def __call__(self, working) -> dict:
        from modalfe.contact.chain import haptic_chain

        scene = working.scene  # the point's question, so that its solve is read back
        near = None if asks_own_question(scene, self.selector, self.near) else self.near
        chain = haptic_chain(scene, self.contact, selector=self.selector, near=near, **dict(self.resolution))
        return chain.outcome(self.voltage).to_json()
