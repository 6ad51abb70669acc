"""Yarns: a name and a colour each, parsed from the command line's ``--yarns`` spelling
(:func:`parse_yarns`), checked at public entry points (:func:`check_yarns`), and the notes a
palette deserves (:func:`yarn_notes`: two colours too close to tell apart, names cleaned).

A :class:`~illuknit.core.pattern.LogicalPattern` holds a tuple of them as its palette; every
name here is importable from :mod:`illuknit.core.pattern` too.
"""

from __future__ import annotations

import re
import unicodedata
import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from illuknit.core.arguments import got
from illuknit.core.colors import color_name, hex_color, parse_color
from illuknit.core.errors import YarnSpecError

__all__ = [
    "JUST_NOTICEABLE_DE",
    "MAX_YARN_NAME",
    "Yarn",
    "YarnNote",
    "check_yarns",
    "clean_yarn_name",
    "parse_yarns",
    "yarn_notes",
]

#: Two yarn colours closer than this (CIEDE2000) are hard to tell apart: a just-noticeable
#: difference (Sharma, Wu & Dalal 2005: about 1 to 2).
JUST_NOTICEABLE_DE = 2.0
# Bidirectional-text controls reorder what a terminal or a page shows; treat them as control
# characters too.
_BIDI_CONTROLS = set("\u061c\u200e\u200f\u202a\u202b\u202c\u202d\u202e\u2066\u2067\u2068\u2069")


class YarnNote(UserWarning):
    """Yarns that work but may not be what was meant: two yarns of one name (the second is
    renamed), colours closer than a just-noticeable difference, control characters in a name
    (removed). The command line prints it as one ``note:`` line."""


def clean_yarn_name(name: str) -> str:
    """``name`` without control characters: tabs and line breaks become spaces, the others
    (escape sequences, NUL, bidirectional overrides) are removed; runs of spaces become one.

    >>> clean_yarn_name("navy\x1b[31m red\n")
    'navy[31m red'
    """
    kept = []
    for ch in name:
        if ch in "\t\n\r\v\f\x85\u2028\u2029":
            kept.append(" ")
        elif unicodedata.category(ch) != "Cc" and ch not in _BIDI_CONTROLS:
            kept.append(ch)
    return re.sub(r" {2,}", " ", "".join(kept)).strip()


def _has_controls(name: str) -> bool:
    return any(unicodedata.category(ch) == "Cc" or ch in _BIDI_CONTROLS for ch in name)


#: The longest yarn name, in characters (it labels charts, instructions and legends).
MAX_YARN_NAME = 100


@dataclass(frozen=True)
class Yarn:
    """A yarn: a display name and its sRGB colour.

    Control characters in the name are removed (:func:`clean_yarn_name`), so no file, chart or
    terminal illuknit writes the name to carries them.
    """

    name: str
    rgb: tuple[int, int, int]

    def __post_init__(self) -> None:
        if not isinstance(self.name, str):
            raise YarnSpecError(f"yarn name must be a string, got {type(self.name).__name__}")
        if len(self.name) > MAX_YARN_NAME:  # before any work on it: a label, not a document
            raise YarnSpecError(
                f"yarn name {self.name[:40]!r}... is {len(self.name)} characters long; "
                f"at most {MAX_YARN_NAME}"
            )
        name = clean_yarn_name(self.name)
        if not name:
            raise YarnSpecError("yarn name must be a non-empty string")
        object.__setattr__(self, "name", name)
        if isinstance(self.rgb, (str, bytes)) or not hasattr(self.rgb, "__len__"):
            raise YarnSpecError(
                f"yarn {name!r}: `rgb` must be 3 integers in 0..255, got {self.rgb!r}"
            )
        try:
            rgb = tuple(int(v) for v in self.rgb)
        except (TypeError, ValueError):
            raise YarnSpecError(
                f"yarn {name!r}: `rgb` must be 3 integers in 0..255, got {self.rgb!r}"
            ) from None
        if len(rgb) != 3 or any(v < 0 or v > 255 for v in rgb):
            raise YarnSpecError(
                f"yarn {self.name!r}: `rgb` must be 3 integers in 0..255, got {self.rgb!r}"
            )
        object.__setattr__(self, "rgb", rgb)

    @property
    def hex(self) -> str:
        return hex_color(self.rgb)

    @classmethod
    def from_string(cls, text: str, *, name: str | None = None) -> Yarn:
        """A yarn from a colour string; named after the colour when no name is given."""
        rgb = parse_color(text)
        if name is None:
            s = text.strip()
            name = s if not s.startswith(("#", "rgb")) else color_name(rgb)
        return cls(name=name, rgb=rgb)


def check_yarns(value: object, name: str = "yarns") -> tuple[Yarn, ...]:
    """``value`` as a tuple when it is a non-empty sequence of :class:`Yarn`, else
    :class:`YarnSpecError` naming the parameter."""
    if (
        isinstance(value, Sequence)
        and not isinstance(value, (str, bytes))
        and len(value) > 0
        and all(isinstance(y, Yarn) for y in value)
    ):
        return tuple(value)
    raise YarnSpecError(
        f"`{name}` must be a non-empty sequence of Yarn (see illuknit.parse_yarns), "
        f"got {got(value)}"
    )


def parse_yarns(spec: str | Sequence[str]) -> tuple[Yarn, ...]:
    """Parse ``"#1b1b1b,#f4f0e8"`` or ``["navy", "white"]`` into yarns.

    ``name=#rrggbb`` gives a yarn an explicit name. Raises :class:`YarnSpecError` on an unknown
    colour, fewer than one yarn, or two yarns with the same colour. Issues a :class:`YarnNote`
    for two yarns of one name (the second becomes "name 2"), for colours closer than a
    just-noticeable difference (CIEDE2000 below 2), and for control characters in a name (they
    are removed).
    """
    if isinstance(spec, str):
        raw = spec.split(",")
    elif isinstance(spec, Sequence) and all(isinstance(s, str) for s in spec):
        raw = list(spec)
    else:
        raise YarnSpecError(
            f"`spec` must be a comma-separated string or a sequence of strings, got {got(spec)}"
        )
    items = [s.strip() for s in raw if s.strip()]
    if not items:
        raise YarnSpecError(f"`spec` gives no yarn colours, got {got(spec)}")
    yarns = []
    named = set()  # names the user gave (colour names made up from a hex code are renamed quietly)
    for item in items:
        yarns.append(_parse_item(item))
        if "=" in item:
            named.add(yarns[-1].name)
    out = _dedupe_yarns(tuple(yarns), named=named)
    for note in yarn_notes(out):
        _note(note)
    return out


def _parse_item(item: str) -> Yarn:
    """One yarn of a spec: ``name=colour`` or ``colour``."""
    if "=" not in item:
        return Yarn.from_string(item)
    name, _, col = item.partition("=")
    if not col.strip():
        raise YarnSpecError(f"`spec` names a yarn without a colour: {item!r} (use name=#rrggbb)")
    if _has_controls(name):
        _note(f"control characters removed from the yarn name {name!r}", stacklevel=4)
    return Yarn.from_string(col, name=name.strip())


def _note(message: str, *, stacklevel: int = 3) -> None:
    warnings.warn(message, YarnNote, stacklevel=stacklevel)


def yarn_notes(yarns: Sequence[Yarn]) -> list[str]:
    """Pairs of yarns whose colours are closer than a just-noticeable difference (CIEDE2000 <
    :data:`JUST_NOTICEABLE_DE`), as sentences; empty when every pair can be told apart."""
    if len(yarns) < 2:
        return []
    from skimage.color import deltaE_ciede2000

    from illuknit.core.colors import lab_from_rgb

    lab = lab_from_rgb(np.array([y.rgb for y in yarns], dtype=np.uint8))
    notes = []
    for i in range(len(yarns)):
        for j in range(i + 1, len(yarns)):
            de = float(deltaE_ciede2000(lab[i], lab[j]))
            if de < JUST_NOTICEABLE_DE:
                a, b = yarns[i], yarns[j]
                notes.append(
                    f"yarns {a.name!r} ({a.hex}) and {b.name!r} ({b.hex}) differ by "
                    f"{de:.1f} (CIEDE2000), less than a just-noticeable difference "
                    f"({JUST_NOTICEABLE_DE:g}): the picture may not show them apart"
                )
    return notes


def _dedupe_yarns(
    yarns: tuple[Yarn, ...], *, named: frozenset[str] | set[str] = frozenset()
) -> tuple[Yarn, ...]:
    seen: dict[tuple[int, int, int], str] = {}
    for y in yarns:
        if y.rgb in seen:
            raise YarnSpecError(f"duplicate yarn colour {y.hex} ({seen[y.rgb]!r} and {y.name!r})")
        seen[y.rgb] = y.name
    names: dict[str, int] = {}
    taken = {y.name for y in yarns}
    out = []
    for y in yarns:
        n = names.get(y.name, 0)
        names[y.name] = n + 1
        if n == 0:
            out.append(y)
            continue
        k = n + 1
        while f"{y.name} {k}" in taken:
            k += 1
        taken.add(f"{y.name} {k}")
        if y.name in named:
            _note(
                f"two yarns are named {y.name!r}: the one of colour {y.hex} is called '{y.name} {k}'"
            )
        out.append(Yarn(f"{y.name} {k}", y.rgb))
    return tuple(out)
