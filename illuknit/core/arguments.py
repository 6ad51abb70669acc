"""Checks of the arguments of illuknit's public functions, done once at the entry point.

Each check names the parameter and says what was expected and what came, as scikit-image's
``check_nD`` does: "`steps` must be a whole number >= 1, got 'ten' (str)". Code behind an entry
point trusts what passed. Each raises the :mod:`illuknit.core.errors` class of its kind:
:class:`~illuknit.core.errors.OptionError` for options, :class:`~illuknit.core.errors.ImageInputError` for
pictures and targets, or the class a caller names. Patterns and yarns are checked by
:func:`illuknit.core.pattern.check_pattern` and :func:`illuknit.core.pattern.check_yarns`, beside their
classes.
"""

from __future__ import annotations

import math
import numbers
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any, TypeVar

import numpy as np
from numpy.typing import NDArray

from illuknit.core.errors import (
    IlluknitError,
    ImageInputError,
    OptionError,
)

__all__ = [
    "MAX_SECONDS",
    "MAX_SEED",
    "UNIT_ASPECT_RANGE",
    "check_array",
    "check_bool",
    "check_callable",
    "check_choice",
    "check_instance",
    "check_int",
    "check_mapping",
    "check_number",
    "check_path",
    "check_seconds",
    "check_seed",
    "check_str",
    "check_unit_aspect",
    "check_views",
    "got",
    "with_knobs",
]

T = TypeVar("T")

#: The longest time limit any call takes, in seconds (a week): longer is a slip of the keyboard.
MAX_SECONDS = 7 * 24 * 3600.0
#: A unit's height over its width, the smallest and largest any fabric has (a unit is 2 x 2
#: stitches; stocking stitch is about 0.7).
UNIT_ASPECT_RANGE = (0.05, 20.0)
#: The largest random seed: every backend takes it (CP-SAT's ``random_seed`` is a 32-bit int).
MAX_SEED = 2**31 - 1


def got(value: object) -> str:
    """``value`` as an error message shows it: short repr and type."""
    text = repr(value)
    if len(text) > 40:
        text = text[:37] + "..."
    return f"{text} ({type(value).__name__})"


def check_path(value: object, name: str) -> Path:
    """A file or folder path: ``str`` or ``os.PathLike`` (not empty)."""
    if isinstance(value, (str, os.PathLike)) and not isinstance(value, bytes):
        path = os.fspath(value)
        if isinstance(path, str) and path and "\x00" not in path:
            return Path(path)
    raise OptionError(f"`{name}` must be a path (str or os.PathLike), got {got(value)}")


def check_instance(
    value: object,
    cls: type[T] | tuple[type, ...],
    name: str,
    *,
    what: str | None = None,
    error: type[IlluknitError] = OptionError,
) -> T:
    """``value`` when it is an instance of ``cls``."""
    classes = cls if isinstance(cls, tuple) else (cls,)
    bool_ok = any(issubclass(bool, c) and c is not int for c in classes) or bool in classes
    if not isinstance(value, cls) or (isinstance(value, bool) and not bool_ok):
        if what is None:
            what = " or ".join(f"{_article(c.__name__)} {c.__name__}" for c in classes)
        raise error(f"`{name}` must be {what}, got {got(value)}")
    return value  # type: ignore[return-value]


def _article(word: str) -> str:
    return "an" if word[:1].lower() in "aeiou" else "a"


def check_bool(value: object, name: str) -> bool:
    """``True`` or ``False`` (a numpy bool too)."""
    if not isinstance(value, (bool, np.bool_)):
        raise OptionError(f"`{name}` must be True or False, got {got(value)}")
    return bool(value)


def check_int(
    value: object,
    name: str,
    *,
    min: int | None = None,
    max: int | None = None,
    error: type[IlluknitError] = OptionError,
) -> int:
    """A whole number (an ``int`` or a numpy integer) within [min, max].

    Floats are refused even when integral: callers keep using the value they were given, and
    ``0.0`` is not a seed numpy accepts.
    """
    ok = isinstance(value, numbers.Integral) and not isinstance(value, bool)
    if ok and (min is None or value >= min) and (max is None or value <= max):  # type: ignore[operator]
        return int(value)  # type: ignore[call-overload]
    bounds = _bounds(min, max)
    raise error(f"`{name}` must be a whole number{bounds}, got {got(value)}")


def check_number(
    value: object,
    name: str,
    *,
    min: float | None = None,
    max: float | None = None,
    min_open: bool = False,
    error: type[IlluknitError] = OptionError,
) -> float:
    """A finite real number within [min, max] (``(min, max]`` with ``min_open``)."""
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        v = float(value)
        if (
            math.isfinite(v)
            and (min is None or (v > min if min_open else v >= min))
            and (max is None or v <= max)
        ):
            return v
    bounds = _bounds(min, max, min_open=min_open)
    raise error(f"`{name}` must be a finite number{bounds}, got {got(value)}")


def _bounds(lo: float | None, hi: float | None, *, min_open: bool = False) -> str:
    if lo is not None and hi is not None:
        return f" in {'(' if min_open else '['}{lo:g}, {hi:g}]"
    if lo is not None:
        return f" {'>' if min_open else '>='} {lo:g}"
    if hi is not None:
        return f" <= {hi:g}"
    return ""


def check_seconds(
    value: object, name: str, *, optional: bool = True, error: type[IlluknitError] = OptionError
) -> float | None:
    """A time limit: positive finite seconds up to :data:`MAX_SECONDS` (``None``, no limit, when
    ``optional``)."""
    if value is None and optional:
        return None
    return check_number(value, name, min=0, max=MAX_SECONDS, min_open=True, error=error)


def check_seed(value: object, name: str = "seed") -> int:
    """A random seed: a whole number in [0, :data:`MAX_SEED`]."""
    return check_int(value, name, min=0, max=MAX_SEED)


def check_unit_aspect(value: object, name: str = "unit_aspect") -> float:
    """A unit's height over its width, within :data:`UNIT_ASPECT_RANGE`."""
    lo, hi = UNIT_ASPECT_RANGE
    return check_number(value, name, min=lo, max=hi)


def check_callable(value: object, name: str, *, optional: bool = True) -> Any:
    """A function (a progress callback, ...), or ``None`` when ``optional``."""
    if (value is None and optional) or callable(value):
        return value
    raise OptionError(
        f"`{name}` must be a function{' or None' if optional else ''}, got {got(value)}"
    )


def check_choice(
    value: object,
    name: str,
    choices: tuple[str, ...],
    *,
    error: type[IlluknitError] = OptionError,
) -> str:
    """One of the strings ``choices`` (checked as a string first: an array is not compared)."""
    if isinstance(value, str) and value in choices:
        return value
    raise error(f"`{name}` must be one of {', '.join(choices)}, got {got(value)}")


def check_str(value: object, name: str) -> str:
    if not isinstance(value, str):
        raise OptionError(f"`{name}` must be a string, got {got(value)}")
    return value


def check_views(
    value: object, name: str = "views", *, error: type[IlluknitError] = OptionError
) -> tuple[str, str]:
    """A pair of view names, e.g. ``("A", "B")``."""
    if (
        isinstance(value, (tuple, list))
        and len(value) == 2
        and all(isinstance(v, str) for v in value)
    ):
        return (value[0], value[1])
    raise error(f"`{name}` must be a pair of view names like ('A', 'B'), got {got(value)}")


def check_mapping(value: object, name: str) -> Mapping[Any, Any]:
    if not isinstance(value, Mapping):
        raise OptionError(f"`{name}` must be a mapping (a dict), got {got(value)}")
    return value


def check_array(
    value: object,
    name: str,
    *,
    ndim: int | tuple[int, ...] | None = None,
    integer: bool = False,
    what: str | None = None,
    error: type[IlluknitError] = ImageInputError,
) -> NDArray[Any]:
    """``value`` as a numeric ndarray of ``ndim`` dimensions, every entry finite (whole numbers
    with ``integer``); ``what`` describes what was expected in the message."""
    if what is None:
        dims = ndim if isinstance(ndim, tuple) else (() if ndim is None else (ndim,))
        what = f"a {' or '.join(f'{d}-D' for d in dims)}{' ' if dims else ''}array of "
        what += f"{'whole ' if integer else ''}numbers"
    if isinstance(value, (str, bytes, Mapping)) or value is None:
        raise error(f"`{name}` must be {what}, got {got(value)}")
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError) as exc:
        raise error(f"`{name}` must be {what}, got {got(value)}: {exc}") from None
    if arr.dtype == np.bool_:
        arr = arr.astype(np.uint8)
    if arr.dtype.kind not in "iuf":
        raise error(f"`{name}` must be {what}, got {got(value)} (dtype {arr.dtype})")
    wanted = (ndim,) if isinstance(ndim, int) else ndim
    if wanted is not None and arr.ndim not in wanted:
        raise error(f"`{name}` must be {what}, got shape {arr.shape}")
    if arr.size == 0:
        raise error(f"`{name}` must not be empty, got shape {arr.shape}")
    if arr.dtype.kind == "f":
        if not np.isfinite(arr).all():
            raise error(f"`{name}` must hold finite numbers, got NaN or infinity")
        if integer and not (arr == np.round(arr)).all():
            raise error(f"`{name}` must hold whole numbers (indices), got fractions")
    return arr


def with_knobs(
    cls: type[T], options: T | None, knobs: Mapping[str, Any], *, name: str = "options", what: str
) -> T:
    """``options`` (default ``cls()``, a frozen dataclass) with the shorthand ``knobs`` in place
    of its fields: the keywords a function takes beside its option object
    (``assign_tiles(qa, qb, candidates=3)``), validated once by ``cls``. ``options`` of another
    type, and a keyword that is no field of ``cls``, are refused with an
    :class:`~illuknit.core.errors.OptionError` naming them (``what`` says whose option it is
    not: "unknown {what} option 'x'; valid: ...")."""
    from dataclasses import fields, replace

    if options is not None and not isinstance(options, cls):
        kind = f"{_article(cls.__name__)} {cls.__name__}"
        raise OptionError(f"`{name}` must be {kind}, got {type(options).__name__}")
    names = [f.name for f in fields(cls)]  # type: ignore[arg-type]
    unknown = sorted(set(knobs) - set(names))
    if unknown:
        raise OptionError(f"unknown {what} option {unknown[0]!r}; valid: {', '.join(names)}")
    base = cls() if options is None else options
    return replace(base, **knobs) if knobs else base  # type: ignore[type-var]
