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

__all__ = ["Advance", "progress"]

#: ``advance(steps=1, description=None)``: count finished steps, optionally relabel the bar.
Advance = Callable[..., None]


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
