"""Which paths a run writes and may write: its outputs apart from its inputs and from each
other, and a record of what it committed.

- An output never replaces an input of the same run (:func:`protecting_inputs`,
  :func:`check_outputs_apart`): links are followed and hard links recognised, so a file is an
  input however it is named, and a folder that holds an input is never replaced as a whole.
- :func:`recording_writes` collects every file and folder committed in its context (the command
  line says what was already written when printing to standard output fails afterwards).

The writing itself is :mod:`illuknit.core.atomic_files` (one file) and
:mod:`illuknit.core.files` (an output folder); both read the helpers here.
"""

from __future__ import annotations

import os
import stat
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass
from pathlib import Path

from illuknit.core.errors import OutputOverInputError, OutputPathError

__all__ = [
    "STDOUT",
    "OutputRecoveryWarning",
    "check_outputs_apart",
    "protecting_inputs",
    "recording_writes",
    "resolve_output_dir",
]

_STAGING_PREFIX = ".illuknit-"
_MAX_LINKS = 40  # as the kernel's MAXSYMLINKS

#: The file name that means standard output in :func:`~illuknit.core.atomic_files.write_output_file`.
STDOUT = "-"


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
