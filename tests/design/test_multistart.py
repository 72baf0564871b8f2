"""run_starts: results in the order of the starts, a failing start returns its exception, the same on every
scheduler (in process, a LocalCluster it starts, an existing scheduler's address).

The task is ``operator.itemgetter("x")`` (picklable by reference, so worker processes need no test module):
a start without "x" raises KeyError, which must come back as that start's result."""

import logging
import operator

import pytest

from modalfe.design.multistart import INLINE, run_starts
from modalfe.errors import SceneError

STARTS = [{"x": 3.0}, {"y": 1.0}, {"x": -1.5}, {"x": 0.0}]
TASK = operator.itemgetter("x")


def _check(results):
    assert [results[i] for i in (0, 2, 3)] == [3.0, -1.5, 0.0]
    assert isinstance(results[1], KeyError)


def test_inline_order_errors_and_progress():
    seen = []
    results = run_starts(TASK, STARTS, scheduler=INLINE, progress=lambda i, r: seen.append(i))
    _check(results)
    assert seen == [0, 1, 2, 3]
    assert run_starts(TASK, [], scheduler=INLINE) == []


def test_local_cluster(caplog):
    """Results as inline, and none of dask's INFO chatter (scheduler, nanny) from this process: importing
    distributed sets its logger to INFO, and its records reached stderr through the root handler."""
    import distributed  # noqa: F401  (its logging config first, as in the CLI)

    before = logging.getLogger("distributed").level
    with caplog.at_level(logging.INFO):
        _check(run_starts(TASK, STARTS, workers=2))
    chatter = [r.getMessage() for r in caplog.records if r.name.startswith("distributed") and r.levelno < 30]
    assert chatter == []
    assert logging.getLogger("distributed").level == before  # restored


def test_scheduler_address():
    from dask.distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as cluster:
        seen = []
        _check(run_starts(TASK, STARTS, scheduler=cluster.scheduler_address, progress=lambda i, r: seen.append(i)))
        assert sorted(seen) == [0, 1, 2, 3]


@pytest.mark.parametrize("workers", [0, 1.5, True])
def test_bad_workers(workers):
    with pytest.raises(SceneError, match="--workers"):
        run_starts(TASK, STARTS, workers=workers)
