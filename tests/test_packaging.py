"""The installed package must contain every subpackage of the source tree."""

import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_every_subpackage_is_listed_in_pyproject():
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    listed = set(config["packages"])
    found = {
        ".".join(p.parent.relative_to(ROOT).parts)
        for p in (ROOT / "illuknit").rglob("__init__.py")
        if "__pycache__" not in p.parts
    }
    assert found <= listed, f"add to [tool.setuptools] packages: {sorted(found - listed)}"
    assert config["package-dir"]["illuknit.solvers"] == "solvers"
    assert (ROOT / "solvers" / "__init__.py").is_file()


def test_bundled_demo_picture_is_package_data():
    from importlib import resources

    assert (resources.files("illuknit") / "data" / "demo.png").is_file()
