"""The app's HTTP routes, one router per resource.

* :mod:`~illuknit.app.routers.static` -- the page, its files, ``/docs`` and ``/api/info``;
* :mod:`~illuknit.app.routers.sessions` -- start, read and end a session; change its settings;
* :mod:`~illuknit.app.routers.pictures` -- upload pictures and see them quantised;
* :mod:`~illuknit.app.routers.jobs` -- background jobs (candidates, knitout) with progress;
* :mod:`~illuknit.app.routers.designs` -- candidates, the pick, tile edits and renders;
* :mod:`~illuknit.app.routers.suggestions` -- suggested edits of the pictures, accepted or refused;
* :mod:`~illuknit.app.routers.history` -- undo and redo of accepted edits;
* :mod:`~illuknit.app.routers.downloads` -- the files a designer takes away;
* :mod:`~illuknit.app.routers.tracker` -- the row tracker for the knitter at the needles.
"""

from __future__ import annotations

from illuknit.app.routers import (
    designs,
    downloads,
    history,
    jobs,
    pictures,
    sessions,
    static,
    suggestions,
    tracker,
)

__all__ = ["ROUTERS"]

#: Every router, in the order the OpenAPI document lists them.
ROUTERS = (
    static.router,
    sessions.router,
    pictures.router,
    jobs.router,
    designs.router,
    suggestions.router,
    history.router,
    downloads.router,
    tracker.router,
)
