"""The knitout program as data (:mod:`~illuknit.knitout.program`) and its parser, below the
scheduler that lowers to it and read by the checker and the machine formats."""

from illuknit.knitout.parse import parse_knitout
from illuknit.knitout.program import (
    Bed,
    Direction,
    KnitoutProgram,
    Needle,
    Opcode,
    Operation,
    format_knitout,
)

__all__ = [
    "Bed",
    "Direction",
    "KnitoutProgram",
    "Needle",
    "Opcode",
    "Operation",
    "format_knitout",
    "parse_knitout",
]
