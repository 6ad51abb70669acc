"""``illuknit bench``: run design methods on benchmark instances and compare them."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from illuknit.cli.knitout_bridge import machine_option
from illuknit.cli.options import (
    COUNT,
    JOBS,
    MEGABYTES,
    SECONDS,
    SECONDS_OR_ZERO,
    SEED,
    InputFile,
    OutputFolder,
)
from illuknit.core.errors import UnknownNameError, YarnSpecError
from illuknit.pictures.sizing import DEFAULT_MAX_WIDTH

__all__ = ["bench"]


def _methods(spec: str) -> list[str]:
    from illuknit.bench.methods import DEFAULT_METHODS, method_names

    names = [s.strip() for s in spec.split(",") if s.strip()]
    out: list[str] = []
    for n in names or ["default"]:
        group = list(DEFAULT_METHODS) if n == "default" else method_names() if n == "all" else [n]
        for m in group:
            if m not in method_names():
                raise UnknownNameError("method", m, ["default", "all", *method_names()])
            if m not in out:
                out.append(m)
    return out


def _split(spec: str) -> list[str]:
    return [x.strip() for x in spec.split(",") if x.strip()]


def _run_solvers(instances: Any, solvers: list[str], outdir: str, **kw: Any) -> None:
    """The solver benchmark: check the names, run the table, print the summary."""
    from illuknit.bench.solver_table import make_tasks, run_solver_table
    from illuknit.design.models.backends.warm_start import WARM_STARTS
    from illuknit.solvers import get_backend

    for s in solvers:  # unknown names fail before any work (NAME+split: NAME's)
        get_backend(s.removesuffix("+split"), check_available=False)
    for ws in kw["warm_starts"]:
        if ws not in WARM_STARTS:
            raise UnknownNameError("warm start", ws, WARM_STARTS)
    tasks = make_tasks(
        instances,
        solvers,
        models=kw["models"],
        warm_starts=kw["warm_starts"],
        time_limit=kw["time_limit"],
        memory_mb=kw["memory_mb"],
        wcnf_files=kw["wcnf_files"],
        repeat=kw["repeat"],
        seed=kw["seed"],
    )

    def show(row: dict[str, Any]) -> None:
        cost = "-" if row["verified_cost"] is None else row["verified_cost"]
        flag = f"  FLAG: {row['flag']}" if row.get("flag") else ""
        click.echo(
            f"{row['instance']:24s} {row['model']:10s} {row['solver']:16s} "
            f"{row['status']:9s} cost {cost!s:>7} {row['wall_s'] or 0:7.2f} s{flag}"
        )

    table = run_solver_table(
        tasks,
        outdir,
        jobs=kw["jobs"],
        executor=kw["executor"],
        dask_address=kw["dask_address"],
        on_row=show,
        certify_time=kw["certify_time"],
    )
    click.echo("solver          runs solved  PAR-2   flagged")
    for entry in table.summary:
        spread = (
            f"  (PAR-2 over {entry['repeats']} runs: {entry['par2_spread']})"
            if entry.get("repeats")
            else ""
        )
        click.echo(
            f"{entry['solver']:16s}{entry['runs']:4d} {entry['solved']:5g} "
            f"{entry['par2']:7.2f}   {entry.get('flagged', '-')}{spread}"
        )
    click.echo(f"results in {outdir}: {', '.join(table.files)}")


@click.command(name="bench")
@click.option(
    "--instances",
    "instances",
    default="quick",
    show_default=True,
    help="Comma-separated instance names, 'quick' or 'all'.",
)
@click.option(
    "--methods",
    default="default",
    show_default=True,
    help="Comma-separated methods (tiles, single, dp, rc2, cpsat, knit-aware, gradient; and "
    "tiles-split, dp-split: with split bumps), 'default' or 'all'.",
)
@click.option(
    "--time-limit", type=SECONDS, default=None, help="Seconds per cell (overrides the manifest)."
)
@click.option(
    "--jobs", "-j", type=JOBS, default=1, show_default=True, help="Parallel worker processes."
)
@click.option(
    "--executor",
    type=click.Choice(["local", "dask"]),
    default="local",
    show_default=True,
    help="Run cells locally or on a Dask cluster (pip install 'illuknit[dask]').",
)
@click.option(
    "--dask-address",
    default=None,
    help="Scheduler address for --executor dask (default: a local cluster).",
)
@click.option(
    "--manifest",
    type=InputFile("manifest", path_type=str),
    default=None,
    help="Instance manifest (default: instances/manifest.toml).",
)
@click.option(
    "--force", is_flag=True, help="Re-run every cell, discarding results of another version."
)
@click.option(
    "--solvers",
    default=None,
    metavar="LIST",
    help="Benchmark solvers instead of design methods: comma-separated backend names "
    "(see `illuknit solve --list-solvers`), e.g. dp,rc2,rc2:cd19,cpsat,uwrmaxsat,'wcnf:maxhs {}'. "
    "Writes solvers.csv, traces.csv, solvers.md, cactus.png.",
)
@click.option(
    "--models",
    default="logical",
    show_default=True,
    help="Solver benchmark: illusion models to encode (logical, knit-aware).",
)
@click.option(
    "--warm-start",
    "warm_starts",
    default="none",
    show_default=True,
    help="Solver benchmark: warm-start policies to run each solver with (none, dp, descent, auto; "
    "comma-separated for several).",
)
@click.option(
    "--memory-mb",
    type=MEGABYTES,
    default=4096.0,
    show_default=True,
    help="Solver benchmark: resident memory limit of one run.",
)
@click.option(
    "--wcnf",
    "wcnf_files",
    multiple=True,
    type=InputFile("WCNF", path_type=str),
    help="Solver benchmark on this WCNF file (repeatable; instead of the bundled instances).",
)
@click.option(
    "--pair",
    "pairs",
    multiple=True,
    nargs=2,
    type=InputFile("picture", path_type=str),
    metavar="A B",
    help="Solver benchmark on this picture pair (repeatable; instead of the bundled instances): "
    "sized and modelled as `illuknit solve A B` would, with the exact reference where the model "
    "has one.",
)
@click.option(
    "--width",
    type=click.IntRange(1, 1000),
    default=None,
    help=f"With --pair: grid width in units (default: picture width, at most {DEFAULT_MAX_WIDTH}).",
)
@click.option(
    "--colors",
    "n_colors",
    type=click.IntRange(2, 8),
    default=None,
    help="With --pair: number of yarn colours K.",
)
@click.option(
    "--yarns",
    default=None,
    metavar="LIST",
    help="With --pair: yarn colours, e.g. '#1b1b1b,#f4f0e8' or 'navy,white'.",
)
@click.option(
    "--resize", is_flag=True, help="With --pair: stretch B onto A's grid when their sizes differ."
)
@click.option(
    "--repeat",
    type=COUNT,
    default=1,
    show_default=True,
    help="Solver benchmark: run every row N times (seeds --seed, --seed + 1, ...); the summary "
    "gives medians and spread.",
)
@click.option(
    "--seed",
    type=SEED,
    default=0,
    show_default=True,
    help="Solver benchmark: the first seed.",
)
@click.option(
    "--certify-time",
    type=SECONDS_OR_ZERO,
    default=None,
    help="Solver benchmark: seconds for each independent SAT check of a claimed optimum or "
    "UNSATISFIABLE that no reference settles (default: the time limit; 0: no checks).",
)
@click.option(
    "--export-wcnf",
    type=OutputFolder(path_type=str),
    default=None,
    help="Write the chosen instances' models as WCNF (2022+) with manifest.json into DIR, then "
    "exit.",
)
@click.option(
    "--export-family",
    type=OutputFolder(path_type=str),
    default=None,
    help="Write a MaxSAT Evaluation benchmark family (xz WCNF over sizes 20-100, 2-4 yarns, "
    "logical and knit-aware, README, manifest.json, SHA256SUMS) into DIR, then exit; "
    "--time-limit: seconds of descent per knit-aware reference (default 10).",
)
@click.option("--list", "list_only", is_flag=True, help="List instances and methods, then exit.")
@click.option("--no-progress", is_flag=True, help="No progress bar.")
@machine_option("Knitting machine the patterns are knit on for passes and times.")
@click.option(
    "-o",
    "--output",
    "outdir",
    type=OutputFolder(path_type=str),
    default=None,
    help="Results folder.",
)
def bench(
    instances: str,
    methods: str,
    time_limit: float | None,
    jobs: int,
    executor: str,
    dask_address: str | None,
    manifest: str | None,
    force: bool,
    solvers: str | None,
    models: str,
    warm_starts: str,
    memory_mb: float,
    wcnf_files: tuple[str, ...],
    pairs: tuple[tuple[str, str], ...],
    width: int | None,
    n_colors: int | None,
    yarns: str | None,
    resize: bool,
    repeat: int,
    seed: int,
    certify_time: float | None,
    export_wcnf: str | None,
    export_family: str | None,
    list_only: bool,
    no_progress: bool,
    machine: str | None,
    outdir: str | None,
) -> None:
    """Benchmark design methods on instances: tiles vs MaxSAT vs optimisation (paper 8.3).

    Each instance x method cell records logical and render error, colour changes per course,
    carriage passes and knitting time, solve time and memory. Finished cells are kept, so an
    interrupted run resumes where it stopped. Writes results.csv, results.json, summary.md,
    contact sheets and pareto.png into the results folder.
    """
    from illuknit.bench.instances import load_manifest, select_instances

    man = load_manifest(manifest)
    if list_only:
        _list(man)
        return
    if export_family is not None:
        _export_family(export_family, time_limit)
        return
    if export_wcnf is not None:
        _export_wcnf(select_instances(man, instances), export_wcnf, _split(models))
        return
    if outdir is None:
        raise click.UsageError("missing option '-o' / '--output' (the results folder)")
    if jobs < 1:
        raise click.BadParameter(f"must be at least 1, got {jobs}", param_hint="--jobs")
    if time_limit is not None and not time_limit > 0:
        raise click.BadParameter(f"must be positive, got {time_limit}", param_hint="--time-limit")
    chosen = select_instances(man, instances)
    sizing = {"width": width, "n_colors": n_colors, "yarns": yarns, "resize": resize}
    _check_sizing(pairs, sizing)
    if solvers is not None or wcnf_files or pairs:
        _check_solver_options(repeat)
        if pairs:
            chosen = _picture_instances(pairs, _split(models), machine, **sizing)
        _run_solvers(
            chosen if pairs or not wcnf_files else [],
            _split(solvers or "rc2"),
            outdir,
            models=_split(models),
            warm_starts=_split(warm_starts),
            time_limit=10.0 if time_limit is None else time_limit,
            memory_mb=memory_mb,
            wcnf_files=wcnf_files,
            jobs=jobs,
            executor=executor,
            dask_address=dask_address,
            repeat=repeat,
            seed=seed,
            certify_time=certify_time,
        )
        return
    for name, value, default in (
        ("--repeat", repeat, 1),
        ("--seed", seed, 0),
        ("--certify-time", certify_time, None),
    ):
        if value != default:
            raise click.UsageError(f"{name} applies only to the solver benchmark (--solvers)")
    _run_methods(
        chosen,
        _methods(methods),
        outdir,
        time_limit=time_limit,
        jobs=jobs,
        executor=executor,
        force=force,
        progress=not no_progress,
        dask_address=dask_address,
        machine=machine,
    )


def _check_sizing(pairs: tuple[tuple[str, str], ...], sizing: dict[str, Any]) -> None:
    """The picture-sizing options apply only to ``--pair`` pictures."""
    given = [k for k, v in sizing.items() if v not in (None, False)]
    if given and not pairs:
        name = "colors" if given[0] == "n_colors" else given[0]
        raise click.UsageError(f"--{name} sizes pictures: it applies only with --pair A B")


def _check_solver_options(repeat: int) -> None:
    """Options of the solver benchmark that do not fit it, before any work."""
    ctx = click.get_current_context()
    if ctx.get_parameter_source("methods") is not click.core.ParameterSource.DEFAULT:
        raise click.UsageError(
            "--methods does not apply to the solver benchmark (--solvers / --wcnf / --pair): "
            "name backends with --solvers"
        )
    if repeat < 1:
        raise click.BadParameter(f"must be at least 1, got {repeat}", param_hint="--repeat")


def _picture_instances(
    pairs: tuple[tuple[str, str], ...],
    models: list[str],
    machine: str | None,
    **sizing: Any,
) -> list[Any]:
    """``--pair A B``: the pairs as bench instances, sized as ``illuknit solve`` sizes them
    (the machine's fabric gauge sets the unit's aspect) and modelled here, on the client."""
    from illuknit.bench.pictures import picture_instances
    from illuknit.cli.knitout_bridge import design_unit_aspect, resolve_machine
    from illuknit.core.pattern import parse_yarns

    ys = parse_yarns(sizing["yarns"]) if sizing["yarns"] else None
    if ys is not None and len(ys) < 2:
        raise YarnSpecError(
            f"an illusion needs at least 2 yarns, got 1 (--yarns {sizing['yarns']})"
        )
    found = picture_instances(
        pairs,
        models=models,
        n_colors=sizing["n_colors"],
        yarns=ys,
        width=sizing["width"],
        stretch=sizing["resize"],
        unit_aspect=design_unit_aspect(resolve_machine(machine)),
    )
    for inst in found:
        refs = ", ".join(
            f"{kind} {'reference (dp) ' + str(opt) if opt is not None else 'no exact reference'}"
            for kind, (_, opt) in inst.built.items()
        )
        click.echo(
            f"{inst.name}: {inst.size[0]}x{inst.size[1]} units, {inst.n_yarns} yarns; {refs}"
        )
    return found


def _list(man: Any) -> None:
    """``--list``: the manifest's instances and the design methods."""
    from illuknit.bench.methods import METHODS

    for inst in man.instances:
        tag = " [quick]" if inst.quick else ""
        click.echo(
            f"{inst.name:24s} {inst.kind:6s} {inst.size[0]}x{inst.size[1]} "
            f"{len(inst.yarns)} yarns {inst.time_limit:g}s{tag}"
        )
    click.echo("methods:")
    for m in METHODS.values():
        click.echo(f"  {m.name:12s} {m.description}")


def _export_family(outdir: str, time_limit: float | None) -> None:
    """``--export-family DIR``: write the MaxSAT Evaluation family, one line per instance."""
    from illuknit.bench.family import write_family

    def shown(e: dict[str, Any]) -> None:
        ref = e["optimum"] if e["optimum"] is not None else f"{e['lower_bound']}..{e['best_known']}"
        click.echo(f"{e['file']:52s} {e['variables']:7d} vars  reference {ref}")

    mf = write_family(
        outdir,
        bound_seconds=10.0 if time_limit is None else time_limit,
        # the folder's own name: the command reproduces the family anywhere
        command=f"illuknit bench --export-family {Path(outdir).name}"
        + ("" if time_limit is None else f" --time-limit {time_limit:g}"),
        on_instance=shown,
    )
    click.echo(
        f"wrote {len(mf['instances'])} instances, README.md, manifest.json and "
        f"SHA256SUMS to {outdir}"
    )


def _export_wcnf(chosen: Any, outdir: str, models: list[str]) -> None:
    """``--export-wcnf DIR``: the chosen instances' models as WCNF files with a manifest."""
    from illuknit.bench.wcnf_files import export_wcnf_family

    mf = export_wcnf_family(chosen, outdir, models=models)
    click.echo(f"wrote {len(mf['files'])} WCNF files and manifest.json to {outdir}")


def _run_methods(chosen: Any, names: list[str], outdir: str, **kw: Any) -> None:
    """The design-method benchmark: run the cells, print the counts and where the results are."""
    from illuknit.bench.runner import run_bench

    run = run_bench(chosen, names, outdir, **kw)
    counts: dict[str, int] = {}
    for r in run.rows:
        counts[r["status"]] = counts.get(r["status"], 0) + 1
    click.echo(
        f"{len(run.ran)} cell(s) run, {len(run.reused)} reused; "
        + ", ".join(f"{v} {k}" for k, v in sorted(counts.items()))
    )
    click.echo(
        f"results in {run.outdir}: results.csv, results.json, summary.md"
        + (", pareto.png" if "pareto" in run.outputs else "")
        + (", contact/" if any(k.startswith("contact:") for k in run.outputs) else "")
    )
