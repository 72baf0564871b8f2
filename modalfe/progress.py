"""Progress on a terminal for the steps that can take more than a couple of seconds: building a mesh and assembling
a model, the eigen solve of each refinement level, the completion of an admittance band, direct frequency loops,
sweeps and multi-starts. tqdm bars on stderr, shown only inside ``shown()``: the command line enters it when stderr
is a terminal and the command prints no JSON; the library called from Python shows nothing unless asked.

Bars appear once the command has run ``DELAY`` seconds (a quick command shows none; a long one shows each of its
steps, short ones included, since a long silence is many steps as often as one long one), and each is removed when
its step ends (the command's own output follows)."""

from __future__ import annotations

import contextlib
import contextvars
import sys
import threading
import time
from collections.abc import Iterable, Iterator

# when the steps began to be shown (time.monotonic() [s]), None where they are not
_SHOWN: contextvars.ContextVar[float | None] = contextvars.ContextVar("modalfe_progress_shown", default=None)
DELAY = 2.0  # seconds a command runs before its bars appear (DESIGN.md: "anything longer than a couple of seconds")
TICK = 0.5  # seconds between refreshes of a running step's elapsed time


@contextlib.contextmanager
def shown(on: bool = True) -> Iterator[None]:
    """Within this block, steps show their progress on stderr (``on``) or nothing."""
    token = _SHOWN.set(time.monotonic() if on else None)
    try:
        yield
    finally:
        _SHOWN.reset(token)


def hide() -> None:
    """Show nothing from here on in this context: a worker process whose parent draws the progress."""
    _SHOWN.set(None)


def is_shown() -> bool:
    """Whether steps show their progress here (``shown``)."""
    return _SHOWN.get() is not None


def _delay() -> float:
    """Seconds until bars may appear: what is left of ``DELAY`` since the steps began to be shown."""
    return max(0.0, DELAY - (time.monotonic() - _SHOWN.get()))


def wanted(json_output: bool, stream=None) -> bool:
    """Whether a command shows progress: on a terminal (``stream``, default stderr) and not printing JSON."""
    stream = sys.stderr if stream is None else stream
    return not json_output and bool(getattr(stream, "isatty", lambda: False)())


@contextlib.contextmanager
def step(description: str) -> Iterator[None]:
    """One step of unknown length: its ``description`` and the seconds it has run, refreshed every ``TICK``."""
    if not is_shown():
        yield
        return
    from tqdm import tqdm

    delay = _delay()
    bar = tqdm(total=None, desc=description, bar_format="{desc}: {elapsed}", leave=False, file=sys.stderr,
               delay=delay)
    start, stop = time.monotonic(), threading.Event()

    def tick() -> None:
        while not stop.wait(TICK):
            if time.monotonic() - start >= delay:
                bar.refresh()

    ticker = threading.Thread(target=tick, name="modalfe-progress", daemon=True)
    ticker.start()
    try:
        yield
    finally:
        stop.set()
        ticker.join()
        bar.close()


def counted(items: Iterable, description: str, *, unit: str = "step", total: int | None = None) -> Iterable:
    """``items`` counted by a bar (its ``description``, ``unit``) where progress is shown, else ``items`` itself."""
    if not is_shown():
        return items
    from tqdm import tqdm

    return tqdm(items, desc=description, unit=unit, total=total, leave=False, file=sys.stderr, delay=_delay())
