"""The overlap table of a tile design, kept readable when the pictures have many colours.

Every place where a colour of picture A lies over a colour of picture B is an *overlap pair*
with its own tile. Two pictures of 4 colours give up to 16 pairs, many covering a handful of
units; listed one per line they bury the few that shape the design. :func:`group_overlaps`
orders them for a designer:

* **grouped by fill** -- overlaps whose tiles show the same fill from one view form one group
  (``by="A"``, the default first view: one group per fill picture A is repainted with, listing
  what lies under it). ``by="both"`` groups overlaps whose tiles show the same fills from both
  views (they share every tile option; under the default brightness order each pair has its own
  fills, so these groups are single pairs unless fills repeat);
* **the rare ones folded** -- an overlap covering less than ``rare_share`` of the units
  (:data:`RARE_SHARE`, 2 %, by default) leaves its group and is counted in one
  "N rare overlaps" line with their total share.

The result, an :class:`OverlapTable`, renders as text (:meth:`OverlapTable.lines`, the CLI's
summary) or JSON (:meth:`OverlapTable.to_json`, ``summary.json`` and the app). Groups and the
rare line together hold every overlap pair exactly once.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from illuknit.core.colors import hex_color
from illuknit.core.errors import OptionError
from illuknit.design.tiles.assignment import TileAssignment, overlap_pairs
from illuknit.design.tiles.tile import Fill

__all__ = ["RARE_SHARE", "OverlapGroup", "OverlapRow", "OverlapTable", "group_overlaps"]

#: Overlaps covering less than this share of the units are folded into the "rare" line.
RARE_SHARE = 0.02
#: Label of a tile that shows no clean fill from a view (a designer's override may do that).
NO_FILL = "no clean fill"


@dataclass(frozen=True)
class OverlapRow:
    """One overlap pair: colour ``a`` of picture A over colour ``b`` of picture B.

    ``fills`` are the labels of what its tile shows from each view; ``share`` is ``units`` over
    the design's units.
    """

    a: int
    b: int
    units: int
    share: float
    color_a: str
    color_b: str
    fills: tuple[str, str]
    tile: str
    overridden: bool

    def to_json(self) -> dict[str, Any]:
        return {
            "a": self.a,
            "b": self.b,
            "units": self.units,
            "share": round(self.share, 4),
            "a_color": self.color_a,
            "b_color": self.color_b,
            "fills": list(self.fills),
            "tile": self.tile,
            "overridden": self.overridden,
        }


@dataclass(frozen=True)
class OverlapGroup:
    """Overlaps whose tiles show the same fill (``fill``, its colour ``fill_color``)."""

    fill: str
    fill_color: str | None
    rows: tuple[OverlapRow, ...]

    @property
    def units(self) -> int:
        return sum(r.units for r in self.rows)

    @property
    def share(self) -> float:
        return sum(r.share for r in self.rows)

    def to_json(self) -> dict[str, Any]:
        return {
            "fill": self.fill,
            "fill_color": self.fill_color,
            "units": self.units,
            "share": round(self.share, 4),
            "overlaps": [r.to_json() for r in self.rows],
        }


@dataclass(frozen=True)
class OverlapTable:
    """The overlaps of a design, grouped by fill, the rare ones folded.

    Attributes
    ----------
    views : (str, str)
        The design's views.
    by : str
        The view whose fill groups the overlaps, or ``"both"``.
    rare_share : float
        The threshold: overlaps below this share of the units are in ``rare``.
    total_units : int
        Units of the design (N x M).
    groups : tuple of OverlapGroup
        Largest first; each row in it covers at least ``rare_share`` of the units.
    rare : tuple of OverlapRow
        The folded overlaps, largest first.
    """

    views: tuple[str, str]
    by: str
    rare_share: float
    total_units: int
    groups: tuple[OverlapGroup, ...]
    rare: tuple[OverlapRow, ...]

    @property
    def rows(self) -> tuple[OverlapRow, ...]:
        """Every overlap pair: the grouped ones, then the rare ones."""
        return tuple(r for g in self.groups for r in g.rows) + self.rare

    @property
    def rare_units(self) -> int:
        return sum(r.units for r in self.rare)

    @property
    def rare_fraction(self) -> float:
        """Share of the units the rare overlaps cover together."""
        return self.rare_units / self.total_units

    def to_json(self) -> dict[str, Any]:
        return {
            "views": list(self.views),
            "grouped_by": self.by,
            "rare_below": self.rare_share,
            "pairs": len(self.rows),
            "groups": [g.to_json() for g in self.groups],
            "rare": {
                "count": len(self.rare),
                "units": self.rare_units,
                "share": round(self.rare_fraction, 4),
                "overlaps": [r.to_json() for r in self.rare],
            },
        }

    def lines(self) -> list[str]:
        """The table as text: a line per group, an indented line per overlap, the rare line."""
        v0, v1 = self.views
        seen = f"from {self.by}" if self.by != "both" else "from both views"
        p0, p1 = (_PICTURE.get(v, v) for v in self.views)
        out = [
            f"{len(self.rows)} overlap pairs, grouped by the fill seen {seen}"
            f" (a colour of {p0} over a colour of {p1}; share of the units):"
        ]
        for g in self.groups:
            colour = f" ({g.fill_color})" if g.fill_color else ""
            out.append(f"  {g.fill}{colour}: {len(g.rows)} overlap(s), {_pct(g.share)}")
            for r in g.rows:
                mark = " (set by hand)" if r.overridden else ""
                out.append(
                    f"    {v0}{r.a} {r.color_a} over {v1}{r.b} {r.color_b}: tile {r.tile}"
                    f" shows {r.fills[0]} | {r.fills[1]}{mark}, {_pct(r.share)}"
                )
        if self.rare:
            out.append(
                f"  {len(self.rare)} rare overlaps (each under {_pct(self.rare_share)}):"
                f" {_pct(self.rare_fraction)} of the units together"
            )
        return out


#: What the input of each view is called in the text table.
_PICTURE = {"headon": "the front picture", "side": "the side"}


def _pct(x: float) -> str:
    return f"{100 * x:.1f} %"


def _label(f: Fill | None, assignment: TileAssignment) -> str:
    return NO_FILL if f is None else f.label(assignment.yarns)


def group_overlaps(
    assignment: TileAssignment, *, by: str | None = None, rare_share: float = RARE_SHARE
) -> OverlapTable:
    """Group a design's overlap pairs by the fill their tiles show, folding the rare ones.

    Parameters
    ----------
    assignment : TileAssignment
        The design (its tiles as used, overrides included).
    by : str, optional
        One of the assignment's views (default the first), or ``"both"``.
    rare_share : float
        Overlaps covering less than this share of the units (0 <= rare_share <= 1) are folded
        into :attr:`OverlapTable.rare`.
    """
    views = (str(assignment.views[0]), str(assignment.views[1]))
    by = views[0] if by is None else by
    if by not in (*views, "both"):
        raise OptionError(f"`by` must be one of {', '.join((*views, 'both'))}, got {by!r}")
    if not 0 <= rare_share <= 1:
        raise OptionError(f"`rare_share` must lie in [0, 1], got {rare_share!r}")
    counts = overlap_pairs(assignment.indices_a, assignment.indices_b)
    total = int(assignment.indices_a.size)
    bank = assignment.bank
    groups: dict[str, tuple[str | None, list[OverlapRow]]] = {}
    rare: list[OverlapRow] = []
    for (a, b), units in sorted(counts.items(), key=lambda kv: (-kv[1], kv[0])):
        tile = assignment.tiles[a, b]
        seen = bank.fills_of(tile)
        fills = (seen.get(views[0]), seen.get(views[1]))  # type: ignore[call-overload]
        labels = (_label(fills[0], assignment), _label(fills[1], assignment))
        row = OverlapRow(
            a=a, b=b, units=units, share=units / total,
            color_a=hex_color(assignment.colors_a[a]), color_b=hex_color(assignment.colors_b[b]),
            fills=labels, tile=tile.code(), overridden=(a, b) in assignment.overridden,
        )  # fmt: skip
        if units < rare_share * total:
            rare.append(row)
            continue
        if by == "both":
            key, color = " | ".join(labels), None
        else:
            f = fills[views.index(by)]
            key, color = labels[views.index(by)], (None if f is None else f.hex)
        groups.setdefault(key, (color, []))[1].append(row)
    built = [OverlapGroup(k, c, tuple(rows)) for k, (c, rows) in groups.items()]
    built.sort(key=lambda g: -g.units)
    return OverlapTable(views, by, rare_share, total, tuple(built), tuple(rare))
