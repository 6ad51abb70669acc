"""The ``illuknit`` command line.

Each command lives in its own module of this package and is imported only when it runs, so
``illuknit --help`` stays fast and a command's heavy dependencies load only for that command. Add a
command by writing its module and one line in ``COMMANDS``.

Every error that is the user's (bad input, bad options) becomes one line on stderr and exit code 2;
tracebacks are for bugs only. Exit codes: 0 done; 1 a command's own verdict (``check``, ``knit``:
something blocking found); 2 bad input or an output that cannot be written, nothing written; 3 the
outputs were written but standard output could not be (closed, a full disk, a broken pipe): the
error line names what was written; 130 interrupted (Ctrl-C); 143 and 129 stopped by SIGTERM and
SIGHUP, which unwind like Ctrl-C so that no temporary file is left behind.
"""

from __future__ import annotations

import contextlib
import errno
import functools
import importlib
import io
import os
import signal
import sys
import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager, suppress
from typing import Any

import click

from illuknit import __version__
from illuknit.core.errors import IlluknitError

__all__ = ["COMMANDS", "EXIT_STDOUT_FAILED", "cli", "main"]

#: Exit code when every output was written but printing to standard output failed.
EXIT_STDOUT_FAILED = 3

#: command name -> "module:function" (a click.Command), listed in the order ``--help`` shows them.
COMMANDS: dict[str, str] = {
    "bench": "illuknit.cli.bench:bench",
    "app": "illuknit.cli.app:app",
    "demo": "illuknit.cli.demo:demo",
    "single": "illuknit.cli.single:single",
    "view": "illuknit.cli.view:view",
    "knit": "illuknit.cli.knit:knit",
    "check": "illuknit.cli.check:check",
    "tiles": "illuknit.cli.tiles:tiles",
    "double": "illuknit.cli.double:double",
    "legible": "illuknit.cli.legible:legible",
    "headon": "illuknit.cli.headon:headon",
    "render": "illuknit.cli.render:render",
    "solve": "illuknit.cli.solve:solve",
    "calibrate": "illuknit.cli.calibrate:calibrate",
}

_HELP = {
    "render": "Ray-cast a pattern from both sides and head-on, with a sweep GIF.",
    "solve": "Solve for an illusion pattern with a constraint model (MaxSAT, CP-SAT, exact DP).",
    "calibrate": "Calibration swatch and bump-height fit for the renderer.",
    "bench": "Benchmark design methods (tiles, MaxSAT, CP-SAT, DP, gradient) on instances.",
    "app": "Start the design app: a local web page for designing illusions.",
    "demo": "Make a single-view illusion from the bundled sample picture.",
    "single": "Compile a 2- or 3-colour picture into a single-view illusion.",
    "view": "Write previews, chart and instructions of a saved pattern.",
    "knit": "Compile a saved pattern to a knitout program (passes, time, check).",
    "check": "Check a knitout program for machine-rule violations and fabric failures.",
    "tiles": "List a tile bank with its fills and draw each tile.",
    "double": "Design a double-view illusion from two pictures with tiles (ranked candidates).",
    "legible": "The smallest width at which each side of a double view reads (by a reader).",
    "headon": "Design a picture seen head-on that disappears at an angle.",
}


class LazyGroup(click.Group):
    """A click group whose subcommands are imported on first use."""

    def list_commands(self, ctx: click.Context) -> list[str]:
        return list(COMMANDS)

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        target = COMMANDS.get(cmd_name)
        if target is None:
            return None
        module, _, attr = target.partition(":")
        cmd = getattr(importlib.import_module(module), attr)
        if not isinstance(cmd, click.Command):  # pragma: no cover - programming error
            raise TypeError(f"{target} is not a click command")
        _guard_files(cmd)
        return cmd

    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        # Short help without importing every command module.
        rows = [(name, _HELP.get(name, "")) for name in COMMANDS]
        with formatter.section("Commands"):
            formatter.write_dl(rows)


def _guard_files(cmd: click.Command) -> None:
    """Make ``cmd`` (and a group's subcommands) compare its output paths with its input files
    before it runs, and refuse any write over an input while it runs
    (:func:`illuknit.core.files.check_outputs_apart`, :func:`~illuknit.core.files.protecting_inputs`)."""
    if getattr(cmd, "_illuknit_files_guarded", False):
        return
    if isinstance(cmd, click.Group):
        for sub in cmd.commands.values():
            _guard_files(sub)
    elif cmd.callback is not None:
        cmd.callback = _outputs_apart(cmd.callback)
    cmd._illuknit_files_guarded = True  # type: ignore[attr-defined]


def _outputs_apart(callback: Callable[..., Any]) -> Callable[..., Any]:
    @functools.wraps(callback)
    def run(*args: Any, **kwargs: Any) -> Any:
        from illuknit.cli.options import file_params
        from illuknit.core.files import check_outputs_apart, protecting_inputs

        ctx = click.get_current_context()
        inputs, files, folders = file_params(ctx)
        check_outputs_apart(inputs, files=files, folders=folders)
        # the app's server has its own shutdown on these signals
        unwinds = _termination_unwinds() if ctx.command.name != "app" else contextlib.nullcontext()
        with protecting_inputs(inputs), unwinds:
            return callback(*args, **kwargs)

    return run


@click.group(cls=LazyGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, "--version", prog_name="illuknit")
def cli() -> None:
    """illuknit: computational illusion (shadow) knitting.

    Turn pictures into illusion patterns, preview them, and compile them to knitout for V-bed
    knitting machines. Run ``illuknit COMMAND --help`` for each command.
    """


def fail(message: str) -> None:
    """Print one error line and exit with code 2 (for commands that detect a problem themselves)."""
    raise click.UsageError(message)


def main(argv: list[str] | None = None) -> int:
    """Console-script entry point.

    Returns 0 on success. Otherwise exits through ``SystemExit``: user errors print one line on
    stderr and exit with code 2; a command may return a non-zero int (e.g. 1 from ``check`` when
    something blocking is found) to exit with it; standard output that cannot be written is one
    line and exit code 2, or :data:`EXIT_STDOUT_FAILED` (3) when the outputs were already written.
    """
    from illuknit.core.files import recording_writes

    with recording_writes() as written:
        try:
            with _guarded_stdout(), _names_printable():
                return _run(argv)
        except _StdoutFailed as e:
            _silence_stdout()
            reason = e.__cause__.strerror if isinstance(e.__cause__, OSError) else None
            line = f"illuknit: error: cannot write to standard output ({reason or 'closed'})"
            if written:
                what = ", ".join(str(p) for p in dict.fromkeys(written))
                _echo_err(f"{line}; the output was written all the same: {what}")
                sys.exit(EXIT_STDOUT_FAILED)
            _echo_err(line)
            sys.exit(2)


class _Terminated(BaseException):
    """SIGTERM or SIGHUP arrived: unwinds like Ctrl-C, so every temporary file is removed."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum


def _terminate(signum: int, frame: object) -> None:
    raise _Terminated(signum)


@contextmanager
def _termination_unwinds() -> Iterator[None]:
    """Turn SIGTERM and SIGHUP into an exception while a command runs (where their action is
    the default one: an ignored SIGHUP, under ``nohup``, stays ignored)."""
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = {}
    for name in ("SIGTERM", "SIGHUP"):
        signum = getattr(signal, name, None)
        if signum is not None and signal.getsignal(signum) == signal.SIG_DFL:
            old[signum] = signal.signal(signum, _terminate)
    try:
        yield
    finally:
        for signum, handler in old.items():
            signal.signal(signum, handler)


def _run(argv: list[str] | None) -> int:
    try:
        with warnings.catch_warnings():
            warnings.showwarning = _show_note
            rv = cli.main(args=argv, prog_name="illuknit", standalone_mode=False)
    except _Terminated as e:
        _echo_err(f"illuknit: stopped by {signal.Signals(e.signum).name}")
        sys.exit(128 + e.signum)
    except click.exceptions.Exit as e:
        code = int(e.exit_code or 0)
        if code:
            sys.exit(code)
        return 0
    except click.exceptions.Abort:
        click.echo("illuknit: interrupted", err=True)
        sys.exit(130)
    except click.ClickException as e:
        click.echo(f"illuknit: error: {_one_line(e.format_message())}", err=True)
        sys.exit(2)
    except IlluknitError as e:
        click.echo(f"illuknit: error: {_one_line(str(e))}", err=True)
        sys.exit(2)
    except KeyboardInterrupt:
        click.echo("illuknit: interrupted", err=True)
        sys.exit(130)
    if isinstance(rv, int) and not isinstance(rv, bool) and rv:
        sys.exit(rv)
    return 0


class _StdoutFailed(Exception):
    """Writing to standard output failed (the ``OSError`` is the cause)."""


class _GuardedStdout(io.TextIOWrapper):
    """Standard output whose write failures are told apart from every other ``OSError``."""

    def write(self, s: str) -> int:
        try:
            return super().write(s)
        except OSError as exc:
            raise _StdoutFailed() from exc

    def flush(self) -> None:
        try:
            super().flush()
        except OSError as exc:
            raise _StdoutFailed() from exc


class _ClosedStdout(io.TextIOBase):
    """Stands in for a closed standard output, so that printing fails once, clearly, instead of
    vanishing (Python sets ``sys.stdout`` to None then, and click and rich print nothing)."""

    encoding = "utf-8"

    def isatty(self) -> bool:
        return False

    def writable(self) -> bool:
        return True

    def write(self, s: str) -> int:
        raise _StdoutFailed() from OSError(errno.EBADF, "it is closed")


@contextmanager
def _guarded_stdout() -> Iterator[None]:
    """Route the process's real standard output through :class:`_GuardedStdout` (left alone when
    a caller, e.g. a test, has replaced ``sys.stdout``); flush it at the end, inside the guard."""
    real = sys.stdout
    if real is None and sys.__stdout__ is None:  # file descriptor 1 closed (`>&-`)
        sys.stdout = _ClosedStdout()
        try:
            yield
        finally:
            sys.stdout = None
        return
    if real is not sys.__stdout__ or not isinstance(real, io.TextIOWrapper):
        yield
        return
    try:
        real.flush()
    except OSError as exc:
        raise _StdoutFailed() from exc
    guarded = _GuardedStdout(
        real.buffer,
        encoding=real.encoding,
        errors=_lenient(real.errors),
        line_buffering=real.line_buffering,
    )
    sys.stdout = guarded
    try:
        yield
        guarded.flush()
    finally:
        sys.stdout = real
        with suppress(OSError, ValueError):
            guarded.detach()  # the buffer stays the real stdout's


def _lenient(errors: str | None) -> str:
    # A file name that is not valid UTF-8 (decoded with surrogate escapes) must print, not raise.
    return "backslashreplace" if errors in (None, "strict") else errors


@contextmanager
def _names_printable() -> Iterator[None]:
    """Let standard output and error print file names that are not valid UTF-8 (as ``\\udcff``)
    while a command runs, whatever stream a caller put there; restored afterwards."""
    changed = []
    for stream in (sys.stdout, sys.stderr):
        errors = getattr(stream, "errors", None)
        if isinstance(stream, io.TextIOWrapper) and _lenient(errors) != errors:
            with suppress(ValueError, OSError):
                stream.reconfigure(errors=_lenient(errors))
                changed.append((stream, errors))
    try:
        yield
    finally:
        for stream, errors in changed:
            with suppress(ValueError, OSError):
                stream.reconfigure(errors=errors)


def _silence_stdout() -> None:
    """Point file descriptor 1 at the null device so the interpreter's final flush of what could
    not be written fails no more (the failure was reported once)."""
    with suppress(OSError):
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, 1)
        os.close(null)


def _echo_err(line: str) -> None:
    with suppress(OSError):
        click.echo(line, err=True)


def _show_note(
    message: Warning | str, category: type[Warning], *args: object, **kw: object
) -> None:
    """Warnings meant for the user as one line: ``warning:`` for long floats kept on request
    (:class:`~illuknit.knitting.pipeline.LongFloatWarning`), ``note:`` for the rest (e.g. a picture's first
    frame used)."""
    from illuknit.knitting.pipeline import LongFloatWarning

    kind = "warning" if issubclass(category, LongFloatWarning) else "note"
    click.echo(f"illuknit: {kind}: {_one_line(str(message))}", err=True)


def _one_line(text: str) -> str:
    return " ".join(text.split())
