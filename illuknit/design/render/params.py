"""Renderer parameters: the geometry of one unit and the viewing angle, and their JSON file.

Lengths are in one arbitrary unit (only their ratios matter): a unit is ``unit_length`` long along
the wale; a flat unit stands ``flat_height`` above the fabric and a bump ``bump_height``. ``theta``
is the camera's elevation above the fabric in degrees (90 = head-on). ``shading`` multiplies the
colour of the leading (vertical) faces a side view sees, 1 = no shading.

Two more parameters describe what the paper's section 9 proposes beyond plain bumps
(``docs/split-bumps.md``): ``split_share``, the share of a split bump's colour that comes from the
course on the viewer's side (view A sees ``split_share`` of the second course's yarn and the rest
of the first's; view B the reverse), and ``tall_bump_height``, the height of a bump knitted with
extra yarn (the knitting option for tall bumps; :meth:`RenderParams.with_tall_bumps` renders with
it). Both defaults are estimates until a swatch is measured.

The JSON file is one object holding any of these keys (missing keys take the defaults)::

    {"format": "illuknit-render-params", "version": 1,
     "flat_height": 0.1, "bump_height": 0.7, "unit_length": 1.0, "theta": 30.0, "shading": 1.0}

``split_share`` and ``tall_bump_height`` are written only when they differ from their defaults.

Unknown keys, non-numbers, angles outside (0, 90], non-positive sizes and bumps that are not
taller than flats are rejected with :class:`~illuknit.core.errors.RenderParamsError`.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import asdict, dataclass, fields, replace
from typing import Any

from illuknit.core.arguments import check_path
from illuknit.core.errors import RenderParamsError
from illuknit.core.files import atomic_write_text
from illuknit.core.views import DEFAULT_SPLIT_SHARE

__all__ = [
    "PARAMS_FORMAT",
    "TALL_RELIEF_ESTIMATE",
    "RenderParams",
    "check_angle",
    "load_params",
    "params_from_json",
    "params_to_json",
    "save_params",
]

#: A tall bump's relief over a plain bump's, assumed until measured: an extra tuck per bump
#: stitch adds a loop's worth of yarn to a bump of two; a guess, not a measurement.
TALL_RELIEF_ESTIMATE = 1.5

PARAMS_FORMAT = "illuknit-render-params"
PARAMS_VERSION = 1


def check_angle(angle: Any, *, name: str = "theta") -> float:
    """Validate an elevation angle in degrees: a finite number in (0, 90]."""
    if isinstance(angle, bool) or not isinstance(angle, int | float):
        raise RenderParamsError(f"`{name}` must be a number of degrees, got {angle!r}")
    a = float(angle)
    if not math.isfinite(a) or not 0.0 < a <= 90.0:
        raise RenderParamsError(f"`{name}` must be an angle in (0, 90] degrees, got {angle!r}")
    return a


#: The largest height or length of :class:`RenderParams`.
MAX_LENGTH = 100.0


@dataclass(frozen=True)
class RenderParams:
    """Geometry and camera of the ray-casting renderer (see the module docstring).

    Parameters
    ----------
    flat_height : float
        Height of a flat unit (> 0).
    bump_height : float
        Height of a bump (> ``flat_height``).
    unit_length : float
        Length of a unit along the wale (> 0).
    theta : float
        Camera elevation in degrees, in (0, 90]; 90 looks straight down.
    shading : float
        Brightness factor of leading faces, in (0, 1].
    split_share : float
        Share of a split bump's colour, seen from one side, that comes from the course on that
        side, in (0.5, 1] (1 = each side shows only its own course). The default 0.75 is the
        cuboid estimate at the default geometry: from view A at 30 degrees a bump shows its
        leading face (the second course) and its top face, half of each course, so the second
        course covers ``(h cos + L sin / 2) / (h cos + L sin)`` = 0.77 of it.
    tall_bump_height : float or None
        Height of a tall bump (>= ``bump_height``). None (the default) estimates it as a relief
        :data:`TALL_RELIEF_ESTIMATE` times a plain bump's (:attr:`tall_height`) until a
        tall-bump swatch is measured.

    Examples
    --------
    >>> RenderParams().with_angle(45).theta
    45.0
    """

    flat_height: float = 0.1
    bump_height: float = 0.7
    unit_length: float = 1.0
    theta: float = 30.0
    shading: float = 1.0
    split_share: float = DEFAULT_SPLIT_SHARE
    tall_bump_height: float | None = None

    def __post_init__(self) -> None:
        for f in fields(self):
            v = getattr(self, f.name)
            if v is None and f.name == "tall_bump_height":
                continue
            if isinstance(v, bool) or not isinstance(v, int | float):
                raise RenderParamsError(f"`{f.name}` must be a number, got {v!r}")
            if not math.isfinite(float(v)):
                raise RenderParamsError(f"`{f.name}` must be finite, got {v!r}")
            object.__setattr__(self, f.name, float(v))
        for name in ("flat_height", "bump_height", "unit_length"):
            if getattr(self, name) <= 0:
                raise RenderParamsError(f"`{name}` must be positive, got {getattr(self, name)!r}")
        for name in ("flat_height", "bump_height", "unit_length", "tall_bump_height"):
            # a fabric's relief is within a few unit lengths; a hundred is a slip of the keyboard
            if (getattr(self, name) or 0) > MAX_LENGTH:
                raise RenderParamsError(
                    f"`{name}` must be at most {MAX_LENGTH:g}, got {getattr(self, name)!r}"
                )
        if self.bump_height <= self.flat_height:
            raise RenderParamsError(
                f"`bump_height` must exceed `flat_height` ({self.flat_height}), got {self.bump_height}"
            )
        check_angle(self.theta)
        if not 0.0 < self.shading <= 1.0:
            raise RenderParamsError(f"`shading` must lie in (0, 1], got {self.shading!r}")
        if not 0.5 < self.split_share <= 1.0:
            raise RenderParamsError(
                f"`split_share` must lie in (0.5, 1] (the near course dominates), "
                f"got {self.split_share!r}"
            )
        if self.tall_bump_height is not None and self.tall_bump_height < self.bump_height:
            raise RenderParamsError(
                f"`tall_bump_height` must be at least `bump_height` ({self.bump_height}), "
                f"got {self.tall_bump_height}"
            )

    def with_angle(self, theta: float) -> RenderParams:
        """A copy seen from another elevation (degrees, in (0, 90])."""
        return replace(self, theta=check_angle(theta))

    def with_tall_bumps(self) -> RenderParams:
        """A copy whose bumps are tall ones (``bump_height = tall_bump_height``), to render a
        pattern knitted with the tall-bump option."""
        return replace(self, bump_height=self.tall_height, tall_bump_height=None)

    @property
    def tall_height(self) -> float:
        """Height of a tall bump: ``tall_bump_height``, or its estimate when unmeasured."""
        if self.tall_bump_height is not None:
            return self.tall_bump_height
        return self.flat_height + TALL_RELIEF_ESTIMATE * self.relief

    @property
    def relief(self) -> float:
        """``bump_height - flat_height``: how far a bump stands above a flat."""
        return self.bump_height - self.flat_height

    @property
    def exact_angle(self) -> float:
        """The elevation (degrees) at which a bump hides exactly the next unit (can_see holds)."""
        return math.degrees(math.atan2(self.relief, self.unit_length))


_OPTIONAL_KEYS = ("split_share", "tall_bump_height")
_DEFAULTS = {f.name: f.default for f in fields(RenderParams)}


def params_to_json(params: RenderParams) -> dict[str, Any]:
    """The parameters as a JSON-ready dict, with the format tag."""
    doc = {"format": PARAMS_FORMAT, "version": PARAMS_VERSION, **asdict(params)}
    for name in _OPTIONAL_KEYS:  # written only when set, so older files read and write as before
        if doc[name] == _DEFAULTS[name]:
            del doc[name]
    return doc


def params_from_json(doc: Any) -> RenderParams:
    """Parse a parameters object; raises :class:`RenderParamsError` naming the bad key."""
    if not isinstance(doc, dict):
        raise RenderParamsError(
            f"render parameters must be a JSON object, got {type(doc).__name__}"
        )
    doc = dict(doc)
    fmt = doc.pop("format", PARAMS_FORMAT)
    if fmt != PARAMS_FORMAT:
        raise RenderParamsError(f"`format` must be {PARAMS_FORMAT!r}, got {fmt!r}")
    version = doc.pop("version", PARAMS_VERSION)
    if version != PARAMS_VERSION or isinstance(version, bool):
        raise RenderParamsError(f"`version` must be {PARAMS_VERSION}, got {version!r}")
    valid = [f.name for f in fields(RenderParams)]
    unknown = sorted(set(doc) - set(valid))
    if unknown:
        raise RenderParamsError(
            f"unknown render parameter(s) {', '.join(map(repr, unknown))}; valid: {', '.join(valid)}"
        )
    return RenderParams(**doc)


def save_params(params: RenderParams, path: str | os.PathLike[str]) -> None:
    """Write parameters as JSON (atomically)."""
    atomic_write_text(path, json.dumps(params_to_json(params), indent=1) + "\n")


def load_params(path: str | os.PathLike[str]) -> RenderParams:
    """Read a parameters file; raises :class:`RenderParamsError` on any problem."""
    check_path(path, "path")
    from illuknit.core.documents import read_json_file

    doc = read_json_file(path, error=RenderParamsError, what="render parameters")
    try:
        return params_from_json(doc)
    except RenderParamsError as e:
        raise RenderParamsError(f"{path}: {e}") from None
