"""One declaration per option: the field of a frozen option class carries its help and range.

An option class (:class:`~illuknit.knit.options.KnitOptions`,
:class:`~illuknit.design.options.SearchOptions`, ...) declares each option once, as a dataclass
field made by :func:`option`: its name and type are the field's, its default the field's default,
and the field's metadata holds a :class:`Declared` with the help text, the numeric range and the
command-line spelling. The command line (:func:`illuknit.cli.options.options_from`) and the app's
settings (:mod:`illuknit.app.schemas`) are generated from these declarations, so a bound or a
help text is written in one place (scikit-image's one name for one concept in one position).

Examples
--------
>>> from dataclasses import dataclass
>>> @dataclass(frozen=True)
... class Opts:
...     seed: int = option(0, help="Random seed.", ge=0, le=9)
>>> declared_options(Opts)["seed"].declared.bounds
(0, 9, False, False)
>>> declared_options(Opts)["seed"].default
0
"""

from __future__ import annotations

import functools
import typing
import warnings
from collections.abc import Callable, Mapping
from dataclasses import MISSING, dataclass, field, fields
from enum import Enum
from types import MappingProxyType, UnionType
from typing import Any, TypedDict, Unpack

__all__ = ["Declared", "DeclaredOption", "accepts_old_names", "declared_options", "option"]

T = typing.TypeVar("T")

#: The key of a field's metadata that holds its :class:`Declared`.
METADATA_KEY = "illuknit.option"


@dataclass(frozen=True)
class Declared:
    """What an option says of itself beyond its name, type and default.

    Parameters
    ----------
    help : str
        One or two sentences for a user (the CLI's ``--help``, the app's description).
    ge, gt, le, lt : float, optional
        The numeric range (pydantic's spelling): at least, above, at most, below.
    flag : str, optional
        The command-line spelling (``"--for"``); default ``--`` and the name with dashes.
    metavar : str, optional
        The command line's name for the value (``NAME``).
    title : str, optional
        A short label (the app's field title); default the name in words.
    old_names : tuple of str
        Former keyword spellings still accepted, with a :class:`DeprecationWarning`, for one
        release.
    """

    help: str
    ge: float | None = None
    gt: float | None = None
    le: float | None = None
    lt: float | None = None
    flag: str | None = None
    metavar: str | None = None
    title: str | None = None
    old_names: tuple[str, ...] = ()

    @property
    def bounds(self) -> tuple[float | None, float | None, bool, bool]:
        """(low, high, low open, high open); None where there is no bound."""
        low = self.gt if self.gt is not None else self.ge
        high = self.lt if self.lt is not None else self.le
        return low, high, self.gt is not None, self.lt is not None

    @property
    def range_text(self) -> str:
        """The range as an interval: ``"(0, 90]"``, ``"[1, 50]"``."""
        low, high, low_open, high_open = self.bounds
        return (
            f"{'(' if low_open or low is None else '['}{'-inf' if low is None else f'{low:g}'}, "
            f"{'inf' if high is None else f'{high:g}'}{')' if high_open or high is None else ']'}"
        )

    def contains(self, value: float) -> bool:
        """Whether ``value`` is within the declared range."""
        low, high, low_open, high_open = self.bounds
        if low is not None and (value <= low if low_open else value < low):
            return False
        return high is None or (value < high if high_open else value <= high)


@dataclass(frozen=True)
class DeclaredOption:
    """One declared option of a class: its name, resolved type, default and declaration."""

    name: str
    type: Any
    default: Any
    declared: Declared

    @property
    def flag(self) -> str:
        """The command-line spelling (``--cast-on-courses``)."""
        return self.declared.flag or "--" + self.name.replace("_", "-")

    @property
    def title(self) -> str:
        """A short label (``"Cast on courses"``)."""
        return self.declared.title or self.name.replace("_", " ").capitalize()

    @property
    def base_type(self) -> Any:
        """The type without ``| None`` (``float | None`` -> ``float``)."""
        args = [a for a in typing.get_args(self.type) if a is not type(None)]
        if typing.get_origin(self.type) in (typing.Union, UnionType) and len(args) == 1:
            return args[0]
        return self.type

    @property
    def choices(self) -> tuple[str, ...] | None:
        """The words an enum option takes (None for any other type)."""
        t = self.base_type
        if isinstance(t, type) and issubclass(t, Enum):
            return tuple(str(m.value) for m in t)
        return None

    @property
    def cli_default(self) -> Any:
        """The default as the command line takes it (an enum member's word)."""
        return self.default.value if isinstance(self.default, Enum) else self.default


class DeclaredKeywords(TypedDict, total=False):
    """The keywords of :func:`option` besides ``help`` (see :class:`Declared`)."""

    ge: float | None
    gt: float | None
    le: float | None
    lt: float | None
    flag: str | None
    metavar: str | None
    title: str | None
    old_names: tuple[str, ...]


def option(default: Any, *, help: str, **declared: Unpack[DeclaredKeywords]) -> Any:
    """A dataclass field declaring an option once (see :class:`Declared` for the keywords)."""
    return field(default=default, metadata={METADATA_KEY: Declared(help=help, **declared)})


@functools.cache
def declared_options(cls: type) -> Mapping[str, DeclaredOption]:
    """The declared options of the dataclass ``cls`` by name, in field order (fields made
    without :func:`option` are left out); read once per class, read-only."""
    hints = typing.get_type_hints(cls)
    out = {}
    for f in fields(cls):
        declared = f.metadata.get(METADATA_KEY)
        if declared is None:
            continue
        default = f.default if f.default is not MISSING else None
        out[f.name] = DeclaredOption(f.name, hints[f.name], default, declared)
    return MappingProxyType(out)


def check_declared_range(cls: type, name: str, value: Any, error: type[Exception]) -> None:
    """Refuse the number ``value`` of the declared option ``name`` of ``cls`` outside its
    declared range, with ``error`` naming the option and the range."""
    declared = declared_options(cls)[name].declared
    if not declared.contains(value):
        raise error(f"`{name}` must be a number in {declared.range_text}, got {value!r}")


def renamed_keywords(cls: type, kwargs: dict[str, Any]) -> dict[str, Any]:
    """``kwargs`` with every former spelling of a declared option of ``cls``
    (:attr:`Declared.old_names`) replaced by its name, with a :class:`DeprecationWarning` each."""
    for name, opt in declared_options(cls).items():
        for old in opt.declared.old_names:
            if old in kwargs:
                if name in kwargs:
                    raise TypeError(f"give `{name}` or the deprecated `{old}`, not both")
                warnings.warn(
                    f"`{old}` is deprecated and goes in the next release; use `{name}`",
                    DeprecationWarning,
                    stacklevel=3,
                )
                kwargs[name] = kwargs.pop(old)
    return kwargs


def accepts_old_names(cls: type[T]) -> type[T]:
    """Class decorator: the option class ``cls`` also takes each former keyword spelling of its
    declared options (:attr:`Declared.old_names`), for one release, with a
    :class:`DeprecationWarning`."""
    init: Callable[..., None] = getattr(cls, "__init__")  # noqa: B009

    @functools.wraps(init)
    def __init__(self: Any, *args: Any, **kwargs: Any) -> None:
        init(self, *args, **renamed_keywords(cls, kwargs))

    setattr(cls, "__init__", __init__)  # noqa: B010
    return cls
