"""A MaxSAT Evaluation benchmark family of illusion-knitting instances, ready to submit.

The Evaluation takes a *family*: a folder of instances in the current WCNF format (2022+, ``h``
hard clauses), compressed with xz, with a description of the problem and the encoding, how the
instances were generated, and what is known about their optima. :func:`write_family` writes

* ``<name>.wcnf.xz`` -- one instance per (picture pair, size, yarns, model): the logical model
  (paper section 4.2: fewest mismatched view cells) and the knit-aware model (view cells against
  the machine passes a knitting machine runs), over a size spectrum and 2-4 yarns, pictures
  drawn or taken from scikit-image's bundled images (nothing needs the network);
* ``README.md`` -- the problem, the encoding, the generator command, and a table of the
  instances with their sizes, reference optima (logical: the exact per-wale DP) or best bounds
  (knit-aware: the best pattern the block descent found within the time given, and the
  Lagrangian lower bound);
* ``manifest.json`` -- the same as data; ``SHA256SUMS`` -- checksums of every file (``sha256sum
  -c SHA256SUMS`` checks them).

Every reference value is an optimum, the cost of a pattern evaluated on the model that wrote the
file (the file holds exactly its clauses), or a proven bound.
"""

from __future__ import annotations

import hashlib
import json
import lzma
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from illuknit.bench.instances import Instance, instance_model
from illuknit.bench.wcnf_files import model_entry
from illuknit.core.files import atomic_write_bytes, atomic_write_text
from illuknit.core.pattern import parse_yarns

__all__ = ["DEFAULT_SIZES", "FAMILY_PAIRS", "family_instances", "write_family"]

#: Sides (units) of the square instances of the default family.
DEFAULT_SIZES = (20, 40, 70, 100)

#: yarns -> (view A input, view B input, yarn colours): one picture pair per yarn count.
FAMILY_PAIRS: dict[int, tuple[dict[str, Any], dict[str, Any], str]] = {
    2: ({"draw": "heart"}, {"draw": "ecg"}, "#1b1b1b,#f4f0e8"),
    3: ({"image": "astronaut"}, {"image": "coffee"}, "#1e1b24,#8c6f5a,#efe6d8"),
    4: ({"image": "chelsea"}, {"image": "camera"}, "#141414,#5a4a3a,#a89078,#f0ebe0"),
}


def family_instances(
    sizes: Sequence[int] = DEFAULT_SIZES, yarn_counts: Sequence[int] = (2, 3, 4)
) -> list[Instance]:
    """The family's instances (before the model is chosen), smallest first."""
    out = []
    for k in yarn_counts:
        a, b, yarns = FAMILY_PAIRS[k]
        tag = "-".join(str(v) for v in (*a.values(), *b.values()))
        for n in sizes:
            out.append(
                Instance(
                    f"{tag}-{n}x{n}-{k}y",
                    "double",
                    (n, n),
                    tuple(parse_yarns(yarns)),
                    10.0,
                    {"A": a, "B": b},
                )
            )
    return out


def write_family(
    outdir: str | Path,
    *,
    sizes: Sequence[int] = DEFAULT_SIZES,
    yarn_counts: Sequence[int] = (2, 3, 4),
    models: Sequence[str] = ("logical", "knit-aware"),
    bound_seconds: float = 10.0,
    command: str = "illuknit bench --export-family DIR",
    on_instance: Any = None,
) -> dict[str, Any]:
    """Write the family into ``outdir`` (see the module docstring); returns the manifest."""
    from illuknit.solvers import solve

    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    entries = []
    for inst in family_instances(sizes, yarn_counts):
        for kind in models:
            model, optimum = instance_model(inst, model=kind)
            name = f"illuknit-{inst.name}-{kind}.wcnf.xz"
            text = model.to_wcnf(style="new")
            data = lzma.compress(text.encode("ascii"), preset=9)
            atomic_write_bytes(out / name, data)
            entry: dict[str, Any] = {
                **model_entry(name, inst, kind, model),
                "sha256": hashlib.sha256(data).hexdigest(),
            }
            if optimum is not None:
                entry.update(optimum=int(optimum), optimum_by="exact per-wale DP")
            else:
                t0 = time.perf_counter()
                sol = solve(model, solver="descent", time_limit=bound_seconds)
                ok, cost = (False, None) if sol.values is None else model.evaluate(sol.values)
                entry.update(
                    optimum=None,
                    best_known=int(cost) if ok and cost is not None else None,
                    lower_bound=None if sol.bound is None else int(sol.bound),
                    bounds_by=f"descent + Lagrangian bound, {bound_seconds:g} s "
                    f"({time.perf_counter() - t0:.1f} s wall)",
                )
            entries.append(entry)
            if on_instance is not None:
                on_instance(entry)
    manifest = {
        "family": "illusion-knitting",
        "format": "MaxSAT Evaluation WCNF (2022+: 'h' hard clauses, weighted soft clauses), xz",
        "generator": command,
        "instances": entries,
    }
    sums = [f"{e['sha256']}  {e['file']}" for e in entries]
    for name, text in (
        ("manifest.json", json.dumps(manifest, indent=1) + "\n"),
        ("README.md", _readme(manifest, sizes, yarn_counts)),
    ):
        atomic_write_text(out / name, text)
        sums.append(f"{hashlib.sha256(text.encode()).hexdigest()}  {name}")
    atomic_write_text(out / "SHA256SUMS", "\n".join(sums) + "\n")
    return manifest


def _readme(manifest: dict[str, Any], sizes: Sequence[int], yarn_counts: Sequence[int]) -> str:
    rows = []
    for e in manifest["instances"]:
        ref = (
            f"optimum {e['optimum']}"
            if e["optimum"] is not None
            else f"best known {e['best_known']}, lower bound {e['lower_bound']}"
        )
        rows.append(
            f"| {e['file']} | {e['rows']} x {e['cols']} | {e['yarns']} | {e['model']} | "
            f"{e['variables']} | {e['hard_clauses']} | {e['soft_clauses']} | {ref} |"
        )
    return f"""# Illusion knitting (MaxSAT Evaluation benchmark family)

**Problem.** Illusion (shadow) knitting hides a picture in the relief of a knitted piece: seen
from one end of its wales it shows picture A, from the other end picture B, and head-on neither
("Computational Illusion Knitting", SIGGRAPH 2024, section 4.2). The piece is a grid of units;
each unit is knit in one of K yarns and is either flat or raised (a bump: a knit course followed
by a purl course). Seen from above, view A at unit (i, j) shows the yarn of the unit below,
`C[i-1, j]`, if that unit is raised, else its own `C[i, j]`; view B mirrors it with the unit
above. The task: choose yarn and relief of every unit so that the two views match their targets
in as many cells as possible -- and, in the knit-aware model, so that the piece is quick to knit
on a V-bed machine.

**Encoding.** Variables `yarn[i, j, k]` (one-hot, hard exactly-one) and `raised[i, j]`. Each
view cell is two soft clauses, `(~R[i-1, j] | yarn[i-1, j, A])` and `(R[i-1, j] | yarn[i, j,
A])` for target yarn A, of which exactly one is live, so the cost of the *logical* model is the
number of mismatched view cells (weight 1 each). The *knit-aware* model weighs a view cell 4
and adds the machine passes a knitting scheduler runs per unit row, 6 each: two per carrier
segment (one per yarn the row uses -- `yarn used[i, k]` -- plus an `extra carrier` for a region
of a yarn starting more than 10 units after its previous one), and for a row with a bump one
transfer pass in and out plus one float-avoidance pass per segment; these are hard definitions
of the auxiliary variables with weighted soft units on them. The logical model falls apart into
one independent component per wale (its optimum is computed exactly by a per-wale dynamic
programme); the knit-aware model couples the wales through the rows and is one component.

**Instances.** Square grids of {", ".join(str(s) for s in sizes)} units a side, with
{", ".join(str(k) for k in yarn_counts)} yarns; each yarn count has its own picture pair (drawn
shapes, or scikit-image's bundled photographs quantised together to the yarns), each size and
pair in both models. Names: `illuknit-<pictures>-<rows>x<cols>-<K>y-<model>.wcnf.xz`.

**Generator.** `{manifest["generator"]}` (illuknit's `illuknit/bench/family.py`).
Deterministic: the same version writes the same instance files (see SHA256SUMS).

**Reference values.** Logical: the optimum of the exact DP. Knit-aware: the cost of the best pattern found by illuknit's block descent
(evaluated on the same model) and a proven lower bound (the better of the DP bound and a
Lagrangian bound that keeps the pass terms); the optimum is open.

| file | size | yarns | model | variables | hard | soft | reference |
|---|---|---|---|---|---|---|---|
{chr(10).join(rows)}
"""
