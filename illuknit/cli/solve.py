"""``illuknit solve``: illusion patterns from constraint models and pluggable solvers.

Two pictures (or one, with ``--model single``) are resized to the unit grid, quantised jointly to
K yarns (so a colour means the same yarn in both), encoded as model (a) ``logical``, (b)
``knit-aware`` or (c) ``single`` (:mod:`illuknit.design.models.illusion_models`), and solved by the named backend
(:mod:`illuknit.solvers`). Writes pattern.json, previews, chart, instructions and report.json;
``--export-wcnf`` writes the model for an external MaxSAT solver.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from illuknit.cli.knitout_bridge import format_option, long_floats_option, machine_option
from illuknit.cli.options import (
    COLOR_CHANGES,
    InputFile,
    OutputFile,
    OutputFolder,
    declared_option,
)
from illuknit.core.gauge import drawn_gauge
from illuknit.design.options import RankOptions, SolveOptions
from illuknit.pictures.sizing import DEFAULT_MAX_WIDTH
from illuknit.pipeline.inputs import PictureOptions

if TYPE_CHECKING:
    from illuknit.core.machine import MachineSpec
    from illuknit.core.pattern import Yarn
    from illuknit.design.models.illusion_problem import KnitWeights

__all__ = ["SolveRequest", "run_solve", "solve"]


class _LiveProgress:
    """A rich progress line: elapsed time against the limit, best objective and bound; then,
    once the solver has answered, a spinner with the time spent on each writing stage
    (:meth:`stage`), so the line moves with the work from start to end."""

    def __init__(self, time_limit: float | None, label: str) -> None:
        from rich.console import Console
        from rich.progress import BarColumn, Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

        self.limit = time_limit
        self.t0 = time.perf_counter()
        self.best: str = "searching"
        from rich.markup import escape

        # the label may hold an external command with "{}"; TextColumn formats its text
        safe = escape(label).replace("{", "{{").replace("}", "}}")
        self.progress = Progress(
            SpinnerColumn(),
            TextColumn(safe),
            BarColumn(),
            TimeElapsedColumn(),
            TextColumn("{task.fields[best]}"),
            console=Console(stderr=True),  # on stderr: stdout stays the command's report
            transient=True,
        )
        self.task = self.progress.add_task("solve", total=time_limit or None, best=self.best)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._tick, daemon=True)

    def __enter__(self) -> _LiveProgress:
        self.progress.start()
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        self._thread.join(timeout=1)
        self.progress.stop()

    def _tick(self) -> None:
        while not self._stop.wait(0.25):
            if self.limit:
                el = time.perf_counter() - self.t0
                self.progress.update(self.task, completed=min(el, self.limit), best=self.best)
            else:
                self.progress.update(self.task, best=self.best)

    def stage(self, message: str) -> None:
        """The solve is over: show ``message`` with a spinner and the time spent (no bar: the
        writing cannot be counted against the time limit)."""
        self.limit = None
        self.best = message
        self.progress.reset(self.task, total=None, best=message)  # the clock restarts

    def __call__(self, event: Any) -> None:
        parts = []
        if event.objective is not None:
            parts.append(f"best {event.objective:g}")
        if event.bound is not None:
            parts.append(f"bound {event.bound:g}")
        self.best = ", ".join(parts) or self.best


@dataclass(frozen=True, eq=False)
class SolveRequest:
    """What ``illuknit solve`` asks for, checked and parsed once.

    Attributes
    ----------
    pictures : pair of Path
        The target pictures A and B (B None for the single-view model).
    outdir : Path or None
        The folder written (None: only the model is exported).
    options : SolveOptions
        The model and how it is solved.
    sizing : PictureOptions
        Width, stretch, unit aspect, colours, yarns and whether to quantise.
    machine : MachineSpec
        The machine as the command resolved it (its gauge sizes the units and the piece).
    knitout : bool
        Also knit the pattern on ``machine`` and check the program.
    export : tuple of (Path or None, str)
        Where ``--export-wcnf`` writes the model (None: nowhere) and in which WCNF style.
    show_progress : bool
        A progress line on a terminal.
    """

    pictures: tuple[Path, Path | None]
    outdir: Path | None
    options: SolveOptions
    sizing: PictureOptions
    machine: MachineSpec
    knitout: bool = False
    export: tuple[Path | None, str] = (None, "new")
    show_progress: bool = True

    @classmethod
    def from_switches(
        cls, image_a: Path | None, image_b: Path | None, outdir: Path | None, **switches: Any
    ) -> SolveRequest:
        """The request of the command line's switches (``--time-limit`` is ``time_limit=``),
        contradictory or impossible ones refused first."""
        from illuknit.cli.knitout_bridge import design_unit_aspect, resolve_machine
        from illuknit.design.options import ModelKind, WarmStart

        s = {**_SWITCH_DEFAULTS, **switches}
        unknown = sorted(set(s) - set(_SWITCH_DEFAULTS))
        if unknown:
            raise TypeError(f"unknown switch of illuknit solve: {unknown[0]}")
        if image_a is None:
            raise click.UsageError(
                "give the target picture(s): illuknit solve A.png B.png -o OUTDIR"
            )
        w, ys = _check_solve_options((image_a, image_b), outdir, s)
        spec = resolve_machine(s["machine"])
        options = SolveOptions(
            model=ModelKind(s["model"]), solver=s["solver"], warm_start=WarmStart(s["warm_start"]),
            weights=w, alternate_rows=s["alternate_rows"], split_bumps=s["split_bumps"],
            time_limit=s["time_limit"], seed=s["seed"], made_for=s["made_for"],
        )  # fmt: skip
        sizing = PictureOptions(
            width=s["width"], stretch=s["resize"],
            unit_aspect=design_unit_aspect(spec, str(s["made_for"])),
            n_colors=s["n_colors"], yarns=ys, quantise=s["quantise"],
        )  # fmt: skip
        return cls(
            (image_a, image_b), outdir, options, sizing, spec, knitout=s["knitout"],
            export=(s["export_wcnf"], s["wcnf_style"]), show_progress=s["show_progress"],
        )  # fmt: skip


#: The switches of ``illuknit solve`` and their defaults.
_SWITCH_DEFAULTS: dict[str, Any] = {
    "model": "logical", "solver": "auto", "warm_start": "auto", "weights": None,
    "max_color_changes": None, "alternate_rows": False, "split_bumps": False,
    "n_colors": None, "yarns": None, "width": None, "resize": False, "quantise": True,
    "time_limit": 60.0, "seed": 0, "export_wcnf": None, "wcnf_style": "new",
    "knitout": False, "machine": None, "show_progress": True, "made_for": "machine",
}  # fmt: skip


def run_solve(request: SolveRequest) -> dict[str, Any]:
    """Everything ``illuknit solve`` does once its switches are parsed: call
    :func:`~illuknit.pipeline.solve.solve_design` as ``request`` asks and write its pattern;
    returns the report dict.

    With ``request.knitout`` the pattern is knit on ``request.machine``; a pattern wider than
    its bed is refused before the model is built.
    """
    from illuknit.core.files import STDOUT
    from illuknit.pipeline.solve import illusion_model, solve_design

    options, outdir, spec = request.options, request.outdir, request.machine
    image_a, image_b = request.pictures
    knit_on = spec if request.knitout else None
    export_wcnf, wcnf_style = request.export
    written: dict[str, Path] = {}
    if export_wcnf is not None:
        mdl = illusion_model(
            image_a, image_b, options=options, pictures=request.sizing, knit_on=knit_on
        )
        where = _export_wcnf(mdl, export_wcnf, wcnf_style, say=outdir is None)
        if str(export_wcnf) != STDOUT:
            written["wcnf"] = Path(where)
        if outdir is None:
            return {"wcnf": where, "model": repr(mdl)}
    from contextlib import nullcontext

    model, solver = options.model.value, options.solver
    live = _live_progress(solver, model, options.time_limit) if request.show_progress else None
    with live or nullcontext():
        design = solve_design(
            image_a, image_b, options=options, pictures=request.sizing, knit_on=knit_on,
            progress=live, machine=spec,
        )  # fmt: skip
        report = dict(design.report)
        if outdir is not None:
            qa, *rest = design.quantised
            pictures = {"target A": qa.rgb(), **({"target B": rest[0].rgb()} if rest else {})}
            title = f"{model} illusion solved by {design.solution.backend}"
            written.update(
                _write_outputs(
                    design.pattern,
                    outdir,
                    report=report,
                    title=title,
                    targets=pictures,
                    machine=knit_on,
                    # made for hands: the documents of the piece knitted by hand, at the gauge
                    # its grid was sized for (knitout_bridge.design_unit_aspect)
                    gauge=drawn_gauge(spec.fabric_gauge, options.made_for),
                    stage=live.stage if live is not None else None,
                )
            )
    _print_report(report, written, outdir)
    return report


def _live_progress(solver: str, model: str, time_limit: float | None) -> _LiveProgress | None:
    """The progress line of a solve, on a terminal only (the dp solver has no time limit to
    count against: a spinner with the time spent)."""
    from rich.console import Console

    if not Console(stderr=True).is_terminal:
        return None
    return _LiveProgress(None if solver == "dp" else time_limit, f"{solver} on the {model} model")


def _export_wcnf(mdl: Any, path: Path, style: str, *, say: bool) -> str:
    """``--export-wcnf``: write the model (to standard output for ``-``); with ``say``, say so.
    Returns where it went."""
    from rich.console import Console

    from illuknit.core.files import STDOUT, write_output_file

    where = write_output_file(path, mdl.to_wcnf(style=style).encode("utf-8"))
    if say:
        Console(highlight=False, soft_wrap=True, stderr=str(path) == STDOUT).print(
            f"wrote {where} ({mdl.num_vars} variables, {mdl.num_hard} hard and "
            f"{mdl.num_soft} soft clauses before encoding cardinality constraints)"
        )
    return str(where)


def _write_outputs(
    pattern: Any,
    outdir: Path,
    *,
    report: dict[str, Any],
    title: str,
    targets: dict[str, Any],
    machine: Any | None,
    gauge: Any = None,
    stage: Callable[[str], None] | None = None,
) -> dict[str, Path]:
    """Write the pattern's outputs (and, given a machine, its knitout) into ``outdir`` at once;
    ``stage(message)`` hears each step as it starts (the progress line)."""
    from illuknit.cli.knitout_bridge import chart_kind, hand_border, write_program
    from illuknit.core.files import staged_dir
    from illuknit.outputs.export import export_pattern

    say = stage or (lambda message: None)
    refused: list[Any] = []  # a knitting refusal, raised once the design is written
    with staged_dir(outdir) as tmp:
        say("writing the pattern, previews, chart and pattern PDF")
        paths = export_pattern(
            pattern,
            tmp,
            report=report,
            title=title,
            targets=targets,
            gauge=gauge,
            chart=chart_kind(),
            border=hand_border(),
        )
        from illuknit.cli.design_files import write_seen

        pictures = list(targets.values())
        mode = "double" if len(pictures) == 2 else "single"
        paths["seen"] = write_seen(pattern, pictures, tmp, mode=mode, gauge=gauge, distance=3.0)
        if machine is not None:
            say("knitting the pattern and checking the knitout")
            paths.update(write_program(pattern, tmp, machine=machine, refused=refused))
    if refused:  # the design is written, with the note saying why there is no program
        raise refused[0]
    return {k: Path(outdir) / p.name for k, p in paths.items()}


def _check_solve_options(
    pictures: tuple[Path, Path | None], outdir: Path | None, s: Mapping[str, Any]
) -> tuple[KnitWeights, tuple[Yarn, ...] | None]:
    """Refuse contradictory or impossible options; the parsed ``(weights, yarns)``."""
    from dataclasses import replace

    from illuknit.core.errors import ImageInputError, YarnSpecError
    from illuknit.core.pattern import parse_yarns
    from illuknit.design.models.illusion_models import parse_weights

    image_b = pictures[1]
    model, weights, yarns, n_colors = s["model"], s["weights"], s["yarns"], s["n_colors"]
    time_limit, export_wcnf = s["time_limit"], s["export_wcnf"]
    max_color_changes = s["max_color_changes"]
    if model == "single" and image_b is not None:
        raise ImageInputError("--model single takes one picture (it is seen from both sides)")
    if model != "single" and image_b is None:
        raise ImageInputError(f"--model {model} needs two pictures A and B (or use --model single)")
    if s["alternate_rows"] and model != "single":
        raise click.BadParameter("applies to --model single only", param_hint="--alternate-rows")
    if outdir is None and export_wcnf is None:
        raise click.UsageError("give -o OUTDIR (or --export-wcnf FILE)")
    if outdir is not None and export_wcnf is not None and str(export_wcnf) == "-":
        raise click.BadParameter(
            "- (standard output) only without -o: the solve prints its summary there",
            param_hint="--export-wcnf",
        )
    if time_limit is not None and time_limit <= 0:
        raise click.BadParameter(
            f"must be positive seconds, got {time_limit}", param_hint="--time-limit"
        )
    w = parse_weights(weights)
    if max_color_changes is not None:
        w = replace(w, max_color_changes=max_color_changes)
    ys = parse_yarns(yarns) if yarns else None
    if (ys is not None and len(ys) < 2) or n_colors == 1:
        # One yarn knits a plain piece: no picture can appear from any side.
        given = f"--yarns {yarns}" if ys is not None else "--colors 1"
        raise YarnSpecError(f"an illusion needs at least 2 yarns, got 1 ({given})")
    return w, ys


def _print_report(report: dict[str, Any], written: dict[str, Path], outdir: Path | None) -> None:
    from rich.table import Table

    from illuknit.cli.summary import console

    c = console()
    s = report["solver"]
    gap = "" if s["gap"] in (None, 0) else f", gap {100 * s['gap']:.1f}%"
    bound = "" if s["bound"] is None else f", bound {s['bound']:g}"
    ws = s["stats"].get("warm_start", {}).get("method", "none")
    found = (
        ""
        if s["found_by"] in ("", s["backend"])
        else f" (pattern found by the {s['found_by']} warm start)"
    )
    c.print(
        f"[bold]{s['backend']}[/] (warm start {ws}): {s['status']} in {s['wall_time']:.2f} s, "
        f"objective {s['objective']}{bound}{gap}{found}"
    )
    if report.get("note"):
        c.print(f"[yellow]{report['note']}[/]")
    t = Table(show_header=True, header_style="bold")
    for col in (
        "logical error A",
        "logical error B",
        "colour changes/course (mean, max)",
        "raised",
        "knit/purl changes",
    ):
        t.add_column(col)
    le = report["logical_error"]
    cc = report["color_changes_per_course"]
    t.add_row(
        f"{le['A']['cells']} ({100 * le['A']['fraction']:.1f}%)",
        f"{le['B']['cells']} ({100 * le['B']['fraction']:.1f}%)",
        f"{cc['mean']:.2f}, {cc['max']}",
        str(report["raised_units"]),
        str(report["knit_purl_changes"]),
    )
    c.print(t)
    if report.get("made_for") == "hands":  # measured on the pattern, not the solver's word
        h = report["hand"]
        c.print(
            f"made for hands: rows knittable by hand {h['knittable_rows']} of {h['rows']} "
            f"(at most 6 intarsia blocks, or 2 yarns with floats of at most 7 stitches); "
            f"colour changes a row max {h['max_changes']} / mean {h['mean_changes']:.1f}, "
            f"longest float {h['longest_float']} sts, about {h['hours']:.1f} hours by hand "
            "(estimated from the stitch counts and colour work)"
        )
    if written:
        names = ", ".join(sorted(p.name for p in written.values()))
        c.print(f"wrote {len(written)} files{f' to [bold]{outdir}[/]' if outdir else ''}: {names}")


def _list_solvers(ctx: click.Context, _param: click.Parameter, value: bool) -> None:
    """Print every backend with its kind, version and availability, smoke-test each installed
    one on a tiny instance (does it answer within a limit? can it be time-limited?), then exit."""
    if not value or ctx.resilient_parsing:
        return
    from illuknit.bench.smoke import SMOKE_INSTANCE, smoke_test_backends
    from illuknit.solvers import ORACLE_BACKENDS

    rows, cols = SMOKE_INSTANCE.size
    click.echo(
        f"Each installed backend runs once on an {rows} x {cols} logical model in its own "
        f"process ({SMOKE_INSTANCE.time_limit:g} s limit):"
    )

    def show(e: dict[str, str]) -> None:
        click.echo(
            f"{e['name']:17s} {e['kind']:9s} {e['version'] or '-':22s} available: "
            f"{e['available']}; smoke test: {e['smoke']}; time limit: {e['limit']}"
        )

    smoke_test_backends(time_limit=SMOKE_INSTANCE.time_limit, on_result=show)
    click.echo(
        f"Also: {', '.join(f'{b}:ORACLE' for b in ORACLE_BACKENDS)} (a python-sat SAT oracle, "
        "e.g. rc2:cd19) and wcnf:COMMAND (any MaxSAT Evaluation solver binary; {} is the WCNF "
        "path). Missing ones: pip install 'illuknit[maxsat]'."
    )
    ctx.exit(0)


@click.command("solve")
@click.argument("image_a", type=InputFile("picture"), required=False)
@click.argument("image_b", type=InputFile("picture"), required=False)
@declared_option(SolveOptions, "solver")
@click.option(
    "--list-solvers",
    is_flag=True,
    expose_value=False,
    is_eager=True,
    callback=_list_solvers,
    help="List every solver backend with its version and availability, then exit.",
)
@declared_option(SolveOptions, "warm_start")
@declared_option(SolveOptions, "model")
@click.option(
    "--weights",
    default=None,
    metavar="LIST",
    help="Knit-aware weights, e.g. 'view=4,color_change=1,transfer=1,max_color_changes=6'.",
)
@click.option(
    "--max-color-changes",
    type=COLOR_CHANGES,
    default=None,
    help="Hard cap on colour changes per course (knit-aware).",
)
@declared_option(SolveOptions, "alternate_rows")
@declared_option(SolveOptions, "split_bumps")
@click.option(
    "--colors",
    "n_colors",
    type=click.IntRange(1, 8),
    default=None,
    help="Number of yarn colours K.",
)
@click.option(
    "--yarns",
    default=None,
    metavar="LIST",
    help="Yarn colours, e.g. '#1b1b1b,#f4f0e8' or 'navy,white'.",
)
@click.option(
    "--width",
    type=click.IntRange(1, 1000),
    default=None,
    help=f"Grid width in units (default: picture width, at most {DEFAULT_MAX_WIDTH}).",
)
@click.option("--resize", is_flag=True, help="Stretch B onto A's grid when their sizes differ.")
@click.option(
    "--quantise/--no-quantise",
    default=True,
    show_default=True,
    help="Cluster pictures with more colours than yarns.",
)
@declared_option(SolveOptions, "time_limit")
@declared_option(SolveOptions, "seed")
@declared_option(
    RankOptions,
    "made_for",
    note="Here hands makes every row knittable by hand a hard constraint of the model (at "
    "most 6 intarsia blocks, or 2 yarns with floats of at most 7 stitches), solved by cpsat or "
    "rc2; not with --model single (its rows are one yarn already) or --split-bumps.",
)
@click.option(
    "--export-wcnf",
    type=OutputFile(allow_dash=True),
    default=None,
    help="Also (or, without -o, only) write the model as WCNF for an external MaxSAT solver "
    "(- for standard output, without -o).",
)
@click.option(
    "--wcnf-style",
    type=click.Choice(["new", "old"]),
    default="new",
    show_default=True,
    help="WCNF dialect: 2022+ 'h' lines, or the old 'p wcnf' header.",
)
@click.option(
    "--knitout", is_flag=True, help="Also write a knitout program (program.k) and its check."
)
@machine_option()
@format_option()
@long_floats_option()
@click.option(
    "-o",
    "--outdir",
    type=OutputFolder(),
    default=None,
    help="Folder to write into.",
)
def solve(image_a: Path | None, image_b: Path | None, outdir: Path | None, **kw: Any) -> None:
    """Solve for an illusion pattern with a constraint model and a pluggable solver.

    A is seen from above (one end of the wales), B from below. Ctrl-C stops a long solve and
    keeps the best pattern found so far. Writes pattern.json, previews, chart, instructions and
    report.json into OUTDIR.
    """
    run_solve(SolveRequest.from_switches(image_a, image_b, outdir, **kw))
