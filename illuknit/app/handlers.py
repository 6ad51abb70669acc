"""Every error the app answers, in one shape, in words written for a designer.

    {"error": {"message": "...", "field": "width_units", "code": "invalid"}}

``field`` names the page control at fault, so the page shows the message next to it. Request
validation errors (pydantic's) are reworded from the field's title and bounds: "Width can be at
most 1000", never "width_units: Input should be less than or equal to 1000".
"""

from __future__ import annotations

from typing import Any

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from starlette.exceptions import HTTPException as StarletteHTTPException

from illuknit.app.schemas import DesignSettings, JobIn, OverrideIn, SelectionIn
from illuknit.app.suggestions import SupersededError
from illuknit.core.errors import AppRequestError, IlluknitError

__all__ = ["designer_message", "error_body", "install_handlers"]

#: Titles of every field a request can carry, for messages (query parameters included).
TITLES: dict[str, str] = {
    "angle": "Viewing angle",
    "view": "View",
    "order": "Order",
    "file": "Picture",
    **{
        key: info.title or key
        for model in (DesignSettings, JobIn, SelectionIn, OverrideIn)
        for key, info in model.model_fields.items()
    },
}


#: Units said after a bound ("Width can be at most 1000 units").
UNITS: dict[str, str] = {
    "width_units": " units",
    "width_cm": " cm",
    "gauge": " stitches per inch",
    "angle": " degrees",
}


def error_body(message: str, field: str | None, code: str) -> dict[str, Any]:
    return {"error": {"message": message, "field": field, "code": code}}


def _expected_choices(ctx: dict[str, Any]) -> str:
    return str(ctx.get("expected", "")).replace("'", "").replace(" or ", ", ")


def designer_message(err: dict[str, Any]) -> tuple[str, str | None]:
    """One pydantic error as (a sentence for a designer, the field it is about)."""
    loc = [p for p in err.get("loc", ()) if p not in ("body", "query", "path")]
    kind = str(err.get("type", ""))
    ctx = err.get("ctx") or {}
    if kind == "json_invalid":
        return "the request is not valid JSON (the page sends JSON; check a script's body)", None
    name = next((str(p) for p in loc if isinstance(p, str)), None)
    if name is None:
        if kind in ("model_attributes_type", "dict_type", "model_type"):
            return "the request body must be a JSON object of settings", None
        return f"the request is invalid: {err.get('msg', 'bad value')}", None
    title = TITLES.get(name, name.replace("_", " "))
    unit = UNITS.get(name, "")

    def bound(key: str) -> str:
        v = ctx.get(key)
        return (f"{v:g}" if isinstance(v, float) else str(v)) + unit

    value = err.get("input")
    shown = repr(value) if not isinstance(value, (dict, list)) else "this value"
    sentences = {
        "less_than_equal": f"{title} can be at most {bound('le')}",
        "less_than": f"{title} must be less than {bound('lt')}",
        "greater_than_equal": f"{title} must be at least {bound('ge')}",
        "greater_than": f"{title} must be more than {bound('gt')}",
        "int_parsing": f"{title} must be a whole number, not {shown}",
        "int_from_float": f"{title} must be a whole number, not {shown}",
        "int_type": f"{title} must be a whole number, not {shown}",
        "float_parsing": f"{title} must be a number, not {shown}",
        "float_type": f"{title} must be a number, not {shown}",
        "finite_number": f"{title} must be a finite number",
        "bool_parsing": f"{title} must be on or off (true or false)",
        "bool_type": f"{title} must be on or off (true or false)",
        "literal_error": f"{title} must be one of: {_expected_choices(ctx)}; not {shown}",
        "enum": f"{title} must be one of: {_expected_choices(ctx)}; not {shown}",
        "too_short": f"choose at least {ctx.get('min_length')} {title.lower()}",
        "too_long": f"choose at most {ctx.get('max_length')} {title.lower()}",
        "missing": f"{title} is missing",
        "extra_forbidden": f"{name!r} is not a setting; the settings are "
        + ", ".join(DesignSettings.model_fields),
        "string_type": f"{title} must be text",
        "value_error": str(ctx.get("error", err.get("msg", "invalid value"))),
        "list_type": f"{title} must be a list",
        "tuple_type": f"{title} must be a list",
    }
    return sentences.get(kind, f"{title}: {err.get('msg', 'invalid value')}"), name


def install_handlers(app: FastAPI) -> None:
    """Answer every error of ``app`` as :func:`error_body`, never as HTML or a traceback."""

    @app.exception_handler(AppRequestError)
    async def _app_error(request: Request, exc: AppRequestError) -> JSONResponse:
        body = error_body(str(exc), exc.field, exc.code)
        if isinstance(exc, SupersededError):  # where the replaced thing's successor is
            body["error"]["successor"] = exc.successor
        return JSONResponse(body, status_code=exc.status)

    @app.exception_handler(IlluknitError)
    async def _lib_error(request: Request, exc: IlluknitError) -> JSONResponse:
        return JSONResponse(error_body(str(exc), None, type(exc).__name__), status_code=422)

    @app.exception_handler(RequestValidationError)
    async def _validation_error(request: Request, exc: RequestValidationError) -> JSONResponse:
        errs = list(exc.errors())
        message, field = designer_message(errs[0] if errs else {})
        if len(errs) > 1:
            message += f" (and {len(errs) - 1} more problem{'s' if len(errs) > 2 else ''})"
        return JSONResponse(error_body(message, field, "invalid"), status_code=422)

    @app.exception_handler(StarletteHTTPException)
    async def _http_error(request: Request, exc: StarletteHTTPException) -> JSONResponse:
        return JSONResponse(
            error_body(str(exc.detail), None, f"http_{exc.status_code}"),
            status_code=exc.status_code,
        )

    @app.exception_handler(Exception)
    async def _bug(request: Request, exc: Exception) -> JSONResponse:
        # Starlette raises the exception again once this answer is sent, for the server to log
        # its traceback, and the server then closes the connection: say so, or a client that
        # keeps connections alive sends its next request into the closed one
        return JSONResponse(
            error_body(f"internal error: {type(exc).__name__}: {exc}", None, "internal"),
            status_code=500,
            headers={"connection": "close"},
        )
