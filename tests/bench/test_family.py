"""The MaxSAT Evaluation benchmark family: xz WCNF files that read back to their models, the
reference values, README, manifest and checksums."""

from __future__ import annotations

import hashlib
import json
import lzma

from illuknit.bench.family import write_family
from illuknit.bench.wcnf_files import read_wcnf_text
from illuknit.solvers import solve


def test_family_files_read_back_with_their_references(tmp_path):
    mf = write_family(tmp_path, sizes=(6,), yarn_counts=(2, 3), bound_seconds=1.0)
    entries = mf["instances"]
    assert {(e["yarns"], e["model"]) for e in entries} == {
        (k, m) for k in (2, 3) for m in ("logical", "knit-aware")
    }
    for e in entries:
        data = (tmp_path / e["file"]).read_bytes()
        assert hashlib.sha256(data).hexdigest() == e["sha256"]
        text = lzma.decompress(data).decode("ascii")
        assert not text.startswith("p ") and "\nh " in text  # the 2022+ format
        model = read_wcnf_text(text)
        assert model.num_soft == e["soft_clauses"]
        if e["model"] == "logical":
            sol = solve(model, solver="rc2", time_limit=30)  # the file alone, another solver
            assert sol.status.value == "optimal" and sol.objective == e["optimum"]
        else:
            assert e["lower_bound"] <= e["best_known"]
    sums = (tmp_path / "SHA256SUMS").read_text().splitlines()
    assert len(sums) == len(entries) + 2
    readme = (tmp_path / "README.md").read_text()
    assert "**Encoding.**" in readme and all(e["file"] in readme for e in entries)
    assert json.loads((tmp_path / "manifest.json").read_text())["instances"] == entries
