"""The design app's HTTP layer: one page and a JSON API (FastAPI; OpenAPI at ``/docs``).

All state lives in per-tab :class:`~illuknit.app.sessions.Session` objects addressed by the id in
the URL (``/api/sessions/{sid}/...``); the pipeline itself is :mod:`illuknit.app.design`; the
routes are one router per resource (:mod:`illuknit.app.routers`); every error answers one shape
(:mod:`illuknit.app.handlers`), so the page can put the message next to the control at fault::

    {"error": {"message": "...", "field": "image_b", "code": "size_mismatch"}}

Long work (candidate search, knitout compilation and checking) runs as a background job
(:mod:`illuknit.app.jobs`) that the page polls and can cancel. Uploads are capped in size before
they are read into memory (:class:`~illuknit.app.middleware.UploadLimit`).
"""

from __future__ import annotations

import importlib.util
import os
import sys
import threading
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from dataclasses import dataclass
from typing import Any

from illuknit import __version__
from illuknit.app import design
from illuknit.core.errors import BackendUnavailableError

__all__ = ["AppConfig", "create_app"]


@dataclass(frozen=True, kw_only=True)
class AppConfig:
    """Server limits. Defaults suit one designer on a laptop."""

    max_upload_bytes: int = design.MAX_UPLOAD_BYTES
    max_sessions: int = 64
    #: Memory all sessions together may hold (pictures, results); least recently used first out.
    max_session_bytes: int = 512 * 2**20
    session_ttl: float = 6 * 3600
    workers: int = 2
    isolate_knit: bool = True
    #: Run the tile search in its own process, killed by Cancel (a solve may take seconds and
    #: cannot be interrupted in-process); None (the default) follows ``isolate_knit``.
    isolate_search: bool | None = None
    #: Host names besides the bound address that may reach the app (e.g. the machine's name
    #: when it is shared on a network with ``--host 0.0.0.0``).
    allowed_hosts: tuple[str, ...] = ()
    #: Folder the sessions are kept in (``illuknit app`` uses
    #: :func:`~illuknit.app.store.default_data_dir` unless told ``--data-dir``); None keeps
    #: them in memory only (stopping the server forgets them).
    data_dir: str | os.PathLike[str] | None = None
    #: Retention of the folder: sessions unused for ``keep_days`` are deleted, and the least
    #: recently used when all together pass ``keep_bytes``.
    keep_days: float = 30.0
    keep_bytes: int = 2 * 2**30

    def __post_init__(self) -> None:
        if self.isolate_search is None:
            object.__setattr__(self, "isolate_search", self.isolate_knit)


def _require_web_stack() -> None:
    """One clear error when the optional web extra is not installed (probed, never caught)."""
    for module in ("fastapi", "uvicorn", "multipart"):
        if importlib.util.find_spec(module) is None:
            raise BackendUnavailableError(
                f"the app needs FastAPI, uvicorn and python-multipart ({module} is missing): "
                "pip install 'illuknit[app]'"
            )


def create_app(config: AppConfig | None = None) -> Any:
    """Build the FastAPI application (import-light: FastAPI is imported here, not at module load)."""
    _require_web_stack()
    from fastapi import FastAPI

    from illuknit.app.handlers import install_handlers
    from illuknit.app.jobs import JobRunner
    from illuknit.app.middleware import SameOriginGuard, SecurityHeaders, UploadLimit
    from illuknit.app.routers import ROUTERS
    from illuknit.app.routers.static import mount_static
    from illuknit.app.sessions import SessionStore

    cfg = config or AppConfig()
    disk = None
    if cfg.data_dir is not None:
        from illuknit.app.store import DiskStore, Retention

        disk = DiskStore(cfg.data_dir, Retention(days=cfg.keep_days, max_bytes=cfg.keep_bytes))
        disk.enforce(force=True)
    store = SessionStore(
        max_sessions=cfg.max_sessions,
        ttl=cfg.session_ttl,
        max_bytes=cfg.max_session_bytes,
        disk=disk,
    )
    runner = JobRunner(workers=cfg.workers)

    @asynccontextmanager
    async def lifespan(app: Any) -> AsyncIterator[None]:
        # Import the heavy parts of the pipeline in the background at start-up, so the designer's
        # first upload is not the one that waits for scikit-image, SciPy and the solvers to load.
        threading.Thread(target=design.warm_up, name="illuknit-warm-up", daemon=True).start()
        yield
        problem = store.close()  # first: jobs the stop cuts short are stored as interrupted
        runner.shutdown()
        if problem is not None:
            print(f"illuknit app: {problem}", file=sys.stderr, flush=True)

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
    # added last, so it runs first: a foreign request is refused before its body is read
    app.add_middleware(SameOriginGuard, allowed_hosts=cfg.allowed_hosts)
    # outermost: every answer, the refusals of the guards above included, carries the headers
    app.add_middleware(SecurityHeaders)
    install_handlers(app)
    for router in ROUTERS:
        app.include_router(router)
    mount_static(app)
    return app
