"""Every exception illuknit raises on purpose, one class per kind of problem.

All of them derive from :class:`IlluknitError`, so a caller (and the CLI, which turns them into one
line on stderr and exit code 2) can catch the family at once. Raise the class that names what went
wrong:

=====================  ==========================================================================
kind of problem        class
=====================  ==========================================================================
picture                :class:`ImageInputError` (target images, too),
                       :class:`PictureSizeMismatchError`, :class:`YarnSpecError`
pattern                :class:`PatternValidationError` (an in-memory pattern IR or its arrays)
option / value         :class:`OptionError` (a keyword or setting out of range or of a wrong
                       type); :class:`UnknownNameError` (a name not in a registry);
                       :class:`RenderParamsError`; :class:`MachineValueError` (a machine
                       value outside its range in :mod:`illuknit.core.machine_ranges`)
machine rule           :class:`MachineRuleError` (carries the needle / carrier / racking)
scheduling             :class:`SchedulingError` and its subclasses (a pattern the machine cannot
                       knit, a malformed schedule; :class:`LongFloatError`: a float that stays
                       longer than the machine's float limit)
solver                 :class:`ModelError` (a constraint model built inconsistently),
                       :class:`SolverError`, :class:`BackendUnavailableError`,
                       :class:`InfeasibleError`
file / output          :class:`PatternFormatError`, :class:`KnitoutParseError`,
                       :class:`ManifestError`, :class:`ResultsVersionError`,
                       :class:`OutputPathError`
tiles, render, app     :class:`TileBankError`, :class:`TileAssignmentError`,
                       :class:`CalibrationError`, :class:`AppRequestError`
=====================  ==========================================================================

Machine-rule violations carry the offending needle, carrier or racking values as attributes, not
only in the message.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

__all__ = [
    "AppRequestError",
    "BackendUnavailableError",
    "CalibrationError",
    "CarrierShortageError",
    "DatFormatError",
    "ExecutorError",
    "FloatSpan",
    "IlluknitError",
    "ImageInputError",
    "InfeasibleError",
    "KcodeError",
    "KnitoutParseError",
    "LongFloatError",
    "MachineFileError",
    "MachineRuleError",
    "MachineValueError",
    "ManifestError",
    "MixedColorworkError",
    "ModelError",
    "OptionError",
    "OutputOverInputError",
    "OutputPathError",
    "PatternFormatError",
    "PatternValidationError",
    "PictureSizeMismatchError",
    "RenderParamsError",
    "ResultsVersionError",
    "SchedulingError",
    "SolverError",
    "TileAssignmentError",
    "TileBankError",
    "UnknownNameError",
    "UnsupportedKnitoutError",
    "YarnSpecError",
]


class IlluknitError(Exception):
    """Base class of every error raised deliberately by illuknit."""


class PatternValidationError(IlluknitError, ValueError):
    """An in-memory pattern (``LogicalPattern``, ``StitchPattern`` or the arrays that make one) does
    not have the expected shape, dtype or values."""


class OptionError(IlluknitError, ValueError):
    """An option or argument value is invalid: of the wrong type, out of range, or not one of the
    choices. The message names the parameter and what was expected."""


class ModelError(IlluknitError, ValueError):
    """A solver-neutral constraint model (:class:`illuknit.solvers.model.Model`) is built inconsistently:
    a duplicate variable block, a literal that names no variable, a non-positive weight."""


class PatternFormatError(IlluknitError, ValueError):
    """A pattern file is malformed, of another format version, or inconsistent."""


class ImageInputError(IlluknitError, ValueError):
    """An input image is missing, unreadable, too small, or cannot be mapped to the yarns."""


class PictureSizeMismatchError(ImageInputError):
    """Two pictures do not cover the same piece (their aspect ratios differ); see
    :mod:`illuknit.pictures.sizing`. ``a_pixels`` and ``b_pixels`` are their (height, width) in pixels."""

    def __init__(
        self, message: str, *, a_pixels: tuple[int, int], b_pixels: tuple[int, int]
    ) -> None:
        super().__init__(message)
        self.a_pixels = a_pixels
        self.b_pixels = b_pixels


class YarnSpecError(IlluknitError, ValueError):
    """A yarn colour string is unknown, or the yarn list is invalid (e.g. duplicate colours)."""


class UnknownNameError(OptionError, KeyError):
    """A name (solver, model, instance, method, preset) is not one of the valid ones.

    The message lists the valid names.
    """

    def __init__(self, kind: str, name: str, valid: list[str] | tuple[str, ...]) -> None:
        self.kind = kind
        self.name = name
        self.valid = tuple(valid)
        super().__init__(f"unknown {kind} {name!r}; valid: {', '.join(self.valid) or '(none)'}")

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0])


class MachineValueError(OptionError):
    """A machine value (needles, gauge, stitch, speed, roller, racking) outside the range the
    machine takes (:data:`illuknit.core.machine_ranges.MACHINE_RANGES`). ``parameter``, ``low``,
    ``high`` and ``source`` say which value, its range and where the range comes from."""

    def __init__(
        self, message: str, *, parameter: str, low: float, high: float, source: str
    ) -> None:
        super().__init__(message)
        self.parameter = parameter
        self.low = low
        self.high = high
        self.source = source


class BackendUnavailableError(IlluknitError, ImportError):
    """A solver backend (or other optional feature) needs a library that is not installed."""


class SolverError(IlluknitError, RuntimeError):
    """A solver backend failed (crashed, printed something unparseable, or was misconfigured)."""


class InfeasibleError(IlluknitError, ValueError):
    """Hard constraints cannot all hold; the message names the constraint family."""


class TileBankError(IlluknitError, ValueError):
    """A tile bank is malformed, or declares a fill that can_see contradicts."""


class TileAssignmentError(IlluknitError, ValueError):
    """No assignment of fills to colours exists; the message says which overlaps fail and why."""


class SchedulingError(IlluknitError, ValueError):
    """A pattern cannot be scheduled on the given machine (too wide, too many colour runs, ...)."""


class MixedColorworkError(SchedulingError):
    """A course changes colour, which only the mixed-colourwork scheduler can knit."""


class CarrierShortageError(SchedulingError):
    """A course needs more carriers at once than the machine has (``course``, ``needed``, ``available``)."""

    def __init__(self, message: str, *, course: int, needed: int, available: int) -> None:
        super().__init__(message)
        self.course = course
        self.needed = needed
        self.available = available


@dataclass(frozen=True)
class FloatSpan:
    """One float of a knitted course: ``length`` needles skipped by ``carrier`` from
    ``from_needle`` to ``to_needle``, in course ``course`` (None at the bind-off)."""

    length: int
    carrier: str
    from_needle: int
    to_needle: int
    course: int | None


class LongFloatError(SchedulingError):
    """A float stays longer than the machine's float limit after tucking, and long floats were not
    allowed (``allow_long_floats=False``, the default; ``--allow-long-floats`` on the CLI).

    The message names where the longest float is and what to change. ``span`` is that float
    (:class:`FloatSpan`), its fields also attributes of the error: ``length`` (needles skipped),
    ``carrier``, ``from_needle``, ``to_needle``, ``course`` (the course index, None at the
    bind-off); ``where`` is the course named as the message names it, ``limit`` the float limit
    and ``count`` how many floats stay long. The span's fields may be given as keywords instead
    of ``span``.
    """

    def __init__(
        self,
        message: str,
        *,
        span: FloatSpan | None = None,
        where: str,
        limit: int,
        count: int,
        **span_fields: Any,
    ) -> None:
        super().__init__(message)
        self.span = replace(span, **span_fields) if span is not None else FloatSpan(**span_fields)
        self.length = self.span.length
        self.carrier = self.span.carrier
        self.from_needle = self.span.from_needle
        self.to_needle = self.span.to_needle
        self.course = self.span.course
        self.where = where
        self.limit = limit
        self.count = count


class MachineRuleError(IlluknitError, ValueError):
    """An operation breaks a knitting-machine rule: a racking out of range or not a quarter pitch,
    a needle off the bed, a carrier the machine does not have, a transfer between unaligned needles.

    Attributes hold whichever of the offending values are known (``needle`` as knitout names it,
    e.g. ``"f12"``).
    """

    def __init__(
        self,
        message: str,
        *,
        needle: str | None = None,
        carrier: str | None = None,
        racking: float | None = None,
        line: int | None = None,
    ) -> None:
        self.needle = needle
        self.carrier = carrier
        self.racking = racking
        self.line = line
        super().__init__(message)


class KcodeError(MachineRuleError):
    """A knitout program cannot be written as Kniterate k-code (``.kc``).

    Raised where the reference Kniterate backend refuses the program, and where it would write a
    wrong file (plated carriers, slider needles, needles off its 252-needle bed); ``line`` is the
    1-based knitout line when known.
    """

    def __init__(
        self,
        message: str,
        *,
        line: int | None = None,
        needle: str | None = None,
        carrier: str | None = None,
        racking: float | None = None,
    ) -> None:
        super().__init__(
            f"line {line}: {message}" if line is not None else message,
            needle=needle,
            carrier=carrier,
            racking=racking,
            line=line,
        )


class KnitoutParseError(IlluknitError, ValueError):
    """A knitout file cannot be parsed; carries the 1-based line number."""

    def __init__(self, message: str, *, line: int | None = None) -> None:
        self.line = line
        super().__init__(f"line {line}: {message}" if line is not None else message)


class AppRequestError(IlluknitError, ValueError):
    """A request to the design app is invalid; ``field`` names the page control that caused it.

    ``status`` is the HTTP status the app answers with; ``code`` a short machine-readable reason.
    """

    def __init__(
        self, message: str, *, field: str | None = None, code: str = "invalid", status: int = 422
    ) -> None:
        self.field = field
        self.code = code
        self.status = status
        super().__init__(message)


class RenderParamsError(OptionError):
    """Renderer parameters are invalid: an unknown key, a wrong type, a non-positive size, or an
    angle outside (0, 90] degrees."""


class CalibrationError(IlluknitError, ValueError):
    """Calibration measurements are malformed or cannot determine a bump height."""


class ManifestError(IlluknitError, ValueError):
    """A benchmark manifest is missing, not TOML, or has an invalid entry (named in the message)."""


class ResultsVersionError(IlluknitError, ValueError):
    """A benchmark results folder holds results of another illuknit version (or is not one)."""


class OutputPathError(IlluknitError, OSError):
    """An output folder or file cannot be written: a file in the way, a read-only file system, no
    permission. The message names the path and the reason."""


class OutputOverInputError(OutputPathError):
    """An output would be written over one of the run's own input files (the same path, a link
    to it, or the same file by device and inode, a hard link); nothing was written."""


class ExecutorError(IlluknitError, RuntimeError):
    """A benchmark executor cannot start (e.g. the Dask scheduler address cannot be reached)."""


class MachineFileError(IlluknitError, ValueError):
    """A machine file (Shima ``.dat``, Kniterate ``.kc``) cannot be written or read.

    ``line`` is the 1-based knitout line at fault when one is known.
    """

    def __init__(self, message: str, *, line: int | None = None) -> None:
        self.line = line
        super().__init__(message if line is None else f"line {line}: {message}")


class UnsupportedKnitoutError(MachineFileError):
    """Valid knitout that this machine-file writer does not implement (it refuses, never guesses)."""


class DatFormatError(MachineFileError):
    """Bytes that are not a Shima ``.dat`` file as illuknit writes and reads them."""
