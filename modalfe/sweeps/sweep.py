"""Parameter sweeps on dask.distributed, written point by point to a CSV table and resumable.

Each point (a combination of parameter values) has a stable id (hash of its parameters); a rerun
reads the table and computes only the missing points. Workers return the working mode chosen by
label and its nearest candidates with their shapes sampled on a grid fixed relative to the main
part, so that after the sweep the working mode is tracked by the modal assurance criterion (MAC)
from point to point; where the best-matching candidate is not the labelled one, or matches poorly,
the row says so (a mode crossing) instead of swapping silently.
"""

from __future__ import annotations

import csv
import hashlib
import itertools
import json
import logging
import os
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

import numpy as np

from modalfe.errors import SceneError

log = logging.getLogger(__name__)

MAC_CROSSING = 0.8  # below this the tracked mode is not the same shape any more (Allemang 2003: MAC > 0.9 consistent)
GRID = (12, 6)  # samples of the normal displacement over the main part's top face (relative coordinates)
FIELDS = ["point_id", "params", "label", "frequency_hz", "candidates", "dofs", "seconds", "extra"]


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
    return [float(v) for v in values]


def point_id(params: Mapping[str, float]) -> str:
    return hashlib.sha1(json.dumps(dict(sorted(params.items())), sort_keys=True).encode()).hexdigest()[:16]


def mac(a: np.ndarray, b: np.ndarray) -> float:
    """Modal assurance criterion |a.b|^2 / (|a|^2 |b|^2) (Allemang & Brown 1982)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    den = float(a @ a) * float(b @ b)
    return float((a @ b) ** 2 / den) if den > 0 else 0.0


def evaluate_point(scene_ref: str, params: dict, base: dict, selector: str, near: float, count: int = 6,
                   extra: Callable | None = None) -> dict:
    """Solve one point: the labelled working mode and its ``count`` nearest candidates (shapes sampled)."""
    from modalfe.results.modes import select
    from modalfe.scene import load_scene
    from modalfe.solve.api import solve_modes

    start = time.perf_counter()
    scene = load_scene(scene_ref, **{**base, **params})
    modes = solve_modes(scene, near=near, count=count, error_estimate=False)
    working = select(modes, selector, near)
    full = scene.full_assembly()
    main = full.main_part
    lo, hi = full.bounds
    U, V = np.meshgrid(np.linspace(0.02, 0.98, GRID[0]), np.linspace(0.05, 0.95, GRID[1]))
    points = np.vstack([lo[0] + U.ravel() * (hi[0] - lo[0]), lo[1] + V.ravel() * (hi[1] - lo[1]),
                        np.full(U.size, main.hi[2])])  # a grid fixed relative to the device
    P = modes.model.displacement_probes(points.T)[2 * U.size:]
    candidates = [{"index": m.index, "label": m.label, "frequency_hz": m.frequency,
                   "shape": [round(float(x), 6) for x in (P @ m.shape) / np.abs(P @ m.shape).max()]}
                  for m in modes]
    return {"point_id": point_id(params), "params": params, "label": working.label,
            "frequency_hz": working.frequency, "candidates": candidates, "dofs": modes.dofs,
            "seconds": time.perf_counter() - start,
            "extra": extra(working) if extra is not None else {}}


def read_table(path: Path) -> dict[str, dict]:
    """Finished points of a results table, by point id (a partly written last line is ignored)."""
    if not path.exists():
        return {}
    rows = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            try:
                rows[row["point_id"]] = {
                    "point_id": row["point_id"], "params": json.loads(row["params"]), "label": row["label"],
                    "frequency_hz": float(row["frequency_hz"]), "candidates": json.loads(row["candidates"]),
                    "dofs": int(row["dofs"]), "seconds": float(row["seconds"]), "extra": json.loads(row["extra"]),
                }
            except (KeyError, TypeError, ValueError, json.JSONDecodeError):
                log.warning("ignoring an unreadable row in %s", path)
    return rows


def _append(path: Path, row: dict) -> None:
    new = not path.exists()
    with open(path, "a", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=FIELDS)
        if new:
            writer.writeheader()
        writer.writerow({k: json.dumps(row[k]) if k in ("params", "candidates", "extra") else row[k] for k in FIELDS})
        f.flush()
        os.fsync(f.fileno())


def sweep(scene_ref: str, params: Mapping[str, Sequence[float]], *, out: str | Path, selector: str, near: float,
          base: Mapping | None = None, scheduler: str | None = None, workers: int = 2, count: int = 6,
          extra: Callable | None = None, progress: bool = True) -> list[dict]:
    """Run (or resume) a sweep over the Cartesian product of ``params``; returns tracked rows in
    parameter order. ``scheduler``: address of an existing dask scheduler, else a LocalCluster of
    ``workers`` single-threaded processes."""
    from dask.distributed import Client, LocalCluster, as_completed

    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    names = list(params)
    points = [dict(zip(names, combo)) for combo in itertools.product(*(params[n] for n in names))]
    if not points:
        raise SceneError("--param: the sweep has no points")
    from modalfe.scene import load_scene

    for p in (points[0], points[-1]):  # bad parameter names or values fail here, in one line
        load_scene(scene_ref, **{**dict(base or {}), **p})
    done = read_table(out)
    todo = [p for p in points if point_id(p) not in done]
    log.info("%d points, %d already finished, %d to compute", len(points), len(points) - len(todo), len(todo))
    if todo:
        cluster = None if scheduler else LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                                      dashboard_address=None)
        client = Client(scheduler or cluster)
        try:
            futures = [client.submit(evaluate_point, scene_ref, p, dict(base or {}), selector, near, count, extra,
                                     key=f"modalfe-{point_id(p)}", pure=False) for p in todo]
            bar = None
            if progress:
                from tqdm import tqdm

                bar = tqdm(total=len(points), initial=len(points) - len(todo), desc="sweep", unit="point")
            for future in as_completed(futures):
                row = future.result()
                _append(out, row)
                done[row["point_id"]] = row
                if bar is not None:
                    bar.update()
            if bar is not None:
                bar.close()
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
    return track([done[point_id(p)] for p in points], selector)


def track(rows: list[dict], selector: str) -> list[dict]:
    """Follow the working mode by MAC along the rows' order; flag crossings."""
    out = []
    previous = None
    for row in rows:
        labelled = next(c for c in row["candidates"] if c["label"] == row["label"]
                        and abs(c["frequency_hz"] - row["frequency_hz"]) < 1e-9 * row["frequency_hz"])
        if previous is None:
            tracked, value = labelled, 1.0
        else:
            tracked = max(row["candidates"], key=lambda c: mac(c["shape"], previous["shape"]))
            value = mac(tracked["shape"], previous["shape"])
        crossing = tracked is not labelled or value < MAC_CROSSING
        out.append({**row, "tracked_label": tracked["label"], "tracked_frequency_hz": tracked["frequency_hz"],
                    "mac_previous": value, "crossing": crossing})
        previous = tracked
    return out


def coupling_extra(working) -> dict:
    """k_eff of the working mode (an open-circuit solve beside the short-circuit one)."""
    from modalfe.results.coupling import antiresonance, k_eff
    from modalfe.solve.api import solve_modes

    open_modes = solve_modes(working.scene, near=working.frequency, count=4, circuit="open", error_estimate=False)
    return {"k_eff": k_eff(working.frequency, antiresonance(working, open_modes).frequency)}


def friction_extra(working, *, volts: float = 10.0, preload: float = 3.0, speed: float = 0.01) -> dict:
    """Foot amplitude per volt (reduced model at the feet, the scene's damping) and the friction
    reduction it gives at ``volts`` [V], preload [N] and sliding speed [m/s] (seed 001's 3 N, 1 cm/s)."""
    from modalfe.contact import simulate_contact
    from modalfe.response.forced import Damping, reduce

    scene = working.scene
    feet = [g for g in scene.full_assembly().faces if g.startswith("foot_")]
    rom = reduce(working, outputs=feet, damping=Damping.parse(scene.drive.damping))
    per_volt = rom.amplitude_per_volt()
    curve = simulate_contact(voltage=[volts], amplitude_per_volt=per_volt, preload=preload, speed=speed)
    return {"amplitude_per_volt_m": per_volt, "friction_reduction": float(np.ravel(curve.friction_reduction)[0]),
            "volts": volts}
