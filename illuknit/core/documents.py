"""Reading the user's files (patterns, pictures, programs, tile banks, render parameters, manifests).

Each kind of document has its own error class; these helpers turn every way a file can fail to
read (missing, unreadable, not UTF-8, not JSON) into one such error with a clear message, so the
loaders only validate content.

Every read is bounded (:func:`open_input_file`): only a regular file is read (a named pipe, a
device such as ``/dev/zero``, a folder or a socket is refused at once, without reading or
waiting), up to a size limit per kind of file (:data:`INPUT_LIMITS`, stated in the error); a
file name too long for the system, or one that is not valid UTF-8, is one clear error too.
"""

from __future__ import annotations

import errno
import json
import os
import stat
from typing import Any, BinaryIO

from illuknit.core.errors import IlluknitError

__all__ = [
    "INPUT_LIMITS",
    "MAX_DOCUMENT_BYTES",
    "file_kind",
    "open_input_file",
    "read_input_bytes",
    "read_json_file",
    "read_text_file",
    "shown_path",
]

_MIB = 1024 * 1024
#: The size limit of an input file whose kind has none of its own in :data:`INPUT_LIMITS`.
MAX_DOCUMENT_BYTES = 64 * _MIB
#: Size limits of input files by kind (the ``what`` of the readers), in bytes. A pattern of the
#: largest grid (1000 x 1000 units) is about 4 MiB of JSON; a knitout program of it a few hundred
#: MiB; pictures above 100 megapixels are refused anyway (:mod:`illuknit.pictures.decode`).
INPUT_LIMITS: dict[str, int] = {
    "picture": 256 * _MIB,
    "program": 1024 * _MIB,
    "knitout": 1024 * _MIB,
}
_SHOWN_MAX = 200  # characters of a file name shown in a message


def shown_path(path: str | os.PathLike[str]) -> str:
    """``path`` as a message shows it, on one line: bytes that are not UTF-8 as ``\\xNN``,
    control characters (a line break, a terminal escape) as ``\\xNN`` too, and a very long one
    cut in the middle (``...``, with its length).

    >>> shown_path("pic\\x1b[31m.png")
    'pic\\\\x1b[31m.png'
    """
    text = os.fspath(path)
    if isinstance(text, bytes):
        text = os.fsdecode(text)
    text = text.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")
    text = "".join(f"\\x{ord(ch):02x}" if _is_control(ch) else ch for ch in text)
    if len(text) > _SHOWN_MAX:
        text = f"{text[: _SHOWN_MAX // 2]}...{text[-_SHOWN_MAX // 3 :]} ({len(text)} characters)"
    return text


def _is_control(ch: str) -> bool:
    return ord(ch) < 0x20 or 0x7F <= ord(ch) < 0xA0 or ch in "\u2028\u2029"


def file_kind(mode: int) -> str:
    """What a file of this ``st_mode`` is, for a message: \"a folder\", \"a named pipe (FIFO)\", ..."""
    if stat.S_ISDIR(mode):
        return "a folder"
    if stat.S_ISFIFO(mode):
        return "a named pipe (FIFO)"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def _size(n: int) -> str:
    return f"{n / _MIB:.0f} MiB" if n >= _MIB else f"{n} bytes"


def open_input_file(
    path: str | os.PathLike[str],
    *,
    error: type[IlluknitError],
    what: str,
    limit: int | None = None,
) -> BinaryIO:
    """Open the input file ``path`` for reading in binary, after checking it can be read whole.

    Raises ``error`` (one line naming the file) when it is missing, not a regular file (a
    folder, a named pipe, a device, a socket: refused at once, nothing read, no waiting), larger
    than ``limit`` bytes (default: its kind's in :data:`INPUT_LIMITS`), or cannot be opened (no
    permission, a name too long). The caller closes the file.
    """
    limit = INPUT_LIMITS.get(what, MAX_DOCUMENT_BYTES) if limit is None else limit
    shown = shown_path(path)
    try:
        # O_NONBLOCK: opening a named pipe must not wait for a writer
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except FileNotFoundError:
        raise error(f"{what} file not found: {shown}") from None
    except (OSError, ValueError) as e:
        raise error(f"cannot read {what} file {shown}: {_why(path, e)}") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise error(
                f"cannot read {what} file {shown}: it is {file_kind(st.st_mode)}, not a regular file"
            )
        if st.st_size > limit:
            raise error(
                f"{what} file {shown} is {_size(st.st_size)}, above the {_size(limit)} limit "
                f"for a {what} file"
            )
        os.set_blocking(fd, True)
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def _why(path: str | os.PathLike[str], e: Exception) -> str:
    if isinstance(e, ValueError):  # a NUL byte in the name
        return "the name is not a valid file name"
    if isinstance(e, OSError) and e.errno == errno.ENAMETOOLONG:
        return "the file name is too long for this system"
    try:
        st = os.stat(path)
    except (OSError, ValueError):
        return (e.strerror if isinstance(e, OSError) else None) or str(e)
    if not stat.S_ISREG(st.st_mode):  # a socket cannot be opened at all
        return f"it is {file_kind(st.st_mode)}, not a regular file"
    return (e.strerror if isinstance(e, OSError) else None) or str(e)


def read_input_bytes(
    path: str | os.PathLike[str],
    *,
    error: type[IlluknitError],
    what: str,
    limit: int | None = None,
) -> bytes:
    """The bytes of the input file ``path``, read within the checks of :func:`open_input_file`
    (and never more than its limit, should the file grow while it is read)."""
    limit = INPUT_LIMITS.get(what, MAX_DOCUMENT_BYTES) if limit is None else limit
    with open_input_file(path, error=error, what=what, limit=limit) as f:
        try:
            data = f.read(limit + 1)
        except OSError as e:
            raise error(f"cannot read {what} file {shown_path(path)}: {e.strerror or e}") from None
    if len(data) > limit:
        raise error(
            f"{what} file {shown_path(path)} grew above the {_size(limit)} limit for a {what} "
            "file while it was read"
        )
    return data


def read_text_file(path: str | os.PathLike[str], *, error: type[IlluknitError], what: str) -> str:
    """The UTF-8 text of ``path``; ``error("<what> file not found: ...")`` and the like on failure
    (read within the limits of :func:`open_input_file`)."""
    data = read_input_bytes(path, error=error, what=what)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        raise error(
            f"cannot read {what} file {shown_path(path)}: not UTF-8 text (byte {e.start})"
        ) from None


def read_json_file(path: str | os.PathLike[str], *, error: type[IlluknitError], what: str) -> Any:
    """The parsed JSON of ``path``, raising ``error`` for a missing, unreadable or invalid file."""
    text = read_text_file(path, error=error, what=what)
    try:
        return json.loads(text)
    except json.JSONDecodeError as e:
        raise error(f"{shown_path(path)} is not valid JSON: {e}") from None
    except RecursionError:  # the decoder recurses once per level of nesting
        raise error(f"{shown_path(path)} is nested too deeply to be a {what} file") from None
