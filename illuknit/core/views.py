"""can_see: which unit a viewer sees, in the boolean model of paper sections 4.2 and 5.

Arrays are in picture order (row 0 = top edge as the piece hangs; see :mod:`illuknit.core.pattern`).

* **View A** is seen from above, looking down the wales from the top edge. Row ``i-1`` lies between
  the viewer and row ``i``, so a raised unit hides the unit below it::

      VA[0] = C[0];   VA[i] = C[i-1] if R[i-1] else C[i]

* **View B** is seen from below, looking up the wales from the bottom edge::

      VB[N-1] = C[N-1];   VB[i] = C[i+1] if R[i+1] else C[i]

* **Head-on**, every unit is seen: ``VH = C``.

Each wale (column) is independent. All functions are vectorised over the whole grid.

**Split bumps** (``LogicalPattern.upper``, ``docs/split-bumps.md``). A raised unit is a knit
course followed, in machine order, by a purl course; a split bump knits them in two yarns, ``C``
(first course, nearer the bottom edge) and ``U`` (second course, nearer the top edge). Each side of
the bump is made mostly of the course on that side: view A, looking from the top edge, sees
mostly ``U``, view B mostly ``C`` (the renderer mixes in the other course with weight
``1 - split_share``, :class:`illuknit.design.render.params.RenderParams`). In the logical model each
view sees the dominant course, and since ``U == C`` on flat units the equations stay those above
with ``U`` in view A::

    VA[0] = U[0];   VA[i] = U[i-1] if R[i-1] else U[i]
    VB[N-1] = C[N-1];   VB[i] = C[i+1] if R[i+1] else C[i]
    VH = C          (head-on both courses show alike; the first one is named)

Without split bumps ``U == C`` everywhere and nothing changes.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.arguments import check_array, check_bool, check_choice
from illuknit.core.errors import ImageInputError, OptionError, PatternValidationError
from illuknit.core.pattern import LogicalPattern

__all__ = [
    "DEFAULT_SPLIT_SHARE",
    "VIEWS",
    "View",
    "can_see",
    "logical_error",
    "seen_courses",
    "seen_rows",
    "view_a",
    "view_b",
    "view_headon",
    "views",
]

View = Literal["A", "B", "headon"]
VIEWS: tuple[View, ...] = ("A", "B", "headon")
#: Share of a split bump's colour, seen from one side, that comes from the course on that side:
#: the cuboid estimate (``docs/split-bumps.md``) until a swatch is measured. The renderer's
#: ``RenderParams.split_share`` and the tile fills of split bumps start from it.
DEFAULT_SPLIT_SHARE = 0.75


def _arrays(
    pattern_or_yarn: LogicalPattern | ArrayLike,
    raised: ArrayLike | None,
    name: str = "pattern_or_yarn",
):
    if isinstance(pattern_or_yarn, LogicalPattern):
        if raised is not None:
            raise PatternValidationError("pass `raised` only with a yarn array, not a pattern")
        return pattern_or_yarn.yarn, pattern_or_yarn.raised
    c = check_array(
        pattern_or_yarn,
        name,
        ndim=2,
        integer=True,
        what="a LogicalPattern or a 2-D array of yarn indices",
        error=PatternValidationError,
    )
    if raised is None:
        raise PatternValidationError(f"`raised` is required when `{name}` is a yarn array")
    r = np.asarray(raised, dtype=bool)
    if c.ndim != 2 or r.shape != c.shape:
        raise PatternValidationError(
            f"`yarn` and `raised` must be 2-D of one shape, got {c.shape} and {r.shape}"
        )
    return c, r


def seen_rows(raised: ArrayLike, view: View) -> NDArray[np.intp]:
    """ndarray of shape (N, M): the row index of the unit seen at each cell from ``view``."""
    r = np.asarray(raised, dtype=bool)
    n = r.shape[0]
    rows = np.broadcast_to(np.arange(n)[:, None], r.shape).copy()
    if view == "A":
        rows[1:] -= r[:-1]
    elif view == "B":
        rows[:-1] += r[1:]
    elif view != "headon":
        raise OptionError(f"`view` must be one of {VIEWS}, got {view!r}")
    return rows


def seen_courses(
    yarn: ArrayLike, raised: ArrayLike, upper: ArrayLike | None, view: View
) -> tuple[NDArray[np.int16], NDArray[np.int16]]:
    """The two courses of the unit each cell shows, ``(near, far)``, each of shape (N, M).

    ``near`` is :func:`can_see` (the course on the viewer's side: the second from A, the first
    from B and head-on); ``far`` is the other course of the same unit, equal to ``near`` except at
    split bumps, which show ``split_share`` of ``near`` and the rest of ``far`` (head-on half of
    each; see the module docstring)."""
    c = np.asarray(yarn)
    r = np.asarray(raised, dtype=bool)
    u = c if upper is None else np.asarray(upper)
    rows = seen_rows(r, view)
    cols = np.broadcast_to(np.arange(c.shape[1])[None, :], c.shape)
    first, second = c[rows, cols], u[rows, cols]
    near, far = (second, first) if view == "A" else (first, second)
    return near.astype(np.int16), far.astype(np.int16)


def can_see(
    pattern_or_yarn: LogicalPattern | ArrayLike,
    view: View,
    raised: ArrayLike | None = None,
    *,
    upper: ArrayLike | None = None,
) -> NDArray[np.int16]:
    """Yarn index seen at every cell from ``view`` ("A", "B" or "headon").

    Parameters
    ----------
    pattern_or_yarn : LogicalPattern or ndarray of shape (N, M)
        A pattern, or its yarn-index array (then pass ``raised`` too).
    view : {"A", "B", "headon"}
    raised : ndarray of shape (N, M), bool, optional
    upper : ndarray of shape (N, M), int, optional
        With a yarn array: the yarn of each unit's second course (split bumps; equal to the yarn
        on flat units). A pattern brings its own (``LogicalPattern.upper``).

    Returns
    -------
    ndarray of shape (N, M)
        The dominant yarn each cell shows (see the module docstring for split bumps).
    """
    return _can_see(pattern_or_yarn, view, raised, "pattern_or_yarn", upper)


def _upper(
    pattern_or_yarn: LogicalPattern | ArrayLike,
    c: NDArray[np.integer],
    r: NDArray[np.bool_],
    upper: ArrayLike | None,
) -> NDArray[np.integer]:
    """The second-course yarns: the pattern's, ``upper`` checked against ``c`` and ``r``, or c."""
    if isinstance(pattern_or_yarn, LogicalPattern):
        if upper is not None:
            raise PatternValidationError("pass `upper` only with a yarn array, not a pattern")
        return pattern_or_yarn.upper_yarn
    if upper is None:
        return c
    u = check_array(
        upper,
        "upper",
        ndim=2,
        integer=True,
        what="a 2-D array of yarn indices",
        error=PatternValidationError,
    )
    if u.shape != c.shape:
        raise PatternValidationError(f"`upper` must have shape {c.shape}, got {u.shape}")
    if (~r & (u != c)).any():
        raise PatternValidationError("`upper` must equal the yarn on flat units")
    return u


def _can_see(
    pattern_or_yarn: LogicalPattern | ArrayLike,
    view: View,
    raised: ArrayLike | None,
    name: str,
    upper: ArrayLike | None = None,
) -> NDArray[np.int16]:
    check_choice(view, "view", VIEWS)
    c, r = _arrays(pattern_or_yarn, raised, name)
    u = _upper(pattern_or_yarn, c, r, upper)
    if view == "A":
        c = u
    if view == "headon":
        return np.array(c, dtype=np.int16, copy=True)
    out = np.array(c, dtype=np.int16, copy=True)
    if view == "A":
        out[1:] = np.where(r[:-1], c[:-1], c[1:])
    elif view == "B":
        out[:-1] = np.where(r[1:], c[1:], c[:-1])
    else:
        raise OptionError(f"`view` must be one of {VIEWS}, got {view!r}")
    return out


def view_a(
    p: LogicalPattern | ArrayLike,
    raised: ArrayLike | None = None,
    *,
    upper: ArrayLike | None = None,
) -> NDArray[np.int16]:
    """Yarn indices seen from above (view A)."""
    return _can_see(p, "A", raised, "p", upper)


def view_b(p: LogicalPattern | ArrayLike, raised: ArrayLike | None = None) -> NDArray[np.int16]:
    """Yarn indices seen from below (view B)."""
    return _can_see(p, "B", raised, "p")


def view_headon(
    p: LogicalPattern | ArrayLike, raised: ArrayLike | None = None
) -> NDArray[np.int16]:
    """Yarn indices seen head-on (every unit)."""
    return _can_see(p, "headon", raised, "p")


def views(p: LogicalPattern) -> dict[View, NDArray[np.int16]]:
    """All three views of a pattern."""
    return {v: can_see(p, v) for v in VIEWS}


def logical_error(
    seen: ArrayLike, target: ArrayLike, *, mask: ArrayLike | None = None, normalize: bool = True
) -> float:
    """Fraction (or count, with ``normalize=False``) of cells where ``seen != target``.

    ``mask`` (bool, same shape) restricts the comparison to the cells where it is True.
    """
    check_array(seen, "seen", integer=False)
    check_array(target, "target", integer=False)
    check_bool(normalize, "normalize")
    s, t = np.asarray(seen), np.asarray(target)
    if s.shape != t.shape:
        raise ImageInputError(
            f"`seen` and `target` must have one shape, got {s.shape} and {t.shape}"
        )
    wrong = s != t
    if mask is not None:
        m = np.asarray(mask, dtype=bool)
        if m.shape != s.shape:
            raise OptionError(f"`mask` must have shape {s.shape}, got {m.shape}")
        wrong = wrong & m
        total = int(m.sum())
    else:
        total = wrong.size
    count = int(wrong.sum())
    if not normalize:
        return float(count)
    return count / total if total else 0.0
