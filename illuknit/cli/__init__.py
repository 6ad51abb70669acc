"""The ``illuknit`` command line.

Each command lives in its own module of this package and is imported only when it runs, so
``illuknit --help`` stays fast and a command's heavy dependencies load only for that command. Add a
command by writing its module and one line in ``COMMANDS``.

Every error that is the user's (bad input, bad options) becomes one line on stderr and exit code 2;
tracebacks are for bugs only.
"""

from __future__ import annotations

import importlib
import sys
import warnings

import click

from illuknit import __version__
from illuknit.core.errors import IlluknitError

__all__ = ["COMMANDS", "cli", "main"]

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
        return cmd

    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        # Short help without importing every command module.
        rows = [(name, _HELP.get(name, "")) for name in COMMANDS]
        with formatter.section("Commands"):
            formatter.write_dl(rows)


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
    something blocking is found) to exit with it.
    """
    try:
        with warnings.catch_warnings():
            warnings.showwarning = _show_note
            rv = cli.main(args=argv, prog_name="illuknit", standalone_mode=False)
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
