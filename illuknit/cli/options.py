"""Click options and option types shared by the commands.

Every numeric option of every command uses one of the types here (or a bounded ``click.IntRange``),
so ``nan``, ``inf`` and meaningless negative values are refused once, while the options are
parsed: one line on stderr and exit code 2, before any work starts.
"""

from __future__ import annotations

import errno
import math
import os
import stat
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

if TYPE_CHECKING:  # `illuknit check` imports these types without loading numpy
    from illuknit.core.pattern import Yarn

__all__ = [
    "ANGLE",
    "CENTIMETRES",
    "COLOR_CHANGES",
    "COUNT",
    "DAYS",
    "FINITE",
    "GAUGE",
    "JOBS",
    "LARGEST",
    "LENGTH",
    "MEGABYTES",
    "MINUTES",
    "NEEDLES",
    "NON_NEGATIVE",
    "PASS_SECONDS",
    "POSITIVE",
    "SECONDS",
    "SECONDS_OR_ZERO",
    "SEED",
    "UNITS",
    "Decorator",
    "FiniteFloat",
    "InputFile",
    "OutputFile",
    "OutputFolder",
    "declared_option",
    "file_params",
    "image_options",
    "knitout_option",
    "old_flag",
    "options_from",
    "options_of",
    "outdir_option",
    "parse_yarn_option",
]


class FiniteFloat(click.FloatRange):
    """A float option that must be a finite number, within a range.

    ``click.FloatRange`` lets ``nan`` through (every comparison with it is false) and ``inf``
    through an open-ended range; this type refuses both, and, where no bound is given, any
    number beyond +-:data:`LARGEST` (no quantity of illuknit's comes near it; a 30-digit number
    is a slip of the keyboard, and would overflow the arithmetic downstream).
    """

    name = "number"

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        rv = super().convert(value, param, ctx)
        if not math.isfinite(rv):
            self.fail(f"{value!r} is not a finite number.", param, ctx)
        if abs(rv) > LARGEST:
            self.fail(f"{value!r} is too large (at most {LARGEST:g} in size).", param, ctx)
        return rv


#: The largest number, in size, that any float option takes when it states no range of its own.
LARGEST = 1e12
_WEEK_SECONDS = 7 * 24 * 3600

#: Any finite number.
FINITE = FiniteFloat()
#: A finite number > 0 (sizes, gauges, time limits).
POSITIVE = FiniteFloat(min=0, min_open=True)
#: A finite number >= 0 (times per needle or pass).
NON_NEGATIVE = FiniteFloat(min=0)
#: An angle in degrees in (0, 90].
ANGLE = FiniteFloat(min=0, max=90, min_open=True)
#: A time limit in seconds: > 0, at most a week.
SECONDS = FiniteFloat(min=0, max=_WEEK_SECONDS, min_open=True)
#: Seconds that may be 0 (0: none), at most a week.
SECONDS_OR_ZERO = FiniteFloat(min=0, max=_WEEK_SECONDS)
#: Seconds per needle crossed or per carriage pass of a linear time model: 0 to an hour.
PASS_SECONDS = FiniteFloat(min=0, max=3600)
#: How long a knit took, in minutes: > 0, at most a week.
MINUTES = FiniteFloat(min=0, max=_WEEK_SECONDS / 60, min_open=True)
#: Megabytes of memory or disk: > 0, at most 1 TiB (1,048,576 MB).
MEGABYTES = FiniteFloat(min=0, max=1024 * 1024, min_open=True)
#: Days: > 0, at most a century.
DAYS = FiniteFloat(min=0, max=36500, min_open=True)
#: Stitches (needles) per inch: > 0, at most 100 (machines knit at 2.5 to 18).
GAUGE = FiniteFloat(min=0, max=100, min_open=True)
#: A finished width in centimetres: > 0, at most 10 m.
CENTIMETRES = FiniteFloat(min=0, max=1000, min_open=True)
#: A renderer length (flat height, unit length; the unit is the renderer's): > 0, at most 1000.
LENGTH = FiniteFloat(min=0, max=1000, min_open=True)
#: A whole number >= 1 (counts, repeats), at most a million.
COUNT = click.IntRange(min=1, max=1_000_000)
#: Parallel worker processes: 1 to 1024.
JOBS = click.IntRange(min=1, max=1024)
#: A distance in needles (a float limit, a racking, every N-th course): 1 to 10,000.
NEEDLES = click.IntRange(min=1, max=10_000)
#: A random seed: 0 to 2**31 - 1 (what every solver backend takes).
SEED = click.IntRange(min=0, max=2**31 - 1)
#: A pattern width or height in units (the library's limit).
UNITS = click.IntRange(1, 1000)
#: Colour changes in one course: 0 to 2000 (a course of the widest pattern has 2000 stitches).
COLOR_CHANGES = click.IntRange(0, 2000)

OUTDIR_HELP = (
    "Folder to write into (created if needed; files of the same name are replaced, others kept)."
)


class InputFile(click.Path):
    """A file the command reads: it must exist and be a regular file (``-`` only when
    ``allow_dash``). A folder, a named pipe, a device or a socket is refused while the options
    are parsed, without opening it; the library reads it within a size limit
    (:func:`illuknit.core.documents.open_input_file`). Every command compares its inputs with its
    outputs before it writes (:func:`file_params`).
    """

    def __init__(
        self, what: str = "input", *, allow_dash: bool = False, path_type: type = Path
    ) -> None:
        super().__init__(dir_okay=False, allow_dash=allow_dash, path_type=path_type)
        self.what = what

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        from illuknit.core.documents import file_kind, shown_path

        if isinstance(value, Path) or (self.allow_dash and value == "-"):
            return super().convert(value, param, ctx)
        shown = shown_path(value)
        try:
            st = os.stat(value)
        except FileNotFoundError:
            self.fail(f"{self.what} file not found: {shown}", param, ctx)
        except (OSError, ValueError) as e:
            too_long = isinstance(e, OSError) and e.errno == errno.ENAMETOOLONG
            why = "the file name is too long for this system" if too_long else _reason(e)
            self.fail(f"cannot read {self.what} file {shown}: {why}", param, ctx)
        if not stat.S_ISREG(st.st_mode):
            self.fail(
                f"cannot read {self.what} file {shown}: it is {file_kind(st.st_mode)}, "
                "not a regular file",
                param,
                ctx,
            )
        return super().convert(value, param, ctx)


def _reason(e: Exception) -> str:
    return (e.strerror if isinstance(e, OSError) else None) or str(e)


class OutputFile(click.Path):
    """A file the command writes (``-``: standard output, when ``allow_dash``)."""

    def __init__(self, *, allow_dash: bool = False, path_type: type = Path) -> None:
        super().__init__(dir_okay=False, allow_dash=allow_dash, path_type=path_type)


class OutputFolder(click.Path):
    """A folder the command writes into."""

    def __init__(self, *, path_type: type = Path) -> None:
        super().__init__(file_okay=False, path_type=path_type)


def file_params(ctx: click.Context) -> tuple[list[Path], list[Path], list[Path]]:
    """The (input files, output files, output folders) named on a parsed command line.

    Inputs are the :class:`InputFile` parameters and a ``--machine FILE.json``; outputs the
    :class:`OutputFile` and :class:`OutputFolder` ones.
    """
    inputs: list[Path] = []
    files: list[Path] = []
    folders: list[Path] = []
    for param in ctx.command.params:
        value = ctx.params.get(param.name or "")
        values = value if isinstance(value, (tuple, list)) else (value,)
        paths = [Path(v) for v in values if isinstance(v, (str, Path)) and str(v) != "-"]
        if isinstance(param.type, InputFile):
            inputs += paths
        elif isinstance(param.type, OutputFile):
            files += paths
        elif isinstance(param.type, OutputFolder):
            folders += paths
        elif param.name == "machine":  # a preset name, or a machine file
            inputs += [p for p in paths if p.suffix.lower() == ".json"]
    return inputs, files, folders


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
            type=CENTIMETRES,
            default=None,
            help="Physical width in cm (with --gauge) instead of --width.",
        ),
        click.option(
            "--gauge",
            type=GAUGE,
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
    # No ``default=None`` on a required option: click 8.3 takes an explicit None for a value
    # given, and the command then ran without a folder (a traceback).
    extra: dict[str, Any] = {} if default is None else {"default": default}
    return click.option(
        "-o",
        "--outdir",
        type=OutputFolder(),
        required=required and default is None,
        show_default=default is not None,
        callback=_check_outdir,
        help=help,
        **extra,
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


# -- options generated from their declarations (illuknit.core.declared) ---------------------

Decorator = Callable[[Callable[..., Any]], Callable[..., Any]]


def declared_option(
    cls: type, name: str, *, default: Any = ..., note: str = "", hidden: bool = False
) -> Decorator:
    """The click option of the declared option ``name`` of the option class ``cls``.

    Its flag, help, type (an enum's words as a ``click.Choice``, a bounded int as a
    ``click.IntRange``, a bounded float as a :class:`FiniteFloat`) and default are the
    declaration's (:func:`illuknit.core.declared.option`); ``default=None`` makes it "not
    given" (the command decides), and ``note`` is added to the help (what the option means to
    this command).
    """
    from illuknit.core.declared import declared_options

    opt = declared_options(cls)[name]
    return click.option(opt.flag, name, hidden=hidden, **click_settings(opt, default, note))


def click_settings(opt: Any, default: Any = ..., note: str = "") -> dict[str, Any]:
    """The keywords of ``click.option`` for the :class:`~illuknit.core.declared.DeclaredOption`
    ``opt`` (see :func:`declared_option`)."""
    value = opt.cli_default if default is ... else default
    kind = opt.base_type
    help_text = opt.declared.help + (f" {note}" if note else "")
    out: dict[str, Any] = {"default": value, "help": help_text}
    if kind is bool:
        if "/" not in opt.flag:
            return {"is_flag": True, "help": help_text}
        return {**out, "show_default": value is not None}
    out["show_default"] = value is not None
    if opt.declared.metavar:
        out["metavar"] = opt.declared.metavar
    low, high, low_open, high_open = opt.declared.bounds
    if opt.choices is not None:
        out["type"] = click.Choice(list(opt.choices))
    elif kind is int:
        out["type"] = click.IntRange(
            None if low is None else int(low), None if high is None else int(high)
        )
    elif kind is float:
        out["type"] = FiniteFloat(_shown(low), _shown(high), min_open=low_open, max_open=high_open)
    return out


def _shown(bound: float | None) -> float | None:
    """A whole-number bound as an int, so ``--help`` shows ``x<=604800``, not ``604800.0``."""
    return int(bound) if bound is not None and float(bound).is_integer() else bound


def options_from(
    cls: type,
    *,
    only: Sequence[str] | None = None,
    defaults: Mapping[str, Any] | None = None,
    notes: Mapping[str, str] | None = None,
) -> Decorator:
    """The click options of the declared options of ``cls`` (those named in ``only``, in that
    order; default all), as one decorator: ``@options_from(SolveOptions, only=("seed",))``.
    ``defaults`` and ``notes`` are :func:`declared_option`'s, by name."""
    from illuknit.core.declared import declared_options

    names = list(declared_options(cls) if only is None else only)
    opts = [
        declared_option(
            cls,
            n,
            default=(defaults or {}).get(n, ...),
            note=(notes or {}).get(n, ""),
        )
        for n in names
    ]

    def apply(func: Callable[..., Any]) -> Callable[..., Any]:
        for opt in reversed(opts):
            func = opt(func)
        return func

    return apply


def options_of(cls: type, params: Mapping[str, Any]) -> Any:
    """The option object ``cls`` of the parsed ``params`` (a command's keywords): its declared
    options that were given a value (not None); the others keep their defaults."""
    from illuknit.core.declared import declared_options

    given = {n: params[n] for n in declared_options(cls) if params.get(n) is not None}
    return cls(**given)


def old_flag(old: str, cls: type, name: str, value: Any) -> Decorator:
    """A former spelling of a declared option, kept for one release: the hidden flag ``old``
    sets the option ``name`` of ``cls`` to ``value`` (unless the option itself is given), with a
    :class:`DeprecationWarning` that names the new spelling (``--soft-brightness``:
    ``--brightness soft``)."""
    from illuknit.core.declared import declared_options

    new = f"{declared_options(cls)[name].flag} {value}"

    def use(ctx: click.Context, param: click.Parameter, given: bool) -> None:
        import warnings

        if not given:
            return
        with warnings.catch_warnings():
            warnings.simplefilter("always", DeprecationWarning)  # the user's, not a library's
            warnings.warn(
                f"{old} is deprecated and goes in the next release; use {new}",
                DeprecationWarning,
                stacklevel=2,
            )
        # eager, so it is read before the option: its default, which the option given wins over
        ctx.default_map = {**(ctx.default_map or {}), name: value}

    return click.option(
        old,
        is_flag=True,
        hidden=True,
        is_eager=True,
        expose_value=False,
        callback=use,
        help=f"Deprecated: {new}.",
    )
