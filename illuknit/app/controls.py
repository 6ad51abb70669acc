"""Errors aimed at the page control that caused them.

The page shows a message next to the control named by the error's ``field``; :func:`blame` turns
the library's errors raised inside a block into such an :class:`~illuknit.core.errors.AppRequestError`.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

from illuknit.core.errors import AppRequestError, IlluknitError

__all__ = ["blame"]


@contextmanager
def blame(field_name: str | None) -> Iterator[None]:
    """Re-raise library errors inside the block as AppRequestError naming the page control."""
    try:
        yield
    except AppRequestError:
        raise
    except IlluknitError as e:
        raise AppRequestError(str(e), field=field_name, code=type(e).__name__) from None
