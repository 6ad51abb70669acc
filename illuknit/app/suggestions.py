"""Suggested edits of a double-view design's pictures, as the page offers them (paper Fig. 11-12).

    Prepared (double view) -> suggest_edits_for -> SuggestionSet: each edit of the library's
                              review (:func:`illuknit.design.tiles.simplify.review_edits`) as the
                              edited pictures, with the worse view's readability and the worst
                              ghosting of the best-reading design before and after
    SuggestionSet + an edit -> accepted (routers.suggestions) -> the session's new input
                              pictures, the design before kept for undo (app.history)

An edit is measured by the one path ``illuknit double --suggest`` and the benchmark take
(:func:`~illuknit.design.tiles.simplify.review_edits` without applying any): the best-reading tile
design of the edited pictures, judged against the designer's *original* quantised pictures. Its
progress hook drives the job's progress bar and cancels it. Every kind of edit the library
returns is offered the same way; nothing here knows the kinds by name.

The edited pictures are kept in their picture colours (the colours the legend maps to yarns), at
the piece's grid size, so that accepting one and quantising again gives back exactly the edited
picture. A set holds the pictures of every edit plus the unedited ones once; :meth:`nbytes`
counts them against the sessions' memory bound.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from illuknit.app.candidates import Progress
from illuknit.app.controls import blame
from illuknit.app.inputs import Prepared
from illuknit.core.errors import AppRequestError

__all__ = [
    "SuggestedEdit",
    "SuggestionSet",
    "SupersededError",
    "colour_counts",
    "require_double",
    "suggest_edits_for",
]


@dataclass(frozen=True, eq=False)
class SuggestedEdit:
    """One suggested edit, measured.

    Attributes
    ----------
    id : str
        ``"<set id>.<k>"``: unique in the server, and says which set (design) it was made for.
    kind, name, description : str
        The library's kind of edit, its name (unique in a set) and what it does, for the
        designer.
    changed : dict of str to int
        Units changed per picture slot (``"a"``, ``"b"``); only slots with changes are listed.
    pictures : dict of str to ndarray of shape (N, M, 3), uint8
        The edited picture of each changed slot, in picture colours.
    before, after : (float, float)
        Worse view's readability and worst ghosting of the best-reading design, before and
        after the edit, both against the original pictures.
    """

    id: str
    kind: str
    name: str
    description: str
    changed: dict[str, int]
    pictures: dict[str, NDArray[np.uint8]]
    before: tuple[float, float]
    after: tuple[float, float]

    @property
    def benefit(self) -> float:
        """What the edit gains: the worse side's readability gained plus the ghosting removed
        (both on a 0..1 scale; negative when it makes the design worse)."""
        return (self.after[0] - self.before[0]) - (self.after[1] - self.before[1])

    @property
    def verdict(self) -> str:
        """``"better"`` (reads better and ghosts no more), ``"worse"`` (reads worse, or ghosts
        more for no gain), ``"mixed"`` (one better, the other worse) or ``"same"``."""
        from illuknit.design.tiles.simplify import MIN_GAIN

        read = self.after[0] - self.before[0]
        ghost = self.after[1] - self.before[1]
        up, down = read > MIN_GAIN, read < -MIN_GAIN
        more, less = ghost > MIN_GAIN, ghost < -MIN_GAIN
        if (up and not more) or (less and not down):
            return "better"
        if (down and not less) or (more and not up):
            return "worse"
        if up or down:
            return "mixed"
        return "same"

    def effect_words(self) -> str:
        """The edit's effect in words, e.g. "the worse side's correlation 2 % higher; 13 % more
        ghosting" (the correlation is not a legibility scale: never "reads better")."""
        from illuknit.design.tiles.simplify import MIN_GAIN

        (r0, g0), (r1, g1) = self.before, self.after
        parts = []
        if abs(r1 - r0) <= MIN_GAIN:
            parts.append("the worse side's correlation unchanged")
        else:
            parts.append(
                f"the worse side's correlation {abs(r1 - r0) / max(abs(r0), 1e-9):.0%} "
                f"{'higher' if r1 > r0 else 'lower'}"
            )
        if abs(g1 - g0) <= MIN_GAIN:
            parts.append("ghosting unchanged")
        elif g1 > g0:
            parts.append(f"{(g1 - g0) / max(g0, 1e-9):.0%} more ghosting")
        else:
            parts.append(f"{(g0 - g1) / max(g0, 1e-9):.0%} less ghosting")
        return "; ".join(parts)

    def to_json(self) -> dict[str, Any]:
        from illuknit.design.tiles.simplify import MIN_GAIN

        r = _rounded
        return {
            "id": self.id,
            "kind": self.kind,
            "edit": self.name,
            "description": self.description,
            "units_changed": {slot.upper(): n for slot, n in self.changed.items()},
            "slots": sorted(self.changed),
            "readability_before": r(self.before[0]),
            "readability_after": r(self.after[0]),
            "ghosting_before": r(self.before[1]),
            "ghosting_after": r(self.after[1]),
            # the gain `illuknit double --simplify` would keep the edit for
            "improves": self.after[0] > self.before[0] + MIN_GAIN,
            "verdict": self.verdict,
            "benefit": r(self.benefit),
            "effect": self.effect_words(),
            "previews": {
                slot: {
                    which: f"suggestions/{self.id}/{slot}/{which}.png"
                    for which in ("before", "after")
                }
                for slot in sorted(self.changed)
            },
        }


@dataclass(frozen=True, eq=False)
class SuggestionSet:
    """The suggested edits made for one design (one revision of a session's inputs).

    ``originals`` are the unedited pictures (slot -> (N, M, 3) uint8, picture colours), the
    "before" of every edit.
    """

    id: str
    revision: int
    before: tuple[float, float]
    originals: dict[str, NDArray[np.uint8]]
    edits: tuple[SuggestedEdit, ...]

    def find(self, edit_id: str) -> SuggestedEdit | None:
        return next((e for e in self.edits if e.id == edit_id), None)

    def arrays(self) -> list[NDArray[np.uint8]]:
        """The pictures the set holds: the originals and every edited picture."""
        return [*self.originals.values(), *(p for e in self.edits for p in e.pictures.values())]

    def nbytes(self) -> int:
        """Memory the set holds: every edited picture and the originals."""
        return int(sum(p.nbytes for p in self.arrays()))


def _rounded(x: float) -> float | None:
    return None if x != x else round(float(x), 4)


def _picture(q: Any, indices: Any) -> NDArray[np.uint8]:
    """Index map ``indices`` of a quantised picture shown in its picture colours."""
    return np.asarray(q.colors, dtype=np.uint8)[np.asarray(indices)]


class SupersededError(AppRequestError):
    """A suggestion made for a design that has since been replaced (410 ``superseded``);
    ``successor`` is the id of the current suggestion set, if there is one."""

    def __init__(self, message: str, *, successor: str | None) -> None:
        super().__init__(message, field="suggestions", code="superseded", status=410)
        self.successor = successor


def require_double(prepared: Prepared) -> None:
    """Refuse (409 ``not_double``) suggestions for anything but a double view."""
    if prepared.mode != "double":
        raise AppRequestError(
            "suggested edits are for double-view designs (two pictures); switch to Double view",
            field="suggestions",
            code="not_double",
            status=409,
        )


def suggest_edits_for(
    prepared: Prepared,
    *,
    sources: dict[str, Any],
    set_id: str,
    revision: int,
    count: int,
    progress: Progress,
) -> SuggestionSet:
    """The library's suggested edits of a double view's two pictures, each measured.

    ``sources`` are the pictures on the grid before quantising (:func:`~illuknit.app.inputs.
    size_inputs`), which a re-quantisation reads again; it may use as many colours as there are
    yarns (at most 4, the app's bound). Each measurement searches the tile designs the candidates
    are found from (``count``, the session's candidate count, or the default pool of
    :mod:`illuknit.design.tiles.perception` if larger); ``progress(fraction, message)`` is called
    before each measurement, and may raise to cancel. Raises AppRequestError (409,
    ``not_double``) outside a double view.
    """
    from illuknit.design import tiles
    from illuknit.design.options import SearchOptions
    from illuknit.design.tiles.simplify import review_edits

    require_double(prepared)
    qa, qb = prepared.quantised["a"], prepared.quantised["b"]
    with blame("suggestions"):
        # the library's one review (as `illuknit double --suggest`): each edit measured on its
        # own; its progress hook reports here, and a cancelled job raises out of it
        results = review_edits(
            qa,
            qb,
            apply=False,
            targets=[qa.rgb(), qb.rgb()],
            sources=[sources["a"], sources["b"]],
            max_colors=min(4, len(prepared.yarns)),
            # the search the double-view stage makes (pipeline.stages.design_tiles)
            **SearchOptions(candidates=count).assign_kwargs(),
            bank=tiles.canonical_bank(prepared.yarns),
            progress=lambda fraction, message: progress(0.02 + 0.98 * fraction, message),
        ).results
    before = results[0].before if results else (float("nan"), float("nan"))
    edits = []
    for k, r in enumerate(results):
        edited = dict(zip(("a", "b"), r.suggestion.pictures(edited=True), strict=True))
        changed = {slot: n for slot, n in zip(("a", "b"), r.suggestion.changed, strict=True) if n}
        edits.append(
            SuggestedEdit(
                id=f"{set_id}.{k + 1}",
                kind=r.suggestion.kind,
                name=r.suggestion.name,
                description=r.suggestion.description,
                changed=changed,
                pictures={slot: np.ascontiguousarray(edited[slot]) for slot in changed},
                before=r.before,
                after=r.after,
            )
        )
    originals = {"a": _picture(qa, qa.indices), "b": _picture(qb, qb.indices)}
    return SuggestionSet(set_id, revision, before, originals, tuple(edits))


def colour_counts(set_: SuggestionSet, edit: SuggestedEdit) -> tuple[int, int]:
    """Colours of the pictures (the most of either) before and after ``edit``."""

    def most(pictures: dict[str, NDArray[np.uint8]]) -> int:
        return max(len(np.unique(p.reshape(-1, 3), axis=0)) for p in pictures.values())

    return most(set_.originals), most({**set_.originals, **edit.pictures})
