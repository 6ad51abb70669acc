"""The knitout IR and its parser, read by the checker and the machine formats."""

from illuknit.knitout.parse import KnitoutProgram, Needle, Operation, parse_knitout

__all__ = ["KnitoutProgram", "Needle", "Operation", "parse_knitout"]
