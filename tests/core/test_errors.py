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
    assert set(classes) <= set(errors.__all__)
    # besides the errors, the one value type an error carries (LongFloatError.span)
    assert set(errors.__all__) - set(classes) == {"FloatSpan"}
    for name, cls in classes.items():
        assert issubclass(cls, IlluknitError), name


def test_unknown_name_is_an_option_error_and_a_key_error():
    e = UnknownNameError("solver", "nope", ["a", "b"])
    assert isinstance(e, OptionError) and isinstance(e, KeyError) and isinstance(e, ValueError)
    assert str(e) == "unknown solver 'nope'; valid: a, b"
    with pytest.raises(OptionError):
        raise e


def test_a_long_float_error_carries_its_float_as_a_span_or_as_keywords():
    span = errors.FloatSpan(length=30, carrier="2", from_needle=4, to_needle=35, course=7)
    e = errors.LongFloatError("too long", span=span, where="course 7", limit=25, count=3)
    same = errors.LongFloatError(
        "too long", length=30, carrier="2", from_needle=4, to_needle=35, course=7,
        where="course 7", limit=25, count=3,
    )  # fmt: skip
    assert e.span == same.span == span
    assert (same.length, same.carrier, same.from_needle, same.to_needle, same.course) == (
        30, "2", 4, 35, 7,
    )  # fmt: skip
    assert (same.where, same.limit, same.count) == ("course 7", 25, 3)
