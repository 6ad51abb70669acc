"""Fixtures shared by the bench's tests."""

from __future__ import annotations

import pytest

from illuknit.bench.instances import Instance
from illuknit.bench.wcnf_files import export_wcnf_family, read_wcnf
from illuknit.core.pattern import Yarn
from illuknit.solvers import solve


@pytest.fixture(scope="session")
def wcnf_file(tmp_path_factory) -> tuple[str, int]:
    """A 12 x 10 two-yarn logical model as a plain WCNF file (10 wales, no reference optimum)
    and its optimum: the formula the lying-solver zoo and the split rows are judged on."""
    yarns = (Yarn("dark", (20, 20, 20)), Yarn("cream", (240, 236, 230)))
    inst = Instance(
        "zoo", "double", (12, 10), yarns, 5.0, {"A": {"draw": "heart"}, "B": {"draw": "ecg"}}
    )
    out = tmp_path_factory.mktemp("zoo")
    mf = export_wcnf_family([inst], out, models=["logical"])
    path = out / mf["files"][0]["file"]
    return str(path), int(solve(read_wcnf(path), solver="rc2").objective)
