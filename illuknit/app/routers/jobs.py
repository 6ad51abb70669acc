"""Jobs: the long work in the background (candidate search, measures, suggested edits, the
smallest width that reads, knitout and its check), with progress and cancel."""

import functools
from collections.abc import Callable
from typing import Annotated, Any

from fastapi import APIRouter, Depends, Request

from illuknit.app import design
from illuknit.app.candidates import hand_model_seconds
from illuknit.app.controls import blame
from illuknit.app.jobs import Job, JobRunner
from illuknit.app.knitting import CheckedKnitout, knit_and_check
from illuknit.app.lookups import SessionDep, current_pattern, prepared_of, runner_of, store_of
from illuknit.app.measures import measure_all
from illuknit.app.schemas import JobIn
from illuknit.app.sessions import Session, SessionStore
from illuknit.core.errors import AppRequestError, IlluknitError

__all__ = ["router"]

router = APIRouter(prefix="/api/sessions/{sid}/jobs", tags=["jobs"])

RunnerDep = Annotated[JobRunner, Depends(runner_of)]


def start_candidates(s: Session, runner: JobRunner, *, isolate: bool = True) -> Job:
    prepared = prepared_of(s)
    count = s.settings.candidates
    split_bumps = s.settings.split_bumps
    made_for = s.settings.made_for
    machine, viewpoint = s.settings.machine, s.settings.viewpoint
    rev = s.revision

    def work(job: Job) -> list[design.Candidate]:
        def run(search: Any) -> Any:
            # The search stops by the pool's time bound (plus one solve's time limit, and made
            # for hands the constraint model's): the bar moves with the time spent against that
            # bound, the words say what is being done.
            from illuknit.design.tiles.perception import POOL_SECONDS

            model = hand_model_seconds() if made_for == "hands" and prepared.mode == "double" else 0
            bound = POOL_SECONDS + 10.0 + model
            what = "finding tile mappings"
            if model:
                what += f" and solving the constraint model made for hands (up to {model:g} s)"
            # the reader comes after the bound: its seconds are said, not hidden in it
            ranking = getattr(search, "keywords", {}).get("ranking")
            then = ", then the reader reads both sides" if getattr(ranking, "read", False) else ""

            def tick(seconds: float) -> None:
                job.report(
                    0.1 + 0.3 * min(1.0, seconds / bound),
                    f"{what}: {seconds:.0f} s so far, done in at most {bound:.0f} s (usually far "
                    f"less){then}",
                )

            return job.run_isolated(search, tick=tick, poll=0.1)

        return design.make_candidates(
            prepared,
            count=count,
            progress=job.report,
            run=run if isolate else None,
            split_bumps=split_bumps,
            made_for=made_for,
            machine=machine,
            viewpoint=viewpoint,
        )

    def done(job: Job) -> None:
        with s.lock:
            if s.revision == job.revision:
                s.candidates = list(job.result)
                s.candidates_revision = job.revision
                s.selected = 1
                s.overrides = {}
                s.knit = None

    return runner.submit("candidates", work, revision=rev, on_done=done)


def start_measures(s: Session, runner: JobRunner, *, isolate: bool = True) -> Job:
    """Readability, ghosting and knitting time of every candidate (kept on the candidates).
    With ``isolate`` the work runs in its own process, killed by Cancel at once (knitting one
    large candidate takes seconds and cannot be interrupted in-process)."""
    with s.lock:
        candidates = list(s.candidates)
        prepared, machine, rev = s.prepared, s.settings.machine, s.revision
        viewpoint = s.settings.viewpoint
    if not candidates or prepared is None:
        raise AppRequestError(
            "no candidates to measure yet: find candidates first",
            field="candidates",
            code="no_candidates",
            status=409,
        )

    def work(job: Job) -> tuple[list[Any], Any]:
        patterns = [c.pattern for c in candidates]
        if not isolate:
            measured = measure_all(patterns, prepared, machine, viewpoint, progress=job.report)
        else:
            measured = job.run_isolated(
                measure_all, patterns, prepared, machine, viewpoint, progress=(0.0, 0.9)
            )
        run = job.run_isolated if isolate else _call
        read = _read_again(job, run, candidates, prepared, measured, (machine, viewpoint))
        return measured, read

    def done(job: Job) -> None:
        with s.lock:
            # the very candidates measured (a new viewpoint replaces them by unmeasured copies)
            same = len(s.candidates) == len(candidates) and all(
                a is b for a, b in zip(s.candidates, candidates, strict=True)
            )
            if s.revision == job.revision and same:
                measured, read = job.result
                for c, m in zip(candidates, measured, strict=True):
                    c.measured = m
                if read is not None:
                    verdicts, why = read
                    for c, v in zip(candidates, verdicts, strict=True):
                        c.legibility, c.not_read = v, why

    return runner.submit("measures", work, revision=rev, on_done=done)


def _call(fn: Callable[..., Any], *args: Any) -> Any:
    return fn(*args)


def _read_again(
    job: Job,
    run: Callable[..., Any],
    candidates: list[design.Candidate],
    prepared: Any,
    measured: list[Any],
    seen: tuple[str, tuple[float, float]],
) -> tuple[list[Any], str | None] | None:
    """The reader's verdicts on candidates read from another viewpoint, read again (by ``run``,
    in the job's worker process or here) on ``seen``'s machine from its viewpoint; None when
    there is nothing to read again. ``(verdicts, None)``, or, when the reader fails now,
    ``([None, ...], why)``."""
    from illuknit.app.reading import read_candidates, reader_failed

    machine, viewpoint = seen
    old = [c.legibility for c in candidates]
    if all(v is None or (v.angle, v.distance) == viewpoint for v in old):
        return None
    job.report(0.9, f"reading both sides of {len(candidates)} candidate(s) from the new viewpoint")
    patterns = [c.pattern for c in candidates]
    correlations = [m.readability for m in measured]
    try:
        verdicts = run(
            functools.partial(
                read_candidates, machine=machine, viewpoint=viewpoint, correlations=correlations
            ),
            patterns,
            prepared,
        )
    except (AppRequestError, IlluknitError) as e:
        if not reader_failed(e):
            raise
        return [None] * len(candidates), str(e)
    return list(verdicts), None


def start_suggestions(
    s: Session, runner: JobRunner, store: SessionStore, *, isolate: bool = True
) -> Job:
    """Suggested edits of the pictures, each measured (kept as the session's suggestion set;
    their pictures count in ``store``'s memory bound, which is enforced once they are kept).
    With ``isolate`` the work runs in its own process, killed by Cancel (each measurement is a
    tile search that cannot be interrupted in-process), reporting its progress from there."""
    from illuknit.app.suggestions import require_double, suggest_edits_for

    prepared = prepared_of(s)
    require_double(prepared)  # refused at once, not as a failed job
    with s.lock:
        images, settings, rev = dict(s.images), s.settings, s.revision
    count = settings.candidates

    def work(job: Job) -> Any:
        job.report(0.01, "sizing the pictures")
        sources, _ = design.size_inputs(images, settings)  # what a re-quantisation reads again
        suggest = functools.partial(
            suggest_edits_for, prepared, sources=sources, set_id=job.id, revision=rev, count=count
        )
        if not isolate:
            return suggest(progress=job.report)
        try:
            return job.run_isolated(suggest, progress=(0.02, 1.0))
        except AppRequestError as e:  # raised in the worker process: name the control
            e.field = e.field or "suggestions"
            raise

    def done(job: Job) -> None:
        with s.lock:
            if s.revision == job.revision:
                s.set_suggestions(job.result)
        store.trim(keep=s.id)

    return runner.submit("suggestions", work, revision=rev, on_done=done)


def start_widths(
    s: Session, runner: JobRunner, widths: list[int] | None = None, *, isolate: bool = True
) -> Job:
    """The smallest width at which both sides of the session's pictures read
    (:func:`illuknit.app.reading.legible_widths`), kept with the session with the pictures and
    settings it holds for. Refused at once (409) without two pictures in a double view or
    without the reader. With ``isolate`` the work runs in its own process, killed by Cancel."""
    from illuknit.app.reading import (
        WidthsResult,
        legible_widths,
        require_reader,
        widths_key,
        widths_to_try,
    )

    with s.lock:
        images, settings, rev = dict(s.images), s.settings, s.revision
    if settings.mode != "double" or not {"a", "b"} <= set(images):
        raise AppRequestError(
            "how wide it must be is found for a double view's two pictures: choose Double view "
            "and give pictures A and B",
            field="widths",
            code="not_double",
            status=409,
        )
    require_reader("widths")
    tried = widths_to_try(settings.machine, widths)
    key = widths_key(images, settings)
    a, b = images["a"].rgb, images["b"].rgb

    def work(job: Job) -> WidthsResult:
        job.report(0.01, f"designing and reading {tried[0]} units wide")
        if not isolate:
            with blame("widths"):
                found = legible_widths(a, b, settings, tried, progress=job.report)
            return WidthsResult(key, found)
        try:
            found = job.run_isolated(legible_widths, a, b, settings, tried, progress=(0.02, 1.0))
        except AppRequestError as e:  # raised in the worker process: name the control
            e.field = e.field or "widths"
            raise
        return WidthsResult(key, found)

    def done(job: Job) -> None:
        with s.lock:
            s.legible_widths = job.result

    return runner.submit("widths", work, revision=rev, on_done=done)


def start_knit(
    s: Session, runner: JobRunner, *, isolate: bool, allow_long_floats: bool = False
) -> Job:
    pattern = current_pattern(s)
    key = design.pattern_key(pattern)
    doc = design.pattern_to_json(pattern)
    machine = s.settings.machine

    def work(job: Job) -> CheckedKnitout:
        job.report(0.05, "compiling knitout and checking it")
        if isolate:
            out = job.run_isolated(knit_and_check, doc, machine, allow_long_floats)
        else:
            out = knit_and_check(doc, machine, allow_long_floats)
        return CheckedKnitout(
            key=key,
            machine=machine,
            knitout=out["knitout"],
            stats=out["stats"],
            report=out["report"],
            report_text=out["report_text"],
            carriers=tuple(out["carriers"]),
            needle_range=tuple(out["needle_range"]),
        )

    def done(job: Job) -> None:
        with s.lock:
            s.knit = job.result

    return runner.submit("knit", work, revision=s.revision, on_done=done)


@router.post(
    "",
    status_code=202,
    summary="Start a background job (candidates, measures, suggestions, widths or knitout); "
    "replaces a live job of that kind",
)
def post_job(request: Request, s: SessionDep, runner: RunnerDep, body: JobIn) -> dict[str, Any]:
    # the job it replaces is cancelled once the new one is saved (Session.replace_job)
    with s.changing():
        if body.kind == "candidates":
            job = start_candidates(s, runner, isolate=request.app.state.config.isolate_search)
        elif body.kind == "measures":
            job = start_measures(s, runner, isolate=request.app.state.config.isolate_knit)
        elif body.kind == "widths":
            job = start_widths(
                s, runner, body.widths, isolate=request.app.state.config.isolate_search
            )
        elif body.kind == "suggestions":
            job = start_suggestions(
                s, runner, store_of(request), isolate=request.app.state.config.isolate_search
            )
        else:
            job = start_knit(
                s,
                runner,
                isolate=request.app.state.config.isolate_knit,
                allow_long_floats=body.allow_long_floats,
            )
        s.replace_job(body.kind, job)
        answer = job.to_json()
    store_of(request).trim(keep=s.id)
    return answer


def job_of(s: Session, job_id: str) -> Job:
    """Job ``job_id`` of this session, or the job that replaced it (404 for another tab's)."""
    job: Job | None = s.find_job(job_id)
    if job is None:
        raise AppRequestError(
            f"no job {job_id!r} in this session", field="job", code="no_job", status=404
        )
    return job


@router.get(
    "/{job_id}",
    summary="Poll a job's progress; a replaced job answers with the job that replaced it",
)
def get_job(s: SessionDep, job_id: str) -> dict[str, Any]:
    with s.lock:
        job = job_of(s, job_id)
        answer = job.to_json()
    if job.id != job_id:
        answer["superseded"] = job_id
    return answer


@router.delete("/{job_id}", summary="Cancel a job (a replaced job is already cancelled)")
def cancel_job(s: SessionDep, job_id: str) -> dict[str, Any]:
    with s.lock:
        job = job_of(s, job_id)
    if job.id != job_id:  # replaced, hence cancelled already; its successor is not touched
        return {**job.to_json(), "superseded": job_id}
    job.cancel()
    job.wait(timeout=5)
    return job.to_json()
