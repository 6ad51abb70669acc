"""Click options and option types shared by the commands.

Every numeric option of every command uses one of the types here (or a bounded ``click.IntRange``),
so ``nan``, ``inf`` and meaningless negative values are refused once, while the options are
parsed: one line on stderr and exit code 2, before any work starts.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

if TYPE_CHECKING:  # `illuknit check` imports these types without loading numpy
    from illuknit.core.pattern import Yarn

__all__ = [
    "ANGLE",
    "COUNT",
    "FINITE",
    "NON_NEGATIVE",
    "POSITIVE",
    "UNITS",
    "FiniteFloat",
    "image_options",
    "knitout_option",
    "outdir_option",
    "parse_yarn_option",
]


class FiniteFloat(click.FloatRange):
    """A float option that must be a finite number, optionally within a range.

    ``click.FloatRange`` lets ``nan`` through (every comparison with it is false) and ``inf``
    through an open-ended range; this type refuses both.
    """

    name = "number"

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        rv = super().convert(value, param, ctx)
        if not math.isfinite(rv):
            self.fail(f"{value!r} is not a finite number.", param, ctx)
        return rv


#: Any finite number.
FINITE = FiniteFloat()
#: A finite number > 0 (sizes, gauges, time limits).
POSITIVE = FiniteFloat(min=0, min_open=True)
#: A finite number >= 0 (times per needle or pass).
NON_NEGATIVE = FiniteFloat(min=0)
#: An angle in degrees in (0, 90].
ANGLE = FiniteFloat(min=0, max=90, min_open=True)
#: A whole number >= 1 (counts, jobs).
COUNT = click.IntRange(min=1)
#: A pattern width or height in units (the library's limit).
UNITS = click.IntRange(1, 1000)

OUTDIR_HELP = (
    "Folder to write into (created if needed; files of the same name are replaced, others kept)."
)


def image_options(func: Callable[..., Any]) -> Callable[..., Any]:
    """--width/--height/--width-cm/--gauge/--yarns/--colors/--no-quantise."""
    opts = [
        click.option(
            "--width",
            type=UNITS,
            default=None,
            help="Pattern width in units (1 unit = 2 stitches). Default: picture width, at most 80.",
        ),
        click.option(
            "--height",
            type=UNITS,
            default=None,
            help="Pattern height in units. Default: keeps the picture's aspect ratio.",
        ),
        click.option(
            "--width-cm",
            type=POSITIVE,
            default=None,
            help="Physical width in cm (with --gauge) instead of --width.",
        ),
        click.option(
            "--gauge",
            type=POSITIVE,
            default=None,
            help="Machine or hand gauge in stitches per inch, used with --width-cm and to knit "
            "(--knitout) [the machine's, 7].",
        ),
        click.option(
            "--yarns",
            default=None,
            metavar="LIST",
            help="Yarn colours, e.g. '#1b1b1b,#f4f0e8' or 'navy,white' or 'Dark=#222,Light=#eee'. "
            "Default: chosen from the picture.",
        ),
        click.option(
            "--colors",
            "n_colors",
            type=click.IntRange(1, 10),
            default=None,
            help="Number of picture colours to keep.",
        ),
        click.option(
            "--quantise/--no-quantise",
            default=True,
            show_default=True,
            help="Cluster a picture with more colours than yarns (else it is an error).",
        ),
    ]
    for opt in reversed(opts):
        func = opt(func)
    return func


def parse_yarn_option(value: str | None) -> tuple[Yarn, ...] | None:
    from illuknit.core.pattern import parse_yarns

    return None if value is None else parse_yarns(value)


def outdir_option(
    *, required: bool = True, default: Path | None = None, help: str = OUTDIR_HELP
) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """``-o/--outdir``: the folder a command writes into (through :func:`illuknit.core.files.staged_dir`).

    The folder is checked when the option is parsed (a file in the way, a read-only file system),
    so a long computation does not run only to fail at the end.
    """
    return click.option(
        "-o",
        "--outdir",
        type=click.Path(file_okay=False, path_type=Path),
        required=required and default is None,
        default=default,
        show_default=default is not None,
        callback=_check_outdir,
        help=help,
    )


def _check_outdir(ctx: click.Context, param: click.Parameter, value: Path | None) -> Path | None:
    from illuknit.core.errors import OutputPathError
    from illuknit.core.files import check_output_dir

    if value is not None and str(value).startswith("-"):
        # `-o --04` takes "--04" as the folder: an option's name where a folder was left out
        # (a stray --04.png was once committed so, by a tool given "-" for standard output)
        raise click.BadParameter(
            f"{str(value)!r} looks like an option, not a folder (was the folder left out?); "
            "to use a name starting with '-', give its full path",
            ctx=ctx,
            param=param,
        )
    if value is not None:
        try:
            check_output_dir(value)
        except OutputPathError as exc:
            raise click.BadParameter(str(exc), ctx=ctx, param=param) from exc
    return value


def knitout_option(
    help: str = "Also write a knitout program (program.k) and the checker's report.",
) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """``--knitout``: also compile the pattern to knitout and check it."""
    return click.option("--knitout", is_flag=True, help=help)
