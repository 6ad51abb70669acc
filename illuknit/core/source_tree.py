"""``illuknit.solvers`` and ``illuknit.instances`` when illuknit runs from a source checkout.

The design keeps the solver backends and the benchmark instances in the top-level folders
``solvers/`` and ``instances/``. An installed illuknit holds them inside the package: pyproject's
``package-dir`` maps the two folders to ``illuknit/solvers`` and ``illuknit/instances`` (the one
packaging mechanism). A checkout run without installing it (``PYTHONPATH=. python -m illuknit``)
has no such folders inside ``illuknit/``; :func:`find_top_level_folders` then lets the import
system find the two subpackages in the checkout's top-level folders, and nothing else.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from importlib.machinery import ModuleSpec, PathFinder
from types import ModuleType

__all__ = ["SOURCE_FOLDERS", "find_top_level_folders"]

#: Subpackage -> top-level folder of the checkout; the same mapping as pyproject's package-dir.
SOURCE_FOLDERS = {"illuknit.solvers": "solvers", "illuknit.instances": "instances"}


class _TopLevelFolders:
    """A meta path finder for the subpackages of :data:`SOURCE_FOLDERS`, from one checkout."""

    def __init__(self, root: str) -> None:
        self.root = root

    def find_spec(
        self, fullname: str, path: Sequence[str] | None = None, target: ModuleType | None = None
    ) -> ModuleSpec | None:
        folder = SOURCE_FOLDERS.get(fullname)
        if folder is None:
            return None
        return PathFinder.find_spec(fullname, [self.root])

    def __repr__(self) -> str:
        return f"<illuknit top-level folders of {self.root}>"


def find_top_level_folders(package_dir: str) -> None:
    """Install the finder when ``package_dir`` (the ``illuknit/`` folder) is in a checkout.

    A checkout is recognised by its ``pyproject.toml`` and its ``solvers/__init__.py`` beside
    the package while the package itself has no ``solvers``; an installed illuknit is left alone.
    The finder goes first on :data:`sys.meta_path`, so that another illuknit installed in
    development mode elsewhere cannot lend this checkout its solvers.
    """
    root = os.path.dirname(os.path.abspath(package_dir))
    if os.path.isdir(os.path.join(package_dir, "solvers")):
        return
    if not (
        os.path.isfile(os.path.join(root, "pyproject.toml"))
        and os.path.isfile(os.path.join(root, "solvers", "__init__.py"))
    ):
        return
    if not any(isinstance(f, _TopLevelFolders) and f.root == root for f in sys.meta_path):
        sys.meta_path.insert(0, _TopLevelFolders(root))
