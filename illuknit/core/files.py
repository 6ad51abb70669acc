"""Writing results so that a failure never leaves half-written output.

The output-folder contract, in one place:

- Output goes into the folder the user named, resolved (``.``, ``..``, symlinks and relative paths
  all mean the folder they point at), never into its parent.
- Files are assembled in a hidden staging folder *inside* that folder, so the final renames never
  cross a file system (an output folder may be a mount point: a Docker volume, a USB stick). A
  rename that fails with ``EXDEV`` anyway is done as copy-then-remove.
- Files of other names already in the folder are kept; same-named ones are replaced (a same-named
  folder as a whole) only once everything has been written.
- A failure, before or during the final moves, leaves the folder as it was: replaced entries are
  moved back, and folders this call created are removed again.
- A folder that cannot be written (a file in the way, a read-only file system, no permission)
  raises :class:`~illuknit.core.errors.OutputPathError` naming the folder and the reason.

Single files go to a temporary name in the same folder and are renamed into place.
"""

from __future__ import annotations

import errno
import os
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from illuknit.core.errors import OutputPathError

__all__ = [
    "atomic_write_bytes",
    "atomic_write_text",
    "check_output_dir",
    "resolve_output_dir",
    "staged_dir",
]

_STAGING_PREFIX = ".illuknit-"


def _umask() -> int:
    # mkstemp/mkdtemp create private (0600/0700) entries; results should get the usual
    # permissions, so apply the process umask as open()/mkdir() would.
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _reason(exc: OSError) -> str:
    return exc.strerror or type(exc).__name__


def atomic_write_bytes(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` via a temporary file and a rename."""
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    except OSError as exc:
        blocker = _file_in_the_way(path.parent)
        reason = f"{blocker} is a file, not a folder" if blocker else _reason(exc)
        raise OutputPathError(f"cannot write {path}: {reason}") from exc
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


def resolve_output_dir(outdir: str | os.PathLike[str]) -> Path:
    """The absolute folder ``outdir`` names: ``.``/``..`` and symlinks resolved, never its parent.

    >>> resolve_output_dir(".") == Path.cwd().resolve()
    True
    """
    return Path(os.path.expanduser(os.fspath(outdir))).resolve()


def _file_in_the_way(folder: Path) -> Path | None:
    """The nearest existing path at or above ``folder`` when it is not a folder, else None."""
    existing = folder.absolute()
    while not existing.exists() and existing != existing.parent:
        existing = existing.parent
    return None if existing.is_dir() else existing


def check_output_dir(outdir: str | os.PathLike[str]) -> Path:
    """Check that ``outdir`` is, or can become, a writable folder; return it resolved.

    Nothing is created. Raises :class:`~illuknit.core.errors.OutputPathError` when the path is a file,
    when a file stands where a parent folder should be, or when the nearest existing folder cannot
    be written (read-only file system, no permission).
    """
    final = resolve_output_dir(outdir)
    blocker = _file_in_the_way(final)
    if blocker is not None:
        where = "is a file" if blocker == final else f"has a file in the way: {blocker}"
        raise OutputPathError(f"output folder {outdir} {where}; name a folder")
    existing = final
    while not existing.exists():
        existing = existing.parent
    if not os.access(existing, os.W_OK | os.X_OK):
        # access() answers for root too on a read-only mount; statvfs says which reason it is.
        ro = os.statvfs(existing).f_flag & os.ST_RDONLY
        reason = "read-only file system" if ro else "permission denied"
        raise OutputPathError(f"cannot write to output folder {outdir} ({existing}): {reason}")
    return final


def _make_dirs(final: Path) -> list[Path]:
    """Create ``final`` and missing parents; return the folders created, deepest first."""
    missing = []
    p = final
    while not p.exists():
        missing.append(p)
        p = p.parent
    for d in reversed(missing):
        d.mkdir()
    return missing


def _move(src: Path, dst: Path) -> None:
    """Rename ``src`` to ``dst``; copy then remove when the rename would cross a file system."""
    try:
        os.replace(src, dst)
    except OSError as exc:
        if exc.errno != errno.EXDEV:
            raise
        if src.is_dir() and not src.is_symlink():
            shutil.copytree(src, dst, symlinks=True)
            shutil.rmtree(src)
        else:
            shutil.copy2(src, dst, follow_symlinks=False)
            src.unlink()


def _remove(path: Path) -> None:
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path)
    elif path.exists() or path.is_symlink():
        path.unlink()


def _commit(staging: Path, final: Path) -> None:
    """Move every entry of ``staging`` into ``final``; on failure put ``final`` back as it was."""
    backup = Path(tempfile.mkdtemp(prefix=_STAGING_PREFIX, suffix=".replaced", dir=final))
    done: list[tuple[str, bool, bool]] = []  # (name, old one moved to backup, new one in place)
    try:
        for entry in sorted(staging.iterdir()):
            target = final / entry.name
            had_old = target.exists() or target.is_symlink()
            if had_old:
                _move(target, backup / entry.name)
            done.append((entry.name, had_old, False))
            _move(entry, target)
            done[-1] = (entry.name, had_old, True)
    except BaseException:
        for name, had_old, placed in reversed(done):
            if placed:
                _remove(final / name)
            if had_old:
                _move(backup / name, final / name)
        raise
    finally:
        shutil.rmtree(backup, ignore_errors=True)


@contextmanager
def staged_dir(outdir: str | os.PathLike[str]) -> Iterator[Path]:
    """Yield a staging folder whose contents land in ``outdir`` only if the block succeeds.

    ``outdir`` is resolved first (``.``, ``..``, symlinks): the files land in the folder it names,
    created if needed. The staging folder is a hidden folder inside it, so the final renames stay
    on one file system. Other files already in ``outdir`` are kept; same-named entries are
    replaced. On any error ``outdir`` is left as it was (and removed again if this call made it).

    >>> with staged_dir("out") as tmp:   # doctest: +SKIP
    ...     (tmp / "pattern.json").write_text("...")
    """
    final = check_output_dir(outdir)
    try:
        created = _make_dirs(final)
    except OSError as exc:
        raise OutputPathError(f"cannot create output folder {outdir}: {_reason(exc)}") from exc
    try:
        try:
            staging = Path(tempfile.mkdtemp(prefix=_STAGING_PREFIX, suffix=".partial", dir=final))
        except OSError as exc:
            raise OutputPathError(
                f"cannot write to output folder {outdir}: {_reason(exc)}"
            ) from exc
        try:
            os.chmod(staging, 0o777 & ~_umask())
            yield staging
            try:
                _commit(staging, final)
            except OSError as exc:
                raise OutputPathError(
                    f"cannot write to output folder {outdir}: {_reason(exc)} (left as it was)"
                ) from exc
        finally:
            shutil.rmtree(staging, ignore_errors=True)
    except BaseException:
        for d in created:  # deepest first; only folders still empty
            try:
                d.rmdir()
            except OSError:
                break
        raise
