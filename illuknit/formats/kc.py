"""Kniterate k-code (``.kc``): knitout -> the file the Kniterate reads (as ``command.kc``).

Two stages: :func:`~illuknit.formats.kc_passes.read_kc_passes` groups knitout operations into
carriage passes, then :func:`write_kcode` places the design on the 252-needle bed (``;;Position:``)
and writes each pass as five lines: the front and back needle selections with the carriage (``/``
... ``\\``) and carrier turning points marked in them, the stitch number of every needle on each
bed, and the pass line (direction, pass type, carrier, speed, roller advance). Transfer passes are
split in two (``x-xfer-style two-pass``) or four (the default: every other needle per pass), and an
empty carriage move is inserted whenever the carriage is on the wrong side for the next pass.

The output is the CMU Kniterate backend's (``knitout-to-kcode.js``) byte for byte, apart from the
third line, a comment naming the file. Where that backend's own consistency checks would fail
(it then still writes a file), :class:`~illuknit.core.errors.KcodeError` is raised instead.

Examples
--------
>>> kc = knitout_to_kc(
...     ";!knitout-2\\n;;Carriers: 1 2 3 4 5 6\\nin 3\\nknit + f10 3\\nknit + f11 3\\nout 3\\n",
...     name="swatch.kc",
... )
>>> kc.splitlines()[:3]
['HOME', 'RACK:0', '// swatch.kc']
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from illuknit.core.errors import KcodeError
from illuknit.formats.kc_ir import KcPass, KcProgram
from illuknit.formats.kc_passes import read_kc_passes
from illuknit.knitout.program import KnitoutProgram

__all__ = [
    "BED_NEEDLES",
    "KcCode",
    "KcRow",
    "knitout_to_kc",
    "knitout_to_kc_code",
    "named_kc",
    "write_kc",
    "write_kcode",
]

BED_NEEDLES = 252
_MARGIN = 15  # unused needle-selection columns on either side of the bed
_COLUMNS = BED_NEEDLES + 1  # the selection strings hold one column beyond the last needle
# where each carrier waits before its first pass, in needles from the bed's left end
_PARKING = {"1": -11.5, "2": -9.5, "3": -9.5, "4": -7.5, "5": -7.5, "6": -7.5}


@dataclass(frozen=True)
class KcRow:
    """One carriage pass of a ``.kc`` (a ``>>`` / ``<<`` line), as written.

    Attributes
    ----------
    kind : str
        Its pass type (``Kn-Kn``, ``Tr-Rr``, ``Tu-Tu``, ...).
    span : int
        Carriage travel between the turning points (``/`` .. ``\\`` of its front needle row), in
        needles.
    speed : str
        The speed number it states.
    """

    kind: str
    span: int
    speed: str


@dataclass(frozen=True)
class KcCode:
    """A ``.kc``: its text and its passes (so its reader need not scrape the text back)."""

    text: str
    rows: tuple[KcRow, ...]


def knitout_to_kc(program: KnitoutProgram | str, *, name: str) -> str:
    """Convert a knitout program (or its text) to Kniterate k-code.

    Parameters
    ----------
    program : KnitoutProgram or str
        Knitout-2 for the Kniterate: ``;;Carriers: 1 2 3 4 5 6``, yarns in with ``in`` and out
        with ``out`` (no hook), one carrier per stitch, ``x-stitch-number`` for stitch sizes.
    name : str
        The file name written in the comment on line 3.

    Returns
    -------
    str
        The ``.kc`` text, LF line endings, ending with a newline.

    Raises
    ------
    KcodeError
        If the program cannot be knitted as written on the Kniterate.
    """
    return knitout_to_kc_code(program, name=name).text


def knitout_to_kc_code(program: KnitoutProgram | str, *, name: str) -> KcCode:
    """:func:`knitout_to_kc` with the passes it writes (:class:`KcCode`)."""
    return write_kc(read_kc_passes(program), name=name)


@dataclass
class _Row:
    """One k-code pass before its carriage stops are final (the next pass may still move them)."""

    front: list[str]
    back: list[str]
    stif: str
    stir: str
    rack: float
    direction: str
    kind: str
    speed: int | str
    roller: float
    left: float = math.inf
    right: float = -math.inf
    carrier: str | None = None
    carrier_left: float = 0.0
    carrier_right: float = 0.0
    comment: str | None = None
    pause_message: str | None = None


@dataclass
class _Carriage:
    """Where the carriage and the carriers are between passes, and the rows written so far."""

    offset: int  # front needle = slot + offset
    spacing: float
    stop_distance: float
    rows: list[_Row] = field(default_factory=list)
    direction: str = "+"
    left: float = -11.5
    right: float = BED_NEEDLES - 1 + 11.5
    rack: float = 0.0
    carrier_at: dict[str, float] = field(default_factory=lambda: dict(_PARKING))
    floor_step: dict[str, bool] = field(default_factory=lambda: {"-": True, "+": True})

    def push(self, row: _Row) -> None:
        self.rows.append(row)
        self.direction = "-" if self.direction == "+" else "+"

    def move(self) -> None:
        """An empty pass taking the carriage to the other side."""
        blank = ["."] * _MARGIN + ["_"] * BED_NEEDLES + ["."] * _MARGIN
        zeros = "0" * len(blank)
        row = _Row(blank, list(blank), zeros, zeros, self.rack, self.direction, "Kn-Kn", 300, 0)
        row.left, row.right = self.left, self.right
        row.comment = "automatically inserted carriage move"
        self.push(row)

    def start(self, direction: str, left: float, right: float) -> tuple[float, float]:
        """Stretch the turning point the carriage starts from (and the previous pass's end) so the
        pass fits; return the pass's carriage stops."""
        prev = self.rows[-1] if self.rows else None
        if direction == "-":
            self.right = max(self.right, right)
            if prev is not None:
                prev.right = self.right
            self.left = left
        else:
            self.left = min(self.left, left)
            if prev is not None:
                prev.left = self.left
            self.right = right
        return self.left, self.right

    def bump(self, carrier: str, stop: float, step: float) -> float:
        """Move a carrier's stop outwards until no other carrier sits there; half-needle steps
        alternate between rounding down and up."""
        side = "-" if step < 0 else "+"
        new = stop
        while any(at == new for c, at in self.carrier_at.items() if c != carrier):
            taken = step
            if abs(step) % 1 == 0.5:
                whole = math.floor(abs(step)) if self.floor_step[side] else math.ceil(abs(step))
                taken = math.copysign(whole, step)
                if new + taken != stop:
                    self.floor_step[side] = not self.floor_step[side]
            new += taken
        return new


def named_kc(kc: str, name: str) -> str:
    """``kc`` (:func:`knitout_to_kc`'s text) naming ``name`` in its line-3 comment instead: the
    same text :func:`knitout_to_kc` writes for that name, without converting again."""
    head = kc.split("\n", 3)
    if len(head) < 4 or not head[2].startswith("// "):
        raise KcodeError("not a .kc written by knitout_to_kc (no name comment on line 3)")
    head[2] = f"// {name}"
    return "\n".join(head)


def write_kcode(program: KcProgram, *, name: str) -> str:
    """Write the passes of ``program`` as k-code text; ``name`` goes in the line-3 comment."""
    return write_kc(program, name=name).text


def write_kc(program: KcProgram, *, name: str) -> KcCode:
    """:func:`write_kcode`'s text and the carriage passes it writes (:class:`KcCode`)."""
    if not program.passes:
        raise KcodeError("the program knits nothing")
    lo = min(p.lo for p in program.passes)
    hi = max(p.hi for p in program.passes)
    offset = {
        "Center": math.floor(0.5 * BED_NEEDLES - 0.5 * (hi + lo)),
        "Keep": -1,
        "Left": -lo,
        "Right": BED_NEEDLES - 1 - hi,
    }[program.headers.position]
    carriage = _Carriage(offset, program.carrier_spacing, program.carrier_stopping_distance)
    for p in program.passes:
        _check_on_bed(p, offset)
        if p.kind.family == "xfer":
            _add_transfers(carriage, p)
        else:
            _add_stitches(carriage, p)
    return _format(carriage.rows, name=name)


def _check_on_bed(p: KcPass, offset: int) -> None:
    for s, op in p.slots.items():
        needles = []
        if op.front:
            needles.append(("f", s + offset))
        if op.back:
            needles.append(("b", s + offset - math.floor(p.racking)))
        for bed, n in needles:
            if not 0 <= n < BED_NEEDLES:
                raise KcodeError(
                    f"needle {bed}{n} (bed position) is off the Kniterate's {BED_NEEDLES}-needle "
                    f"bed: the piece is too wide or placed off the bed",
                    line=p.line,
                    needle=f"{bed}{n}",
                )


def _stitch_numbers(
    p: KcPass, sizes: dict[int, dict[str, str]], direction: str, default: str, offset: int
) -> tuple[str, str]:
    """STIF/STIR: each bed's stitch number per column, gaps filled from the next set needle in the
    pass direction (or the only neighbour at the ends)."""
    shift = math.floor(p.racking)
    by_bed: dict[str, dict[int, str]] = {"f": {}, "b": {}}
    for s, size in sizes.items():
        for bed, number in size.items():
            by_bed[bed][s] = number
    f, b = by_bed["f"], by_bed["b"]
    pad = ["*"] * _MARGIN
    front = pad + [f.get(n - offset, "*") for n in range(_COLUMNS)] + pad
    back = pad + [b.get(n + shift - offset, "*") for n in range(_COLUMNS)] + pad
    return _fill(front, direction, default), _fill(back, direction, default)


def _fill(values: list[str], direction: str, default: str) -> str:
    if all(v == "*" for v in values):
        return default * len(values)
    out = values
    # each gap of unknown columns takes its left or right neighbour
    result: list[str] = []
    prev_value: str | None = None
    i = 0
    while i < len(out):
        if out[i] != "*":
            prev_value = out[i]
            result.append(out[i])
            i += 1
            continue
        j = i
        while j < len(out) and out[j] == "*":
            j += 1
        fill = out[j] if prev_value is None or (j < len(out) and direction == "+") else prev_value
        result.extend(fill * (j - i))
        i = j
    return "".join(result)


def _add_transfers(carriage: _Carriage, p: KcPass) -> None:
    """A transfer pass becomes two k-code passes (front-to-back, back-to-front) or four (each of
    those on every other needle, in needle order)."""
    shift, off = math.floor(p.racking), carriage.offset
    front_slots = {s for s, op in p.slots.items() if op.front}
    back_slots = {s for s, op in p.slots.items() if op.back}
    fronts = [n for n in range(_COLUMNS) if n - off in front_slots]
    backs = [n for n in range(_COLUMNS) if n + shift - off in back_slots]
    if p.kind.xfer_style == "two-pass":
        groups = [("f", fronts, "[front-to-back]"), ("b", backs, "[back-to-front]")]
    else:
        groups = [
            ("f", fronts[0::2], "[front-to-back, even]"),
            ("f", fronts[1::2], "[front-to-back, odd]"),
            ("b", backs[0::2], "[back-to-front, even]"),
            ("b", backs[1::2], "[back-to-front, odd]"),
        ]
    for bed, needles, comment in groups:
        if needles:
            _add_transfer_row(carriage, p, bed, needles, comment)


def _add_transfer_row(
    carriage: _Carriage, p: KcPass, bed: str, needles: list[int], comment: str
) -> None:
    rack = int(p.racking)
    direction = carriage.direction
    to = {("f", "+"): "Tr-Rr", ("f", "-"): "Tr-Rl", ("b", "+"): "Rr-Tr", ("b", "-"): "Rl-Tr"}
    blank = ["."] * _MARGIN + ["_"] * _COLUMNS + ["."] * _MARGIN
    row = _Row(
        list(blank),
        list(blank),
        "",
        "",
        p.racking,
        direction,
        to[bed, direction],
        p.speed,
        p.roller,
        comment=comment,
    )
    if p.pause and p.pause_message:
        row.pause_message = p.pause_message
    sizes: dict[int, dict[str, str]] = {}
    for n in needles:
        fn, bn = (n, n - rack) if bed == "f" else (n + rack, n)
        if not (0 <= fn < _COLUMNS and 0 <= bn < _COLUMNS):
            raise KcodeError(f"transfer f{fn} <-> b{bn} is off the bed", line=p.line)
        row.front[_MARGIN + fn] = "-"
        row.back[_MARGIN + bn] = "-"
        row.left = min(row.left, n - carriage.stop_distance)
        row.right = max(row.right, n + carriage.stop_distance)
        fs, bs = fn - carriage.offset, bn + math.floor(p.racking) - carriage.offset
        sizes.setdefault(fs, {})["f"] = p.sizes[fs]["f"]
        sizes.setdefault(bs, {})["b"] = p.sizes[bs]["b"]
    row.stif, row.stir = _stitch_numbers(p, sizes, direction, "!", carriage.offset)
    row.left, row.right = carriage.start(direction, row.left, row.right)
    carriage.push(row)


def _add_stitches(carriage: _Carriage, p: KcPass) -> None:
    """A knit/tuck/split/soft-miss pass: one k-code pass, after a carriage move if needed."""
    carriage.rack = p.racking
    soft = p.kind.family == "soft"
    comment = "(decayed from a SOFT_MISS)" if soft else None
    if p.gripper == "out":
        comment = (comment or "") + "; carrier out"
    lo = p.lo + carriage.offset - carriage.stop_distance
    hi = p.hi + carriage.offset + carriage.stop_distance
    row = _Row(
        [],
        [],
        "",
        "",
        p.racking,
        carriage.direction,
        p.kind.kcode,
        p.speed,
        p.roller,
        comment=comment,
    )
    if p.pause and p.pause_message:
        row.pause_message = p.pause_message
    if p.carriers:
        _place_carrier(carriage, p, row, lo, hi)
    if row.direction != carriage.direction:
        carriage.move()
    if row.direction == "-":
        start_right = max(hi, row.carrier_right) if p.carriers else hi
        end_left = min(lo, row.carrier_left) if row.carrier_left else lo
        row.left, row.right = carriage.start("-", end_left, start_right)
    else:
        start_left = min(lo, row.carrier_left) if p.carriers else lo
        end_right = max(hi, row.carrier_right) if row.carrier_right else hi
        row.left, row.right = carriage.start("+", start_left, end_right)
    shift = math.floor(p.racking)
    fronts = {s for s, op in p.slots.items() if op.front}
    backs = {s for s, op in p.slots.items() if op.back}
    off = carriage.offset
    pad = ["."] * _MARGIN
    row.front = pad + ["-" if n - off in fronts else "_" for n in range(_COLUMNS)] + pad
    row.back = pad + ["-" if n + shift - off in backs else "_" for n in range(_COLUMNS)] + pad
    row.stif, row.stir = _stitch_numbers(p, p.sizes, row.direction, "0", carriage.offset)
    carriage.push(row)


def _place_carrier(carriage: _Carriage, p: KcPass, row: _Row, lo: float, hi: float) -> None:
    """Where the pass's carrier starts and stops (parked ones are not stacked on each other)."""
    c = p.carriers[0]
    row.direction = p.direction
    row.carrier = c
    if p.direction == "-":
        row.carrier_right = carriage.carrier_at[c]
        if p.gripper == "out":
            if _PARKING[c] > lo:
                raise KcodeError(f"carrier {c} goes out left of its parking place", line=p.line)
            row.carrier_left = _PARKING[c]
        else:
            row.carrier_left = carriage.bump(c, lo, -carriage.spacing)
        carriage.carrier_at[c] = row.carrier_left
    else:
        row.carrier_left = carriage.carrier_at[c]
        row.carrier_right = carriage.bump(c, hi, carriage.spacing)
        carriage.carrier_at[c] = row.carrier_right


def _js_number(x: float) -> str:
    """A number as JavaScript prints it (``1``, ``0.5``, ``-1.5``)."""
    return str(int(x)) if float(x).is_integer() else repr(float(x))


def _format(rows: list[_Row], *, name: str) -> KcCode:
    out = ["HOME", "RACK:0", f"// {name}"]
    written: list[KcRow] = []
    last_rack = 0.0
    for row in rows:
        if row.pause_message is not None:
            out.append(row.pause_message)
        out += ["//"] * 4
        if row.comment is not None:
            out.append("// " + row.comment)
        if row.rack != last_rack:
            out.append("RACK:" + _js_number(row.rack))
            last_rack = row.rack
        marks = [(row.right, "\\"), (row.left, "/")]
        if row.carrier is not None:
            marks = [
                (row.right, "\\"),
                (row.carrier_right, row.carrier),
                (row.carrier_left, row.carrier),
                (row.left, "/"),
            ]
        _check_stops(row)
        front, back = "".join(row.front), "".join(row.back)
        for at, mark in marks:  # right to left, so earlier marks do not shift later ones
            i = int(at + _MARGIN + 0.5)
            front = front[:i] + mark + front[i:]
            back = back[:i] + mark + back[i:]
        op = ">>" if row.direction == "+" else "<<"
        written.append(KcRow(row.kind, max(0, front.find("\\") - front.find("/")), f"{row.speed}"))
        out += [
            "FRNT:" + front,
            "STIF:" + row.stif,
            "REAR:" + back,
            "STIR:" + row.stir,
            f"{op} {row.kind} {row.carrier or '0'} {row.speed} {_js_number(row.roller)}",
        ]
    return KcCode("\n".join(out) + "\n", tuple(written))


def _check_stops(row: _Row) -> None:
    """The backend's own consistency checks on turning points (it warns and writes anyway)."""
    stops = [row.left, row.right]
    ordered = row.left < row.right
    if row.carrier is not None:
        stops += [row.carrier_left, row.carrier_right]
        ordered = ordered and row.left <= row.carrier_left < row.carrier_right <= row.right
    half = all(s - math.floor(s) == 0.5 for s in stops)
    inside = row.left + _MARGIN + 0.5 >= 0 and row.right + _MARGIN + 0.5 <= len(row.front)
    if not (ordered and half and inside):
        raise KcodeError(
            f"carriage/carrier turning points {stops} are inconsistent (pass {row.kind} "
            f"{row.direction} carrier {row.carrier}); the backend could not write this pass",
            carrier=row.carrier,
        )


def summarise_kc(kc: str) -> dict[str, object]:
    """What a knitter needs from a ``.kc``: passes, needles used, stitch numbers.

    Read from the k-code itself: ``passes`` counts its pass lines (carriage moves included),
    ``needles`` is the (first, last) bed needle selected on either bed, numbered 1..252 from the
    left end (the numbers ``;;Position: Keep`` uses), ``stitch_numbers`` the stitch numbers set on
    selected needles. (Its time: :func:`illuknit.knitting.carriage.kc_run` and the time model.)
    """
    passes = 0
    used: set[int] = set()
    numbers: set[str] = set()
    selection: dict[str, str] = {}
    for line in kc.split("\n"):
        tag, _, value = line.partition(":")
        if tag in ("FRNT", "REAR"):
            selection[tag] = value
        elif tag in ("STIF", "STIR"):
            bed = "FRNT" if tag == "STIF" else "REAR"
            marks = _selected(selection[bed])
            numbers.update(value[i] for i in marks)
            used.update(i - _MARGIN + 1 for i in marks)
        elif line.startswith((">>", "<<")):
            passes += 1
    return {
        "passes": passes,
        "needles": (min(used), max(used)) if used else None,
        "stitch_numbers": sorted(numbers),
    }


def _selected(row: str) -> list[int]:
    """Column indices of selected needles, with the stop marks taken out."""
    plain = [ch for ch in row if ch not in "/\\123456"]
    return [i for i, ch in enumerate(plain) if ch == "-"]
