"""Writing one file so that a failure, or a kill at any moment, never leaves half of it.

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

Single files' temporary files (``.<name>.illuknit-<pid>-<random>.tmp``) are removed on every
error, Ctrl-C included (the command line turns SIGTERM and SIGHUP into the same unwinding); one
left by a ``kill -9`` is removed by the next write into that folder once it is abandoned: its
writer holds a lock on it while it lives, and the pid in its name says whether that writer is
gone (:func:`remove_stale_temp_files`). A temporary file of a live process is never touched
(except one more than a day old that nobody holds), nor any file of another name.

For tests only: the environment variable ``ILLUKNIT_TEST_SIGNAL_IN_FILE_WRITE=KILL`` (or
``TERM``) makes the process send itself that signal once a single file's temporary file is
written, before the rename.

Folders of outputs are :mod:`illuknit.core.files`; which paths may be written
:mod:`illuknit.core.output_guard`.
"""

from __future__ import annotations

import os
import re
import signal
import stat
import sys
import tempfile
import warnings
from pathlib import Path

from illuknit.core.errors import OutputPathError
from illuknit.core.output_guard import (
    STDOUT,
    OutputRecoveryWarning,
    _file_in_the_way,
    _in_staging,
    _reason,
    _record,
    _refuse_over_input,
    _shown,
    _umask,
    _write_target,
)

__all__ = [
    "SIGNAL_IN_FILE_WRITE_ENV",
    "atomic_write_bytes",
    "atomic_write_text",
    "remove_stale_temp_files",
    "write_output_file",
]

#: The test-only hook of single files: ``KILL`` or ``TERM`` sends that signal to the process
#: itself once a temporary file is written, before its rename (see the module docstring).
SIGNAL_IN_FILE_WRITE_ENV = "ILLUKNIT_TEST_SIGNAL_IN_FILE_WRITE"
_MAX_LINKS = 40  # as the kernel's MAXSYMLINKS
#: A single file's temporary name: ``.<name>.illuknit-<pid>-<random>.tmp`` (the name cut short).
_TEMP = re.compile(r"^\..*\.illuknit-(?P<pid>[0-9]+)-[A-Za-z0-9_]+\.tmp$", re.DOTALL)
_TEMP_NAME_KEEP = 100  # characters of the target's name kept in its temporary name
#: A temporary file of a live process is removed only when it is older than this (seconds).
_TEMP_ABANDONED_AFTER = 24 * 3600


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
