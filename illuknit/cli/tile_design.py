"""Running ``illuknit double`` and ``headon``: what the command asks for, parsed once into a
:class:`DesignRequest` (the pictures, where to write, the size and colours, the search, the
ranking and the machine), the design made by :func:`~illuknit.pipeline.tiles.design_double` or
:func:`~illuknit.pipeline.tiles.design_headon`, and every candidate written (:func:`write_design`).
"""

from __future__ import annotations

import json
import shutil
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from illuknit.cli.design_files import summary_text, write_candidate, write_edits
from illuknit.core.gauge import Gauge, drawn_gauge, finished_size
from illuknit.core.progress import Report
from illuknit.design.options import MadeFor, RankOptions, SearchOptions
from illuknit.pipeline.inputs import PictureOptions

if TYPE_CHECKING:
    from illuknit.core.errors import LongFloatError
    from illuknit.core.machine import MachineSpec
    from illuknit.core.pattern import Yarn
    from illuknit.pipeline.designs import RankedDesign, TileDesign

__all__ = ["DesignRequest", "legible_step", "run_design", "write_design"]


@dataclass(frozen=True, eq=False)
class DesignRequest:
    """What ``illuknit double`` or ``headon`` asks for, checked and parsed once.

    Attributes
    ----------
    mode : {"double", "headon"}
    pictures : pair of Path
        Picture A and B (the front and the side of a head-on design; no side: None).
    outdir : Path
        The folder written (atomically).
    sizing : PictureOptions
        Width, stretch, unit aspect, colours (None: the pictures' own count, said in a note)
        and yarns.
    search, ranking : SearchOptions, RankOptions
    machine : MachineSpec
        The machine as the command resolved it (its gauge sizes the units and the finished
        piece; with ``knitout`` the default candidate is knit on it).
    bank_file : Path or None
        A tile bank of the user's own.
    pick : int
        The default candidate (copied to the top of ``outdir``).
    knitout : bool
        Also knit the default candidate and check the program.
    hand_model_asked : bool
        ``--hand-model-seconds`` was given (even at its default), so a design not made for
        hands notes that it changed nothing.
    """

    mode: Literal["double", "headon"]
    pictures: tuple[Path, Path | None]
    outdir: Path
    sizing: PictureOptions
    search: SearchOptions
    ranking: RankOptions
    machine: MachineSpec
    bank_file: Path | None = None
    pick: int = 1
    knitout: bool = False
    hand_model_asked: bool = False

    @property
    def sources(self) -> list[str | None]:
        """The pictures as the summaries name them."""
        a, b = self.pictures
        return [str(a), str(b) if b else None]

    @classmethod
    def from_switches(
        cls,
        path_a: Path,
        path_b: Path | None,
        outdir: Path,
        *,
        mode: Literal["double", "headon"] = "double",
        **switches: Any,
    ) -> DesignRequest:
        """The request of the command line's switches (``--candidates`` is ``candidates=``, the
        names of :func:`design_options`), contradictions refused first."""
        s = {**_SWITCH_DEFAULTS, **switches}
        unknown = sorted(set(s) - set(_SWITCH_DEFAULTS))
        if unknown:
            raise TypeError(f"unknown switch of illuknit {mode}: {unknown[0]}")
        return _request(cls, (path_a, path_b), outdir, mode, s)


#: The switches of ``double`` and ``headon`` and their defaults (``read`` None: when the reader
#: is installed, for a double view).
_SWITCH_DEFAULTS: Mapping[str, Any] = {
    "n_colors": None, "yarns": None, "width": None, "resize": False, "candidates": 5,
    "pool": None, "bank_file": None, "pick": 1, "solver": "cpsat", "brightness": "hard",
    "one_sided": False, "split_bumps": False, "split_share": None, "tile": (),
    "knitout": False, "machine": None, "rank_by": "auto", "knit_time": False,
    "simplify": False, "suggest": False, "distance": 3.0, "angle": 30.0, "read": None,
    "made_for": "machine", "hand_model_seconds": None,
}  # fmt: skip


def _request(
    cls: type[DesignRequest],
    pictures: tuple[Path, Path | None],
    outdir: Path,
    mode: Literal["double", "headon"],
    s: Mapping[str, Any],
) -> DesignRequest:
    """:meth:`DesignRequest.from_switches`, the switches ``s`` complete."""
    from illuknit.cli.knitout_bridge import design_unit_aspect, resolve_machine
    from illuknit.core.errors import ImageInputError
    from illuknit.core.views import DEFAULT_SPLIT_SHARE
    from illuknit.design.options import Brightness, PictureEdits, RankBy

    path_a, path_b = pictures
    edits = (s["simplify"] or s["suggest"]) and (mode != "double" or not path_b)
    _check_counts(s["candidates"], s["pool"], edits=edits)
    overrides = tuple(_parse_overrides(s["tile"]).items())
    ranking = RankOptions(
        RankBy(s["rank_by"]), s["knit_time"], s["machine"], overrides, s["angle"], s["distance"],
        read=_read(s["read"], mode), made_for=MadeFor(s["made_for"]),
    )  # fmt: skip
    spec = resolve_machine(s["machine"])
    search = SearchOptions(
        candidates=s["candidates"],
        solver=s["solver"],
        brightness=Brightness(s["brightness"]),
        one_sided=s["one_sided"],
        split_bumps=s["split_bumps"] or s["split_share"] is not None,
        split_share=DEFAULT_SPLIT_SHARE if s["split_share"] is None else s["split_share"],
        edits=PictureEdits("apply" if s["simplify"] else "suggest" if s["suggest"] else "none"),
        **({} if s["pool"] is None else {"pool": s["pool"]}),
        **(
            {}
            if s["hand_model_seconds"] is None
            else {"hand_model_seconds": s["hand_model_seconds"]}
        ),
    )
    sizing = PictureOptions(
        width=s["width"],
        stretch=s["resize"],
        unit_aspect=design_unit_aspect(spec, s["made_for"]),
        n_colors=s["n_colors"],
        yarns=_yarns_option(s["yarns"]),
    )
    if mode == "double" and path_b is None:
        raise ImageInputError("a double-view design needs two pictures (A and B)")
    return cls(
        mode, (path_a, path_b), outdir, sizing, search, ranking, spec,
        bank_file=s["bank_file"], pick=s["pick"], knitout=s["knitout"],
        hand_model_asked=s["hand_model_seconds"] is not None,
    )  # fmt: skip


def run_design(request: DesignRequest, *, progress: Report | None = None) -> dict[str, Any]:
    """Call :func:`~illuknit.pipeline.tiles.design_double` (or
    :func:`~illuknit.pipeline.tiles.design_headon`) as ``request`` asks and write every candidate
    (atomically into ``request.outdir``); with ``request.knitout`` the default candidate is knit
    on ``request.machine``. ``progress(fraction, message)`` hears how far the work is (the
    command line's bar); the designs are judged from the ranking's angle and distance, the
    reader asked whether each side reads when ``ranking.read``; ``made_for="hands"`` ranks the
    designs a hand knitter can work first. Returns the summary."""
    from illuknit.core.errors import LongFloatError, TileAssignmentError
    from illuknit.pipeline.tiles import design_double, design_headon

    report: Report = progress or (lambda fraction, message: None)
    pictures = [p for p in request.pictures if p is not None]
    n_colors, notes = _colour_count(
        pictures, request.sizing.n_colors, given_yarns=request.sizing.yarns is not None
    )
    sizing = replace(request.sizing, n_colors=n_colors)
    stage: Callable[..., TileDesign] = design_double if request.mode == "double" else design_headon

    def redo(search: SearchOptions, say: Report) -> TileDesign:
        return stage(
            *request.pictures, pictures=sizing, bank=request.bank_file, search=search,
            ranking=request.ranking, knit_on=request.machine if request.knitout else None,
            progress=say,
        )  # fmt: skip

    design = redo(request.search, lambda f, message: report(0.7 * f, message))
    written = len(design.designs)
    if not 1 <= request.pick <= written:
        raise TileAssignmentError(
            f"--pick must be between 1 and {written} (candidates found), got {request.pick}"
        )
    notes += _split_note(design, request.search) + _read_note(design, request.ranking)
    notes += _hand_model_note(request)
    try:
        return write_design(design, request, progress=report, notes=notes)
    except LongFloatError as e:
        report(0.97, "the knitting was refused: measuring what knits it")
        quiet: Report = lambda f, message: None  # noqa: E731
        raise _share_remedy(e, request, lambda s: redo(s, quiet)) from None


def _yarns_option(spec: str | None) -> tuple[Yarn, ...] | int | None:
    """``--yarns``: a number of yarns to choose from the pictures, or a list of yarns."""
    from illuknit.core.pattern import parse_yarns

    if spec is not None and not spec.strip().isdigit():
        return parse_yarns(spec)
    if spec is None:
        return None
    n = int(spec)
    if not 1 <= n <= 8:
        from illuknit.core.errors import YarnSpecError

        raise YarnSpecError(f"--yarns N must be between 1 and 8, got {n}")
    return n


def _check_counts(candidates: int, pool: int | None, *, edits: bool) -> None:
    """Refuse counts below one, and picture edits where there are no two pictures."""
    from illuknit.core.errors import OptionError, TileAssignmentError

    if candidates < 1:
        raise TileAssignmentError(f"--candidates must be at least 1, got {candidates}")
    if pool is not None and pool < 1:
        raise TileAssignmentError(f"--pool must be at least 1, got {pool}")
    if edits:
        raise OptionError("--simplify and --suggest work on double-view designs (two pictures)")


def _share_remedy(
    error: LongFloatError, request: DesignRequest, redesign: Callable[[SearchOptions], TileDesign]
) -> LongFloatError:
    """``error`` (a knitting refusal of a split-bump design, the folder written) with the
    default split share measured as a remedy: the design made again at that share and its best
    candidate knit. Said in the error and in the folder's note; ``error`` itself otherwise."""
    import warnings
    from dataclasses import replace

    from illuknit.cli.knitout_bridge import REFUSAL_NOTE
    from illuknit.core.errors import LongFloatError
    from illuknit.core.files import atomic_write_text
    from illuknit.core.views import DEFAULT_SPLIT_SHARE
    from illuknit.knitting import knit_pattern

    search, outdir, machine = request.search, request.outdir, request.machine
    if not search.split_bumps or search.split_share <= DEFAULT_SPLIT_SHARE:
        return error
    share = DEFAULT_SPLIT_SHARE
    best = redesign(replace(search, split_share=share, candidates=1)).designs[0].pattern
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            knit = knit_pattern(best, machine=machine).summary()
        line = (
            f"designed again with --split-share {share:g}, it knits (measured: "
            f"{int(best.split.sum())} split bumps, longest float {knit['longest_float']} "
            f"needles skipped, {knit['passes']} passes)"
        )
    except LongFloatError as again:
        line = (
            f"--split-share {share:g} was tried and does not help (a float of {again.length} stays)"
        )
    note, summary = outdir / REFUSAL_NOTE, outdir / "summary.json"
    if note.exists():
        atomic_write_text(note, note.read_text() + f"{line[0].upper()}{line[1:]}\n")
    if summary.exists():
        doc = json.loads(summary.read_text())
        doc["program_refused"] = f"{error}; {line}"
        atomic_write_text(summary, json.dumps(doc, indent=1) + "\n")
    return LongFloatError(
        f"{error}; {line}",
        length=error.length, carrier=error.carrier, from_needle=error.from_needle,
        to_needle=error.to_needle, course=error.course, where=error.where, limit=error.limit,
        count=error.count,
    )  # fmt: skip


#: Most distinct colours a picture may have to count as drawn in flat colours.
_FLAT_MAX = 8


def _flat_colours(path: Path) -> int | None:
    """How many colours ``path`` is drawn in, when it is drawn in a few flat ones (None for a
    photo, a drawing with soft edges, or a picture ``design_*`` will refuse with its own error)."""
    from illuknit.core.errors import ImageInputError
    from illuknit.pictures.decode import read_picture
    from illuknit.pictures.images import flat_color_count

    try:
        return flat_color_count(read_picture(path).rgb, most=_FLAT_MAX)
    except ImageInputError:
        return None


def _colour_count(
    pictures: list[Path], n_colors: int | None, *, given_yarns: bool
) -> tuple[int, list[str]]:
    """The colours each picture is quantised to, and a note saying what was chosen and how to
    change it. Given ``--colors``, that; else the pictures' own count when each is drawn in
    the same 2 to 4 flat colours, else 2 (with a note naming any picture that has more)."""
    if n_colors is not None:
        return n_colors, []
    if given_yarns:  # the yarns decide: no picture is read for its colours
        return 2, []
    counts = [_flat_colours(p) for p in pictures]
    if counts and len(set(counts)) == 1 and counts[0] in (3, 4):
        n = counts[0]
        return n, [f"colours: {n}, the pictures' own count (each is drawn in {n} flat colours); "
                   "--colors N chooses another"]  # fmt: skip
    more = [f"{p.name} has {c}" for p, c in zip(pictures, counts, strict=True) if c and c > 2]
    if more:
        return 2, [f"colours: each picture quantised to 2 (the default), though {', '.join(more)} "
                   "flat colours; --colors 3 or 4 keeps more"]  # fmt: skip
    return 2, []


def _read_note(design: TileDesign, ranking: RankOptions) -> list[str]:
    """A note when --no-read changed nothing: the default order found two pictures of words
    and ranked by the reader, which reads every design."""
    from illuknit.design.options import RankBy

    order = design.order
    if ranking.read or order is None or order.asked is not RankBy.AUTO:
        return []
    if order.by is not RankBy.LEGIBILITY:
        return []
    return [
        "--no-read changed nothing: both pictures are words, so the default order (--rank-by "
        "auto) ranked the designs by the reader, which read every one; add --rank-by perception "
        "to read nothing"
    ]


def _hand_model_note(request: DesignRequest) -> list[str]:
    """A note when --hand-model-seconds changed nothing: the design is not made for hands."""
    from illuknit.design.options import HAND_MODEL_SECONDS

    asked = request.hand_model_asked or request.search.hand_model_seconds != HAND_MODEL_SECONDS
    if not asked or request.ranking.made_for is MadeFor.HANDS:
        return []
    return [
        "--hand-model-seconds changed nothing: the constraint model made for hands is solved "
        "only for a double view made for hands (--for hands)"
    ]


def _split_note(design: TileDesign, search: SearchOptions) -> list[str]:
    """A note when split bumps were allowed but no candidate uses one, and why."""
    if not search.split_bumps or any(int(d.pattern.split.sum()) for d in design.designs):
        return []
    n = len(design.designs)
    return [
        f"--split-bumps changed nothing: none of the {n} candidate(s) uses a split bump. At "
        f"split share {search.split_share:g} (each side sees {100 * search.split_share:.0f} % "
        "of a split bump's colour from its own course) the tile search found plain tiles at "
        "least as good for every overlap; a split share measured higher on a swatch "
        "(--split-share, docs/split-bumps.md) may let it choose them"
    ]


def write_design(
    design: TileDesign,
    request: DesignRequest,
    *,
    progress: Report | None = None,
    notes: Sequence[str] = (),
) -> dict[str, Any]:
    """Write a :class:`~illuknit.pipeline.designs.TileDesign` into ``request.outdir``
    (atomically): each candidate's folder, the suggested edits, the default candidate
    (``request.pick``)'s pattern (and, with ``request.knitout``, its knitout program for
    ``request.machine``) and the summary. Returns the summary dict. The machine's fabric gauge
    gives the finished size; the ranking's angle and distance (metres) the views of each
    candidate's ``seen.png``; ``notes`` (what a switch did or did not do) go into the summary."""
    from illuknit.core.files import atomic_write_text, staged_dir
    from illuknit.outputs.previews import unit_scale
    from illuknit.pipeline.alternatives import alternatives

    gauge = request.machine.fabric_gauge
    # made for hands, the documents (pattern, previews, seen.png) are of the piece knitted by
    # hand, at the gauge its grid was sized for (cli.knitout_bridge.design_unit_aspect)
    documents = drawn_gauge(gauge, design.ranking.made_for)
    pick, sources = request.pick, request.sources
    machine = request.machine if request.knitout else None
    report: Report = progress or (lambda fraction, message: None)

    qa = design.quantised["A"]
    rows = []
    chosen = None
    overlap_lines: list[str] = []
    refused: list[Any] = []  # a knitting refusal, raised once the design is written
    with staged_dir(request.outdir) as tmp:
        for k, d in enumerate(design.designs):
            n = len(design.designs)
            report(0.7 + 0.24 * k / n, f"writing candidate {k + 1} of {n}")
            row, lines = write_candidate(
                d,
                tmp,
                design,
                pick=pick,
                sources=sources,
                gauge=documents,
                distance=design.ranking.distance,
                angle=design.ranking.angle,
            )
            rows.append(row)
            if row["default"]:
                chosen, overlap_lines = d.pattern, lines
        if design.edits:
            write_edits(list(design.edits), tmp / "suggestions", scale=max(2, unit_scale(qa.shape)))
        for name in ("pattern.json", "pattern.pdf", "chart.svg"):  # the picked design's
            shutil.copyfile(tmp / f"candidate_{pick}" / name, tmp / name)
        if machine is not None and chosen is not None:
            # The default candidate as a checked knitout program (mixed-colourwork scheduler).
            from illuknit.cli.knitout_bridge import write_program

            report(0.94, "knitting the default candidate and checking it")
            write_program(chosen, tmp, machine=machine, refused=refused)
        picked = design.designs[pick - 1]  # its bank and yarns: a stripe design has its own
        summary = {
            "mode": design.mode,
            "yarns": [{"name": y.name, "rgb": y.hex} for y in picked.pattern.yarns],
            "size": {"rows": int(qa.shape[0]), "cols": int(qa.shape[1])},
            "finished_size": finished_size(qa.shape, gauge).as_dict(),
            **_hand_size_json(design, qa.shape, documents),
            **_bank_json(picked),
            "solver": design.search.solver,
            "ranked_by": design.ranking.rank_by.value,
            **({"order": design.order.to_json()} if design.order is not None else {}),
            "made_for": design.ranking.made_for.value,
            "hand": _hand_json(picked),
            **_machine_json(design.machine_first),
            **({"hand_model": _jsonable(design.hand_model)} if design.hand_model else {}),
            "searched": design.searched,
            "edits": [e.to_json() for e in design.edits],
            "default": pick,
            "candidates": rows,
            **({"program_refused": str(refused[0])} if refused else {}),
            "notes": list(notes or ()),
        }
        if rows and rows[0].get("legibility"):
            summary["read_by"] = rows[0]["legibility"]["reader"]
        summary.update(alternatives(design, pick))
        step = legible_step(design, pick, request)
        if step is not None:
            summary["next_step"] = step
        atomic_write_text(tmp / "summary.json", json.dumps(summary, indent=1) + "\n")
        text = summary_text(summary, overlap_lines)
        atomic_write_text(tmp / "summary.txt", text + "".join(f"note: {n}\n" for n in notes or ()))
    if refused:
        raise refused[0]
    return summary


#: Widths (units) ``illuknit legible`` is offered past a design's own, a few at most.
_WIDER = (40, 50, 60, 70, 80, 100, 120, 150, 200, 250, 300)


def legible_step(design: TileDesign, pick: int, request: DesignRequest) -> dict[str, Any] | None:
    """When a word side of the design picked (``pick``, from 1) does not read: what to run next, as a
    command line (``illuknit legible A B --widths ...``, the widths past this design's, with
    the switches of ``request`` that change what it finds); None when every word side reads
    or none was read, or another candidate shown reads on every side (``--pick`` it: the
    summary says so). The width search is only named, never run here."""
    import shlex

    chosen = design.designs[pick - 1]
    verdict = chosen.legibility
    if verdict is None:
        return None
    failed = [s for s in verdict.sides if s.words is not None and not s.reads]
    if not failed or any(d.legibility and d.legibility.all_read for d in design.designs):
        return None
    width = int(chosen.pattern.shape[1])
    wider = [w for w in _WIDER if w > width][:4] or [width + 50, width + 100]
    a, b = request.pictures
    words = [shlex.quote(str(a)), shlex.quote(str(b))]
    words += ["--widths", ",".join(map(str, wider))]
    n_colors = len(design.quantised["A"].colors)  # as quantised: what `legible` quantises to
    if n_colors != 2:
        words += ["--colors", str(n_colors)]
    if request.sizing.stretch:
        words.append("--resize")
    ranking = request.ranking
    if ranking.angle != 30.0:
        words += ["--angle", f"{ranking.angle:g}"]
    if ranking.distance != 3.0:
        words += ["--distance", f"{ranking.distance:g}"]
    if isinstance(ranking.machine, str):
        words += ["--machine", shlex.quote(ranking.machine)]
    sides = ", ".join(f"side {s.view} does not read {s.words}" for s in failed)
    return {
        "why": f"{sides} at {width} units wide",
        "width": width,
        "widths": wider,
        "command": "illuknit legible " + " ".join(words),
    }


def _read(read: bool | None, mode: str) -> bool:
    """``--read/--no-read``: None reads a double view's sides when the reader is installed."""
    if read is not None:
        return read
    from illuknit.design.legibility import reader_available

    return mode == "double" and reader_available()


def _parse_overrides(specs: tuple[str, ...]) -> dict[tuple[int, int], str]:
    """``("0,1=0/1/0^", ...)`` -> ``{(0, 1): "0/1/0^"}`` (colour a of A, colour b of B)."""
    from illuknit.core.errors import TileAssignmentError

    out: dict[tuple[int, int], str] = {}
    for spec in specs:
        pair, sep, rows = spec.partition("=")
        try:
            a, b = (int(v) for v in pair.split(","))
        except ValueError:
            a = b = -1
        if not sep or not rows.strip() or a < 0 or b < 0:
            raise TileAssignmentError(
                f"--tile must look like 'A,B=ROWS' (e.g. '0,1=0/1/0^'), got {spec!r}"
            )
        out[a, b] = rows.strip()
    return out


def _bank_json(picked: RankedDesign) -> dict[str, Any]:
    """The default design's tile bank, or, for a design without tiles (the constraint model's
    made for hands), ``bank`` None and its ``method``."""
    if picked.assignment is None:
        return {"bank": None, "method": picked.label}
    bank = picked.assignment.bank
    return {"bank": {"name": bank.name, "tiles": len(bank)}}


def _jsonable(value: Any) -> Any:
    """Mappings and sequences as JSON's dicts and lists (a solver summary holds tuples)."""
    if isinstance(value, Mapping):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_jsonable(v) for v in value]
    return value


def _hand_size_json(design: Any, shape: tuple[int, int], documents: Gauge) -> dict[str, Any]:
    """Made for hands: ``{"hand_finished_size": ...}``, the size the hand pattern gives (at
    ``documents``, the gauge the documents are written at, and with the garter border,
    ``--border``); nothing when made for a machine."""
    if design.ranking.made_for is not MadeFor.HANDS:
        return {}
    from illuknit.cli.knitout_bridge import hand_border

    framed = (shape[0] + 2 * hand_border(), shape[1] + 2 * hand_border())
    size = finished_size(framed, documents).as_dict()
    return {"hand_finished_size": {**size, "estimate": documents.estimate}}


def _hand_json(d: RankedDesign) -> dict[str, Any] | None:
    hand = getattr(d.measures, "hand", None)
    return None if hand is None else dict(hand.to_json())


def _machine_json(first: Any) -> dict[str, Any]:
    """Made for hands: ``{"machine_design": ...}``, the hand cost and worse-side correlation of
    the design the ranking puts first for a machine (nothing when made for a machine)."""
    if first is None or first.hand is None:
        return {}
    return {
        "machine_design": {
            "hand": dict(first.hand.to_json()),
            "worse_readability": round(float(first.worse_readability), 4),
        }
    }
