"""Independent runs from several starting points (multi-start tuning, calibration) on the sweep's Dask cluster.

``run_starts(task, starts)`` evaluates ``task(start)`` for every start dict and returns the results in the
order of ``starts``; a start whose task raises gets the exception object as its result, so one bad start
never loses the others. Where the runs happen is the same choice as ``modalfe sweep --scheduler``:
``None`` starts a LocalCluster of single-threaded worker processes, ``"inline"`` runs them one after
another in this process, anything else is the address of an existing dask scheduler.
``dask_client`` is the one place that creates that client (the sweep uses it too).
"""

from __future__ import annotations

import contextlib
import logging
import math
import os
import time
from collections.abc import Callable, Iterator, Mapping, Sequence

import numpy as np

from modalfe.errors import SceneError

INLINE = "inline"  # ``scheduler=INLINE``: run in this process, one after another, no dask


def check_workers(workers) -> int:
    """``workers`` as a positive int, else SceneError naming ``--workers``."""
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise SceneError(f"--workers: must be an integer >= 1, got {workers!r}")
    return int(workers)


@contextlib.contextmanager
def dask_client(scheduler: str | None, workers: int) -> Iterator:
    """A ``dask.distributed.Client`` on ``scheduler`` (an address), or on a LocalCluster of ``workers``
    single-threaded processes when ``scheduler`` is None; closed (with its cluster) on exit."""
    from dask.distributed import Client, LocalCluster

    # importing distributed sets its logger to INFO (its logging config), undoing the CLI's WARNING
    # (cli.main.configure_logging); LocalCluster's silence_logs only quiets distributed's own stderr handler, which
    # it does not add when the root logger has one: the scheduler's and nannies' INFO lines (this process) then
    # reached stderr through the root handler. Held at WARNING here, restored on exit.
    quiet = logging.getLogger("distributed")
    level = quiet.level
    quiet.setLevel(max(level, logging.WARNING))
    cluster = None
    try:
        if not scheduler:
            cluster = LocalCluster(n_workers=check_workers(workers), threads_per_worker=1, processes=True,
                                   dashboard_address=None, scheduler_kwargs={"dashboard": False},
                                   silence_logs=logging.WARNING)
        client = Client(scheduler or cluster)
        try:
            yield client
        finally:
            client.close()
    finally:
        if cluster is not None:
            cluster.close()
        quiet.setLevel(level)


def submit_all(client, fn: Callable, calls: Sequence[tuple[int, tuple]]) -> dict:
    """Submit ``fn(*args)`` for each ``(index, args)`` as impure tasks with unique keys; {future: index}."""
    return {client.submit(fn, *args, key=f"modalfe-{i}-{time.time_ns()}", pure=False): i for i, args in calls}


def _outcome(fn: Callable, *args):
    """``fn(*args)``, or the exception it raised (returned, not raised)."""
    try:
        return fn(*args)
    except Exception as exc:  # one start's failure is that start's result (module docstring)
        return exc


def run_starts(task: Callable, starts: Sequence[Mapping], *, scheduler: str | None = None,
               workers: int | None = None, progress=None) -> list:
    """``[task(s) for s in starts]`` computed on ``scheduler`` (module docstring); an exception raised by a
    start is returned as its result. ``workers`` (LocalCluster only): default one per start, at most the
    CPU count. ``progress``: None/False for nothing, True for a tqdm bar, or a callable
    ``progress(index, result)`` called as each start finishes (in completion order)."""
    starts = list(starts)
    if not starts:
        return []
    if workers is None:
        workers = min(len(starts), os.cpu_count() or 1)
    workers = check_workers(workers)
    bar = None
    if progress is True:
        from tqdm import tqdm

        bar = tqdm(total=len(starts), desc="starts", unit="start")

    def finished(i: int, result) -> None:
        results[i] = result
        if bar is not None:
            bar.update()
        elif callable(progress):
            progress(i, result)

    results: list = [None] * len(starts)
    try:
        if scheduler == INLINE:
            for i, start in enumerate(starts):
                finished(i, _outcome(task, start))
            return results
        from dask.distributed import as_completed

        with dask_client(scheduler, workers) as client:
            futures = submit_all(client, task, [(i, (s,)) for i, s in enumerate(starts)])
            for future in as_completed(futures):
                finished(futures[future], _outcome(future.result))  # the task's exception, re-raised here
        return results
    finally:
        if bar is not None:
            bar.close()


def latin_hypercube(bounds: Mapping[str, tuple[float, float]], count: int, *, seed: int = 0) -> list[dict]:
    """``count`` starting points of a multi-start (``tune``, ``calibrate``), a Latin hypercube in ln |p| (the scale
    both step in) within ``bounds`` (name -> (low, high), one sign):
    each parameter's range cut in ``count`` equal slices of ln |p|, one point in each, slices paired at random
    (McKay, Beckman & Conover, Technometrics 21 (1979) 239); ``seed`` makes it reproducible."""
    if isinstance(count, bool) or not isinstance(count, int) or count < 1:
        raise SceneError(f"--starts: must be an integer >= 1, got {count!r}")
    rng = np.random.default_rng(seed)
    starts: list[dict] = [{} for _ in range(count)]
    for name, (lo, hi) in bounds.items():
        if not (lo < hi and lo * hi > 0):
            raise SceneError(f"--bounds {name}: LOW < HIGH of one sign needed for a start in ln |p|")
        a, b = sorted((math.log(abs(lo)), math.log(abs(hi))))
        fractions = (rng.permutation(count) + rng.random(count)) / count
        for start, u in zip(starts, fractions):
            start[name] = math.copysign(math.exp(a + u * (b - a)), lo)
    return starts
