"""Input validation at the public boundary.

Every public function converts its array arguments with :func:`as_float_array`
and checks their domain with :func:`check_range`; inside the library the values
are then trusted. Errors are :class:`ParameterError` (a ``ValueError``) whose
message names the parameter, the offending value and the accepted range.

Public objects: ``ParameterError``, ``as_float_array``, ``check_range``,
``check_shape_last``, ``check_positive_int``, ``check_broadcast``, ``check_choice``, ``choose``, ``safe_line``.

Texts that reach a generated file (a file name in a shader include's comment, a command in a table's header, a scene's
name in its report's title) pass through :func:`safe_line`, the one function that makes any text one inert line.
"""

from __future__ import annotations

import json
import numbers
import re

import numpy as np

__all__ = [
    "ParameterError",
    "as_float_array",
    "check_broadcast",
    "check_choice",
    "check_positive_int",
    "check_range",
    "check_shape_last",
    "choose",
    "safe_line",
]


class ParameterError(ValueError):
    """A public input is out of its documented domain, malformed or not finite."""


def _describe(value: np.ndarray) -> str:
    """Short text for the first offending element (the whole array would be unreadable)."""
    return repr(float(value)) if np.ndim(value) == 0 else repr(value.tolist())[:60]


def as_float_array(name: str, value, finite: bool = True) -> np.ndarray:
    """Convert ``value`` to a float64 array, rejecting non-numeric input and (if ``finite``) NaN/inf.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : array_like
        Scalar or array of real numbers (bool is refused: it is never a physical quantity; so is a masked array
        with masked entries).
    """
    if isinstance(value, (str, bytes)) or value is None:
        raise ParameterError(f"{name} must be a real number or array of them, got {value!r}")
    if isinstance(value, np.ma.MaskedArray):  # np.asarray would drop the mask and use the hidden values
        if np.any(np.ma.getmaskarray(value)):
            raise ParameterError(
                f"{name} has masked entries, which would be computed with the values under the mask: fill them "
                "(numpy.ma.filled) or leave them out"
            )
        value = np.ma.getdata(value)
    try:
        array = np.asarray(value)
    except (TypeError, ValueError) as error:
        raise ParameterError(f"{name} must be a real number or array of them: {error}") from None
    if array.dtype == bool or isinstance(value, bool):
        raise ParameterError(f"{name} must be a real number, got a boolean")
    if array.dtype.kind not in "iuf":
        if array.dtype.kind == "c":
            raise ParameterError(f"{name} must be real; pass eta and kappa separately")
        raise ParameterError(f"{name} must be a real number or array of them, got dtype {array.dtype}")
    array = array.astype(np.float64, copy=False)
    if finite and array.size and not np.all(np.isfinite(array)):
        bad = array[~np.isfinite(array)].flat[0]
        raise ParameterError(f"{name} must be finite, got {float(bad)}")
    return array


def check_range(
    name: str,
    value,
    low: float | None = None,
    high: float | None = None,
    *,
    low_open: bool = False,
    high_open: bool = False,
) -> np.ndarray:
    """Return ``value`` as a finite float64 array lying in the stated interval.

    ``low``/``high`` of ``None`` mean unbounded; ``low_open``/``high_open`` exclude
    the end point. The error message spells the interval in standard notation,
    e.g. ``roughness must be in [0, 1], got 1.5``.
    """
    array = as_float_array(name, value, finite=False)
    bad = ~np.isfinite(array)  # NaN and inf get the same message: the accepted interval
    if low is not None:
        bad |= (array <= low) if low_open else (array < low)
    if high is not None:
        bad |= (array >= high) if high_open else (array > high)
    if np.any(bad):
        left = "(" if low_open or low is None else "["
        right = ")" if high_open or high is None else "]"
        low_text = "-inf" if low is None else f"{low:g}"
        high_text = "inf" if high is None else f"{high:g}"
        raise ParameterError(
            f"{name} must be in {left}{low_text}, {high_text}{right}, got {_describe(array[bad].flat[0])}"
        )
    return array


def check_shape_last(name: str, array: np.ndarray, size: int) -> np.ndarray:
    """Require a trailing axis of length ``size`` (e.g. 3 for an RGB triple)."""
    if array.ndim == 0 or array.shape[-1] != size:
        raise ParameterError(f"{name} must have a trailing axis of length {size}, got shape {array.shape}")
    return array


def check_positive_int(name: str, value, low: int = 1, high: int | None = None) -> int:
    """Return ``value`` as an int in ``[low, high]``; floats with a fraction and bools are refused."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ParameterError(f"{name} must be an integer, got {value!r}")
    if value < low or (high is not None and value > high):
        upper = "inf" if high is None else str(high)
        raise ParameterError(f"{name} must be an integer in [{low}, {upper}], got {value}")
    return int(value)


def check_broadcast(**arrays) -> tuple[int, ...]:
    """The broadcast shape of named arrays, or an error naming them and their shapes."""
    try:
        return np.broadcast_shapes(*(np.shape(array) for array in arrays.values()))
    except ValueError:
        shapes = ", ".join(f"{name} {np.shape(array)}" for name, array in arrays.items())
        raise ParameterError(f"{' and '.join(arrays)} must broadcast against each other, got shapes {shapes}") from None


def check_choice(name: str, value, choices, error=ParameterError):
    """``value`` if it is one of ``choices`` (a registry's names, in the order to show them), else ``error``
    with one line naming the parameter, the value and every valid choice (as colour's ``validate_method``).

    Examples
    --------
    >>> check_choice("visibility", "separable", ["height-correlated", "separable"])
    'separable'
    """
    options = list(choices)
    try:
        valid = any(type(value) is type(option) and value == option for option in options)
    except (TypeError, ValueError):  # an array compared with a name
        valid = False
    if not valid:
        shown = " ".join(repr(value).split())
        raise error(f"{name} must be one of {options}, got {shown[:60] + ('…' if len(shown) > 60 else '')}")
    return value


def choose(name: str, value, registry, error=ParameterError):
    """``registry[value]`` for a name of the registry (a mapping), refused as :func:`check_choice` refuses."""
    return registry[check_choice(name, value, registry, error)]


#: A line that needs no quoting: printable ASCII, no comment delimiter, not ending in a backslash.
_INERT_LINE = re.compile(r"(?!.*(?:/\*|\*/))[ -~]*(?<!\\)")


def safe_line(text) -> str:
    """``text`` as one line that is inert wherever the project writes it: in a ``//`` or ``/* */`` comment of a
    GLSL, HLSL, WGSL or C include, an EXR, KTX2 or PNG attribute, a Markdown title.

    Text of printable ASCII with no comment delimiter (``/*``, ``*/``) that does not end in a backslash (which would
    continue a GLSL comment onto the next line) is returned as it is; any other text is quoted with JSON's escapes
    (``\\n``, ``\\u00e9``, ``\\u0000``, and ``\\u002a`` for a ``*`` beside a ``/``), so that it reads back with ``json.loads``.
    The result is never two lines, holds no control or non-ASCII character and is its own safe line (quoting
    twice changes nothing).

    Examples
    --------
    >>> safe_line("scene.toml")
    'scene.toml'
    >>> print(safe_line("x\\nfloat injected() { return 42.0; } */ é"))
    "x\\nfloat injected() { return 42.0; } \\u002a/ \\u00e9"
    >>> safe_line(safe_line("a\\tb")) == safe_line("a\\tb")
    True
    """
    text = str(text)
    if _INERT_LINE.fullmatch(text):
        return text
    quoted = json.dumps(text, ensure_ascii=True)
    return re.sub(r"\*(?=/)|(?<=/)\*", r"\\u002a", quoted)
