"""The checks every design stage makes of its inputs, once, at its entry: the pictures, their
sizes and yarns, the bank, the option objects, and the bed the grid must fit."""

from __future__ import annotations

import os
import warnings
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass, fields, replace
from typing import TYPE_CHECKING, Any

from illuknit.core.errors import ImageInputError, OptionError, YarnSpecError
from illuknit.core.machine import BedFitWarning, MachineSpec, resolve_machine

if TYPE_CHECKING:
    from illuknit.core.pattern import LogicalPattern, Yarn

__all__ = [
    "PictureOptions",
    "check_bank",
    "check_fits",
    "check_picture",
    "check_sizes",
    "check_type",
    "check_yarns",
    "fit_machine",
    "fit_notes",
    "picture_options",
    "source_name",
    "unit_aspect_or_default",
    "with_meta",
]


def fit_machine(knit_on: str | MachineSpec | None) -> MachineSpec | None:
    from illuknit.core.arguments import check_instance

    if knit_on is None:
        return None
    what = "a machine name or a MachineSpec"
    return resolve_machine(check_instance(knit_on, (str, MachineSpec), "knit_on", what=what))


def fit_notes(machine: str | MachineSpec | None, units: int) -> tuple[str, ...]:
    """The design-time note on a grid ``units`` wide for ``machine`` (None: the default), as a
    :class:`~illuknit.core.machine.BedFitWarning` too (the CLI prints it as one line)."""
    note = resolve_machine(machine).fit_note(int(units))
    if note is None:
        return ()
    warnings.warn(note, BedFitWarning, stacklevel=3)
    return (note,)


def check_fits(machine: MachineSpec | None, units: int | None) -> None:
    """Refuse a pattern ``units`` wide that ``machine``'s bed cannot hold, before design work."""
    if machine is not None and units is not None:
        machine.check_units(units)


def source_name(p: Any) -> str | None:
    """How a picture is named in reports: its path, or None for an array."""
    if isinstance(p, (str, bytes)) or hasattr(p, "__fspath__"):
        return str(p)
    return None


def check_picture(value: Any, name: str, *, optional: bool = False) -> None:
    """A picture argument: a file path or an sRGB array (None only when ``optional``)."""
    from illuknit.core.arguments import check_array, check_path, got

    if value is None:
        if optional:
            return
        raise ImageInputError(f"`{name}` must be a picture (a file path or an RGB array), got None")
    if isinstance(value, (str, os.PathLike)):
        check_path(value, name)
    elif not hasattr(value, "indices"):  # a QuantisedImage is checked where it is taken
        try:
            check_array(value, name, ndim=(2, 3))
        except ImageInputError:
            raise ImageInputError(
                f"`{name}` must be a picture (a file path or an RGB array), got {got(value)}"
            ) from None


def check_sizes(**sizes: Any) -> None:
    """Grid sizes in units (``width``, ``height``: 1-1000) and ``width_cm`` (> 0), or None."""
    from illuknit.core.arguments import check_int, check_number

    for name, value in sizes.items():
        if value is None:
            continue
        if name == "width_cm":
            check_number(value, name, min=0, min_open=True)
        elif name == "gauge":  # stitches per inch: the finest machines knit about 20
            check_number(value, name, min=0, max=100, min_open=True)
        else:
            check_int(value, name, min=1, max=1000)


def check_yarns(yarns: Any, *, count_ok: bool) -> None:
    """``yarns``: None, a sequence of Yarn, or (``count_ok``) how many to choose (1-8)."""
    from illuknit.core.arguments import check_int, got
    from illuknit.core.pattern import Yarn

    if yarns is None:
        return
    if count_ok and isinstance(yarns, int) and not isinstance(yarns, bool):
        check_int(yarns, "yarns", min=1, max=8, error=YarnSpecError)
        return
    if not isinstance(yarns, (list, tuple)) or not yarns:
        what = "a number of yarns or a sequence of Yarn" if count_ok else "a sequence of Yarn"
        raise YarnSpecError(f"`yarns` must be {what}, got {got(yarns)}")
    if not all(isinstance(y, Yarn) for y in yarns):
        raise YarnSpecError(f"`yarns` must hold Yarn objects, got {got(yarns)}")


def check_bank(bank: Any) -> None:
    from illuknit.core.arguments import got
    from illuknit.design.tiles.bank import TileBank

    if bank is not None and not isinstance(bank, (TileBank, str, os.PathLike)):
        raise OptionError(f"`bank` must be a TileBank or a bank file, got {got(bank)}")


def unit_aspect_or_default(unit_aspect: float | None) -> float:
    """``unit_aspect`` for the sizing functions, checked; None is a stocking-stitch unit (the
    finished piece keeps the picture's proportions)."""
    from illuknit.core.arguments import check_unit_aspect
    from illuknit.core.gauge import STOCKINETTE_COURSE_ASPECT

    if unit_aspect is None:
        return STOCKINETTE_COURSE_ASPECT
    return check_unit_aspect(unit_aspect)


def check_type(name: str, value: Any, cls: type) -> None:
    if not isinstance(value, cls):
        raise OptionError(f"`{name}` must be a {cls.__name__}, got {type(value).__name__}")


def with_meta(pattern: LogicalPattern, meta: Mapping[str, Any]) -> LogicalPattern:
    """``pattern`` with ``meta`` added to its metadata."""
    return replace(pattern, meta={**pattern.meta, **meta})


@dataclass(frozen=True, eq=False)
class PictureOptions:
    """How a stage makes its grid of the pictures: their size and their colours.

    A stage takes these as ``pictures=PictureOptions(...)`` or, shorter, as keywords of their
    own (``design_double(a, b, width=60)`` is ``design_double(a, b,
    pictures=PictureOptions(width=60))``); a keyword replaces that field of ``pictures`` when
    both are given. Each stage reads the fields it documents and refuses the others by name.
    Values are checked by the stage that takes them, naming the field.

    Attributes
    ----------
    width, height : int, optional
        The grid's size in units (default: the picture's, at most 80 units wide).
    width_cm : float, optional
        The finished width, sized at ``gauge`` (single view).
    gauge : float, optional
        Stitches per inch ``width_cm`` is sized at (default: the machine's).
    stretch : bool
        Stretch a second picture of another shape onto the first's grid.
    unit_aspect : float, optional
        Height over width of a unit (default: a stocking-stitch unit).
    n_colors : int, optional
        The colours each picture is quantised to (the tile stages: 2 when None).
    yarns : sequence of Yarn or int, optional
        The yarns, or (tile stages) how many to choose from the pictures.
    quantise : bool
        Cluster a picture with more colours than yarns (else refuse it).
    """

    width: int | None = None
    height: int | None = None
    width_cm: float | None = None
    gauge: float | None = None
    stretch: bool = False
    unit_aspect: float | None = None
    n_colors: int | None = None
    yarns: Sequence[Yarn] | int | None = None
    quantise: bool = True

    def __post_init__(self) -> None:
        # checked where they are made too (the fuzz of the exports), naming the field; each
        # stage still refuses the fields it does not take
        from illuknit.core.arguments import check_bool, check_int, check_number, check_unit_aspect

        check_sizes(width=self.width, height=self.height, width_cm=self.width_cm, gauge=self.gauge)
        if self.width_cm is not None:  # 1000 units at 1 stitch per inch are 5080 cm
            check_number(self.width_cm, "width_cm", min=0, max=10_000, min_open=True)
        check_bool(self.stretch, "stretch")
        check_bool(self.quantise, "quantise")
        if self.unit_aspect is not None:
            check_unit_aspect(self.unit_aspect)
        if self.n_colors is not None:
            check_int(self.n_colors, "n_colors", min=1, max=8)
        check_yarns(self.yarns, count_ok=True)


def picture_options(
    pictures: PictureOptions | None, knobs: Mapping[str, Any], *, takes: Collection[str]
) -> PictureOptions:
    """``pictures`` (default ``PictureOptions()``) with the shorthand ``knobs`` in place of its
    fields; a knob or a field set that the stage does not take (``takes``) is refused by name."""
    if pictures is not None:
        check_type("pictures", pictures, PictureOptions)
    base = PictureOptions() if pictures is None else pictures
    names = {f.name for f in fields(PictureOptions)}
    for name in knobs:
        if name not in names:
            raise OptionError(f"unknown picture option {name!r}; valid: {', '.join(sorted(takes))}")
    opts = replace(base, **knobs) if knobs else base
    default = PictureOptions()
    for name in sorted(names - set(takes)):
        if getattr(opts, name) != getattr(default, name):
            raise OptionError(
                f"`{name}` is not an option of this stage; it takes {', '.join(sorted(takes))}"
            )
    return opts
