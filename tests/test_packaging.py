"""The installed package must contain every subpackage and data file of the source tree."""

import os
import tomllib
from fnmatch import fnmatch
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SETUPTOOLS = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]


def test_every_subpackage_is_listed_in_pyproject():
    listed = set(SETUPTOOLS["packages"])
    found = {
        ".".join(p.parent.relative_to(ROOT).parts)
        for p in (ROOT / "illuknit").rglob("__init__.py")
        if "__pycache__" not in p.parts
    }
    assert found <= listed, f"add to [tool.setuptools] packages: {sorted(found - listed)}"
    assert len(SETUPTOOLS["packages"]) == len(listed), "a package is listed twice"


def test_top_level_folders_install_as_subpackages_without_links():
    from illuknit.core.source_tree import SOURCE_FOLDERS

    mapped = {k: v for k, v in SETUPTOOLS["package-dir"].items() if k != "illuknit"}
    assert (
        mapped
        == SOURCE_FOLDERS
        == {"illuknit.solvers": "solvers", "illuknit.instances": "instances"}
    )
    assert set(mapped) <= set(SETUPTOOLS["packages"])
    assert (ROOT / "solvers" / "__init__.py").is_file()
    assert not any(p.is_symlink() for p in (ROOT / "illuknit").rglob("*"))
    assert not (ROOT / "illuknit" / "solvers").exists()


def test_a_checkout_imports_the_top_level_folders():
    import illuknit.instances
    import illuknit.solvers

    assert Path(illuknit.solvers.__file__).parent == ROOT / "solvers"
    assert [Path(p) for p in illuknit.instances.__path__] == [ROOT / "instances"]


def test_one_version_source():
    import illuknit

    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert "version" not in project and "version" in project["dynamic"]
    assert SETUPTOOLS["dynamic"]["version"] == {"attr": "illuknit.__version__"}
    assert illuknit.__version__.count(".") == 2


def test_bundled_demo_picture_is_package_data():
    from importlib import resources

    assert (resources.files("illuknit") / "data" / "demo.png").is_file()


def test_every_data_file_is_package_data():
    # A wheel holds only what package-data names; `illuknit bench` failed after `pip install .`
    # when the manifest lived outside the package.
    from illuknit.bench.instances import DEFAULT_MANIFEST

    assert DEFAULT_MANIFEST.resolve() == (ROOT / "instances" / "manifest.toml").resolve()
    data = SETUPTOOLS["package-data"]
    for package, folder in (
        ("illuknit", ROOT / "illuknit"),
        ("illuknit.instances", ROOT / "instances"),
    ):
        files = [
            (Path(d) / f).relative_to(folder).as_posix()
            for d, _, names in os.walk(folder)
            for f in names
            if not f.endswith((".py", ".pyc")) and "__pycache__" not in d
        ]
        missing = [f for f in files if not any(fnmatch(f, pat) for pat in data[package])]
        assert missing == [], f"add to [tool.setuptools.package-data] {package}: {missing}"
