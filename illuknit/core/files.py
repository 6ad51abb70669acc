"""Writing results so that a failure, or a kill at any moment, never leaves half-written output.

Single files (:func:`atomic_write_bytes`)
-----------------------------------------
- The data goes to a temporary file beside the target, is flushed to disk, and is renamed over
  the target, so the path holds either the old file or the new one, never a part.
- Only a regular file, or a path where nothing is yet, is ever written. A folder, a device
  (``/dev/null``, ``/dev/full``), a named pipe (FIFO) or a socket at the path raises
  :class:`~illuknit.core.errors.OutputPathError` and is left untouched: a rename would otherwise put a
  regular file where the device was.
- A symbolic link is written *through*, as ``cp``, editors and shell redirections do: its final
  target is replaced (created, when the link dangles) and the link stays a link. The same rules
  then apply to the target. A link loop is an ``OutputPathError``.
- A replaced file keeps its permission bits; a new one gets the usual ones (``0666`` less the
  umask). A failure while writing (a full disk: ``ENOSPC``) removes the temporary file, keeps the
  old file as it was, and raises ``OutputPathError`` saying so.
- ``-`` is standard output in :func:`write_output_file` (the ``-o -`` of commands that write one
  file).

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

Single files' temporary files (``.<name>.illuknit-<pid>-<random>.tmp``) are removed on every
error, Ctrl-C included (the command line turns SIGTERM and SIGHUP into the same unwinding); one
left by a ``kill -9`` is removed by the next write into that folder once it is abandoned: its
writer holds a lock on it while it lives, and the pid in its name says whether that writer is
gone (:func:`remove_stale_temp_files`). A temporary file of a live process is never touched
(except one more than a day old that nobody holds), nor any file of another name.

For tests only: the environment variable ``ILLUKNIT_TEST_SIGNAL_IN_FILE_WRITE=KILL`` (or
``TERM``) makes the process send itself that signal once a single file's temporary file is
written, before the rename. The environment variable ``ILLUKNIT_TEST_KILL_AT_COMMIT_STEP=k`` makes the
process ``SIGKILL`` itself right after the k-th step of a folder commit (steps are counted per
process: 1 staging synced, 2 journal written, then one per rename, then backup, journal and
staging removed). ``tests/test_outputs_kill.py`` uses it to kill inside the commit; never set it
otherwise.
"""

from __future__ import annotations

import errno
import json
import os
import re
import shutil
import signal
import stat
import sys
import tempfile
import warnings
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass
from pathlib import Path

from illuknit.core.errors import OutputOverInputError, OutputPathError

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

_STAGING_PREFIX = ".illuknit-"
_LEFTOVER = re.compile(
    r"^\.illuknit-(?P<id>.+?)\.(?P<kind>partial|replaced|journal|journal\.tmp)$", re.DOTALL
)
#: The test-only fault-injection hook (see the module docstring).
KILL_AT_COMMIT_STEP_ENV = "ILLUKNIT_TEST_KILL_AT_COMMIT_STEP"
#: The test-only hook of single files: ``KILL`` or ``TERM`` sends that signal to the process
#: itself once a temporary file is written, before its rename (see the module docstring).
SIGNAL_IN_FILE_WRITE_ENV = "ILLUKNIT_TEST_SIGNAL_IN_FILE_WRITE"
_MAX_LINKS = 40  # as the kernel's MAXSYMLINKS
#: A single file's temporary name: ``.<name>.illuknit-<pid>-<random>.tmp`` (the name cut short).
_TEMP = re.compile(r"^\..*\.illuknit-(?P<pid>[0-9]+)-[A-Za-z0-9_]+\.tmp$", re.DOTALL)
_TEMP_NAME_KEEP = 100  # characters of the target's name kept in its temporary name
#: A temporary file of a live process is removed only when it is older than this (seconds).
_TEMP_ABANDONED_AFTER = 24 * 3600
_DISK_FULL = {errno.ENOSPC, errno.EDQUOT, errno.EFBIG}
_JOURNAL_VERSION = 1


class OutputRecoveryWarning(UserWarning):
    """A write into a folder found an interrupted earlier write there and finished or undid it;
    the message says which (the command line prints it as one ``note:`` line)."""


def _umask() -> int:
    # mkstemp/mkdtemp create private (0600/0700) entries; results should get the usual
    # permissions, so apply the process umask as open()/mkdir() would.
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _shown(path: object) -> str:
    from illuknit.core.documents import shown_path

    return shown_path(os.fspath(path)) if isinstance(path, (str, os.PathLike)) else str(path)


def _reason(exc: OSError) -> str:
    return exc.strerror or type(exc).__name__


# -- what this process wrote (for the CLI's message when stdout fails afterwards) --------------

_written: ContextVar[list[Path] | None] = ContextVar("illuknit_written", default=None)


@contextmanager
def recording_writes() -> Iterator[list[Path]]:
    """Collect, in the yielded list, every file and folder committed in this context.

    The command line uses it to say what was already written when printing to standard output
    fails afterwards.
    """
    log: list[Path] = []
    token = _written.set(log)
    try:
        yield log
    finally:
        _written.reset(token)


def _in_staging(path: Path) -> bool:
    return any(p.startswith(_STAGING_PREFIX) for p in path.parent.parts)


def _record(path: Path) -> None:
    log = _written.get()
    if log is not None and not _in_staging(path):
        log.append(path)


# -- no output over an input ---------------------------------------------------------------------


@dataclass(frozen=True)
class _Input:
    """An input file of this run: as the user named it, where it really is, and its identity."""

    shown: str
    named: Path  # absolute, its folder resolved, the last link (if any) not followed
    real: Path  # every link followed
    ident: tuple[int, int] | None  # (st_dev, st_ino); None when it cannot be stat-ed


_inputs: ContextVar[tuple[_Input, ...]] = ContextVar("illuknit_inputs", default=())


def _identity(path: str | os.PathLike[str]) -> tuple[int, int] | None:
    try:
        st = os.stat(path)
    except (OSError, ValueError):
        return None
    return (st.st_dev, st.st_ino)


def _as_input(path: str | os.PathLike[str]) -> _Input:
    shown = os.fspath(path)
    absolute = Path(os.path.abspath(shown))
    named = Path(os.path.realpath(absolute.parent)) / absolute.name
    return _Input(shown, named, Path(os.path.realpath(absolute)), _identity(absolute))


def _over_input(target: Path, *, whole: bool, inputs: tuple[_Input, ...]) -> str | None:
    """Why writing ``target`` would destroy an input (None: it would not).

    ``whole``: ``target`` is an entry a folder commit replaces as a whole (a folder with all it
    holds, or a link itself rather than the file it points at).
    """
    real = Path(os.path.realpath(target))
    ident = _identity(target)
    for inp in inputs:
        if target in (inp.named, inp.real) or real == inp.real:
            return f"it is the input file {_shown(inp.shown)}"
        if ident is not None and ident == inp.ident:
            return f"it is the input file {_shown(inp.shown)} (the same file by a hard link)"
        if whole and (inp.named.is_relative_to(target) or inp.real.is_relative_to(target)):
            return f"it holds the input file {_shown(inp.shown)}"
    return None


def _refuse_over_input(shown: object, target: Path, *, whole: bool = False) -> None:
    why = _over_input(target, whole=whole, inputs=_inputs.get())
    if why is not None:
        other = "output folder" if whole else "output"
        raise OutputOverInputError(
            f"refusing to write {_shown(shown)}: {why}; name another {other} (nothing was written)"
        )


def check_outputs_apart(
    inputs: Iterable[str | os.PathLike[str]],
    *,
    files: Iterable[str | os.PathLike[str]] = (),
    folders: Iterable[str | os.PathLike[str]] = (),
) -> None:
    """Refuse, before anything is written, an output that is one of the ``inputs``.

    An output file is compared with every input file as writing it would land (links
    followed), and by device and inode (a hard link); an output folder is refused when it is an
    input file. ``-`` (standard input or output) is skipped. Raises
    :class:`~illuknit.core.errors.OutputOverInputError` naming both. Which entries a folder
    commit replaces is known only at its end: :func:`protecting_inputs` guards those.

    >>> check_outputs_apart(["p.json"], files=["p.json"])
    Traceback (most recent call last):
    ...
    illuknit.core.errors.OutputOverInputError: refusing to write p.json: it is the input file p.json; name another output (nothing was written)
    """
    ins = tuple(_as_input(p) for p in inputs if os.fspath(p) != STDOUT)
    for f in files:
        if os.fspath(f) != STDOUT:
            why = _over_input(_write_target(Path(f)), whole=False, inputs=ins)
            if why is not None:
                raise OutputOverInputError(
                    f"refusing to write {_shown(f)}: {why}; name another output (nothing was written)"
                )
    for d in folders:
        # only same-named entries of a folder are replaced: those are checked at the commit
        why = _over_input(resolve_output_dir(d), whole=False, inputs=ins)
        if why is not None:
            raise OutputOverInputError(
                f"refusing to write into output folder {_shown(d)}: {why}; name another folder "
                "(nothing was written)"
            )


@contextmanager
def protecting_inputs(inputs: Iterable[str | os.PathLike[str]]) -> Iterator[None]:
    """Within the block, refuse every write that would replace one of ``inputs``.

    :func:`atomic_write_bytes` refuses a file that is an input (links followed, or the same
    device and inode), and a folder commit (:func:`staged_dir`) refuses, before it moves
    anything, to replace an entry that is an input or holds one: an input of another name in
    the output folder is kept, as every file of another name is. Raises
    :class:`~illuknit.core.errors.OutputOverInputError`.
    """
    token = _inputs.set(
        _inputs.get() + tuple(_as_input(p) for p in inputs if os.fspath(p) != STDOUT)
    )
    try:
        yield
    finally:
        _inputs.reset(token)


# -- single files --------------------------------------------------------------------------------


def _kind(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a folder"
    if stat.S_ISCHR(mode):
        return "a character device"
    if stat.S_ISBLK(mode):
        return "a block device"
    if stat.S_ISFIFO(mode):
        return "a named pipe (FIFO)"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def _write_target(path: Path) -> Path:
    """Where a write to ``path`` lands: ``path``, or the final target of the links it names."""
    p = Path(os.path.abspath(path))
    for _ in range(_MAX_LINKS):
        try:
            st = os.lstat(p)
        except (FileNotFoundError, NotADirectoryError):
            return p
        except OSError as exc:  # ELOOP in a parent folder, no permission
            raise OutputPathError(f"cannot write {_shown(path)}: {_reason(exc)}") from exc
        if not stat.S_ISLNK(st.st_mode):
            return p
        link = os.readlink(p)
        p = Path(link) if os.path.isabs(link) else p.parent / link
    raise OutputPathError(
        f"cannot write {_shown(path)}: too many levels of symbolic links (a link loop)"
    )


def _existing_regular(path: Path, target: Path) -> os.stat_result | None:
    """The target's stat when it is a regular file, None when nothing is there; else refuse."""
    try:
        st = os.stat(target)
    except (FileNotFoundError, NotADirectoryError):
        return None
    except OSError as exc:
        raise OutputPathError(f"cannot write {_shown(path)}: {_reason(exc)}") from exc
    if stat.S_ISREG(st.st_mode):
        return st
    via = "" if target == Path(os.path.abspath(path)) else f" (a link to {target})"
    raise OutputPathError(
        f"cannot write {_shown(path)}{via}: it is {_kind(st.st_mode)}, not a regular file; "
        "name a regular file (it was left untouched)"
    )


def atomic_write_bytes(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to the regular file ``path`` via a temporary file and a rename.

    A symbolic link is written through to its target. Raises
    :class:`~illuknit.core.errors.OutputPathError` (and touches nothing) when ``path`` is a folder, a
    device, a FIFO or a socket, or a link loop; and when writing fails (a full disk), after
    removing the temporary file: the old file is kept as it was. Within
    :func:`protecting_inputs`, a ``path`` that is one of the inputs is refused
    (:class:`~illuknit.core.errors.OutputOverInputError`). The temporary file,
    ``.<name>.illuknit-<pid>-<random>.tmp`` beside the target, is removed on every error, and
    one that a killed run left behind is removed by the next write into that folder
    (:func:`remove_stale_temp_files`). Returns ``path``.
    """
    path = Path(path)
    target = _write_target(path)
    _refuse_over_input(path, target)
    existing = _existing_regular(path, target)
    staging = _in_staging(target)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        if not staging:  # a staging folder is removed as a whole
            _note_stale_temps(target.parent)
        fd, tmp = tempfile.mkstemp(
            prefix=f".{target.name[:_TEMP_NAME_KEEP]}.illuknit-{os.getpid()}-",
            suffix=".tmp",
            dir=target.parent,
        )
    except OSError as exc:
        blocker = _file_in_the_way(target.parent)
        reason = f"{blocker} is a file, not a folder" if blocker else _reason(exc)
        raise OutputPathError(f"cannot write {_shown(path)}: {reason}") from exc
    try:
        # The lock tells a later run that this temporary file is alive; it is released when the
        # file is closed, after the rename.
        with os.fdopen(fd, "wb") as f:
            _lock_file(fd)
            f.write(data)
            f.flush()
            if not staging:  # a folder commit syncs its staging folder once
                os.fsync(f.fileno())
                _signal_for_test()
            os.chmod(tmp, stat.S_IMODE(existing.st_mode) if existing else 0o666 & ~_umask())
            _existing_regular(path, target)  # again, just before the rename
            os.replace(tmp, target)
    except OutputPathError:
        Path(tmp).unlink(missing_ok=True)
        raise
    except OSError as exc:
        Path(tmp).unlink(missing_ok=True)
        kept = f"{_shown(path)} was kept as it was" if existing else "nothing was written"
        raise OutputPathError(f"cannot write {_shown(path)}: {_reason(exc)}; {kept}") from exc
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    _record(path)
    return path


def _signal_for_test() -> None:
    """The test-only hook: ``SIGNAL_IN_FILE_WRITE_ENV=KILL`` (or ``TERM``) signals this process."""
    name = os.environ.get(SIGNAL_IN_FILE_WRITE_ENV)
    if name:
        os.kill(os.getpid(), getattr(signal, f"SIG{name}"))
        import time

        time.sleep(1)  # a caught signal's handler runs here


def _lock_file(fd: int) -> None:
    if sys.platform != "win32":  # pragma: no branch - no flock on Windows
        import fcntl

        fcntl.flock(fd, fcntl.LOCK_EX)


def _pid_alive(pid: int) -> bool:
    if pid <= 0:  # 0 and negative numbers would mean process groups to kill()
        return False
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True  # another user's process
    except (OSError, OverflowError):
        return False
    return True


def _remove_if_abandoned(path: Path, pid: int) -> bool:
    """Remove the temporary file ``path`` when no process writes it any more; whether it did."""
    try:
        st = os.lstat(path)
    except OSError:
        return False
    if not stat.S_ISREG(st.st_mode):
        return False
    import time

    if _pid_alive(pid) and time.time() - st.st_mtime < _TEMP_ABANDONED_AFTER:
        return False  # its writer may still be at work (and may not hold the lock yet)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK)
    except OSError:
        return False
    try:
        import fcntl

        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)  # a live writer holds it
        os.unlink(path)
    except OSError:
        return False
    finally:
        os.close(fd)
    return True


def remove_stale_temp_files(folder: str | os.PathLike[str]) -> list[Path]:
    """Remove the temporary files that killed single-file writes left in ``folder``.

    Only illuknit's own (``.<name>.illuknit-<pid>-<random>.tmp``, a regular file) are touched,
    and only when abandoned: no process holds the lock its writer takes, and that writer (the
    pid in the name) is gone, or the file is more than a day old. Every
    :func:`atomic_write_bytes` does this first in its target's folder. Returns what was removed.
    """
    if sys.platform == "win32":  # pragma: no cover - no flock: a live writer cannot be told
        return []
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return []
    removed = []
    for entry in entries:
        m = _TEMP.match(entry.name)
        if m and _remove_if_abandoned(Path(entry.path), int(m["pid"])):
            removed.append(Path(entry.path))
    return removed


def _note_stale_temps(folder: Path) -> None:
    removed = remove_stale_temp_files(folder)
    if removed:
        what = removed[0].name if len(removed) == 1 else f"{len(removed)} temporary files"
        warnings.warn(
            f"removed {what} left in {folder} by an interrupted earlier write",
            OutputRecoveryWarning,
            stacklevel=3,
        )


def atomic_write_text(path: str | os.PathLike[str], text: str) -> Path:
    """Write UTF-8 text (LF line endings) to ``path`` via a temporary file and a rename."""
    return atomic_write_bytes(path, text.encode("utf-8"))


#: The file name that means standard output in :func:`write_output_file`.
STDOUT = "-"


def write_output_file(path: str | os.PathLike[str], data: bytes) -> str:
    """The one file a command writes: ``-`` is standard output, anything else
    :func:`atomic_write_bytes`. Returns what was written to (``"standard output"`` or the path).
    """
    if os.fspath(path) != STDOUT:
        return str(atomic_write_bytes(path, data))
    out = sys.stdout
    if out is None:
        raise OutputPathError("cannot write to standard output: it is closed")
    buffer = getattr(out, "buffer", None)
    try:
        if buffer is None:  # a text-only stand-in
            out.write(data.decode("utf-8", "surrogateescape"))
            out.flush()
        else:
            out.flush()
            buffer.write(data)
            buffer.flush()
    except OSError as exc:
        raise OutputPathError(f"cannot write to standard output: {_reason(exc)}") from exc
    return "standard output"


# -- folders -------------------------------------------------------------------------------------


def resolve_output_dir(outdir: str | os.PathLike[str]) -> Path:
    """The absolute folder ``outdir`` names: ``.``/``..`` and symlinks resolved, never its parent.

    Raises :class:`~illuknit.core.errors.OutputPathError` for a symbolic link loop.

    >>> resolve_output_dir(".") == Path.cwd().resolve()
    True
    """
    try:
        return Path(os.path.expanduser(os.fspath(outdir))).resolve()
    except (RuntimeError, OSError) as exc:  # RuntimeError: a link loop (Python < 3.13)
        raise OutputPathError(
            f"output folder {_shown(outdir)}: too many levels of symbolic links (a link loop)"
        ) from exc


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
