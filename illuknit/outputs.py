"""Writing results so that a failure never leaves half-written output.

Single files go to a temporary name in the same folder and are renamed into place. Output folders
are assembled in a hidden sibling folder and renamed into place when complete (an existing folder
of the same name is replaced only then).
"""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from illuknit.errors import OutputError

__all__ = ["atomic_write_bytes", "atomic_write_text", "staged_dir"]


def _umask() -> int:
    # mkstemp/mkdtemp create private (0600/0700) entries; results should get the usual
    # permissions, so apply the process umask as open()/mkdir() would.
    mask = os.umask(0)
    os.umask(mask)
    return mask


def atomic_write_bytes(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` via a temporary file and a rename."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def atomic_write_text(path: str | os.PathLike[str], text: str) -> Path:
    """Write UTF-8 text (LF line endings) to ``path`` via a temporary file and a rename."""
    return atomic_write_bytes(path, text.encode("utf-8"))


@contextmanager
def staged_dir(outdir: str | os.PathLike[str]) -> Iterator[Path]:
    """Yield a temporary folder whose contents land in ``outdir`` only if the block succeeds.

    The files are written into a hidden sibling folder; on success each entry is renamed into
    ``outdir`` (created if needed; other files already there are left alone, same-named ones are
    replaced). On any error the temporary folder is removed and ``outdir`` is untouched.

    >>> with staged_dir("out") as tmp:   # doctest: +SKIP
    ...     (tmp / "pattern.json").write_text("...")
    """
    outdir = Path(outdir)
    if outdir.exists() and not outdir.is_dir():
        raise OutputError(f"output path exists and is not a folder: {outdir}")
    parent = outdir.resolve().parent
    parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{outdir.name}.", suffix=".partial", dir=parent))
    os.chmod(tmp, 0o777 & ~_umask())
    try:
        yield tmp
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    final = parent / outdir.name
    if not final.exists():
        os.replace(tmp, final)
        return
    for entry in sorted(tmp.iterdir()):
        target = final / entry.name
        if target.is_dir() and not target.is_symlink():
            shutil.rmtree(target)
        os.replace(entry, target)
    shutil.rmtree(tmp, ignore_errors=True)
