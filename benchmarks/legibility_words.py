"""Issue #38 target: at 100 units wide, every side of every word pair reads, by a reader.

Word pairs of this script's own (never the words of the tests) are drawn with Pillow in the
bundled DejaVu Sans Bold, black on white, designed with ``illuknit double``'s library call
(:func:`illuknit.pipeline.stages.design_double`, two colours) at 60, 80 and 100 units wide, and
the default design of two rankings is read by tesseract OCR
(:mod:`illuknit.design.legibility`: each side's angled render from 3 m at 30 degrees, on the
default machine's gauge):

* **perception** -- the old default order (the worse side's correlation, contrast floor), as
  ``illuknit double --rank-by perception`` ranks;
* **auto** -- the new default (``RankBy.AUTO``): the reader's order (designs whose both sides
  read first, then as perception) when both pictures are words and tesseract is installed,
  perception otherwise; the order it chose is printed.

Both read the kept designs as ``double`` does by default (``read=True``). Printed per pair and
width: what each default reads per side and the seconds of ranking (compiling, measuring and
reading); per width the sides that read out of all sides, against the target (at 100 units: all
of them, under the new default), and the mean seconds of ranking under each, whose difference
is what reading the whole pool costs.

Then the **picture measure** (``--no-calibrate`` skips it): over the candidates both rankings
keep at those widths, how often "the side's correlation is at least T" agrees with the reader's
verdict, for a few T (the floor :data:`~illuknit.design.legibility.PICTURE_FLOOR` a picture
side is judged by), and the same for contrast.

Then **A/B balance** on the bundled double-view instances (``--no-balance`` skips it; the
330 x 200 photo pair only with ``--all``): the default design's correlation per side, its
difference and the weaker side, under both rankings (their pictures are not words, except
the two ILLUSION / KNITTING pairs, so the verdict there is the shape agreement's estimate).

    python benchmarks/legibility_words.py [--widths 60,80,100] [--no-calibrate] [--no-balance] [--all]
"""

from __future__ import annotations

import argparse
import time
from importlib.resources import files
from typing import Any

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from illuknit.core.machine import resolve_machine
from illuknit.design.legibility import PICTURE_FLOOR, reader_available, shape_agreement
from illuknit.design.options import RankOptions
from illuknit.pipeline.stages import design_double

#: The benchmark's own words (the tests use others).
PAIRS = (("WOOL", "YARN"), ("LOOP", "PURL"), ("MOTH", "SILK"), ("KNIT", "FELT"))
RANKINGS = ("perception", "auto")


def word_picture(word: str, *, size: tuple[int, int] = (400, 130)) -> np.ndarray:
    """``word`` in DejaVu Sans Bold, black on white, centred in ``size`` (width, height) pixels."""
    font_file = files("illuknit") / "data" / "DejaVuSans-Bold.ttf"
    font = ImageFont.truetype(str(font_file), 100)
    box = ImageDraw.Draw(Image.new("L", (1, 1))).textbbox((0, 0), word, font=font)
    w, h = box[2] - box[0], box[3] - box[1]
    im = Image.new("RGB", size, "white")
    at = ((size[0] - w) // 2 - box[0], (size[1] - h) // 2 - box[1])
    ImageDraw.Draw(im).text(at, word, font=font, fill="black")
    return np.asarray(im)


def _cell(v: Any) -> str:
    s = v.sides
    return " ".join(f"{x.view}:{'+' if x.reads else '-'}{x.read or '.'}" for x in s)


def words(
    widths: list[int],
    calibrate: list[tuple[float, float, bool]],
    seconds: dict[tuple[str, int], list[float]],
) -> dict[tuple[str, int], int]:
    """Design and read every pair at every width under both rankings; returns sides read (and
    the seconds of ranking each design, in ``seconds``)."""
    read: dict[tuple[str, int], int] = {}
    print(f"{'pair':<10} {'width':>5}  " + "  ".join(f"{r + ' default':<62}" for r in RANKINGS))
    for a, b in PAIRS:
        pa, pb = word_picture(a), word_picture(b)
        for w in widths:
            cells = []
            for by in RANKINGS:
                t0 = time.perf_counter()
                # as `illuknit double --rank-by BY` searches, ranks and reads (5 candidates kept)
                ranking = RankOptions(rank_by=by, read=True)
                d = design_double(pa, pb, width=w, ranking=ranking)
                best = d.designs[0].legibility
                read[by, w] = read.get((by, w), 0) + best.sides_read
                seconds.setdefault((by, w), []).append(d.seconds["rank"])
                order = "" if d.order is None or by != "auto" else f" ({d.order.by.value})"
                cells.append(
                    f"{_cell(best):<28} {time.perf_counter() - t0:4.0f} s, rank {d.seconds['rank']:4.1f} s{order}"
                )
                for rd in d.designs:  # the candidates each ranking keeps (some twice)
                    m = rd.measures
                    for k, side in enumerate(rd.legibility.sides):
                        agree = shape_agreement(rd.pattern, d.targets[k], side.view)
                        calibrate.append((m.readability[k], agree, side.reads))
            print(f"{a + '/' + b:<10} {w:>5}  " + "  ".join(f"{c:<62}" for c in cells))
    return read


def agreement(calibrate: list[tuple[float, float, bool]]) -> None:
    """How well a floor on the correlation (or the contrast) agrees with the reader."""
    data = np.array([(c, g, r) for c, g, r in calibrate], dtype=float)
    n = len(data)
    reads = data[:, 2] > 0.5
    print(
        f"\npicture measure against the reader: {n} sides of the candidates kept, {reads.sum():.0f} read"
    )
    for name, col, floors in (
        ("correlation", 0, (0.80, 0.85, 0.88, 0.90, 0.92, 0.95, 0.97)),
        ("shapes", 1, (0.84, 0.86, 0.88, PICTURE_FLOOR, 0.90, 0.92)),
    ):
        cells = []
        for t in sorted(set(floors)):
            agree = float(((data[:, col] >= t) == reads).mean())
            cells.append(f">= {t:.2f}: {100 * agree:3.0f} %")
        print(f"  {name:<12} " + ", ".join(cells))
    print(
        f"  (base rate: {100 * max(reads.mean(), 1 - reads.mean()):.0f} %; PICTURE_FLOOR, the floor picture sides are judged by, is {PICTURE_FLOOR})"
    )


def balance(everything: bool) -> None:
    """A/B balance of the default design on every bundled double-view instance."""
    from illuknit.bench.instances import instance_targets, load_manifest

    insts = [i for i in load_manifest().instances if i.kind == "double"]
    if not everything:
        insts = [i for i in insts if i.size[0] * i.size[1] <= 20_000]
    print(
        "\nA/B balance of the default design (correlation A / B, |A - B|, weaker side by it; "
        "sides that read):"
    )
    print(f"{'instance':<24} " + "  ".join(f"{r:<60}" for r in RANKINGS))
    for inst in insts:
        t = instance_targets(inst)
        a, b = t.palette[t.a], t.palette[t.b]
        cells = []
        for by in RANKINGS:
            d = design_double(
                a, b, yarns=inst.yarns, n_colors=len(inst.yarns), width=t.a.shape[1],
                unit_aspect=1.0, ranking=RankOptions(rank_by=by, read=True),
            )  # fmt: skip
            r = d.designs[0].measures.readability
            order = "" if d.order is None or by != "auto" else f" [{d.order.by.value}]"
            weaker = "A" if r[0] < r[1] else "B"
            said = d.designs[0].legibility
            shapes = "/".join(
                "-" if x.agreement is None else f"{100 * x.agreement:.0f}" for x in said.sides
            )
            cells.append(
                f"{r[0]:.3f} / {r[1]:.3f}  {abs(r[0] - r[1]):.3f}  {weaker}  "
                f"reads {said.sides_read}/2{'' if said.sides[0].words else '*'} ({shapes} %){order}"
            )
        print(f"{inst.name:<24} " + "  ".join(f"{c:<60}" for c in cells))
    print(
        "(* judged by the shape agreement, in % per side A/B: the reader reads no words in these "
        "pictures)"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--widths", default="60,80,100", help="widths in units, comma-separated")
    ap.add_argument("--no-words", action="store_true", help="skip the word pairs")
    ap.add_argument("--no-calibrate", action="store_true", help="skip the picture measure")
    ap.add_argument("--no-balance", action="store_true", help="skip the bundled instances")
    ap.add_argument("--all", action="store_true", help="include the 330 x 200 photo pair")
    args = ap.parse_args()
    if not reader_available():
        raise SystemExit(
            "this benchmark needs the tesseract program: apt-get install tesseract-ocr"
        )
    widths = [int(w) for w in args.widths.split(",")]
    machine = resolve_machine(None)
    print(
        f"default machine: {machine.label} ({machine.gauge:g} stitches per inch), read from 3 m "
        "at 30 degrees"
    )
    if not args.no_words:
        report_words(widths, calibrate=not args.no_calibrate)
    if not args.no_balance:
        balance(args.all)


def report_words(widths: list[int], *, calibrate: bool) -> None:
    """The word pairs' verdicts, the sides that read per width, and the picture measure."""
    samples: list[tuple[float, float, bool]] = []
    seconds: dict[tuple[str, int], list[float]] = {}
    read = words(widths, samples, seconds)
    total = 2 * len(PAIRS)
    print("\nsides that read (of all sides of every pair's default design):")
    for w in widths:
        got = ", ".join(f"{by} {read[by, w]}/{total}" for by in RANKINGS)
        print(f"  {w:>4} units: {got}")
    print("\nseconds of ranking a design (compile, measure, read), mean over the pairs [min-max]:")
    for w in widths:
        got = ", ".join(
            f"{by} {np.mean(seconds[by, w]):.1f} [{min(seconds[by, w]):.1f}-{max(seconds[by, w]):.1f}]"
            for by in RANKINGS
        )
        extra = np.mean(seconds["auto", w]) - np.mean(seconds["perception", w])
        print(f"  {w:>4} units: {got}; the new default's extra: {extra:+.1f} s")
    last = max(widths)
    ok = read["auto", last] == total
    print(
        f"target at {last} units: every side reads under the new default: {'met' if ok else 'NOT met'}"
    )
    if calibrate:
        agreement(samples)


if __name__ == "__main__":
    main()
