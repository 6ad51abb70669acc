"""The page and its files, the plain ``/docs`` page, and ``/api/info``."""

from pathlib import Path
from typing import Any

from fastapi import APIRouter, FastAPI, Request
from fastapi.responses import FileResponse, HTMLResponse
from fastapi.staticfiles import StaticFiles

from illuknit import __version__
from illuknit.app import design
from illuknit.app.knitting import machines_json
from illuknit.app.schemas import DesignSettings, choice_control
from illuknit.core.pattern import MAX_UNITS

__all__ = ["STATIC_DIR", "api_docs_html", "mount_static", "router"]

#: The page's files (one HTML page, its script and style sheet; no build step).
STATIC_DIR = Path(__file__).parent.parent / "static"

router = APIRouter()


def mount_static(app: FastAPI) -> None:
    """Serve the page's files under ``/static`` (a mount, which routers cannot carry)."""
    app.mount("/static", StaticFiles(directory=STATIC_DIR), name="static")


#: The ``/docs`` page's policy: no script at all, its one inline style sheet.
DOCS_POLICY = (
    "default-src 'none'; style-src 'unsafe-inline'; base-uri 'none'; form-action 'none'; "
    "frame-ancestors 'none'"
)


@router.get("/docs", include_in_schema=False)
def docs(request: Request) -> HTMLResponse:
    return HTMLResponse(
        api_docs_html(request.app.openapi()), headers={"Content-Security-Policy": DOCS_POLICY}
    )


@router.get("/", include_in_schema=False)
def index() -> FileResponse:
    return FileResponse(STATIC_DIR / "index.html", headers={"Cache-Control": "no-cache"})


@router.get(
    "/api/info", tags=["app"], summary="Version, installed capabilities, limits, yarn presets"
)
def info(request: Request) -> dict[str, Any]:
    cfg = request.app.state.config
    return {
        "version": __version__,
        "capabilities": design.capabilities(),
        "limits": {
            "max_upload_bytes": cfg.max_upload_bytes,
            # the words the server refuses a larger file with, for the page's own check
            "too_large": design.too_large_message(cfg.max_upload_bytes),
            "max_units": MAX_UNITS,
            "max_pixels": design.MAX_UPLOAD_PIXELS,
        },
        "presets": {k: list(v) for k, v in design.YARN_PRESETS.items()},
        "machines": machines_json(),
        "defaults": DesignSettings().to_json(),
        # menus generated from the declared options they set
        "controls": {"made_for": choice_control(DesignSettings, "made_for")},
        "storage": storage_json(request),
    }


def storage_json(request: Request) -> dict[str, Any]:
    """Where the sessions are kept and for how long (the page says it in one line)."""
    store = request.app.state.store
    disk = store.disk
    if disk is None:
        return {
            "kept": False,
            "text": "Work is kept in the server's memory only: stopping the app forgets it.",
            "sessions_in_memory": len(store),
        }
    return {
        "kept": True,
        "folder": str(disk.folder),
        "days": disk.retention.days,
        "max_bytes": disk.retention.max_bytes,
        "used_bytes": disk.used_bytes(),
        "sessions_in_memory": len(store),
        "sessions_saved": len(disk.ids()),
        "text": f"Your work is saved as you go in {disk.folder}: {disk.retention.describe()}.",
    }


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
