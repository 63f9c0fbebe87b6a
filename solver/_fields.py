"""Reading one entry of a scene file with messages that name the file, the entry and the fault.

Number ranges (docs/scenes.md, "Number ranges")
    Every number must be finite, and after conversion to SI:

    * a length that must be positive (a link, a crank, a radius, a vector's r):
      ``LENGTH_MIN ≤ L ≤ LENGTH_MAX``, i.e. 1e-9 m … 1e9 m;
    * a signed length (a fixed point's coordinate, an offset, a point's distance along a link,
      a ``plus`` of a linked length): ``|x| ≤ LENGTH_MAX``;
    * an angle: ``|α| ≤ ANGLE_MAX`` = 1e4 rad (about 1,600 turns).

    Why these: the closed forms raise lengths to the fourth power at most — the RRR dyad's
    4D⁴h² = ((l₁+l₂)² − D²)(D² − (l₁−l₂)²) and its rounding slack (l₁²+l₂²)(l₁+l₂)², the
    spherical and vector modules' squared sums — and divide by squares (D², the 2×2 systems'
    determinants ~ L²). With every length and coordinate within 1e-9 … 1e9 m, any sum of a
    scene's lengths stays below ~1e12 m (even with a thousand of them), so a fourth power stays
    below ~1e48 and a squared ratio of the largest to the smallest length below 1e36, all far
    inside float64's 2.2e-308 … 1.8e308; ``lengths: [1.0e+154, 0.3]`` (whose square is already
    inf) is refused on load instead of giving B = (inf, nan) at "valid" samples. Below 1e-9 m
    (a nanometre) a mechanism is no longer a linkage of rigid bodies, above 1e9 m (a million
    km) not a machine. An angle beyond 1e4 rad still names its direction to ~2e-12 rad (its
    ulp), which is why angles are bounded at all: at 1e16 rad the ulp exceeds a turn.
"""

from __future__ import annotations

import difflib
import math
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

from ._yaml import line_of
from .errors import SceneError

__all__ = ["Units", "Entry", "MISSING", "LENGTH_MIN", "LENGTH_MAX", "ANGLE_MAX", "NAME_MAX", "show", "suggest",
           "read_units"]

MISSING: Any = object()

LENGTH_UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001}
ANGLE_UNITS = {"rad": 1.0, "deg": math.pi / 180.0}

#: Smallest positive length, m (after unit conversion).
LENGTH_MIN = 1e-9
#: Largest length or |coordinate|, m (after unit conversion).
LENGTH_MAX = 1e9
#: Largest |angle|, rad (after unit conversion).
ANGLE_MAX = 1e4
#: Longest name (a point, joint, group, vector or contour).
NAME_MAX = 100

#: What YAML 1.1 (PyYAML) leaves as text although it reads like a number: ``1e-3``, ``2E5``,
#: ``1.5e3`` (YAML 1.1 wants a dot in the mantissa and a sign in the exponent: ``1.0e-3``).
_FLOATISH = re.compile(r"^\s*[-+]?(\d+\.?\d*|\.\d+)[eE][-+]?\d+\s*$")


@dataclass(frozen=True)
class Units:
    """Scale factors from the scene's declared units to m and rad."""

    length: float
    angle: float


class Entry:
    """A mapping read from YAML; every getter checks a type and records the key as used.

    Errors carry the YAML line of the key (or of the mapping) when the data came from
    :func:`solver._yaml.load_yaml`.
    """

    def __init__(self, data: Any, *, file: str | None, where: str, line: int | None = None) -> None:
        self.file = file
        self.where = where
        self.line = line_of(data) or line
        if not isinstance(data, Mapping):
            raise self.error(f"must be a mapping, got {show(data)}")
        self.source = data
        self.data = dict(data)
        self.used: set[str] = set()

    def line_of(self, key: Any = None) -> int | None:
        return (line_of(self.source, key) if key is not None else None) or self.line

    def error(self, message: str, key: str | None = None) -> SceneError:
        entry = f"{self.where}.{key}" if key and self.where else (key or self.where)
        line = self.line_of(key) if hasattr(self, "source") else self.line
        if not self.where and (key is None or key not in getattr(self, "data", {})):
            line = None  # the whole file: no line to point at
        return SceneError(message, file=self.file, entry=entry or None, line=line)

    def child(self, key: str, data: Any) -> Entry:
        return type(self)(  # (a subclass's children are of its kind: solver.synthesis reads arrays)
            data,
            file=self.file,
            where=f"{self.where}.{key}" if self.where else key,
            line=self.line_of(key) if hasattr(self, "source") else self.line,
        )

    def expect(self, known: Iterable[str]) -> None:
        """Refuse fields not in ``known``, before anything else is checked (a misspelt key is
        reported as the unknown key it is, with the closest known one)."""
        allowed = list(known)
        unknown = [k for k in self.data if k not in allowed]
        if unknown:
            raise self.unknown(unknown, allowed)

    def unknown(self, keys: list[Any], allowed: Iterable[str]) -> SceneError:
        allowed = list(dict.fromkeys(allowed))
        names = [k[:30] if isinstance(k, str) else show(k, 30) for k in keys]
        near = [suggest(k, allowed)[:1] if isinstance(k, str) else [] for k in keys]
        if len(keys) == 1 and near[0]:
            text = f"unknown field '{names[0]}' (did you mean '{near[0][0]}'?)"
        else:
            hints = [f"'{m[0]}' for '{n}'" for n, m in zip(names, near) if m]
            text = f"unknown field(s): {', '.join(names)}"
            if hints:
                text += f" (did you mean {', '.join(hints)}?)"
        if allowed:
            text += f"; known: {', '.join(allowed)}"
        entry = self.where or None
        return SceneError(text, file=self.file, entry=entry, line=self.line_of(keys[0]))

    def raw(self, key: str, default: Any = MISSING) -> Any:
        self.used.add(key)
        if key not in self.data:
            if default is MISSING:
                near = [k for k in self.data if isinstance(k, str) and k not in self.used and suggest(k, [key])]
                if near:  # a misspelt key: name it, not the field its absence leaves missing
                    text = f"unknown field '{near[0][:30]}' (did you mean '{key}'?)"
                    line = self.line_of(near[0])
                    raise SceneError(text, file=self.file, entry=self.where or None, line=line)
                raise self.error("missing required field", key)
            return default
        return self.data[key]

    def number(self, key: str, default: Any = MISSING) -> float:
        return self.as_number(self.raw(key, default), key)

    def as_number(self, value: Any, key: str) -> float:
        """``value`` as a finite float, or the SceneError that says why not."""
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            if isinstance(value, str) and _FLOATISH.match(value):
                raise self.error(
                    f"must be a number, got the text {show(value)}: YAML 1.1 reads a number in exponent "
                    f"form only with a dot in the mantissa and a sign in the exponent, write {_yaml11(value)}",
                    key,
                )
            raise self.error(f"must be a number, got {show(value)}", key)
        try:
            number = float(value)
        except OverflowError:
            raise self.error(f"must be finite, got an integer of {digits(int(value))} digits", key) from None
        if not math.isfinite(number):
            raise self.error(f"must be finite, got {value}", key)
        return number

    def length(self, key: str, units: Units, *, positive: bool = True, default: Any = MISSING) -> float:
        return self.length_value(self.number(key, default), key, units, positive=positive)

    def length_value(self, value: float, key: str, units: Units, *, positive: bool = True) -> float:
        """``value`` (scene units) in m, within the ranges of the module docstring."""
        if positive and value <= 0.0:
            raise self.error(f"length must be positive, got {value}", key)
        si = value * units.length
        if positive and not (LENGTH_MIN <= si <= LENGTH_MAX):
            raise self.error(
                f"length {value:g} is {si:g} m, outside {LENGTH_MIN:g} … {LENGTH_MAX:g} m, where the closed "
                "forms stay finite in float64 (docs/scenes.md#number-ranges)",
                key,
            )
        if not positive and abs(si) > LENGTH_MAX:
            raise self.error(
                f"{value:g} is {si:g} m, beyond ±{LENGTH_MAX:g} m, where the closed forms stay finite in "
                "float64 (docs/scenes.md#number-ranges)",
                key,
            )
        return si

    def angle(self, key: str, units: Units, default: Any = MISSING) -> float:
        value = self.number(key, default)
        si = value * units.angle
        if abs(si) > ANGLE_MAX:
            raise self.error(
                f"angle {value:g} is {si:g} rad, beyond ±{ANGLE_MAX:g} rad (docs/scenes.md#number-ranges)", key
            )
        return si

    def name(self, key: str, default: Any = MISSING) -> str:
        value = self.raw(key, default)
        if not isinstance(value, str) or not value.strip():
            raise self.error(f"must be a name, got {show(value)}", key)
        self.check_name(value, key)
        return value

    def check_name(self, value: str, key: str | None = None) -> None:
        if len(value) > NAME_MAX:
            raise self.error(f"a name of {len(value)} characters: at most {NAME_MAX}, got {show(value)}", key)
        if any(c in value for c in "\n\r\t\0"):
            raise self.error(f"a name on one line without tabs, got {show(value)}", key)

    def names(self, key: str, count: int | None = None, default: Any = MISSING) -> tuple[str, ...]:
        value = self.raw(key, default)
        if not isinstance(value, (list, tuple)) or not all(isinstance(v, str) for v in value):
            raise self.error(f"must be a list of names, got {show(value)}", key)
        if count is not None and len(value) != count:
            raise self.error(f"must name exactly {count} points, got {len(value)}", key)
        for v in value:
            self.check_name(v, key)
        return tuple(value)

    def mode(self, key: str = "M") -> int:
        value = self.raw(key)
        if isinstance(value, bool) or not isinstance(value, (int, float)) or value not in (1, -1):
            raise self.error(f"assembly mode must be +1 or -1, got {show(value)}", key)
        return int(value)

    def done(self) -> None:
        unknown = [k for k in self.data if k not in self.used]
        if unknown:
            raise self.unknown(unknown, sorted(self.used))


def suggest(word: str, known: Iterable[str]) -> list[str]:
    """The known names closest to a misspelt ``word`` (``lenghts`` → ``lengths``)."""
    return difflib.get_close_matches(word, list(known), n=1, cutoff=0.75)


def digits(n: int) -> int:
    """About how many decimal digits ``n`` has (without converting it to text: Python refuses
    str() of an integer beyond 4,300 digits)."""
    return int(abs(n).bit_length() * math.log10(2)) + 1


def _yaml11(text: str) -> str:
    mantissa, _, exponent = text.strip().lower().partition("e")
    if "." not in mantissa:
        mantissa += ".0"
    if exponent[:1] not in "+-":
        exponent = "+" + exponent
    return f"{mantissa}e{exponent}"


def show(value: Any, limit: int = 60) -> str:
    """A short text for ``value`` in a message, built within ``limit`` characters: never the
    repr of a whole (possibly huge or alias-expanded) structure."""
    out: list[str] = []
    budget = [limit + 1]

    def put(text: str) -> bool:
        out.append(text[: max(budget[0], 0)])
        budget[0] -= len(text)
        return budget[0] > 0

    def walk(v: Any, depth: int) -> bool:
        if isinstance(v, Mapping):
            if not put("{") or depth > 4:
                return False
            for i, (k, x) in enumerate(v.items()):
                if (i and not put(", ")) or not walk(k, depth + 1) or not put(": ") or not walk(x, depth + 1):
                    return False
            return put("}")
        if isinstance(v, (list, tuple)):
            if not put("[") or depth > 4:
                return False
            for i, x in enumerate(v):
                if (i and not put(", ")) or not walk(x, depth + 1):
                    return False
            return put("]")
        if isinstance(v, int) and not isinstance(v, bool) and abs(v) > 10**30:
            return put(f"<an integer of {digits(v)} digits>")
        if isinstance(v, str) and len(v) > limit:
            return put(repr(v[: limit + 1]))
        return put(repr(v))

    complete = walk(value, 0)
    text = "".join(out)
    return text if complete and len(text) <= limit else text[: limit - 3] + "..."


def read_units(top: Entry, *, done: bool = True) -> Units:
    """The scene's ``units:`` (SI where absent); one line for an unknown unit. ``done``: also
    refuse unknown keys there (the drawing's reader leaves that to the loader)."""
    u = top.child("units", top.raw("units"))
    length, angle = u.name("length"), u.name("angle")
    if length not in LENGTH_UNITS:
        raise u.error(f"unknown length unit '{length}'; use one of {sorted(LENGTH_UNITS)}", "length")
    if angle not in ANGLE_UNITS:
        raise u.error(f"unknown angle unit '{angle}'; use one of {sorted(ANGLE_UNITS)}", "angle")
    if done:
        u.done()
    return Units(LENGTH_UNITS[length], ANGLE_UNITS[angle])
