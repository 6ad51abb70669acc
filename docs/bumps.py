"""Draw docs/img/split-bump.svg and docs/img/tall-bump.svg from the code: the carriage passes
that knit one split bump and one tall bump.

Each picture knits a tiny pattern with :func:`illuknit.knitting.knit_pattern` (3 units wide, the
middle unit of the top row raised) and draws the passes of the top unit row as the scheduler
emitted them, first pass at the top: for each pass its two needle beds (back above front) over the
fabric's needles, a knit as a filled loop and a tuck as an open ``V`` in the carrier's yarn
colour, a transfer as an arrow between the beds, and the carriage direction. Changing the
lowering or the schedulers changes the pictures; ``python docs/bumps.py --check`` exits 1 when
the SVGs on disk are not what the code draws (the test suite runs it).
"""

from __future__ import annotations

import sys
from html import escape
from pathlib import Path

import numpy as np

from illuknit.core.pattern import LogicalPattern, Yarn
from illuknit.knit.ir import Opcode, Pass, PassKind
from illuknit.knitting import knit_pattern

ROOT = Path(__file__).resolve().parent.parent
IMG = ROOT / "docs" / "img"

YARNS = (Yarn("cream", (236, 226, 200)), Yarn("navy", (31, 58, 110)), Yarn("red", (200, 16, 46)))
CELL, ROW, LEFT, TOP = 22, 44, 190, 46


def _pattern(split: bool) -> LogicalPattern:
    yarn = np.zeros((2, 3), int)
    yarn[0, 1] = 1
    raised = np.zeros((2, 3), bool)
    raised[0, 1] = True
    upper = np.where(raised, 2, yarn) if split else None
    return LogicalPattern(yarn, raised, YARNS, upper=upper)


def _passes(split: bool) -> tuple[list[Pass], dict[str, tuple[int, int, int]], range]:
    """The passes of the top unit row's two courses (and the transfers around them)."""
    result = knit_pattern(_pattern(split), tall_bumps=not split)
    s = result.schedule
    colour = {c: s.yarns[y].rgb for y, cs in s.carrier_of_yarn.items() for c in cs}
    top = [p for p in s.passes if p.course in (2, 3) or (p.course == 4 and p.kind is PassKind.XFER)]
    return top, colour, range(s.left, s.left + s.wales)


def _hex(rgb: tuple[int, int, int]) -> str:
    return "#" + "".join(f"{v:02x}" for v in rgb)


def _label(p: Pass) -> str:
    if p.kind is PassKind.XFER:
        return f"course {p.course}: transfer"
    made = {o.op for o in p.ops if o.op is not Opcode.MISS}
    what = "tuck" if made == {Opcode.TUCK} else "knit" if made else "move"
    return f"course {p.course}: {what}, carrier {' '.join(p.carriers)}"


def draw(split: bool) -> str:
    passes, colour, needles = _passes(split)
    width = max(LEFT + CELL * len(needles) + 60, 500)
    height = TOP + ROW * len(passes) + 30
    title = (
        "split bump: first course navy, second (purl) course red"
        if split
        else "tall bump: a tuck on each purl needle, then the purl through it"
    )
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
        f'viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="11">',
        '<rect width="100%" height="100%" fill="white"/>',
        f'<text x="8" y="18" font-size="13">{escape(title)}</text>',
    ]
    for k, n in enumerate(needles):
        x = LEFT + CELL * k + CELL / 2
        out.append(f'<text x="{x}" y="{TOP - 10}" text-anchor="middle" fill="#666">{n}</text>')
    for i, p in enumerate(passes):
        y0 = TOP + ROW * i
        out.append(f'<text x="8" y="{y0 + 24}">{escape(_label(p))}</text>')
        for bed, dy in (("b", 10), ("f", 30)):
            out.append(f'<text x="{LEFT - 14}" y="{y0 + dy + 4}" fill="#999">{bed}</text>')
            for k in range(len(needles)):
                x = LEFT + CELL * k + CELL / 2
                out.append(f'<circle cx="{x}" cy="{y0 + dy}" r="1.5" fill="#bbb"/>')
        for o in p.ops:
            if o.needle not in needles:
                continue
            x = LEFT + CELL * (o.needle - needles.start) + CELL / 2
            y = y0 + (10 if o.bed == "b" else 30)
            if o.op is Opcode.XFER:
                y1 = y0 + (30 if o.bed == "b" else 10)
                tip = y1 + (-4 if y1 > y else 4)
                out.append(
                    f'<line x1="{x}" y1="{y}" x2="{x}" y2="{tip}" stroke="#555" stroke-width="1.5"/>'
                    f'<path d="M{x - 4},{tip} L{x + 4},{tip} L{x},{y1} Z" fill="#555"/>'
                )
                continue
            fill = _hex(colour[p.carriers[0]])
            if o.op is Opcode.KNIT:
                out.append(
                    f'<circle cx="{x}" cy="{y}" r="6" fill="{fill}" stroke="#333" stroke-width="0.6"/>'
                )
            elif o.op is Opcode.TUCK:
                out.append(
                    f'<path d="M{x - 6},{y - 6} L{x},{y + 5} L{x + 6},{y - 6}" fill="none" '
                    f'stroke="{fill}" stroke-width="3"/>'
                )
        if p.direction is not None:
            arrow = "\u2192" if p.direction == "+" else "\u2190"
            xa = LEFT + CELL * len(needles) + 14
            out.append(f'<text x="{xa}" y="{y0 + 24}" font-size="16">{arrow}</text>')
    out.append(
        f'<text x="8" y="{height - 8}" fill="#666">filled: knit, V: tuck, arrow: transfer; '
        "b back bed (purls), f front bed; first pass at the top</text>"
    )
    out.append("</svg>")
    return "\n".join(out) + "\n"


PICTURES = {"split-bump.svg": True, "tall-bump.svg": False}


def main(argv: list[str]) -> int:
    stale = []
    for name, split in PICTURES.items():
        svg = draw(split)
        path = IMG / name
        if "--check" in argv:
            if not path.exists() or path.read_text(encoding="utf-8") != svg:
                stale.append(name)
            continue
        path.write_text(svg, encoding="utf-8")
        print(f"wrote {path.relative_to(ROOT)}")
    if stale:
        print(f"docs/img/{', '.join(stale)} out of date: run python docs/bumps.py")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
