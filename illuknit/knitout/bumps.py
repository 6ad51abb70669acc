"""What bumps a program knits, declared in a comment line of the program itself.

A program that knits split bumps (a yarn change inside a bump, ``docs/split-bumps.md``) or tall
bumps says so in one ``;`` comment line right after its ``;;`` header::

    ; illuknit-bumps: split 684 (split: a yarn change inside a bump is meant; docs/split-bumps.md)

:func:`declare_bumps` writes it (:func:`~illuknit.knitting.knit_pattern` does, for every
program with such bumps) and :func:`declared_bumps` reads it
(:func:`~illuknit.check.check_knitout` does, so one file has one verdict without
``--split-bumps``). A comment, not a ``;;X-`` header: both reference backends ignore comment
lines (the ``.dat`` and ``.kc`` stay byte-identical; tests/formats/test_oracles.py) and the PyPI
simulator refuses unknown headers.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass

from illuknit.knitout.program import KnitoutProgram

__all__ = ["BUMPS_COMMENT", "DeclaredBumps", "bumps_comment", "declare_bumps", "declared_bumps"]

#: How the declaring comment line starts.
BUMPS_COMMENT = "; illuknit-bumps:"


@dataclass(frozen=True)
class DeclaredBumps:
    """What a program declares: how many split bumps (0: none) and whether its bumps are tall."""

    split: int = 0
    tall: bool = False

    def __bool__(self) -> bool:
        return bool(self.split or self.tall)

    def text(self) -> str:
        """``"684 split bumps, tall bumps"``."""
        parts = ([f"{self.split} split bumps"] if self.split else []) + (
            ["tall bumps"] if self.tall else []
        )
        return ", ".join(parts) or "plain bumps"


def bumps_comment(*, split: int, tall: bool) -> str | None:
    """The declaring comment line (None when there are neither split nor tall bumps); the
    lowering writes it right after the ``;;`` header."""
    words = ([f"split {split}"] if split else []) + (["tall"] if tall else [])
    if not words:
        return None
    why = "split: a yarn change inside a bump is meant; " if split else ""
    return f"{BUMPS_COMMENT} {' '.join(words)} ({why}docs/split-bumps.md)"


def declare_bumps(text: str, *, split: int, tall: bool) -> str:
    """``text`` with the declaring comment line after its ``;;`` header (``text`` unchanged
    when it has neither split nor tall bumps)."""
    note = bumps_comment(split=split, tall=tall)
    if note is None:
        return text
    lines = text.split("\n")
    at = next((i for i, line in enumerate(lines) if i and not line.startswith(";;")), len(lines))
    return "\n".join([*lines[:at], note, *lines[at:]])


def declared_bumps(program: str | KnitoutProgram) -> DeclaredBumps:
    """The bumps a program (its text or the program) declares: the first declaring line among
    its leading comment lines (before its first operation); :class:`DeclaredBumps` ``()`` when
    there is none."""
    if isinstance(program, KnitoutProgram):
        first = program.operations[0].line if program.operations else program.n_lines + 1
        return _declared(text for line, text in program.comments if line < first)
    return _declared(_leading_comments(program))


def _leading_comments(text: str) -> Iterator[str]:
    for line in text.split("\n"):
        if line.strip() and not line.startswith(";"):
            return  # the first operation: the header and its comments are over
        yield line


def _declared(lines: Iterable[str]) -> DeclaredBumps:
    for line in lines:
        if line.startswith(BUMPS_COMMENT):
            words = line[len(BUMPS_COMMENT) :].split("(")[0].split()
            split = 0
            if "split" in words:
                i = words.index("split")
                nxt = words[i + 1] if i + 1 < len(words) else ""
                split = int(nxt) if nxt.isdigit() else 1
            return DeclaredBumps(split, "tall" in words)
    return DeclaredBumps()
