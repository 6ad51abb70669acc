"""The app's request and settings models, in one place (pydantic).

:class:`DesignSettings` is what a session keeps *and* what ``PUT /settings`` validates: the patch
model :data:`SettingsPatch` is derived from it field by field (every field optional, the same
bounds), so a bound is written once. The page reads the bounds and titles from ``/openapi.json``
and error messages quote the titles, never the identifiers.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal, get_args

from pydantic import AfterValidator, BaseModel, ConfigDict, Field, create_model, model_validator

from illuknit.core.declared import declared_options
from illuknit.core.machine import DEFAULT_MACHINE_NAME, MACHINES
from illuknit.core.pattern import MAX_UNITS
from illuknit.design.options import RankOptions, SearchOptions
from illuknit.knit.options import KnitOptions

__all__ = [
    "DesignSettings",
    "JobIn",
    "OverrideIn",
    "SelectionIn",
    "SettingsPatch",
    "choice_control",
    "declared_field",
    "declared_fields",
]


def declared_field(cls: type, name: str, **narrower: float) -> Any:
    """The pydantic field of the declared option ``name`` of the option class ``cls``
    (:func:`illuknit.core.declared.option`): its default, range, title and help. ``narrower``
    bounds (``le=12``) may only narrow the declared range: what the app takes, the library
    takes."""
    opt = declared_options(cls)[name]
    d = opt.declared
    bounds = {k: getattr(d, k) for k in ("ge", "gt", "le", "lt") if getattr(d, k) is not None}
    for key, value in narrower.items():
        if key not in ("ge", "gt", "le", "lt") or not d.contains(value):
            raise ValueError(f"`{key}={value}` does not narrow {cls.__name__}.{name}'s range")
        bounds[key] = value
    return Field(default=opt.cli_default, title=opt.title, description=_sentence(d.help), **bounds)


def choice_control(model: type[BaseModel], name: str) -> dict[str, Any]:
    """The page's control of the choice field ``name`` of ``model``: its title, description,
    words and default, as the declared option gives them (the page builds its menu from this)."""
    info = model.model_fields[name]
    return {
        "title": info.title,
        "description": info.description,
        "choices": list(get_args(info.annotation)),
        "default": info.get_default(),
    }


def declared_fields(cls: type, only: tuple[str, ...] | None = None) -> dict[str, Any]:
    """``{name: (type, field)}`` of the declared options of ``cls`` (those in ``only``; default
    all), for :func:`pydantic.create_model`: an option class as app settings."""
    opts = declared_options(cls)
    return {
        n: (_app_type(opts[n]), declared_field(cls, n)) for n in (opts if only is None else only)
    }


def _app_type(opt: Any) -> Any:
    """An enum option's type in the app: its words (the JSON the page sends)."""
    choices = opt.choices
    return Literal[choices] if choices is not None else opt.type


def _sentence(text: str) -> str:
    """A help sentence as the app's description: lower case first, no full stop."""
    return (text[:1].lower() + text[1:]).rstrip(".")


def _known_machine(name: str) -> str:
    key = name.strip().lower()
    if key not in MACHINES:
        raise ValueError(f"unknown machine {name!r}; the machines are {', '.join(MACHINES)}")
    return key


#: A machine preset's name (:data:`illuknit.core.machine.MACHINES`), case-insensitive.
MachineName = Annotated[str, AfterValidator(_known_machine)]


class DesignSettings(BaseModel):
    """What the designer chose. Frozen: a change makes a new settings object."""

    model_config = ConfigDict(frozen=True, extra="forbid", allow_inf_nan=False)

    mode: Literal["single", "double", "headon"] = Field(
        default="double",
        title="Mode",
        description="single view (one picture), double view or head-on (two pictures)",
    )
    size_mode: Literal["picture", "units", "physical"] = Field(
        default="picture",
        title="Size by",
        description="size from the picture as the command line does (picture A's width in "
        "pixels, at most 100 units), give the width in units, or as a physical width and a "
        "gauge",
    )
    width_units: int = Field(
        default=60,
        ge=2,
        le=MAX_UNITS,
        title="Width",
        description="width in units (1 unit = 2 stitches)",
    )
    width_cm: float = Field(
        default=20.0, gt=0, le=500, title="Width in cm", description="physical width in cm"
    )
    gauge: float = Field(default=7.0, gt=0, le=40, title="Gauge", description="stitches per inch")
    n_colors: int = Field(
        default=2, ge=2, le=4, title="Colours", description="colours to quantise each picture to"
    )
    yarns: tuple[str, ...] = Field(
        default=("#1b1b1b", "#f4f0e8"),
        min_length=2,
        max_length=6,
        title="Yarns",
        description="yarn colours, '#rrggbb' or CSS names",
    )
    # the page shows at most 12 candidates; the library writes up to 50
    candidates: int = declared_field(SearchOptions, "candidates", le=12)
    resize: bool = Field(
        default=False, title="Resize B", description="stretch picture B to picture A's size"
    )
    machine: MachineName = Field(
        default=DEFAULT_MACHINE_NAME,
        title="Machine",
        description="the knitting machine: its bed bounds the width, its carriers hold the yarns",
    )
    smooth: bool = Field(
        default=True,
        title="Smooth resizing",
        description="anti-aliased resizing (photos) vs nearest (pixel art)",
    )
    square_units: bool = Field(
        default=False,
        title="Square units",
        description="size the grid with square units (as many unit rows as the picture is "
        "units tall): the piece comes out shorter than the picture by the gauge's row-to-stitch "
        "ratio; by default the grid keeps the picture's proportions in the finished fabric",
    )
    split_bumps: bool = declared_field(SearchOptions, "split_bumps")
    # `view_`: the page's own angle is the preview's, not the one the measures are taken at
    view_angle: float = declared_field(RankOptions, "angle")
    view_distance: float = declared_field(RankOptions, "distance")
    # who knits it: hands ranks first the designs a hand knitter can work (`illuknit double --for`)
    made_for: Literal["machine", "hands"] = declared_field(RankOptions, "made_for")

    @model_validator(mode="before")
    @classmethod
    def _sized_by_the_width_given(cls, data: Any) -> Any:
        """Settings given a width but no ``size_mode`` are sized by that width (a width in
        units, or a physical one), not from the picture."""
        if isinstance(data, dict) and "size_mode" not in data:
            if "width_units" in data:
                return {**data, "size_mode": "units"}
            if "width_cm" in data or "gauge" in data:
                return {**data, "size_mode": "physical"}
        return data

    def __setstate__(self, state: dict[str, Any]) -> None:
        # settings saved (pickled with their session) before a field existed get its default
        values = state.get("__dict__", {})
        for key, info in type(self).model_fields.items():
            if key not in values:
                values[key] = info.get_default(call_default_factory=True)
        super().__setstate__(state)

    @property
    def viewpoint(self) -> tuple[float, float]:
        """Where the measures look from: (angle in degrees, distance in metres)."""
        return (self.view_angle, self.view_distance)

    def to_json(self) -> dict[str, Any]:
        return self.model_dump(mode="json")


def _patch_of(model: type[BaseModel], name: str) -> type[BaseModel]:
    """``model`` with every field optional (``None`` = unchanged) and the same bounds."""
    fields: dict[str, Any] = {}
    for key, info in model.model_fields.items():
        patch = info._copy()  # keeps title, description and the bounds
        patch.default = None
        patch.annotation = info.annotation | None  # type: ignore[operator,assignment]
        fields[key] = (patch.annotation, patch)
    return create_model(
        name,
        __config__=ConfigDict(extra="forbid", allow_inf_nan=False),
        __doc__="Design settings to change; only the given fields change.",
        **fields,
    )


#: Body of ``PUT /settings``: any subset of :class:`DesignSettings`' fields.
SettingsPatch = _patch_of(DesignSettings, "SettingsPatch")


class JobIn(BaseModel):
    """Body of ``POST /jobs``."""

    kind: Literal["candidates", "knit", "measures", "suggestions", "widths"] = Field(
        ...,
        title="Job",
        description="candidates, knitout of the picked one, measures of every candidate, "
        "suggested edits of the pictures (double view), or the smallest width at which both "
        "sides read (double view; needs tesseract)",
    )
    # a knit job's: the knitting option, declared on KnitOptions
    allow_long_floats: bool = declared_field(KnitOptions, "allow_long_floats")
    # a widths job's: the widths tried (default: illuknit legible's, those the bed holds)
    widths: list[Annotated[int, Field(ge=4, le=MAX_UNITS)]] | None = Field(
        default=None,
        min_length=1,
        max_length=20,
        title="Widths",
        description="widths in units to try, narrowest first (default 40, 50, 60, 70, 80, "
        "100, 120: those the machine's bed holds)",
    )


class SelectionIn(BaseModel):
    """Body of ``PUT /selection``."""

    candidate: int = Field(..., ge=1, title="Candidate", description="rank of the candidate")


class OverrideIn(BaseModel):
    """Body of ``PUT /pairs/{a}/{b}``."""

    tile: str | None = Field(
        None,
        title="Tile",
        description="tile id from the bank; null restores the candidate's own",
    )
