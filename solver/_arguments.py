"""The checks of the public functions' arguments, in one place (issue 30).

Each public function checks each of its arguments in one line, as the scene loader checks a
file's entries: ``args = Arguments("steady_state", scene=scene.name, error=DynamicsArgumentError)``,
then ``flywheel = args.number("flywheel", flywheel, low=0.0, unit="kg·m²")``. A wrong type, a
non-finite number or a value out of range raises the function's :class:`~solver.errors.ArgumentError`
(one line naming the scene, the function, the argument and the value); a good value is returned
as the function uses it (a float, an int, a bool, a tuple of names).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Callable, Sequence
from typing import Any, NoReturn

import numpy as np

from .errors import ArgumentError

__all__ = ["Arguments", "is_number"]

_FLOAT = np.dtype(float)


def is_number(value: Any) -> bool:
    """A real number (Python's or numpy's, or a 0-d array of one), not a bool."""
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iuf":
        return True
    return isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))


def _span(low: float | None, high: float | None, low_open: bool, high_open: bool) -> str:
    if low is not None and high is not None:
        return f"in {'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}"
    if low is not None:
        return f"{'>' if low_open else '≥'} {low:g}"
    if high is not None:
        return f"{'<' if high_open else '≤'} {high:g}"
    return ""


class Arguments:
    """The argument checks of one public function (``function``) on one scene (``scene``, or
    None), raising ``error`` (an :class:`ArgumentError` class)."""

    __slots__ = ("function", "scene", "error")

    def __init__(self, function: str, *, scene: str | None = None, error: type[ArgumentError] = ArgumentError) -> None:
        self.function, self.scene, self.error = function, scene, error

    def fail(self, argument: str, value: Any, reason: str) -> NoReturn:
        """Raise the one-line error: ``argument`` ``reason``, got ``value``."""
        raise self.error(reason, function=self.function, argument=argument, value=value, scene=self.scene)

    def number(
        self, argument: str, value: Any, *, low: float | None = None, high: float | None = None,
        low_open: bool = False, high_open: bool = False, unit: str = "", span: str | None = None,
        none: bool = False, infinite: bool = False,
    ) -> Any:
        """A finite real number within [low, high] (``*_open``: the bound excluded), as a float;
        None passes where ``none``, ±inf where ``infinite`` (within the bounds). ``span``: the
        range as the message says it (default from the bounds), ``unit`` after it."""
        if value is None and none:
            return None
        ok = is_number(value) and (math.isfinite(v := float(value)) or (infinite and not math.isnan(v)))
        if not ok and is_number(value):  # a number, but nan or ±inf: said as the compiled instant says it
            self.fail(argument, value, "must not be nan" if infinite else "must be finite")
        if ok:
            ok = (low is None or (v > low if low_open else v >= low)) and \
                 (high is None or (v < high if high_open else v <= high))
        if not ok:
            text = span if span is not None else _span(low, high, low_open, high_open)
            if unit:
                unit = unit if text else f"({unit})"
            what = " ".join(part for part in ("a number" if infinite else "a finite number", text, unit) if part)
            self.fail(argument, value, f"must be {what}" + (" or None" if none else ""))
        return v

    def integer(self, argument: str, value: Any, *, low: int | None = None, high: int | None = None) -> int:
        """A whole number (not a bool, not a float) within [low, high], as an int."""
        whole = isinstance(value, numbers.Integral) and not isinstance(value, (bool, np.bool_))
        if not whole or (low is not None and int(value) < low) or (high is not None and int(value) > high):
            text = _span(low, high, False, False)
            self.fail(argument, value, "must be a whole number" + (f" {text}" if text else ""))
        return int(value)

    def flag(self, argument: str, value: Any) -> bool:
        """True or False (a bool: not 1, "yes" or None)."""
        if not isinstance(value, (bool, np.bool_)):
            self.fail(argument, value, "must be True or False")
        return bool(value)

    def choice(self, argument: str, value: Any, options: Sequence[Any]) -> Any:
        """One of ``options``."""
        if not isinstance(value, str | int) or isinstance(value, bool) or value not in options:
            self.fail(argument, value, "must be one of " + ", ".join(repr(o) for o in options))
        return value

    def name(self, argument: str, value: Any, *, none: bool = False) -> str | None:
        """A name (a str); None passes where ``none``."""
        if value is None and none:
            return None
        if not isinstance(value, str):
            self.fail(argument, value, "must be a name (a str)" + (" or None" if none else ""))
        return value

    def names(self, argument: str, value: Any, *, none: bool = False) -> tuple[str, ...] | None:
        """A list (any iterable but a str) of names; None passes where ``none``."""
        if value is None and none:
            return None
        if isinstance(value, str | bytes):
            self.fail(argument, value, f"must be a list of names (write [{value!r}] for one)")
        try:
            out = tuple(value)
        except TypeError:
            out = None
        if out is None or not all(isinstance(v, str) for v in out):
            self.fail(argument, value, "must be a list of names")
        return out

    def function_(self, argument: str, value: Any, *, none: bool = True) -> Callable[..., Any] | None:
        """A callable; None passes where ``none``."""
        if value is None and none:
            return None
        if not callable(value):
            self.fail(argument, value, "must be a function" + (" or None" if none else ""))
        return value  # type: ignore[no-any-return]

    def functions(self, argument: str, value: Any) -> tuple[Callable[..., Any], ...]:
        """A list of callables."""
        try:
            out = tuple(value)
        except TypeError:
            out = None
        if out is None or not all(callable(f) for f in out):
            self.fail(argument, value, "must be a list of functions")
        return out

    def numbers(self, argument: str, value: Any, *, unit: str = "") -> np.ndarray:
        """A number or an array of numbers, every one finite, as a float array."""
        if value.__class__ is np.ndarray and value.dtype == _FLOAT:  # the usual sweep: no conversion
            arr = value
        else:
            try:
                raw = np.asarray(value)
            except (TypeError, ValueError):  # ragged
                raw = None
            if raw is None or raw.dtype.kind not in "iuf":
                self.fail(argument, value, "must be a number or an array of numbers" + (f" ({unit})" if unit else ""))
            arr = raw.astype(float, copy=False)
        if not np.isfinite(arr).all():
            bad = arr[~np.isfinite(arr)] if arr.ndim else arr
            self.fail(argument, value if arr.ndim == 0 else np.ravel(bad)[:3].tolist(), "must be finite")
        return arr

    def span(self, argument: str, value: Any, *, unit: str = "") -> tuple[float, float]:
        """(lo, hi): two finite numbers with lo < hi."""
        ok = isinstance(value, Sequence | np.ndarray) and not isinstance(value, str | bytes) and len(value) == 2 \
            and all(is_number(v) and math.isfinite(float(v)) for v in value)
        if not ok or not float(value[0]) < float(value[1]):
            self.fail(argument, value, "must be (lo, hi), two finite numbers with lo < hi" + (f" ({unit})" if unit
                                                                                            else ""))
        return float(value[0]), float(value[1])
