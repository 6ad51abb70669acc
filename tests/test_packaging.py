"""The installed package must contain every subpackage of the source tree."""

import os
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


def test_every_data_file_is_package_data():
    # A wheel holds only what package-data names; `illuknit bench` failed after `pip install .`
    # when the manifest lived outside the package.
    from fnmatch import fnmatch

    from illuknit.bench.instances import DEFAULT_MANIFEST

    package = ROOT / "illuknit"
    assert DEFAULT_MANIFEST.is_file()
    assert DEFAULT_MANIFEST.resolve() == (ROOT / "instances" / "manifest.toml").resolve()
    assert DEFAULT_MANIFEST.parent.parent == package  # read through the package, not the clone
    patterns = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"][
        "package-data"
    ]["illuknit"]
    data = [
        (Path(d) / f).relative_to(package).as_posix()
        for d, _, files in os.walk(package, followlinks=True)  # instances/ is a link
        for f in files
        if not f.endswith((".py", ".pyc")) and "__pycache__" not in d
    ]
    data = [f for f in data if not f.startswith("solvers/")]
    assert "instances/manifest.toml" in data
    missing = [f for f in data if not any(fnmatch(f, pat) for pat in patterns)]
    assert missing == [], f"add to [tool.setuptools.package-data]: {missing}"
