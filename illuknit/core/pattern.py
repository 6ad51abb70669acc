"""The logical illusion pattern (paper section 4.2) and its JSON file format.

A :class:`LogicalPattern` is an N x M grid of *units*. Each unit has a yarn index into the pattern's
palette and a *raised* flag (a bump that occludes the next unit along the wale, seen from an
angle). One unit becomes a 2 x 2 block of stitches when lowered for knitting.

A raised unit may be a *split bump*: its two courses are knitted in two yarns, ``yarn`` for the
first course in machine order (the one nearer the bottom edge) and ``upper`` for the second (nearer
the top edge). Which view sees which course is described in :mod:`illuknit.core.views` and
``docs/split-bumps.md``. A pattern without split bumps has ``upper is None``.

Orientation, used everywhere in illuknit (see the README figure):

* arrays are indexed ``[row, col]`` in *picture order*: row 0 is the top edge of the piece as it
  hangs, column 0 its left edge seen from the technical face;
* view A is seen from above (looking down the wales from the top edge), view B from below;
  both come out upright, in the same ``[row, col]`` order as the pattern and the target images;
* the machine knits from the bottom edge up: course 0 is pattern row N-1.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.arguments import check_mapping, check_path, got
from illuknit.core.colors import luminance, parse_color
from illuknit.core.errors import PatternFormatError, PatternValidationError, YarnSpecError
from illuknit.core.files import atomic_write_text
from illuknit.core.yarns import (
    JUST_NOTICEABLE_DE,
    MAX_YARN_NAME,
    Yarn,
    YarnNote,
    _has_controls,
    _note,
    check_yarns,
    clean_yarn_name,
    parse_yarns,
    yarn_notes,
)

__all__ = [
    "FORMAT_NAME",
    "FORMAT_VERSION",
    "JUST_NOTICEABLE_DE",
    "MAX_UNITS",
    "MAX_YARNS",
    "MAX_YARN_NAME",
    "SPLIT_FORMAT_VERSION",
    "LogicalPattern",
    "Yarn",
    "YarnNote",
    "check_pattern",
    "check_yarns",
    "clean_yarn_name",
    "load_pattern",
    "parse_yarns",
    "pattern_from_json",
    "pattern_to_json",
    "save_pattern",
    "yarn_notes",
]

FORMAT_NAME = "illuknit-pattern"
FORMAT_VERSION = 1
#: The version written when a pattern has split bumps (the ``upper`` rows); version 1 readers
#: would drop them silently, so such a file says it needs a newer reader.
SPLIT_FORMAT_VERSION = 2
_READ_VERSIONS = (FORMAT_VERSION, SPLIT_FORMAT_VERSION)
#: Yarn indices are written as one base-36 digit per unit.
MAX_YARNS = 36
#: No knitting bed is wider than this many units (2000 needles); also a sanity cap on height.
MAX_UNITS = 1000
_DIGITS = "0123456789abcdefghijklmnopqrstuvwxyz"


def check_pattern(value: object, name: str = "pattern") -> LogicalPattern:
    """``value`` when it is a :class:`LogicalPattern`, else :class:`PatternValidationError`
    naming the parameter."""
    if not isinstance(value, LogicalPattern):
        raise PatternValidationError(f"`{name}` must be a LogicalPattern, got {got(value)}")
    return value


def _readonly(a: NDArray[Any]) -> NDArray[Any]:
    a = np.array(a, copy=True)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class LogicalPattern:
    """An N x M logical illusion pattern.

    Parameters
    ----------
    yarn : ndarray of shape (N, M), integer
        Yarn index of each unit, into ``yarns``.
    raised : ndarray of shape (N, M), bool
        True where the unit is a bump (a knit with a purl child), False where it is flat.
    yarns : sequence of Yarn
        The palette; at least one yarn, all colours distinct.
    meta : mapping, optional
        JSON-serialisable provenance (which compiler or solver made it, with what settings).
    upper : ndarray of shape (N, M), integer, optional
        Split bumps: the yarn of each unit's second course in machine order (the course nearer
        the top edge as the piece hangs); the first course is ``yarn``. Flat units must have
        ``upper == yarn``; a raised unit with ``upper != yarn`` is a split bump. ``None`` (the
        default) means no split bumps anywhere, and an ``upper`` equal to ``yarn`` everywhere is
        stored as ``None``, so ``upper is None`` exactly when the pattern has no split bump.

    Examples
    --------
    >>> p = LogicalPattern(np.zeros((2, 3), int), np.zeros((2, 3), bool), (Yarn("white", (255, 255, 255)),))
    >>> p.shape
    (2, 3)
    """

    yarn: NDArray[np.int16]
    raised: NDArray[np.bool_]
    yarns: tuple[Yarn, ...]
    meta: Mapping[str, Any] = field(default_factory=dict)
    upper: NDArray[np.int16] | None = None

    def __post_init__(self) -> None:
        yarn = np.asarray(self.yarn)
        raised = np.asarray(self.raised)
        if yarn.ndim != 2:
            raise PatternValidationError(f"`yarn` must be 2-D (N, M), got shape {yarn.shape}")
        if raised.shape != yarn.shape:
            raise PatternValidationError(
                f"`raised` must have the shape of `yarn` {yarn.shape}, got {raised.shape}"
            )
        if yarn.size == 0:
            raise PatternValidationError(
                f"pattern must have at least one unit, got shape {yarn.shape}"
            )
        if max(yarn.shape) > MAX_UNITS:
            raise PatternValidationError(
                f"pattern of {yarn.shape[0]} x {yarn.shape[1]} units exceeds the {MAX_UNITS}-unit limit"
            )
        if not np.issubdtype(yarn.dtype, np.integer):
            if np.issubdtype(yarn.dtype, np.floating) and np.all(np.mod(yarn, 1) == 0):
                yarn = yarn.astype(np.int64)
            else:
                raise PatternValidationError(f"`yarn` must hold integers, got dtype {yarn.dtype}")
        if raised.dtype != np.bool_:
            if not np.all(np.isin(raised, (0, 1))):
                raise PatternValidationError("`raised` must hold booleans (or 0/1)")
            raised = raised.astype(bool)
        if isinstance(self.yarns, (str, bytes)) or not isinstance(self.yarns, Sequence):
            raise PatternValidationError(
                f"`yarns` must be a non-empty sequence of Yarn, got {type(self.yarns).__name__}"
            )
        yarns = tuple(self.yarns)
        if not yarns or not all(isinstance(y, Yarn) for y in yarns):
            raise PatternValidationError("`yarns` must be a non-empty sequence of Yarn")
        if len(yarns) > MAX_YARNS:
            raise PatternValidationError(f"at most {MAX_YARNS} yarns, got {len(yarns)}")
        if len({y.rgb for y in yarns}) != len(yarns):
            raise PatternValidationError("`yarns` must have distinct colours")
        lo, hi = int(yarn.min()), int(yarn.max())
        if lo < 0 or hi >= len(yarns):
            raise PatternValidationError(
                f"yarn indices must lie in 0..{len(yarns) - 1}, got values in {lo}..{hi}"
            )
        object.__setattr__(self, "yarn", _readonly(yarn.astype(np.int16)))
        object.__setattr__(self, "raised", _readonly(raised))
        object.__setattr__(self, "yarns", yarns)
        check_mapping(self.meta, "meta")
        object.__setattr__(self, "meta", MappingProxyType(dict(self.meta)))
        object.__setattr__(self, "upper", _check_upper(self.upper, self.yarn, raised, len(yarns)))

    # -- convenience -------------------------------------------------------------------------
    @property
    def shape(self) -> tuple[int, int]:
        """(rows N, columns M) in units."""
        return (int(self.yarn.shape[0]), int(self.yarn.shape[1]))

    @property
    def palette(self) -> NDArray[np.uint8]:
        """ndarray of shape (K, 3): the yarns' sRGB colours."""
        return np.array([y.rgb for y in self.yarns], dtype=np.uint8)

    @property
    def brightness(self) -> NDArray[np.float64]:
        """ndarray of shape (K,): relative luminance of each yarn."""
        return luminance(self.palette)

    @property
    def upper_yarn(self) -> NDArray[np.int16]:
        """ndarray of shape (N, M): the yarn of every unit's second course (``upper``, or
        ``yarn`` when the pattern has no split bumps)."""
        return self.yarn if self.upper is None else self.upper

    @property
    def split(self) -> NDArray[np.bool_]:
        """ndarray of shape (N, M), bool: True at the split bumps (raised, two yarns)."""
        if self.upper is None:
            return np.zeros(self.yarn.shape, dtype=bool)
        return self.raised & (self.upper != self.yarn)

    def rgb(self, indices: ArrayLike | None = None) -> NDArray[np.uint8]:
        """Colour an index image (default: the head-on yarn grid) with the palette."""
        idx = self.yarn if indices is None else np.asarray(indices)
        return self.palette[idx]

    def replace(self, **changes: Any) -> LogicalPattern:
        """A copy with some fields replaced (the pattern itself is immutable)."""
        kw: dict[str, Any] = {
            "yarn": self.yarn,
            "raised": self.raised,
            "yarns": self.yarns,
            "meta": dict(self.meta),
            "upper": self.upper,
        }
        kw.update(changes)
        return LogicalPattern(**kw)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, LogicalPattern):
            return NotImplemented
        return (
            self.yarns == other.yarns
            and np.array_equal(self.yarn, other.yarn)
            and np.array_equal(self.raised, other.raised)
            and np.array_equal(self.upper_yarn, other.upper_yarn)
            and dict(self.meta) == dict(other.meta)
        )

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        n, m = self.shape
        names = ", ".join(y.name for y in self.yarns)
        split = "" if self.upper is None else f", split={int(self.split.sum())}"
        return (
            f"LogicalPattern({n}x{m} units, yarns=[{names}], raised={int(self.raised.sum())}"
            f"{split})"
        )


def _check_upper(
    upper: ArrayLike | None, yarn: NDArray[np.int16], raised: NDArray[np.bool_], k: int
) -> NDArray[np.int16] | None:
    """``upper`` validated and read-only, or None when it is None or equals ``yarn``."""
    if upper is None:
        return None
    u = np.asarray(upper)
    if u.shape != yarn.shape:
        raise PatternValidationError(
            f"`upper` must have the shape of `yarn` {yarn.shape}, got {u.shape}"
        )
    if not np.issubdtype(u.dtype, np.integer):
        if np.issubdtype(u.dtype, np.floating) and np.all(np.mod(u, 1) == 0):
            u = u.astype(np.int64)
        else:
            raise PatternValidationError(f"`upper` must hold integers, got dtype {u.dtype}")
    lo, hi = int(u.min()), int(u.max())
    if lo < 0 or hi >= k:
        raise PatternValidationError(
            f"`upper` yarn indices must lie in 0..{k - 1}, got values in {lo}..{hi}"
        )
    flat_split = ~raised & (u != yarn)
    if flat_split.any():
        r, c = (int(v) for v in np.argwhere(flat_split)[0])
        raise PatternValidationError(
            f"`upper` differs from `yarn` at {int(flat_split.sum())} flat unit(s) (first at row "
            f"{r}, column {c}): only a raised unit can be a split bump"
        )
    if np.array_equal(u, yarn):
        return None
    return _readonly(u.astype(np.int16))


# -- JSON format ------------------------------------------------------------------------------


def pattern_to_json(pattern: LogicalPattern) -> dict[str, Any]:
    """The pattern as a JSON-ready dict (format ``illuknit-pattern`` version 1).

    Layout::

        {"format": "illuknit-pattern", "version": 1, "rows": N, "cols": M,
         "yarns": [{"name": "black", "rgb": "#1b1b1b"}, ...],
         "yarn":   ["0101...", ...],   # N strings of M base-36 digits (yarn index per unit)
         "raised": ["0010...", ...],   # N strings of M '0'/'1'
         "meta": {...}}

    Rows are in picture order (row 0 = top edge as the piece hangs). A pattern with split bumps
    is written as version 2 with one more key, ``"upper"`` (N strings of base-36 digits: the yarn
    of each unit's second course), placed after ``"raised"``; a pattern without them is written
    exactly as before.
    """
    n, m = pattern.shape
    digits = np.array(list(_DIGITS))
    doc: dict[str, Any] = {
        "format": FORMAT_NAME,
        "version": FORMAT_VERSION if pattern.upper is None else SPLIT_FORMAT_VERSION,
        "rows": n,
        "cols": m,
        "yarns": [{"name": y.name, "rgb": y.hex} for y in pattern.yarns],
        "yarn": ["".join(row) for row in digits[pattern.yarn]],
        "raised": ["".join(row) for row in np.where(pattern.raised, "1", "0")],
    }
    if pattern.upper is not None:
        doc["upper"] = ["".join(row) for row in digits[pattern.upper]]
    doc["meta"] = dict(pattern.meta)
    return doc


def pattern_from_json(doc: Any) -> LogicalPattern:
    """Inverse of :func:`pattern_to_json`; raises :class:`PatternFormatError` on any problem."""
    if not isinstance(doc, dict):
        raise PatternFormatError("pattern file must hold a JSON object")
    if doc.get("format") != FORMAT_NAME:
        raise PatternFormatError(f"not an illuknit pattern (format is {doc.get('format')!r})")
    version = doc.get("version")
    if isinstance(version, bool) or version not in _READ_VERSIONS:
        raise PatternFormatError(
            f"pattern format version {version!r} is not supported (this illuknit reads versions "
            f"{FORMAT_VERSION} and {SPLIT_FORMAT_VERSION})"
        )
    if "upper" in doc and version == FORMAT_VERSION:
        raise PatternFormatError(
            f"malformed pattern file: `upper` (split bumps) needs version {SPLIT_FORMAT_VERSION}"
        )
    for key in ("rows", "cols"):
        v = doc.get(key)
        if isinstance(v, bool) or not isinstance(v, int) or not 1 <= v <= MAX_UNITS:
            raise PatternFormatError(
                f"malformed pattern file: `{key}` must be a whole number from 1 to {MAX_UNITS}, "
                f"got {v!r}"
            )
    try:
        n, m = int(doc["rows"]), int(doc["cols"])
        yarns = tuple(Yarn(str(y["name"]), parse_color(str(y["rgb"]))) for y in doc["yarns"])
        for y in doc["yarns"]:
            if _has_controls(str(y["name"])):
                _note(f"control characters removed from the yarn name {str(y['name'])!r}")
        rows_y, rows_r = list(doc["yarn"]), list(doc["raised"])
        meta = doc.get("meta", {})
    except (KeyError, TypeError, ValueError) as e:
        raise PatternFormatError(f"malformed pattern file: {e}") from None
    if len(rows_y) != n or len(rows_r) != n:
        raise PatternFormatError(
            f"pattern declares {n} rows but holds {len(rows_y)} / {len(rows_r)}"
        )
    yarn = np.empty((n, m), dtype=np.int16)
    raised = np.empty((n, m), dtype=bool)
    for i, (ry, rr) in enumerate(zip(rows_y, rows_r, strict=True)):
        if not isinstance(ry, str) or not isinstance(rr, str) or len(ry) != m or len(rr) != m:
            raise PatternFormatError(f"row {i}: expected two strings of {m} characters")
        yarn[i] = _digit_row(ry, i, "yarn")
        if set(rr) - {"0", "1"}:
            raise PatternFormatError(f"row {i}: raised flags must be '0' or '1'")
        raised[i] = np.frombuffer(rr.encode(), dtype=np.uint8) == ord("1")
    upper = _upper_rows(doc.get("upper"), n, m)
    if not isinstance(meta, dict):
        raise PatternFormatError("`meta` must be a JSON object")
    for what, arr in (("yarn", yarn), ("upper", upper)):
        if arr is not None and arr.size and int(arr.max()) >= len(yarns):
            raise PatternFormatError(
                f"{what} index {int(arr.max())} is out of range: the palette has "
                f"{len(yarns)} yarn(s)"
            )
    try:
        return LogicalPattern(yarn, raised, yarns, meta, upper=upper)
    except (PatternValidationError, YarnSpecError) as e:
        raise PatternFormatError(f"invalid pattern: {e}") from None


_LOOKUP = np.full(128, -1, dtype=np.int16)
for _i, _ch in enumerate(_DIGITS):
    _LOOKUP[ord(_ch)] = _i


def _digit_row(text: str, i: int, what: str) -> NDArray[np.int16]:
    codes = np.frombuffer(text.lower().encode("ascii", "replace"), dtype=np.uint8)
    vals = _LOOKUP[np.minimum(codes, 127)]
    if (vals < 0).any():
        raise PatternFormatError(f"row {i}: {what} digits must be 0-9 or a-z")
    return vals


def _upper_rows(rows: Any, n: int, m: int) -> NDArray[np.int16] | None:
    """The ``upper`` rows of a pattern file as an array, None when the key is absent."""
    if rows is None:
        return None
    if not isinstance(rows, list) or len(rows) != n:
        raise PatternFormatError(f"malformed pattern file: `upper` must be a list of {n} strings")
    upper = np.empty((n, m), dtype=np.int16)
    for i, ru in enumerate(rows):
        if not isinstance(ru, str) or len(ru) != m:
            raise PatternFormatError(f"row {i}: `upper` must be a string of {m} characters")
        upper[i] = _digit_row(ru, i, "upper")
    return upper


def save_pattern(pattern: LogicalPattern, path: str | os.PathLike[str]) -> None:
    """Write a pattern as JSON (atomically)."""
    check_pattern(pattern)
    check_path(path, "path")
    atomic_write_text(path, json.dumps(pattern_to_json(pattern), indent=1) + "\n")


def load_pattern(path: str | os.PathLike[str]) -> LogicalPattern:
    """Read a pattern written by :func:`save_pattern`.

    Raises :class:`PatternFormatError` for a missing, unreadable, malformed or other-version file.
    """
    check_path(path, "path")
    from illuknit.core.documents import read_json_file

    return pattern_from_json(read_json_file(path, error=PatternFormatError, what="pattern"))
