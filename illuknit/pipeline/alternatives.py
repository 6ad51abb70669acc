"""Candidates shown that a user may prefer to the default, and why.

The orders rank by what reads, ghosting breaking ties only, and the order made for hands by the
rows a hand knitter can work, then by what reads. So the default can be a design in which much
of the other picture shows (the constraint model's design made for hands is solved for the
views alone), or one with far more colour work by hand than a candidate that reads nearly as
well. :func:`alternatives` names such a candidate, with both designs' figures
(:func:`~illuknit.design.tiles.perception.cleaner_alternative`,
:func:`~illuknit.design.tiles.perception.quicker_alternative`); :func:`alternative_sentences`
says it in words. ``double`` and ``headon`` write it to ``summary.json`` and ``summary.txt``
and print it; the app puts it on its first card.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from illuknit.design.options import MadeFor
from illuknit.pipeline.designs import TileDesign

__all__ = ["alternative_sentences", "alternatives"]


def alternatives(design: TileDesign, pick: int = 1) -> dict[str, dict[str, Any]]:
    """The candidates of ``design`` a user may prefer to ``pick`` (from 1): ``"cleaner"``, in
    which much less of the other picture shows, and, made for hands, ``"quicker_by_hand"``,
    much less hand knitting by the cover's estimate
    (:attr:`~illuknit.design.hand_cost.HandCost.hours`); each reads nearly as well. Each
    entry has the candidate's ``rank`` and its and the default's figures; none when there is
    no such candidate."""
    from illuknit.design.tiles.perception import cleaner_alternative, quicker_alternative

    hands = design.ranking.made_for is MadeFor.HANDS
    measures = [d.measures for d in design.designs]
    d = measures[pick - 1]
    out: dict[str, dict[str, Any]] = {}
    k = cleaner_alternative(measures, pick - 1, hands=hands)
    if k is not None:
        m = measures[k]
        out["cleaner"] = {
            "rank": design.designs[k].rank,
            "visible_ghosting": round(m.worst_visible_ghosting, 4),
            "perceptual_score": round(m.perceptual_score, 4),
            "default_visible_ghosting": round(d.worst_visible_ghosting, 4),
            "default_perceptual_score": round(d.perceptual_score, 4),
            "made_for": design.ranking.made_for.value,
        }
    if hands and all(m.hand is not None for m in measures):
        hours = [m.hand.hours for m in measures if m.hand is not None]
        k = quicker_alternative(measures, hours, pick - 1)
        if k is not None:
            m = measures[k]
            assert d.hand is not None and m.hand is not None  # measured for hands
            out["quicker_by_hand"] = {
                "rank": design.designs[k].rank,
                "hours": round(hours[k], 2),
                "colour_rows": m.hand.colour_rows,
                "perceptual_score": round(m.perceptual_score, 4),
                "default_hours": round(hours[pick - 1], 2),
                "default_colour_rows": d.hand.colour_rows,
                "default_perceptual_score": round(d.perceptual_score, 4),
                "rows": d.hand.rows,
            }
    return out


def _than(c: Mapping[str, Any]) -> str:
    """``c``'s perceptual score against the default's, in words."""
    drop = c["default_perceptual_score"] - c["perceptual_score"]
    than = f"{drop:.3f} lower" if drop > 0 else f"{-drop:.3f} higher" if drop < 0 else "the same"
    return (
        f"at a perceptual score {than} ({c['perceptual_score']:.3f} against "
        f"{c['default_perceptual_score']:.3f})"
    )


def alternative_sentences(found: Mapping[str, Mapping[str, Any]]) -> list[tuple[int, str]]:
    """:func:`alternatives`' entries (as written to ``summary.json``) in words, each with the
    rank of the candidate it names."""
    out = []
    c = found.get("cleaner")
    if c:
        hands = ", with as many rows knittable by hand" if c.get("made_for") == "hands" else ""
        out.append(
            (
                c["rank"],
                f"the other picture shows through the default's worse view on "
                f"{c['default_visible_ghosting']:.0%} of its variation (visible ghosting); in "
                f"candidate {c['rank']} on {c['visible_ghosting']:.0%}, {_than(c)}{hands}",
            )
        )
    q = found.get("quicker_by_hand")
    if q:
        out.append(
            (
                q["rank"],
                f"by hand, candidate {q['rank']} is quicker: colour in {q['colour_rows']} of "
                f"{q['rows']} rows against the default's {q['default_colour_rows']}, about "
                f"{q['hours']:.1f} hours against {q['default_hours']:.1f} (the cover's "
                f"estimate), {_than(q)}, every row as knittable",
            )
        )
    return out
