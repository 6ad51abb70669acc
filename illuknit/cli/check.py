"""``illuknit check PROGRAM.k``: find machine-rule violations and fabric failures in knitout.

Exit codes: 0 nothing blocking, 1 blocking findings, 2 the file cannot be read or parsed (binary,
no magic line, malformed instruction: one line ``illuknit: error: PROGRAM.k line 12: ...``).
"""

from __future__ import annotations

import sys
from pathlib import Path

import click

from illuknit.cli.knitout_bridge import machine_option
from illuknit.cli.options import NEEDLES, FiniteFloat, InputFile
from illuknit.core.errors import KnitoutParseError

__all__ = ["check"]


def read_knitout_file(path: Path) -> str:
    """Read a knitout file as UTF-8 text; binary or unreadable files raise KnitoutParseError."""
    from illuknit.core.documents import read_input_bytes

    # a regular file within INPUT_LIMITS["program"]: a pipe or a device is refused unread
    data = read_input_bytes(path, error=KnitoutParseError, what="program")
    if b"\x00" in data:
        raise KnitoutParseError(
            f"{path}: binary file (contains NUL bytes), not knitout text; "
            "a .dat file must be converted back to knitout first"
        )
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        raise KnitoutParseError(
            f"{path}: not UTF-8 text (byte {e.start}); is this a binary file?"
        ) from None


@click.command(
    "check",
    help=(
        "Check a knitout program: machine-rule violations and fabric failures (yarn floating over "
        "purls, stitches with the carrier on the wrong side, separate pieces, long floats, loops "
        "or carriers left at the end), with line numbers. Exit code 1 when anything blocks."
    ),
)
@click.argument("program", type=InputFile("program"), metavar="PROGRAM.k")
@click.option("--json", "as_json", is_flag=True, help="Print the report as JSON.")
@click.option(
    "--simulate",
    is_flag=True,
    help="Also run the PyPI knitout-interpreter simulator (pip install 'illuknit[sim]'); slow.",
)
@machine_option(
    "Machine to judge against (default: the one the program's ;;Machine/;;Width headers name).",
    transfer=False,
)
@click.option(
    "--float-limit",
    type=NEEDLES,
    default=None,
    help="Longest float, in needles skipped, before a warning [the machine's, 20].",
)
@click.option(
    "--max-racking",
    type=FiniteFloat(min=0, max=100, min_open=True),
    default=None,
    help="Largest allowed |racking| [the machine's, 4].",
)
@click.option(
    "--bed-width",
    type=click.IntRange(min=1),
    default=None,
    help="Needles per bed [the ;;Width header, else the machine's].",
)
@click.option(
    "--split-bumps",
    is_flag=True,
    help="The program knits split bumps (a pattern with two yarns in some bumps): a yarn "
    "change inside a bump is meant, not an error. Needed only for a program that does not "
    "declare them (illuknit's programs do, in a '; illuknit-bumps:' comment line).",
)
def check(
    program: Path,
    as_json: bool,
    simulate: bool,
    machine: str | None,
    float_limit: int | None,
    max_racking: float | None,
    bed_width: int | None,
    split_bumps: bool,
) -> None:
    from illuknit.check import check_knitout, render_report
    from illuknit.core.machine import get_machine
    from illuknit.core.progress import run_with_bar

    spec = None if machine is None else get_machine(machine)
    text = read_knitout_file(program)
    try:
        report = run_with_bar(
            "check",
            "checking the program",
            check_knitout,
            text,
            machine=spec,
            float_limit=float_limit,
            max_racking=max_racking,
            bed_width=bed_width,
            simulate=simulate,
            split_bumps=True if split_bumps else None,
        )
    except KnitoutParseError as e:
        raise KnitoutParseError(
            f"{program} {e}" if e.line is not None else f"{program}: {e}"
        ) from None
    if as_json:
        click.echo(report.to_json())
    else:
        from illuknit.cli.summary import console

        console().print(render_report(report, name=str(program)))
    if not report.ok:
        # sys.exit, not ctx.exit: the group runs with standalone_mode=False, which would turn
        # click's Exit into a return value that `python -m illuknit` drops.
        sys.exit(1)
