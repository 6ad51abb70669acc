"""Progress bars for long work (renders, GIF sweeps, solves), shown only on a terminal.

:func:`progress` yields an ``advance`` callback; library code that runs long takes such a callback
as an optional keyword (``on_progress``) so the command line can show a bar and tests and the app
can pass nothing. On a non-terminal stderr (a pipe, a log, the test suite) nothing is printed.

>>> with progress(3, "render") as advance:   # doctest: +SKIP
...     for _ in range(3):
...         advance()
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any, TypeVar

T = TypeVar("T")

__all__ = ["DELAY", "Advance", "Report", "progress", "run_with_bar", "work_bar"]

#: ``advance(steps=1, description=None)``: count finished steps, optionally relabel the bar.
Advance = Callable[..., None]

#: ``report(fraction, message)``: how far a piece of work is (0..1) and what it does now; the
#: progress hook the library's long calls take (``rank_designs``, ``review_edits``, the app's jobs).
Report = Callable[[float, str], None]


@contextmanager
def progress(total: int | None, label: str, *, force: bool = False) -> Iterator[Advance]:
    """A rich progress bar on stderr for ``total`` steps (None: unknown, a running counter).

    Parameters
    ----------
    total : int or None
    label : str
        Shown before the bar.
    force : bool
        Show the bar even when stderr is not a terminal.
    """
    from rich.console import Console

    console = Console(stderr=True)
    if not (force or console.is_terminal):
        yield lambda steps=1, description=None: None
        return
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    bar = Progress(
        TextColumn(f"[bold]{label}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        TimeRemainingColumn(),
        TextColumn("{task.description}"),
        console=console,
        transient=True,
    )
    task = bar.add_task("", total=total)

    def advance(steps: int = 1, description: str | None = None) -> None:
        if description is None:
            bar.update(task, advance=steps)
        else:
            bar.update(task, advance=steps, description=description)

    with bar:
        yield advance


#: Seconds a command runs before :func:`work_bar` shows its bar (quicker commands print nothing).
DELAY = 1.0


@contextmanager
def work_bar(label: str, *, delay: float | None = None, force: bool = False) -> Iterator[Report]:
    """A progress bar on stderr for work reported as fractions, shown once it has run ``delay``
    seconds (default :data:`DELAY`; quick work prints nothing) and only when stderr is a
    terminal (or ``force``). Every command that can run over about 2 s has one.

    Yields ``report(fraction, message)``; the bar shows the fraction, the time spent, an
    estimate of the time left once the work can be counted, and the message. It is removed when
    the block ends, so the command's own output follows on a clean line.
    """
    import threading

    from rich.console import Console

    console = Console(stderr=True)
    if not (force or console.is_terminal):
        yield lambda fraction, message: None
        return
    from rich.markup import escape
    from rich.progress import (
        BarColumn,
        Progress,
        SpinnerColumn,
        TaskProgressColumn,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    bar = Progress(
        SpinnerColumn(),
        TextColumn(f"[bold]{escape(label)}"),
        BarColumn(),
        TaskProgressColumn(),
        TimeElapsedColumn(),
        TextColumn("left"),
        TimeRemainingColumn(),
        TextColumn("{task.description}"),
        console=console,
        transient=True,
    )
    task = bar.add_task("", total=1.0)
    lock = threading.Lock()
    started = [False, False]  # started, stopped

    def start() -> None:
        with lock:
            if not started[1]:
                bar.start()
                started[0] = True

    timer = threading.Timer(DELAY if delay is None else delay, start)
    timer.daemon = True

    def report(fraction: float, message: str) -> None:
        bar.update(task, completed=max(0.0, min(1.0, float(fraction))), description=message)

    timer.start()
    try:
        yield report
    finally:
        timer.cancel()
        with lock:
            started[1] = True
            if started[0]:
                bar.stop()


def run_with_bar(
    label: str, message: str, work: Callable[..., T], /, *args: Any, **kwargs: Any
) -> T:
    """``work(*args, **kwargs)`` under a :func:`work_bar` (its spinner, ``message`` and the time
    spent) for work that cannot say how far it is."""
    with work_bar(label) as report:
        report(0.0, message)
        return work(*args, **kwargs)
