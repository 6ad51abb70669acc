"""The knitting machine as data: every machine limit and default lives in :class:`MachineSpec`.

Nothing in illuknit hard-codes a needle count, a carrier name, a racking limit, a float limit or a
speed: the lowering, the scheduler, the knitout writer, the time model and the checker all read
them from the spec they are given, and one spec travels with a piece from scheduling to checking.

This module finds a machine: by preset name (:func:`get_machine`, :func:`resolve_machine`;
``--machine NAME`` on the CLI), in a machine file (:func:`load_machine_file`, written by
``illuknit calibrate time``) or in a program's own headers (:func:`machine_from_headers`, the
checker's default). The spec and its presets (:data:`MACHINES`, their sources) are
:mod:`illuknit.core.machine_spec`; the carriage's transfer settings and time model
:mod:`illuknit.core.machine_timing`. Every name of those two is importable from here.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from dataclasses import fields, replace
from pathlib import Path

from illuknit.core.errors import OptionError, UnknownNameError
from illuknit.core.machine_ranges import ranges_for
from illuknit.core.machine_spec import (
    BACKENDS,
    DEFAULT_MACHINE,
    DEFAULT_MACHINE_NAME,
    KNITERATE,
    MACHINES,
    SWG_CARRIERS,
    BedFitWarning,
    MachineSpec,
    machine_names,
)
from illuknit.core.machine_timing import (
    KNITERATE_TIMING,
    SWG_TIMING,
    CarriageTiming,
    TransferSettings,
)

__all__ = [
    "BACKENDS",
    "DEFAULT_MACHINE",
    "DEFAULT_MACHINE_NAME",
    "KNITERATE",
    "KNITERATE_TIMING",
    "MACHINES",
    "SWG_CARRIERS",
    "SWG_TIMING",
    "BedFitWarning",
    "CarriageTiming",
    "MachineSpec",
    "TransferSettings",
    "get_machine",
    "load_machine_file",
    "machine_from_headers",
    "machine_names",
    "resolve_machine",
    "save_machine_file",
]


#: ``kind`` of a machine file (:func:`save_machine_file`).
MACHINE_FILE_KIND = "illuknit-machine"


def save_machine_file(spec: MachineSpec, path: str | os.PathLike[str], *, base: str) -> Path:
    """Write ``spec`` as a machine file: the preset ``base`` and the time model
    (:class:`CarriageTiming`) measured on your machine. ``--machine FILE.json`` (and
    :func:`get_machine`) read it back, so later estimates use the calibration."""
    from illuknit.core.files import atomic_write_text

    doc = {
        "kind": MACHINE_FILE_KIND,
        "version": 1,
        "base": base,
        "timing": {f.name: getattr(spec.timing, f.name) for f in fields(CarriageTiming)},
    }
    return atomic_write_text(path, json.dumps(doc, indent=1) + "\n")


def load_machine_file(path: str | os.PathLike[str]) -> MachineSpec:
    """The machine a machine file describes (:func:`save_machine_file`): its base preset with
    the file's time model.

    Raises
    ------
    OptionError
        For a missing, unreadable or malformed file (one line saying what is wrong).
    """
    from illuknit.core.documents import read_json_file

    doc = read_json_file(path, error=OptionError, what="machine")
    if not isinstance(doc, dict) or doc.get("kind") != MACHINE_FILE_KIND:
        raise OptionError(f"{path} is not an illuknit machine file (written by `calibrate time`)")
    base = get_machine(str(doc.get("base", "")))
    raw = doc.get("timing")
    names = {f.name for f in fields(CarriageTiming)}
    if not isinstance(raw, dict) or not set(raw) <= names:
        raise OptionError(f"{path}: `timing` must be an object with keys among {sorted(names)}")
    try:
        timing = replace(base.timing, **raw)
    except (TypeError, ValueError) as e:
        raise OptionError(f"{path}: bad `timing`: {e}") from None
    return replace(base, timing=timing, description=f"{base.label} calibrated ({Path(path).name})")


def get_machine(name: str | MachineSpec | None = None) -> MachineSpec:
    """The preset called ``name`` (case-insensitive); ``None`` gives the default machine; a
    name ending in ``.json`` is a machine file (:func:`load_machine_file`).

    A :class:`MachineSpec` is returned as it is, so callers may take either.

    Raises
    ------
    UnknownNameError
        For a name not in :data:`MACHINES`; the message lists the known ones.

    Examples
    --------
    >>> get_machine("swg091n2").needles
    252
    """
    if name is None:
        return MACHINES[DEFAULT_MACHINE_NAME]
    if isinstance(name, MachineSpec):
        return name
    key = str(name).strip().lower()
    if key.endswith(".json"):
        return load_machine_file(str(name).strip())
    if key not in MACHINES:
        raise UnknownNameError("machine", str(name), machine_names())
    return MACHINES[key]


def resolve_machine(machine: str | MachineSpec | None = None) -> MachineSpec:
    """The machine an argument names: a preset name (case-insensitive), a
    :class:`MachineSpec` (returned as it is) or None (the default machine).

    Every public call that takes a ``machine`` reads it through this function, so a name and
    the spec it names give the same result everywhere.

    Raises
    ------
    UnknownNameError
        For a name not in :data:`MACHINES`; the message lists the valid names.
    OptionError
        For anything else (the message names the argument and its type).

    Examples
    --------
    >>> resolve_machine("Kniterate") is MACHINES["kniterate"]
    True
    >>> resolve_machine("swg09")
    Traceback (most recent call last):
    ...
    illuknit.core.errors.UnknownNameError: unknown machine 'swg09'; valid: generic540, swg091n2, kniterate
    """
    if machine is not None and not isinstance(machine, (str, MachineSpec)):
        raise OptionError(
            "`machine` must be a machine name "
            f"({', '.join(machine_names())}) or a MachineSpec, got {type(machine).__name__}"
        )
    return get_machine(machine)


def machine_from_headers(headers: Mapping[str, str]) -> MachineSpec:
    """The machine a knitout program was written for, from its ``;;`` headers.

    The preset whose ``;;Machine`` name and bed width match is taken as it is; otherwise the
    first preset of that name (else the default machine) with the program's ``;;Width`` and
    ``;;Gauge``. The preset's carriers, racking and float limits apply: headers do not carry them,
    and a program whose ``;;Machine`` or ``;;Carriers`` differ from the preset's is what the
    checker's header rules report. Malformed values are left to those rules too.

    Examples
    --------
    >>> machine_from_headers({"Machine": "SWG091N2", "Width": "252"}) is MACHINES["swg091n2"]
    True
    """
    model = headers.get("Machine", "").strip().lower()
    width = _int_or_none(headers.get("Width"))
    gauge = _float_or_none(headers.get("Gauge"))
    same_model = [m for m in MACHINES.values() if model and m.name.lower() == model]
    base = same_model[0] if same_model else DEFAULT_MACHINE
    base = next((m for m in same_model if m.needles == width), base)
    changes: dict[str, float] = {}
    # a value out of range is left to the checker's machine-value rule, not taken as the bed
    ranges = ranges_for(base.runs_on())
    if width is not None and width != base.needles and ranges["needles"].contains(width):
        changes["needles"] = width
    if gauge is not None and gauge != base.gauge and ranges["gauge"].contains(gauge):
        changes["gauge"] = gauge
    if not changes:
        return base
    return replace(base, description="from the program's headers", **changes)  # type: ignore[arg-type]


def _int_or_none(value: str | None) -> int | None:
    v = (value or "").strip()
    return int(v) if v.isdigit() and int(v) > 0 else None


def _float_or_none(value: str | None) -> float | None:
    try:
        v = float((value or "").strip())
    except ValueError:
        return None
    return v if v > 0 else None
