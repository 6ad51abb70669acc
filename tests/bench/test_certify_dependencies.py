"""The certifier needs only core dependencies: its engines are python-sat's RC2 and OR-Tools
CP-SAT. The ``[certify]`` extra (pindakaas) promised encodings the certifier never used."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

from illuknit.bench.certify import ENGINES

PYPROJECT = Path(__file__).resolve().parents[2] / "pyproject.toml"


def _names(requirements):
    return {re.split(r"[<>=!~;\[ ]", r, maxsplit=1)[0].strip().lower() for r in requirements}


def test_the_certifier_engines_are_core_dependencies_and_no_extra_promises_more():
    project = tomllib.loads(PYPROJECT.read_text(encoding="utf-8"))["project"]
    core = _names(project["dependencies"])
    wanted = {"rc2": "python-sat", "cpsat": "ortools"}
    assert {wanted[e] for e in ENGINES} <= core
    extras = project["optional-dependencies"]
    assert "certify" not in extras
    assert all("pindakaas" not in _names(reqs) for reqs in extras.values())
