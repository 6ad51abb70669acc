"""The design app's HTTP layer: one page and a JSON API (FastAPI; OpenAPI at ``/docs``).

All state lives in per-tab :class:`~illuknit.app.sessions.Session` objects addressed by the id in
the URL (``/api/sessions/{sid}/...``); the pipeline itself is :mod:`illuknit.app.design`. Every
error answer has one shape, so the page can put the message next to the control at fault::

    {"error": {"message": "...", "field": "image_b", "code": "size_mismatch"}}

Long work (candidate search, knitout compilation and checking) runs as a background job
(:mod:`illuknit.app.jobs`) that the page polls and can cancel. Uploads are capped in size before
they are read into memory (:class:`UploadLimit`).
"""

import threading
from collections.abc import AsyncIterator, Awaitable, Callable, MutableMapping
from dataclasses import replace
from pathlib import Path
from typing import Annotated, Any, Literal

from illuknit import __version__
from illuknit.app import design
from illuknit.app.jobs import Job, JobRunner
from illuknit.app.sessions import DesignSettings, Session, SessionStore, UploadedImage
from illuknit.errors import AppRequestError, IlluknitError
from illuknit.pattern import MAX_UNITS, LogicalPattern

__all__ = ["STATIC_DIR", "AppConfig", "create_app"]

STATIC_DIR = Path(__file__).parent / "static"

Scope = MutableMapping[str, Any]
Message = MutableMapping[str, Any]
Receive = Callable[[], Awaitable[Message]]
Send = Callable[[Message], Awaitable[None]]


class AppConfig:
    """Server limits. Defaults suit one designer on a laptop."""

    def __init__(
        self,
        *,
        max_upload_bytes: int = design.MAX_UPLOAD_BYTES,
        max_sessions: int = 64,
        session_ttl: float = 6 * 3600,
        workers: int = 2,
        isolate_knit: bool = True,
    ) -> None:
        self.max_upload_bytes = max_upload_bytes
        self.max_sessions = max_sessions
        self.session_ttl = session_ttl
        self.workers = workers
        self.isolate_knit = isolate_knit


def _error_body(message: str, field: str | None, code: str) -> dict[str, Any]:
    return {"error": {"message": message, "field": field, "code": code}}


class UploadLimit:
    """ASGI middleware: refuse image uploads over the size limit before the app reads them.

    A declared ``Content-Length`` over the limit is refused at once; a chunked body is counted as
    it arrives and refused as soon as it passes the limit. Either way the answer is a 413 with the
    usual error body naming the upload control, never a dropped connection.
    """

    def __init__(self, app: Any, *, limit: int) -> None:
        self.app = app
        # multipart framing adds a few hundred bytes; allow some slack over the file limit
        self.limit = limit + 64 * 1024
        self.file_limit = limit

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        path = scope.get("path", "")
        if (
            scope["type"] != "http"
            or scope.get("method") not in ("PUT", "POST")
            or "/images/" not in path
        ):
            await self.app(scope, receive, send)
            return
        slot = path.rstrip("/").rsplit("/", 1)[-1]
        field = f"image_{slot}" if slot in ("a", "b") else "image_a"
        headers = dict(scope.get("headers") or [])
        declared = headers.get(b"content-length")
        if declared is not None and declared.isdigit() and int(declared) > self.limit:
            await self._refuse(send, field, int(declared))
            return
        chunks: list[bytes] = []
        total = 0
        more = True
        while more:
            message = await receive()
            if message["type"] == "http.disconnect":
                return
            body = message.get("body", b"")
            total += len(body)
            if total > self.limit:
                await self._refuse(send, field, total)
                return
            chunks.append(body)
            more = message.get("more_body", False)
        replay = [{"type": "http.request", "body": b"".join(chunks), "more_body": False}]

        async def replay_receive() -> Message:
            if replay:
                return replay.pop()
            return await receive()

        await self.app(scope, replay_receive, send)

    async def _refuse(self, send: Send, field: str, size: int) -> None:
        import json

        mb = self.file_limit / 1e6
        body = json.dumps(
            _error_body(
                f"the upload is {'over ' if size <= self.limit else ''}{max(size, self.limit) / 1e6:.1f} MB;"
                f" pictures are limited to {mb:.0f} MB. Save a smaller copy (a knitted piece is at most "
                f"{MAX_UNITS} units across, so a few hundred pixels are plenty).",
                field,
                "too_large",
            )
        ).encode()
        await send(
            {
                "type": "http.response.start",
                "status": 413,
                "headers": [
                    (b"content-type", b"application/json"),
                    (b"connection", b"close"),
                    (b"content-length", str(len(body)).encode()),
                ],
            }
        )
        await send({"type": "http.response.body", "body": body})


def create_app(config: AppConfig | None = None) -> Any:
    """Build the FastAPI application (import-light: FastAPI is imported here, not at module load)."""
    try:
        from fastapi import FastAPI, File, Query, Request, UploadFile
        from fastapi.exceptions import RequestValidationError
        from fastapi.responses import FileResponse, HTMLResponse, JSONResponse, Response
        from fastapi.staticfiles import StaticFiles
        from pydantic import BaseModel, Field
        from starlette.exceptions import HTTPException as StarletteHTTPException
    except ImportError as e:  # pragma: no cover - depends on the install
        from illuknit.errors import BackendUnavailableError

        raise BackendUnavailableError(
            f"the app needs FastAPI and uvicorn ({e.name} is missing): pip install 'illuknit[app]'"
        ) from None

    cfg = config or AppConfig()
    store = SessionStore(max_sessions=cfg.max_sessions, ttl=cfg.session_ttl)
    runner = JobRunner(workers=cfg.workers)

    from contextlib import asynccontextmanager

    @asynccontextmanager
    async def lifespan(app: Any) -> AsyncIterator[None]:
        # Import the heavy parts of the pipeline in the background at start-up, so the designer's
        # first upload is not the one that waits for scikit-image, SciPy and the solvers to load.
        threading.Thread(target=design.warm_up, name="illuknit-warm-up", daemon=True).start()
        yield
        runner.shutdown()

    app = FastAPI(
        title="illuknit design app",
        version=__version__,
        description=(
            "Designer-in-the-loop illusion knitting: upload pictures, quantise them to yarns, "
            "get ranked tile mappings, look at angled renders, edit tiles, download the pattern, "
            "chart, instructions and checked knitout. All state is per session "
            '(`/api/sessions/{sid}`); every error answers `{"error": {"message", "field", "code"}}`.'
        ),
        lifespan=lifespan,
        # FastAPI's own /docs pages load their scripts from a CDN; the app must work offline, so
        # /docs is a plain page rendered here from the same OpenAPI document (/openapi.json).
        docs_url=None,
        redoc_url=None,
    )
    app.state.store = store
    app.state.runner = runner
    app.state.config = cfg
    app.add_middleware(UploadLimit, limit=cfg.max_upload_bytes)

    # -- errors: one shape, always JSON --------------------------------------------------------
    @app.exception_handler(AppRequestError)
    async def _app_error(request: Request, exc: AppRequestError) -> JSONResponse:
        return JSONResponse(_error_body(str(exc), exc.field, exc.code), status_code=exc.status)

    @app.exception_handler(IlluknitError)
    async def _lib_error(request: Request, exc: IlluknitError) -> JSONResponse:
        return JSONResponse(_error_body(str(exc), None, type(exc).__name__), status_code=422)

    @app.exception_handler(RequestValidationError)
    async def _validation_error(request: Request, exc: RequestValidationError) -> JSONResponse:
        errs = exc.errors()
        first = errs[0] if errs else {"loc": (), "msg": "invalid request"}
        loc = [str(p) for p in first.get("loc", ()) if p not in ("body", "query", "path")]
        field = loc[0] if loc else None
        label = ".".join(loc) if loc else "request"
        msg = f"{label}: {first.get('msg', 'invalid value')}"
        if len(errs) > 1:
            msg += f" (and {len(errs) - 1} more problem{'s' if len(errs) > 2 else ''})"
        return JSONResponse(_error_body(msg, field, "invalid"), status_code=422)

    @app.exception_handler(StarletteHTTPException)
    async def _http_error(request: Request, exc: StarletteHTTPException) -> JSONResponse:
        return JSONResponse(
            _error_body(str(exc.detail), None, f"http_{exc.status_code}"),
            status_code=exc.status_code,
        )

    @app.exception_handler(Exception)
    async def _bug(request: Request, exc: Exception) -> JSONResponse:
        return JSONResponse(
            _error_body(f"internal error: {type(exc).__name__}: {exc}", None, "internal"),
            status_code=500,
        )

    # -- request models ------------------------------------------------------------------------
    class SettingsIn(BaseModel):
        """Design settings; every field optional (only the given ones change)."""

        mode: Literal["single", "double", "headon"] | None = Field(
            None, description="single view (one picture), double view or head-on (two pictures)"
        )
        size_mode: Literal["units", "physical"] | None = Field(
            None, description="give the width in units, or as a physical width and a gauge"
        )
        width_units: int | None = Field(
            None, ge=2, le=MAX_UNITS, description="width in units (1 unit = 2 stitches)"
        )
        width_cm: float | None = Field(None, gt=0, le=500, description="physical width in cm")
        gauge: float | None = Field(None, gt=0, le=40, description="stitches per inch")
        n_colors: int | None = Field(
            None, ge=2, le=4, description="colours to quantise each picture to"
        )
        yarns: list[str] | None = Field(
            None, min_length=2, max_length=6, description="yarn colours, '#rrggbb' or CSS names"
        )
        candidates: int | None = Field(None, ge=1, le=12, description="ranked candidates to show")
        resize: bool | None = Field(None, description="stretch picture B to picture A's size")
        smooth: bool | None = Field(
            None, description="anti-aliased resizing (photos) vs nearest (pixel art)"
        )

    class JobIn(BaseModel):
        kind: Literal["candidates", "knit"] = Field(..., description="what to compute")

    class SelectionIn(BaseModel):
        candidate: int = Field(..., ge=1, description="rank of the candidate to use")

    class OverrideIn(BaseModel):
        tile: str | None = Field(
            None, description="tile id from the bank; null restores the candidate's own"
        )

    # -- helpers -------------------------------------------------------------------------------
    def session_of(sid: str) -> Session:
        return store.get(sid)

    def state_json(s: Session) -> dict[str, Any]:
        jobs = {k: j.to_json() for k, j in s.jobs.items()}
        return {
            "id": s.id,
            "revision": s.revision,
            "settings": s.settings.to_json(),
            "images": {slot: image_json(s, slot) for slot in s.images},
            "candidates": len(s.candidates),
            "selected": s.selected if s.candidates else None,
            "overrides": [{"a": a, "b": b, "tile": t} for (a, b), t in s.overrides.items()],
            "knit_ready": s.knit is not None,
            "jobs": jobs,
        }

    def image_json(s: Session, slot: str) -> dict[str, Any]:
        im = s.images[slot]
        w, h = im.size
        return {
            "slot": slot,
            "filename": im.filename,
            "width": w,
            "height": h,
            "bytes": len(im.data),
            "url": f"/api/sessions/{s.id}/images/{slot}?r={s.revision}",
        }

    def check_slot(slot: str) -> None:
        if slot not in ("a", "b"):
            raise AppRequestError(
                f"image slot must be 'a' or 'b', got {slot!r}",
                field="slot",
                code="bad_slot",
                status=404,
            )

    def prepared_of(s: Session) -> design.Prepared:
        # Quantising is done outside the session lock so that quick requests of the same tab
        # (thumbnails, state) are not held up; the result is kept only if nothing changed since.
        with s.lock:
            if s.prepared is not None:
                return s.prepared
            images, settings, revision = dict(s.images), s.settings, s.revision
        prepared = design.prepare_inputs(images, settings)
        with s.lock:
            if s.revision == revision:
                s.prepared = prepared
        return prepared

    def candidate_of(s: Session, rank: int | None) -> design.Candidate:
        if not s.candidates:
            raise AppRequestError(
                "no candidates yet: press 'Find candidates'",
                field="candidates",
                code="no_candidates",
                status=409,
            )
        r = s.selected if rank is None else rank
        if not 1 <= r <= len(s.candidates):
            raise AppRequestError(
                f"candidate must be 1..{len(s.candidates)}, got {r}",
                field="candidate",
                code="range",
            )
        return s.candidates[r - 1]

    def current_pattern(s: Session, rank: int | None = None) -> LogicalPattern:
        with s.lock:
            cand = candidate_of(s, rank)
            if rank is not None and rank != s.selected:
                return cand.pattern
            return design.pattern_for(cand, s.overrides)

    # -- page ----------------------------------------------------------------------------------
    @app.get("/docs", include_in_schema=False)
    def docs() -> HTMLResponse:
        return HTMLResponse(api_docs_html(app.openapi()))

    @app.get("/", include_in_schema=False)
    def index() -> FileResponse:
        return FileResponse(STATIC_DIR / "index.html", headers={"Cache-Control": "no-cache"})

    app.mount("/static", StaticFiles(directory=STATIC_DIR), name="static")

    # -- API -----------------------------------------------------------------------------------
    @app.get(
        "/api/info", tags=["app"], summary="Version, installed capabilities, limits, yarn presets"
    )
    def info() -> dict[str, Any]:
        return {
            "version": __version__,
            "capabilities": design.capabilities(),
            "limits": {
                "max_upload_bytes": cfg.max_upload_bytes,
                "max_units": MAX_UNITS,
                "max_pixels": design.MAX_UPLOAD_PIXELS,
            },
            "presets": {k: list(v) for k, v in design.YARN_PRESETS.items()},
            "defaults": DesignSettings().to_json(),
        }

    @app.post(
        "/api/sessions", tags=["sessions"], status_code=201, summary="Start a session (one per tab)"
    )
    def create_session() -> dict[str, Any]:
        return state_json(store.create())

    @app.get("/api/sessions/{sid}", tags=["sessions"], summary="The session's state")
    def get_session(sid: str) -> dict[str, Any]:
        s = session_of(sid)
        with s.lock:
            return state_json(s)

    @app.delete(
        "/api/sessions/{sid}", tags=["sessions"], summary="End a session, cancelling its jobs"
    )
    def delete_session(sid: str) -> dict[str, Any]:
        session_of(sid)
        store.delete(sid)
        return {"deleted": sid}

    @app.put(
        "/api/sessions/{sid}/images/{slot}",
        tags=["inputs"],
        summary="Upload (or replace) picture A or B; settings are kept",
    )
    def put_image(
        sid: str, slot: str, file: Annotated[UploadFile | None, File()] = None
    ) -> dict[str, Any]:
        check_slot(slot)
        s = session_of(sid)
        field = f"image_{slot}"
        if file is None:
            raise AppRequestError(
                "no file in the upload (form field 'file')", field=field, code="missing"
            )
        data = file.file.read(cfg.max_upload_bytes + 1)
        if len(data) > cfg.max_upload_bytes:
            raise AppRequestError(
                f"the file is over {cfg.max_upload_bytes / 1e6:.0f} MB, the limit for pictures",
                field=field,
                code="too_large",
                status=413,
            )
        rgb = design.decode_upload(data, file.filename or "", field=field)
        with s.lock:
            s.images[slot] = UploadedImage(file.filename or f"{slot}.png", data, rgb)
            s.bump()
            return state_json(s)

    @app.get(
        "/api/sessions/{sid}/images/{slot}", tags=["inputs"], summary="The uploaded picture as sent"
    )
    def get_image(sid: str, slot: str) -> Response:
        check_slot(slot)
        s = session_of(sid)
        with s.lock:
            im = s.images.get(slot)
        if im is None:
            raise AppRequestError(
                f"no picture {slot.upper()} uploaded",
                field=f"image_{slot}",
                code="missing",
                status=404,
            )
        import mimetypes

        mime = mimetypes.guess_type(im.filename)[0] or "application/octet-stream"
        if not mime.startswith("image/"):
            return Response(
                design.png_bytes((im.rgb * 255).round().astype("uint8")), media_type="image/png"
            )
        return Response(im.data, media_type=mime)

    @app.delete("/api/sessions/{sid}/images/{slot}", tags=["inputs"], summary="Remove a picture")
    def delete_image(sid: str, slot: str) -> dict[str, Any]:
        check_slot(slot)
        s = session_of(sid)
        with s.lock:
            if s.images.pop(slot, None) is not None:
                s.bump()
            return state_json(s)

    @app.put("/api/sessions/{sid}/settings", tags=["inputs"], summary="Change design settings")
    def put_settings(sid: str, body: SettingsIn) -> dict[str, Any]:
        s = session_of(sid)
        changes = body.model_dump(exclude_none=True)
        if "yarns" in changes:
            from illuknit.pattern import parse_yarns

            with design.blame("yarns"):
                parse_yarns(changes["yarns"])
            changes["yarns"] = tuple(changes["yarns"])
        with s.lock:
            new = replace(s.settings, **changes)
            if new != s.settings:
                s.settings = new
                s.bump()
            return state_json(s)

    @app.get(
        "/api/sessions/{sid}/inputs",
        tags=["inputs"],
        summary="Quantise the pictures under the settings: sizes and legends",
    )
    def get_inputs(sid: str) -> dict[str, Any]:
        s = session_of(sid)
        with s.lock:
            p = prepared_of(s)
            rev = s.revision
        n, m = p.shape
        return {
            "revision": rev,
            "mode": p.mode,
            "rows": n,
            "cols": m,
            "yarns": [{"name": y.name, "rgb": y.hex} for y in p.yarns],
            "legend": p.legend(),
            "notes": list(p.notes),
            "images": {
                slot: f"/api/sessions/{sid}/inputs/{slot}.png?r={rev}" for slot in p.quantised
            },
        }

    @app.get(
        "/api/sessions/{sid}/inputs/{slot}.png", tags=["inputs"], summary="A quantised picture"
    )
    def get_input_png(sid: str, slot: str) -> Response:
        check_slot(slot)
        s = session_of(sid)
        p = prepared_of(s)
        if slot not in p.quantised:
            raise AppRequestError(
                f"no quantised picture {slot.upper()} in this mode",
                field=f"image_{slot}",
                code="missing",
                status=404,
            )
        return Response(
            design.png_bytes(p.quantised[slot].rgb()),
            media_type="image/png",
            headers={"Cache-Control": "no-store"},
        )

    # -- jobs ----------------------------------------------------------------------------------
    def start_candidates(s: Session) -> Job:
        prepared = prepared_of(s)
        count = s.settings.candidates
        rev = s.revision

        def work(job: Job) -> list[design.Candidate]:
            return design.make_candidates(prepared, count=count, progress=job.report)

        def done(job: Job) -> None:
            with s.lock:
                if s.revision == job.revision:
                    s.candidates = list(job.result)
                    s.candidates_revision = job.revision
                    s.selected = 1
                    s.overrides = {}
                    s.knit = None

        return runner.submit("candidates", work, revision=rev, on_done=done)

    def start_knit(s: Session) -> Job:
        design.require_part(
            "illuknit.knit",
            "knit_pattern",
            needs="knitout needs the knitout compiler (illuknit.knit)",
            field="knit",
        )
        pattern = current_pattern(s)
        key = design.pattern_key(pattern)
        doc = design.pattern_to_json(pattern)
        check = design.capabilities()["check"]

        def work(job: Job) -> design.KnitResult:
            job.report(0.05, "compiling knitout" + (" and checking it" if check else ""))
            if cfg.isolate_knit:
                out = job.run_isolated(design.knit_and_check, doc, check)
            else:
                out = design.knit_and_check(doc, check)
            return design.KnitResult(
                key=key,
                knitout=out["knitout"],
                stats=out["stats"],
                report=out["report"],
                report_text=out["report_text"],
            )

        def done(job: Job) -> None:
            with s.lock:
                s.knit = job.result

        return runner.submit("knit", work, revision=s.revision, on_done=done)

    @app.post(
        "/api/sessions/{sid}/jobs",
        tags=["jobs"],
        status_code=202,
        summary="Start a background job (candidates or knitout); replaces a live job of that kind",
    )
    def post_job(sid: str, body: JobIn) -> dict[str, Any]:
        s = session_of(sid)
        with s.lock:
            old = s.jobs.get(body.kind)
            if old is not None and old.live:
                old.cancel()
            job = start_candidates(s) if body.kind == "candidates" else start_knit(s)
            s.jobs[body.kind] = job
            return job.to_json()

    def job_of(s: Session, job_id: str) -> Job:
        # Only jobs of this session are visible in it: no peeking at another tab's work.
        for job in s.jobs.values():
            if job.id == job_id:
                return job
        raise AppRequestError(
            f"no job {job_id!r} in this session", field="job", code="no_job", status=404
        )

    @app.get("/api/sessions/{sid}/jobs/{job_id}", tags=["jobs"], summary="Poll a job's progress")
    def get_job(sid: str, job_id: str) -> dict[str, Any]:
        s = session_of(sid)
        with s.lock:
            return job_of(s, job_id).to_json()

    @app.delete("/api/sessions/{sid}/jobs/{job_id}", tags=["jobs"], summary="Cancel a job")
    def cancel_job(sid: str, job_id: str) -> dict[str, Any]:
        s = session_of(sid)
        with s.lock:
            job = job_of(s, job_id)
        job.cancel()
        job.wait(timeout=5)
        return job.to_json()

    # -- candidates, selection, tiles ----------------------------------------------------------
    @app.get("/api/sessions/{sid}/candidates", tags=["design"], summary="Ranked candidates")
    def get_candidates(sid: str) -> dict[str, Any]:
        s = session_of(sid)
        with s.lock:
            return {
                "revision": s.candidates_revision,
                "selected": s.selected if s.candidates else None,
                "candidates": [c.to_json() for c in s.candidates],
            }

    @app.put("/api/sessions/{sid}/selection", tags=["design"], summary="Pick a candidate")
    def put_selection(sid: str, body: SelectionIn) -> dict[str, Any]:
        s = session_of(sid)
        with s.lock:
            candidate_of(s, body.candidate)
            if body.candidate != s.selected:
                s.selected = body.candidate
                s.overrides = {}
                s.knit = None
            return state_json(s)

    @app.get(
        "/api/sessions/{sid}/pairs",
        tags=["design"],
        summary="Overlap pairs of the picked candidate, their tiles and the bank's alternatives",
    )
    def get_pairs(sid: str) -> dict[str, Any]:
        s = session_of(sid)
        with s.lock:
            cand = candidate_of(s, None)
            return design.pairs_json(cand, s.overrides)

    @app.put(
        "/api/sessions/{sid}/pairs/{a}/{b}",
        tags=["design"],
        summary="Use another tile for the overlap pair (a, b) of the picked candidate",
    )
    def put_pair(sid: str, a: int, b: int, body: OverrideIn) -> dict[str, Any]:
        s = session_of(sid)
        with s.lock:
            cand = candidate_of(s, None)
            overrides = dict(s.overrides)
            if body.tile is None:
                overrides.pop((a, b), None)
            else:
                overrides[(a, b)] = body.tile
            design.pattern_for(cand, overrides)  # validates before keeping it
            s.overrides = overrides
            s.knit = None
            return design.pairs_json(cand, s.overrides)

    @app.get(
        "/api/sessions/{sid}/tiles/{tile_id}.png", tags=["design"], summary="Picture of a bank tile"
    )
    def get_tile_png(sid: str, tile_id: str) -> Response:
        s = session_of(sid)
        with s.lock:
            cand = candidate_of(s, None)
        return Response(design.tile_png(tile_id, cand), media_type="image/png")

    @app.get(
        "/api/sessions/{sid}/tile.png",
        tags=["design"],
        summary="Picture of any tile: a bank number or rows such as 0/1^",
    )
    def get_any_tile_png(
        sid: str, tile: str = Query(..., description="bank tile number, or rows like 0/1^")
    ) -> Response:
        return get_tile_png(sid, tile)

    @app.get(
        "/api/sessions/{sid}/render",
        tags=["design"],
        summary="Render a candidate from one side or head-on at an angle (PNG, fast)",
    )
    def render(
        sid: str,
        view: Literal["A", "B", "headon"] = Query(
            "A", description="side A (above), side B (below) or head-on"
        ),
        angle: float = Query(30.0, gt=0, le=90, description="elevation of the eye in degrees"),
        candidate: int | None = Query(None, ge=1, description="rank; default: the picked one"),
    ) -> Response:
        s = session_of(sid)
        pattern = current_pattern(s, candidate)
        img = design.render_view(pattern, view, angle=angle)
        return Response(
            design.png_bytes(img), media_type="image/png", headers={"Cache-Control": "no-store"}
        )

    # -- downloads -----------------------------------------------------------------------------
    DOWNLOADS = (
        "pattern.json",
        "previews.zip",
        "chart.png",
        "instructions.txt",
        "knitout.k",
        "check.json",
        "check.txt",
        "pattern.dat",
    )

    @app.get(
        "/api/sessions/{sid}/download/{name}",
        tags=["downloads"],
        summary="Download the picked pattern, previews, chart, instructions, knitout, check report",
    )
    def download(sid: str, name: str, angle: float = Query(30.0, gt=0, le=90)) -> Response:
        s = session_of(sid)
        if name not in DOWNLOADS:
            raise AppRequestError(
                f"unknown download {name!r}; valid: {', '.join(DOWNLOADS)}",
                field="downloads",
                code="unknown",
                status=404,
            )
        if name == "pattern.dat":
            raise AppRequestError(
                "Shima .dat files are not available: illuknit writes knitout, and no working "
                "knitout-to-.dat converter is installable from PyPI today. Convert the knitout with "
                "the CMU textiles-lab knitout-backend-swg (knitout-to-dat.js).",
                field="knit",
                code="unavailable",
                status=501,
            )
        pattern = current_pattern(s)
        stem = f"illuknit-{pattern.shape[0]}x{pattern.shape[1]}"
        if name == "pattern.json":
            return _attachment(
                design.pattern_json_bytes(pattern), f"{stem}.json", "application/json"
            )
        if name == "previews.zip":
            with s.lock:
                prepared = s.prepared
            return _attachment(
                design.previews_zip(pattern, prepared, angle=angle),
                f"{stem}-previews.zip",
                "application/zip",
            )
        if name == "chart.png":
            return _attachment(design.chart_png(pattern), f"{stem}-chart.png", "image/png")
        if name == "instructions.txt":
            return _attachment(
                design.instructions_text(pattern).encode(),
                f"{stem}-instructions.txt",
                "text/plain; charset=utf-8",
            )
        with s.lock:
            knit = s.knit
        if knit is None or knit.key != design.pattern_key(pattern):
            raise AppRequestError(
                "make the knitout first (the picked pattern changed since)",
                field="knit",
                code="not_ready",
                status=409,
            )
        if name == "knitout.k":
            return _attachment(knit.knitout.encode(), f"{stem}.k", "text/plain; charset=utf-8")
        if knit.report is None:
            raise AppRequestError(
                "the knitout checker (illuknit.check) is not in this install",
                field="knit",
                code="unavailable",
                status=501,
            )
        if name == "check.json":
            import json

            return _attachment(
                json.dumps(knit.report, indent=1).encode(), f"{stem}-check.json", "application/json"
            )
        return _attachment(
            (knit.report_text or "").encode(), f"{stem}-check.txt", "text/plain; charset=utf-8"
        )

    @app.get(
        "/api/sessions/{sid}/knit",
        tags=["downloads"],
        summary="Knitout statistics and check summary",
    )
    def get_knit(sid: str) -> dict[str, Any]:
        s = session_of(sid)
        pattern = current_pattern(s)
        with s.lock:
            knit = s.knit
        if knit is None or knit.key != design.pattern_key(pattern):
            return {"ready": False}
        return {
            "ready": True,
            "stats": knit.stats,
            "report": knit.report,
            "lines": knit.knitout.count("\n"),
        }

    def _attachment(data: bytes, filename: str, media_type: str) -> Response:
        return Response(
            data,
            media_type=media_type,
            headers={
                "Content-Disposition": f'attachment; filename="{filename}"',
                "Cache-Control": "no-store",
            },
        )

    return app


def api_docs_html(spec: dict[str, Any]) -> str:
    """A self-contained HTML page listing the API from its OpenAPI document (no scripts, no CDN)."""
    from html import escape

    rows = []
    for path, ops in spec.get("paths", {}).items():
        for method, op in ops.items():
            params = ", ".join(
                f"<code>{escape(p['name'])}</code> ({escape(p.get('in', ''))})"
                + (f": {escape(p.get('description', ''))}" if p.get("description") else "")
                for p in op.get("parameters", [])
            )
            body = op.get("requestBody", {}).get("content", {})
            kinds = ", ".join(escape(k) for k in body)
            rows.append(
                f"<tr><td class=m>{escape(method.upper())}</td><td><code>{escape(path)}</code></td>"
                f"<td>{escape(op.get('summary', ''))}<div class=p>{params}"
                f"{' &middot; body: ' + kinds if kinds else ''}</div></td></tr>"
            )
    info = spec.get("info", {})
    return (
        "<!doctype html><html lang=en><head><meta charset=utf-8><title>illuknit API</title><style>"
        "body{font:14px system-ui,sans-serif;margin:24px;color:#1f2328}"
        "table{border-collapse:collapse;width:100%}td{border-top:1px solid #e4e7ec;padding:6px 8px;"
        "vertical-align:top}.m{font-weight:700;color:#0f766e}.p{color:#667085;font-size:12.5px}"
        "</style></head><body>"
        f"<h1>{escape(info.get('title', 'API'))} <small>{escape(info.get('version', ''))}</small></h1>"
        f"<p>{escape(info.get('description', ''))}</p>"
        "<p>Machine-readable: <a href=/openapi.json>/openapi.json</a> (OpenAPI "
        f"{escape(str(spec.get('openapi', '')))}).</p>"
        f"<table>{''.join(rows)}</table></body></html>"
    )
