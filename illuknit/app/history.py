"""Undo and redo of accepted suggested edits: the session's earlier designs, kept whole.

    Session.remember(label) -> a DesignState on the session's undo steps (before an accept)
    Session.undo() / redo() -> the last state undone (redone) is the session's again

Accepting a suggested edit replaces the session's input pictures (and, for a re-quantisation, the
colour count) and designs again. Just before, the session keeps a :class:`DesignState`: its
pictures, settings and the design made from them -- quantised inputs, candidates with their
measures, the pick, tile edits, and the suggested edits with the refused ones. *Undo* makes that
state the session's again, so the design comes back exactly (no search is run again: the same
candidates, the same numbers) with the same suggestions, and another edit can be tried. The state
left by an undo is kept for *Redo*; any other change of the inputs (an upload, a setting, another
accepted edit) forgets the redo steps, as in any editor. Undo returns to the state before the
accept as a whole: what was changed after the accept is undone with it, and Redo brings it back.

Every restored state gets a new revision, so results still being computed for the state left
behind are never shown as current. A kept state shares its arrays with the session (a picture is
never copied) and :func:`held_arrays` counts each distinct array once, so the sessions' memory
bound sees what the history really costs: the pictures an accepted edit replaced (an upload, up to
2000 pixels on its long side: 12 MB at most per picture; an edited picture, at the grid, a few kB)
and the design of each step. At most :data:`STEPS_KEPT` steps are kept each way, the oldest
dropped first. The knitout is not kept (it is made again in seconds from the restored pattern).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from illuknit.core.errors import AppRequestError

__all__ = ["STEPS_KEPT", "DesignState", "held_arrays", "nothing_to"]

#: Undo steps (and redo steps) a session keeps; the oldest is dropped first.
STEPS_KEPT = 10


@dataclass(frozen=True, eq=False)
class DesignState:
    """A session's inputs and the design made from them, as undo and redo keep them.

    Attributes
    ----------
    label : str
        What the step taken from this state did (the accepted edit's description).
    images : dict of str to UploadedImage
        The input pictures (shared with the session, never copied).
    settings : DesignSettings
    prepared : Prepared or None
        The quantised inputs, when they had been made.
    candidates : tuple of Candidate
        The ranked candidates (with their measures, once measured) of these inputs; empty when
        they were not found yet.
    selected : int
    overrides : dict of (int, int) to str
        The designer's tile edits of the picked candidate.
    suggestions : SuggestionSet or None
        The suggested edits made for this design.
    refused : frozenset of str
        The ids of the refused ones.
    """

    label: str
    images: dict[str, Any]
    settings: Any
    prepared: Any
    candidates: tuple[Any, ...]
    selected: int
    overrides: dict[tuple[int, int], str]
    suggestions: Any
    refused: frozenset[str]

    def held(self) -> dict[int, int]:
        """The arrays it holds (see :func:`held_arrays`)."""
        return held_arrays(
            images=self.images,
            prepared=self.prepared,
            candidates=self.candidates,
            suggestions=self.suggestions,
        )


def held_arrays(
    *, images: dict[str, Any], prepared: Any, candidates: Any, suggestions: Any
) -> dict[int, int]:
    """``id -> bytes`` of every array held by pictures, quantised inputs, candidates (their
    patterns) and a suggestion set (its pictures). A union of these dicts counts an
    array shared by the session and its history once."""
    held = {id(im.rgb): int(im.nbytes) for im in images.values()}
    if prepared is not None:
        held.update({id(q.indices): int(q.indices.nbytes) for q in prepared.quantised.values()})
    for c in candidates:
        held[id(c.pattern.yarn)] = int(c.pattern.yarn.nbytes)
        held[id(c.pattern.raised)] = int(c.pattern.raised.nbytes)
    if suggestions is not None:
        held.update({id(p): int(p.nbytes) for p in suggestions.arrays()})
    return held


def nothing_to(what: str) -> AppRequestError:
    """The answer to an undo (``what="undo"``) or redo with no step to take: 409."""
    why = (
        "no suggested edit has been accepted in this session (or every accepted one has been "
        "undone already)"
        if what == "undo"
        else "nothing has been undone since the pictures or settings last changed"
    )
    return AppRequestError(
        f"there is nothing to {what}: {why}",
        field="suggestions",
        code=f"nothing_to_{what}",
        status=409,
    )
