"""Writing results so that a failure, or a kill at any moment, never leaves half-written output.

Output folders (:func:`staged_dir`)
-----------------------------------
- Output goes into the folder the user named, resolved (``.``, ``..``, symlinks and relative paths
  all mean the folder they point at), never into its parent.
- Files are assembled in a hidden staging folder *inside* that folder
  (``.illuknit-<id>.partial``), so the final renames never cross a file system (an output folder
  may be a mount point: a Docker volume, a USB stick). A rename that fails with ``EXDEV`` anyway
  is done as copy-then-remove.
- Files of other names already in the folder are kept (the user's own files, and outputs of an
  earlier run that this run does not write); same-named entries are replaced (a same-named folder
  as a whole).
- A folder that cannot be written (a file in the way, a read-only file system, no permission, a
  full disk) raises :class:`~illuknit.core.errors.OutputPathError` naming the folder and the reason,
  and leaves the folder as it was.

The commit: a journal, then the moves
-------------------------------------
Moving N entries into place takes N renames, and nothing in POSIX makes several renames in a
shared folder one atomic step. So the commit has a single *decision point* instead, and every
run into the folder finishes what an interrupted run decided:

1. everything in the staging folder is fsynced;
2. the journal ``.illuknit-<id>.journal`` (the staging and backup folders' names and the entries
   to move) is written to a temporary name, fsynced, and renamed into place; the folder is
   fsynced. From this moment the new set is committed;
3. each entry: the old same-named entry (if any) is moved into ``.illuknit-<id>.replaced``, the
   new one from the staging folder into its place;
4. the backup folder is removed, then the journal, then the (empty) staging folder.

A kill before the journal exists leaves the old set in place (plus a staging folder); a kill
after the journal is removed leaves the new set (plus perhaps empty leftovers). A kill in
between leaves the journal, and the next write into the folder (:func:`staged_dir`, or
:func:`recover_output_dir` alone) *rolls forward*: every entry still in the staging folder is
moved into place exactly as in step 3 (each step can be repeated), and step 4 is done. A staging
folder without a journal is an unfinished run and is removed (rolled back: none of it was in
place). Either way the folder ends with exactly the old or exactly the new set of illuknit's
entries, the user's own files untouched, no hidden ``.illuknit-*`` leftovers, and a
:class:`OutputRecoveryWarning` (a ``note:`` line on the command line) says once what was done.
A failure inside a running commit (an ``OSError`` during the moves) is undone on the spot: the
new entries go back into the staging folder, the old ones back into place, the journal is
removed.

Runs into the same folder take an exclusive ``flock`` on it while they recover, set up staging
and commit, and each holds a lock on its own staging folder while it works, so a recovery never
removes the staging folder of a run that is still alive (a killed process's locks are released
by the kernel).

Single files (:func:`atomic_write_bytes`, their temporary files' hygiene) are
:mod:`illuknit.core.atomic_files`; keeping outputs off inputs and recording what was written
:mod:`illuknit.core.output_guard`. Every name of those two is importable from here.

For tests only: the environment variable ``ILLUKNIT_TEST_KILL_AT_COMMIT_STEP=k`` makes the
process ``SIGKILL`` itself right after the k-th step of a folder commit (steps are counted per
process: 1 staging synced, 2 journal written, then one per rename, then backup, journal and
staging removed). ``tests/core/test_outputs_kill.py`` uses it to kill inside the commit; never set it
otherwise.
"""

from __future__ import annotations

import errno
import json
import os
import re
import shutil
import signal
import sys
import tempfile
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from illuknit.core.atomic_files import (
    SIGNAL_IN_FILE_WRITE_ENV,
    atomic_write_bytes,
    atomic_write_text,
    remove_stale_temp_files,
    write_output_file,
)
from illuknit.core.errors import OutputPathError
from illuknit.core.output_guard import (
    _STAGING_PREFIX,
    STDOUT,
    OutputRecoveryWarning,
    _file_in_the_way,
    _reason,
    _record,
    _refuse_over_input,
    _shown,
    _umask,
    check_outputs_apart,
    protecting_inputs,
    recording_writes,
    resolve_output_dir,
)

__all__ = [
    "KILL_AT_COMMIT_STEP_ENV",
    "SIGNAL_IN_FILE_WRITE_ENV",
    "STDOUT",
    "OutputRecoveryWarning",
    "atomic_write_bytes",
    "atomic_write_text",
    "check_output_dir",
    "check_outputs_apart",
    "protecting_inputs",
    "recording_writes",
    "recover_output_dir",
    "remove_stale_temp_files",
    "resolve_output_dir",
    "staged_dir",
    "write_output_file",
]

_LEFTOVER = re.compile(
    r"^\.illuknit-(?P<id>.+?)\.(?P<kind>partial|replaced|journal|journal\.tmp)$", re.DOTALL
)
#: The test-only fault-injection hook (see the module docstring).
KILL_AT_COMMIT_STEP_ENV = "ILLUKNIT_TEST_KILL_AT_COMMIT_STEP"
_DISK_FULL = {errno.ENOSPC, errno.EDQUOT, errno.EFBIG}
_JOURNAL_VERSION = 1


# -- folders -------------------------------------------------------------------------------------


def check_output_dir(outdir: str | os.PathLike[str]) -> Path:
    """Check that ``outdir`` is, or can become, a writable folder; return it resolved.

    Nothing is created. Raises :class:`~illuknit.core.errors.OutputPathError` when the path is a file,
    when a file stands where a parent folder should be, or when the nearest existing folder cannot
    be written (read-only file system, no permission).
    """
    final = resolve_output_dir(outdir)
    try:
        blocker = _file_in_the_way(final)
    except OSError as exc:  # a name too long for the system
        raise OutputPathError(
            f"cannot write to output folder {_shown(outdir)}: {_reason(exc)}"
        ) from exc
    if blocker is not None:
        where = "is a file" if blocker == final else f"has a file in the way: {blocker}"
        raise OutputPathError(f"output folder {_shown(outdir)} {where}; name a folder")
    existing = final
    while not existing.exists():
        existing = existing.parent
    if not os.access(existing, os.W_OK | os.X_OK):
        # access() answers for root too on a read-only mount; statvfs says which reason it is.
        ro = os.statvfs(existing).f_flag & os.ST_RDONLY
        reason = "read-only file system" if ro else "permission denied"
        raise OutputPathError(
            f"cannot write to output folder {_shown(outdir)} ({existing}): {reason}"
        )
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


def _lexists(path: Path) -> bool:
    return os.path.lexists(path)


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
    elif _lexists(path):
        path.unlink()


def _fsync_path(path: Path, *, folder: bool) -> None:
    flags = os.O_RDONLY | (getattr(os, "O_DIRECTORY", 0) if folder else 0)
    try:
        fd = os.open(path, flags)
    except OSError:
        return  # nothing to sync on a file system that cannot open folders
    try:
        os.fsync(fd)
    except OSError as exc:
        if exc.errno not in (errno.EINVAL, errno.EBADF):  # folders on some file systems
            raise
    finally:
        os.close(fd)


def _fsync_tree(root: Path) -> None:
    for here, _, files in os.walk(root):
        for name in files:
            p = Path(here) / name
            if not p.is_symlink():
                _fsync_path(p, folder=False)
        _fsync_path(Path(here), folder=True)


_steps = 0


def _step() -> None:
    """Count one step of a folder commit; the test-only hook kills the process after step k."""
    global _steps
    wanted = os.environ.get(KILL_AT_COMMIT_STEP_ENV)
    if not wanted:
        return
    _steps += 1
    if _steps == int(wanted):
        os.kill(os.getpid(), signal.SIGKILL)


@contextmanager
def _folder_lock(folder: Path) -> Iterator[None]:
    """An exclusive lock on ``folder`` for recovering, setting up staging and committing."""
    if sys.platform == "win32":  # pragma: no cover - no flock; one writer per folder assumed
        yield
        return
    import fcntl

    fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)  # releases the lock


def _lock_staging(staging: Path) -> int | None:
    """Hold a lock on ``staging`` while this run works in it; its fd (close to release)."""
    if sys.platform == "win32":  # pragma: no cover
        return None
    import fcntl

    fd = os.open(staging, os.O_RDONLY | os.O_DIRECTORY)
    fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    return fd


def _in_use(staging: Path) -> bool:
    """Whether a live run still works in ``staging`` (it holds the staging folder's lock)."""
    if sys.platform == "win32":  # pragma: no cover
        return False
    import fcntl

    try:
        fd = os.open(staging, os.O_RDONLY | os.O_DIRECTORY)
    except OSError:
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return True
    finally:
        os.close(fd)
    return False


def _write_journal(journal: Path, doc: dict[str, object]) -> None:
    tmp = journal.with_name(journal.name + ".tmp")
    with open(tmp, "w", encoding="utf-8") as f:
        json.dump(doc, f)
        f.flush()
        os.fsync(f.fileno())
    os.rename(tmp, journal)
    _fsync_path(journal.parent, folder=True)


def _roll_forward(final: Path, staging: Path, backup: Path) -> int:
    """Move every entry still in ``staging`` into ``final`` (old ones into ``backup``); then
    remove the backup. Each move can be repeated after a kill. Returns the entries moved."""
    moved = 0
    if staging.is_dir():
        for name in sorted(os.listdir(staging)):
            target = final / name
            if _lexists(target):
                backup.mkdir(exist_ok=True)
                if _lexists(backup / name):  # cannot happen in a commit; be safe
                    _remove(backup / name)
                _move(target, backup / name)
                _step()
            _move(staging / name, target)
            _step()
            moved += 1
        _fsync_path(final, folder=True)
    if backup.exists():
        shutil.rmtree(backup)
    _step()
    return moved


def _undo(final: Path, staging: Path, backup: Path, names: list[str]) -> None:
    """Put a commit that failed part-way back: new entries into ``staging``, old into place."""
    for name in reversed(names):
        target = final / name
        if not _lexists(staging / name) and _lexists(target):
            _move(target, staging / name)
        if _lexists(backup / name):
            _move(backup / name, target)
    if backup.exists():
        shutil.rmtree(backup)


def _commit(staging: Path, final: Path) -> None:
    """Move every entry of ``staging`` into ``final`` through the journal (module docstring)."""
    ident = staging.name[len(_STAGING_PREFIX) : -len(".partial")]
    backup = final / f"{_STAGING_PREFIX}{ident}.replaced"
    journal = final / f"{_STAGING_PREFIX}{ident}.journal"
    names = sorted(os.listdir(staging))
    for name in names:  # before anything moves: never replace an input of this run
        _refuse_over_input(final / name, final / name, whole=True)
    _fsync_tree(staging)
    _step()
    _write_journal(
        journal,
        {
            "illuknit-journal": _JOURNAL_VERSION,
            "staging": staging.name,
            "backup": backup.name,
            "names": names,
        },
    )
    _step()
    try:
        _roll_forward(final, staging, backup)
    except BaseException:
        # Undo on the spot; if even that fails, the journal stays and the next run finishes.
        _undo(final, staging, backup, names)
        journal.unlink()
        raise
    journal.unlink()
    _fsync_path(final, folder=True)
    _step()
    staging.rmdir()
    _step()


def _recover(final: Path) -> str | None:
    """Finish or undo what interrupted runs left in ``final`` (the folder lock is held)."""
    groups: dict[str, dict[str, Path]] = {}
    for entry in os.scandir(final):
        m = _LEFTOVER.match(entry.name)
        if m:
            groups.setdefault(m["id"], {})[m["kind"]] = Path(entry.path)
    finished = undone = restored = 0
    for ident, parts in sorted(groups.items()):
        staging = parts.get("partial", final / f"{_STAGING_PREFIX}{ident}.partial")
        if staging.is_dir() and _in_use(staging):
            continue  # a live run's staging folder
        backup = parts.get("replaced", final / f"{_STAGING_PREFIX}{ident}.replaced")
        if "journal" in parts:
            _roll_forward(final, staging, backup)
            parts["journal"].unlink()
            finished += 1
        else:
            if staging.is_dir():
                undone += bool(os.listdir(staging))  # empty: the commit had finished
                shutil.rmtree(staging)
            if backup.is_dir():
                # Left by an older illuknit, whose commit kept no journal: whatever is missing
                # from the folder goes back, the rest was superseded by the newer entries.
                for name in os.listdir(backup):
                    if not _lexists(final / name):
                        _move(backup / name, final / name)
                        restored += 1
                shutil.rmtree(backup)
        if "journal.tmp" in parts:
            parts["journal.tmp"].unlink()
        if staging.is_dir():  # emptied by the roll-forward
            shutil.rmtree(staging)
    said = []
    if finished:
        said.append(
            f"finished putting in place the files of an interrupted earlier run into {final} "
            "(it had been stopped while moving them)"
            if finished == 1
            else f"finished putting in place the files of {finished} interrupted runs into {final}"
        )
    if undone:
        said.append(
            f"removed the unfinished files of {'an interrupted run' if undone == 1 else f'{undone} interrupted runs'} "
            f"from {final} (none of them had been put in place)"
        )
    if restored:
        said.append(f"put back {restored} entries an interrupted run had moved aside in {final}")
    return "; ".join(said) or None


def recover_output_dir(outdir: str | os.PathLike[str]) -> str | None:
    """Finish or undo an interrupted write into ``outdir``; say what was done (None: nothing).

    Every :func:`staged_dir` into the folder does this first; call it alone to bring a folder to
    a whole state without writing anything new. Raises
    :class:`~illuknit.core.errors.OutputPathError` when the leftovers cannot be moved or removed.
    """
    final = resolve_output_dir(outdir)
    if not final.is_dir():
        return None
    try:
        with _folder_lock(final):
            return _recover(final)
    except OSError as exc:
        if isinstance(exc, OutputPathError):
            raise
        raise OutputPathError(
            f"cannot finish an interrupted write into {_shown(outdir)}: {_reason(exc)}"
        ) from exc


@contextmanager
def staged_dir(outdir: str | os.PathLike[str]) -> Iterator[Path]:
    """Yield a staging folder whose contents land in ``outdir`` only if the block succeeds.

    ``outdir`` is resolved first (``.``, ``..``, symlinks): the files land in the folder it names,
    created if needed. What an interrupted earlier run left there is finished or undone first
    (an :class:`OutputRecoveryWarning` says what). The staging folder is a hidden folder inside
    it, so the final renames stay on one file system. Other files already in ``outdir`` are kept;
    same-named entries are replaced through a journal (module docstring), so even a kill leaves
    the old or the new set. On any error ``outdir`` is left as it was (and removed again if this
    call made it); a full disk inside the block is an :class:`~illuknit.core.errors.OutputPathError`.

    >>> with staged_dir("out") as tmp:   # doctest: +SKIP
    ...     (tmp / "pattern.json").write_text("...")
    """
    final = check_output_dir(outdir)
    try:
        created = _make_dirs(final)
    except OSError as exc:
        raise OutputPathError(
            f"cannot create output folder {_shown(outdir)}: {_reason(exc)}"
        ) from exc
    try:
        try:
            with _folder_lock(final):
                said = _recover(final)
                staging = Path(
                    tempfile.mkdtemp(prefix=_STAGING_PREFIX, suffix=".partial", dir=final)
                )
                lock = _lock_staging(staging)
        except OSError as exc:
            raise OutputPathError(
                f"cannot write to output folder {_shown(outdir)}: {_reason(exc)}"
            ) from exc
        if said:
            warnings.warn(said, OutputRecoveryWarning, stacklevel=3)
        journal = final / f"{staging.name[: -len('.partial')]}.journal"
        try:
            os.chmod(staging, 0o777 & ~_umask())
            try:
                yield staging
            except OSError as exc:
                if isinstance(exc, OutputPathError) or exc.errno not in _DISK_FULL:
                    raise
                raise OutputPathError(
                    f"cannot write to output folder {_shown(outdir)}: {_reason(exc)} "
                    "(the folder was left as it was)"
                ) from exc
            try:
                with _folder_lock(final):
                    _commit(staging, final)
            except OSError as exc:
                if isinstance(exc, OutputPathError):
                    raise
                raise OutputPathError(
                    f"cannot write to output folder {_shown(outdir)}: {_reason(exc)} (left as it was)"
                ) from exc
            _record(final)
        finally:
            if lock is not None:
                os.close(lock)
            if not journal.exists():  # else the next run rolls forward from the staging folder
                shutil.rmtree(staging, ignore_errors=True)
    except BaseException:
        for d in created:  # deepest first; only folders still empty
            try:
                d.rmdir()
            except OSError:
                break
        raise
