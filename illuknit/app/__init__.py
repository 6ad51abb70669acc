"""The designer-in-the-loop web app (paper section 6.3, Fig. 9): ``illuknit app``.

A local FastAPI server with one hand-written page (no build step, no CDN: everything is served from
this package) and a JSON API over the library, documented by OpenAPI at ``/docs``.

* :mod:`illuknit.app.design` -- the pipeline the page drives (pure functions over the library),
  the front door of :mod:`~illuknit.app.inputs`, :mod:`~illuknit.app.candidates`,
  :mod:`~illuknit.app.tile_edits` and :mod:`~illuknit.app.exports`;
* :mod:`illuknit.app.schemas` -- the settings and request models (pydantic), written once;
* :mod:`illuknit.app.sessions` -- per-tab sessions, so two tabs never share state;
* :mod:`illuknit.app.jobs` -- cancellable background jobs with progress;
* :mod:`illuknit.app.server` -- the HTTP layer (:func:`create_app`), assembled from
  :mod:`illuknit.app.routers` (one router per resource), :mod:`illuknit.app.lookups`,
  :mod:`illuknit.app.handlers` (errors) and :mod:`illuknit.app.middleware`.

FastAPI and uvicorn are an optional extra: ``pip install 'illuknit[app]'``.
"""

from __future__ import annotations

from typing import Any

__all__ = ["create_app"]


def create_app(config: Any = None) -> Any:
    """Build the app's ASGI application (see :func:`illuknit.app.server.create_app`)."""
    from illuknit.app.server import create_app as _create

    return _create(config)
