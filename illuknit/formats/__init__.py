"""Machine files: knitout translated into what a knitting machine reads.

``dat``: Shima Seiki KnitPaint ``.dat`` (:func:`illuknit.formats.dat.knitout_to_dat`, read back
with :func:`illuknit.formats.dat.read_dat`); the carriage passes behind it, which the schedulers
count with, are :func:`illuknit.formats.swg_passes.machine_passes`.

``kc``: Kniterate k-code (``.kc``), via :func:`illuknit.formats.kc.knitout_to_kc`.

:func:`machine_formats` says which files a machine takes, :func:`check_format` refuses the others
before any work is done, and :func:`knitout_to_format` converts. Submodules are imported on use.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from illuknit.core.errors import UnknownNameError
from illuknit.formats.swg_ir import MachinePass, MachinePassKind
from illuknit.formats.swg_passes import machine_passes
from illuknit.knitout.program import KnitoutProgram, format_knitout

if TYPE_CHECKING:
    from illuknit.core.machine import MachineSpec

__all__ = [
    "FORMAT_SUFFIXES",
    "MachinePass",
    "MachinePassKind",
    "check_format",
    "knitout_to_format",
    "machine_formats",
    "machine_passes",
]

#: output format -> file suffix
FORMAT_SUFFIXES: dict[str, str] = {"knitout": ".k", "dat": ".dat", "kc": ".kc"}


def machine_formats(machine: MachineSpec) -> tuple[str, ...]:
    """Output formats ``machine`` can take: knitout, then its machine files (``machine.formats``)."""
    return ("knitout", *machine.formats)


def check_format(machine: MachineSpec, fmt: str) -> None:
    """Refuse (:class:`~illuknit.core.errors.UnknownNameError`) a format ``machine`` cannot take."""
    valid = machine_formats(machine)
    if fmt not in valid:
        raise UnknownNameError(f"output format for the {machine.label}", fmt, valid)


def knitout_to_format(program: KnitoutProgram | str, fmt: str, *, name: str = "program") -> bytes:
    """The bytes of ``program`` (a knitout program or its text) as a file of format ``fmt``
    (``knitout``, ``dat`` or ``kc``).

    ``name`` is the file name a ``.kc`` records in its comment line.

    Raises
    ------
    UnknownNameError
        For a format illuknit does not write.
    MachineRuleError, UnsupportedKnitoutError
        When the program cannot become that machine file (see
        :func:`~illuknit.formats.dat.knitout_to_dat`).
    """
    if fmt == "knitout":
        text = program if isinstance(program, str) else format_knitout(program)
        return text.encode("utf-8")
    if fmt == "dat":
        from illuknit.formats.dat import knitout_to_dat

        return knitout_to_dat(program)
    if fmt == "kc":
        from illuknit.formats.kc import knitout_to_kc

        return knitout_to_kc(program, name=name).encode("utf-8")

    raise UnknownNameError("output format", fmt, list(FORMAT_SUFFIXES))
