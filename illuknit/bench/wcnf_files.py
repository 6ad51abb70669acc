"""WCNF files for the solver benchmark: read any MaxSAT Evaluation instance, export ours.

:func:`read_wcnf` parses both dialects of the MaxSAT Evaluation format into a
:class:`~illuknit.solvers.model.Model` (variables ``("x", i)`` are ids 1..NV): the 2022+ one
(``h <lits> 0`` hard, ``<weight> <lits> 0`` soft) and the older ``p wcnf NV NC TOP`` one (a clause
weighted ``TOP`` is hard). An empty soft clause is, as the Evaluation's rules define the cost
(the total weight of the soft clauses an assignment falsifies), falsified by every assignment:
its weight is a constant added to every assignment's cost (the model's ``offset``, which every
objective, bound and claimed cost the bench reports includes), never a hard clause.
:func:`export_wcnf_family` writes every bundled instance's models as
2022+ WCNF with a ``manifest.json`` (sizes, the known optimum where the DP proves one, how each
file was made), so the family can be shared and run by other tools.
"""

from __future__ import annotations

import json
from collections import defaultdict
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from illuknit.bench.instances import instance_model
from illuknit.core.errors import PatternFormatError
from illuknit.core.files import atomic_write_text
from illuknit.solvers.model import Model

__all__ = [
    "add_clause_groups",
    "export_wcnf_family",
    "model_entry",
    "read_wcnf",
    "read_wcnf_text",
    "wcnf_model_name",
]


def add_clause_groups(model: Model, clauses: list[list[int]], weights: list[int] | None) -> None:
    """Add ``clauses`` to ``model`` grouped by length (one block per length keeps the model
    compact): hard clauses when ``weights`` is None, else soft ones weighted ``weights``.

    An empty hard clause makes the model unsatisfiable; an empty soft clause is falsified by
    every assignment, so its weight goes to ``model.offset`` (a constant cost), never to a hard
    clause.
    """
    by_len: dict[int, list[int]] = defaultdict(list)
    for i, c in enumerate(clauses):
        by_len[len(c)].append(i)
    for length, idx in by_len.items():
        if length == 0 and weights is not None:
            model.offset += int(np.asarray([weights[i] for i in idx], dtype=np.int64).sum())
            continue
        if length == 0:
            model.add_hard_block(np.zeros((len(idx), 1), dtype=np.int64), family="hard")
            continue
        block = np.asarray([clauses[i] for i in idx], dtype=np.int64)
        if weights is None:
            model.add_hard_block(block, family="hard")
        else:
            model.add_soft_block(block, np.asarray([weights[i] for i in idx], dtype=np.int64))


def read_wcnf(path: str | Path) -> Model:
    """The WCNF file at ``path`` as a Model (see the module docstring; the weight of empty soft
    clauses is the model's constant ``offset``).

    Raises
    ------
    PatternFormatError
        A line is not a clause of either dialect; the message names the file and line.
    """
    p = Path(path)
    with p.open(encoding="ascii", errors="replace") as fh:
        return _parse_wcnf(fh, p.stem, str(p))


def read_wcnf_text(text: str, name: str = "wcnf") -> Model:
    """A WCNF file's text as a Model named ``name`` (as :func:`read_wcnf`)."""
    return _parse_wcnf(text.splitlines(), name, name)


def _parse_wcnf(lines: Iterable[str], name: str, where: str) -> Model:
    hard: list[list[int]] = []
    soft: list[list[int]] = []
    weights: list[int] = []
    top: int | None = None
    nv = 0
    for no, raw in enumerate(lines, 1):
        line = raw.strip()
        if not line or line.startswith("c"):
            continue
        parts = line.split()
        if parts[0] == "p":
            if len(parts) >= 5 and parts[1] == "wcnf":
                top = int(parts[4])
            continue
        try:
            nums = [int(t) for t in parts[1:]] if parts[0] == "h" else [int(t) for t in parts]
        except ValueError:
            raise PatternFormatError(f"{where}:{no}: not a WCNF clause: {line[:60]!r}") from None
        if parts[0] == "h":
            weight = None
            lits = nums
        else:
            weight, lits = nums[0], nums[1:]
        if not lits or lits[-1] != 0:
            raise PatternFormatError(f"{where}:{no}: a clause must end with 0: {line[:60]!r}")
        lits = lits[:-1]
        if lits:
            nv = max(nv, max(abs(x) for x in lits))
        if weight is None or (top is not None and weight >= top):
            hard.append(lits)
        elif weight <= 0:
            raise PatternFormatError(f"{where}:{no}: soft clause weight must be positive")
        else:
            soft.append(lits)
            weights.append(weight)
    model = Model(name)
    model.pool.block("x", (nv,))
    add_clause_groups(model, hard, None)
    add_clause_groups(model, soft, weights)
    return model


def wcnf_model_name(instance: str, model: str) -> str:
    """File name of one exported model: ``<instance>.<model>.wcnf``."""
    return f"{instance}.{model}.wcnf"


def model_entry(file: str, inst: Any, kind: str, model: Model) -> dict[str, Any]:
    """A manifest's description of one instance's ``kind`` model written to ``file``: where it
    comes from and its size (variables, hard and soft clauses, total soft weight)."""
    cs = model.to_clauses()
    return {
        "file": file,
        "instance": inst.name,
        "model": kind,
        "rows": inst.size[0],
        "cols": inst.size[1],
        "yarns": len(inst.yarns),
        "variables": cs.nv,
        "hard_clauses": len(cs.hard),
        "soft_clauses": model.num_soft,
        "total_soft_weight": model.total_soft_weight(),
    }


def export_wcnf_family(
    instances: Sequence[Any],
    outdir: str | Path,
    *,
    models: Sequence[str] = ("logical", "knit-aware"),
) -> dict[str, Any]:
    """Write each instance's models as 2022+ WCNF and a manifest.json; returns the manifest.

    Single-view instances get the single-view model only (one target). The known optimum is
    the DP's where it is exact (logical and single-view models), else None.
    """
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    entries = []
    for inst in instances:
        kinds = ["single"] if inst.kind == "single" else list(models)
        for kind in kinds:
            model, optimum = instance_model(inst, model=kind)
            name = wcnf_model_name(inst.name, kind)
            text = model.to_wcnf(style="new")
            atomic_write_text(out / name, text)
            entries.append(
                {
                    **model_entry(name, inst, kind, model),
                    "known_optimum": optimum,
                    "optimum_by": "dp (exact)" if optimum is not None else None,
                    "made_by": f"illuknit bench --export-wcnf (illusion model {kind!r}, "
                    f"instance {inst.name!r}: {inst.notes or 'see instances/manifest.toml'})",
                }
            )
    manifest = {"format": "MaxSAT Evaluation WCNF, 2022+ ('h' hard clauses)", "files": entries}
    atomic_write_text(out / "manifest.json", json.dumps(manifest, indent=2) + "\n")
    return manifest
