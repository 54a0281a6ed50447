"""Input validation helpers (basis.validation): messages, interval notation, rejected types."""

import re

import numpy as np
import pytest

from basis.validation import ParameterError, as_float_array, check_positive_int, check_range, check_shape_last


def test_parameter_error_is_a_value_error():
    """ParameterError subclasses ValueError (callers may catch either)."""
    assert issubclass(ParameterError, ValueError)


@pytest.mark.parametrize(
    "kwargs, value, interval, shown",
    [
        (dict(low=0.0, high=1.0), 1.5, "[0, 1]", "1.5"),
        (dict(low=0.0, high=1.0), -0.25, "[0, 1]", "-0.25"),
        (dict(low=0.0, high=1.0, low_open=True), 0.0, "(0, 1]", "0.0"),
        (dict(low=0.0, high=1.0, high_open=True), 1.0, "[0, 1)", "1.0"),
        (dict(low=0.0, high=1.0, low_open=True, high_open=True), 1.0, "(0, 1)", "1.0"),
        (dict(low=0.0), -3.0, "[0, inf)", "-3.0"),
        (dict(high=2.5), 7.0, "(-inf, 2.5]", "7.0"),
        (dict(low=0.0, high=1e6, low_open=True), 2e6, "(0, 1e+06]", "2000000.0"),
    ],
)
def test_check_range_message_names_value_and_interval(kwargs, value, interval, shown):
    """Message is '<name> must be in <interval>, got <value>' with [ ] closed and ( ) open ends."""
    expected = f"roughness must be in {interval}, got {shown}"
    with pytest.raises(ParameterError, match=re.escape(expected)):
        check_range("roughness", value, **kwargs)


def test_check_range_reports_first_offending_element_of_an_array():
    """For an array the message shows the first bad element (here 2.0), not the whole array."""
    with pytest.raises(ParameterError, match=re.escape("mu must be in [0, 1], got 2.0")):
        check_range("mu", [0.5, 2.0, 3.0], 0.0, 1.0)


@pytest.mark.parametrize(
    "kwargs, value",
    [
        (dict(low=0.0, high=1.0), 0.0),
        (dict(low=0.0, high=1.0), 1.0),
        (dict(low=0.0, high=1.0, low_open=True), 1e-300),
        (dict(low=0.0, high=1.0, high_open=True), np.nextafter(1.0, 0.0)),
        (dict(), -1e300),
        (dict(low=-1.0), 1e300),
    ],
)
def test_check_range_accepts_values_inside(kwargs, value):
    """Closed ends include the end point, open ends only what is strictly inside; value returned as float64 unchanged."""
    result = check_range("x", value, **kwargs)
    assert result.dtype == np.float64
    np.testing.assert_allclose(result, value, rtol=0, atol=0)


def test_check_range_keeps_shape_and_converts_ints():
    """Integer arrays become float64 of the same shape and values (atol 0)."""
    result = check_range("x", np.arange(6).reshape(2, 3), 0, 10)
    assert result.shape == (2, 3) and result.dtype == np.float64
    np.testing.assert_allclose(result, np.arange(6).reshape(2, 3), rtol=0, atol=0)


def test_check_range_empty_array_is_accepted():
    """An empty array has nothing out of range and is returned empty."""
    assert check_range("x", np.array([]), 0.0, 1.0).size == 0


@pytest.mark.parametrize(
    "value, fragment",
    [
        ("1.0", "real number"),
        (b"1.0", "real number"),
        (None, "real number"),
        (True, "boolean"),
        (np.bool_(False), "boolean"),
        (np.array([True, False]), "boolean"),
        (1 + 2j, "real"),
        (np.array([1.0 + 0j]), "real"),
        (np.nan, "finite"),
        (np.inf, "finite"),
        (-np.inf, "finite"),
        ([1.0, np.nan], "finite"),
        (np.array([1.0, object()], dtype=object), "dtype"),
        (np.array(["a", "b"]), "dtype"),
        ([[1.0, 2.0], [3.0]], "real number"),
    ],
)
def test_as_float_array_rejects(value, fragment):
    """str, bytes, None, bool, complex, NaN, inf, object/str arrays, ragged lists -> ParameterError naming 'eta'."""
    with pytest.raises(ParameterError, match=rf"^eta\b.*{fragment}"):
        as_float_array("eta", value)


@pytest.mark.parametrize("value", [0, 1.5, -2, [1, 2, 3], np.float32(0.5), np.arange(4, dtype=np.uint8)])
def test_as_float_array_accepts_real_numbers(value):
    """int, float, lists, float32 and unsigned ints become float64 with equal values (atol 0)."""
    result = as_float_array("x", value)
    assert result.dtype == np.float64
    np.testing.assert_allclose(result, np.asarray(value, dtype=np.float64), rtol=0, atol=0)


@pytest.mark.parametrize("value", [1.0, 2.5, True, False, "3", None, np.float64(4.0)])
def test_check_positive_int_rejects_non_integers(value):
    """Floats (even integral ones), bools, str and None -> ParameterError 'count must be an integer'."""
    with pytest.raises(ParameterError, match=r"^count must be an integer"):
        check_positive_int("count", value)


@pytest.mark.parametrize("value, low, high", [(0, 1, None), (-5, 1, None), (15, 16, None), (17, 2, 16)])
def test_check_positive_int_rejects_out_of_range(value, low, high):
    """Integers outside [low, high] -> message with the interval and the value."""
    upper = "inf" if high is None else str(high)
    with pytest.raises(ParameterError, match=re.escape(f"n_terms must be an integer in [{low}, {upper}], got {value}")):
        check_positive_int("n_terms", value, low=low, high=high)


@pytest.mark.parametrize("value, low, high", [(1, 1, None), (16, 16, 16), (np.int64(7), 2, 16), (10**12, 1, None)])
def test_check_positive_int_accepts(value, low, high):
    """Integers (including numpy ints) inside [low, high] are returned as the same Python int."""
    result = check_positive_int("n", value, low=low, high=high)
    assert type(result) is int and result == value


def test_check_shape_last():
    """Trailing axis of the stated length passes; wrong length or 0-d -> ParameterError with the shape."""
    array = np.zeros((5, 3))
    assert check_shape_last("rgb", array, 3) is array
    with pytest.raises(ParameterError, match=re.escape("rgb must have a trailing axis of length 3, got shape (5, 4)")):
        check_shape_last("rgb", np.zeros((5, 4)), 3)
    with pytest.raises(ParameterError, match=r"^rgb .*shape \(\)"):
        check_shape_last("rgb", np.zeros(()), 3)


def test_check_choice_returns_a_valid_name_and_lists_every_choice_otherwise():
    from basis.validation import check_choice, choose

    assert check_choice("visibility", "separable", ("height-correlated", "separable")) == "separable"
    assert choose("fit", "b", {"a": 1, "b": 2}) == 2
    for bad in ("Separable", "", None, 1, True, ["separable"], np.array(["separable"]), {"separable": 1}, b"separable"):
        with pytest.raises(
            ParameterError, match=r"^visibility must be one of \['height-correlated', 'separable'\], got "
        ):
            check_choice("visibility", bad, ("height-correlated", "separable"))
    with pytest.raises(ParameterError, match="got 'x{59}…$"):  # a long value is cut, on one line
        check_choice("name", "x" * 200, ("a",))


def test_masked_entries_are_refused_not_computed():
    """A masked array's hidden values were computed as if unmasked (issue 26 item 15); a mask with nothing masked
    is a plain array."""
    import numpy as np

    from basis import coefficients_from_nk

    with pytest.raises(ParameterError, match="masked entries"):
        as_float_array("eta", np.ma.array([1.5, 0.2], mask=[False, True]))
    with pytest.raises(ParameterError, match="eta has masked entries"):
        coefficients_from_nk(np.ma.array([1.5, 0.2], mask=[False, True]), 0.0)
    np.testing.assert_array_equal(as_float_array("eta", np.ma.array([1.5, 0.2])), [1.5, 0.2])
