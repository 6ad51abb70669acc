import inspect

import pytest

from illuknit.core import errors
from illuknit.core.errors import IlluknitError, OptionError, UnknownNameError


def test_every_error_is_an_illuknit_error_and_exported():
    classes = {
        n: c
        for n, c in vars(errors).items()
        if inspect.isclass(c) and issubclass(c, BaseException) and c.__module__ == errors.__name__
    }
    assert set(classes) == set(errors.__all__)
    for name, cls in classes.items():
        assert issubclass(cls, IlluknitError), name


def test_unknown_name_is_an_option_error_and_a_key_error():
    e = UnknownNameError("solver", "nope", ["a", "b"])
    assert isinstance(e, OptionError) and isinstance(e, KeyError) and isinstance(e, ValueError)
    assert str(e) == "unknown solver 'nope'; valid: a, b"
    with pytest.raises(OptionError):
        raise e
