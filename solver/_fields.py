"""Reading one entry of a scene file with messages that name the file, the entry and the fault."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from .errors import SceneError

__all__ = ["Units", "Entry", "MISSING"]

MISSING: Any = object()

LENGTH_UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001}
ANGLE_UNITS = {"rad": 1.0, "deg": math.pi / 180.0}


@dataclass(frozen=True)
class Units:
    """Scale factors from the scene's declared units to m and rad."""

    length: float
    angle: float


class Entry:
    """A mapping read from YAML; every getter checks a type and records the key as used."""

    def __init__(self, data: Any, *, file: str | None, where: str) -> None:
        self.file = file
        self.where = where
        if not isinstance(data, Mapping):
            raise self.error(f"must be a mapping, got {_show(data)}")
        self.data = dict(data)
        self.used: set[str] = set()

    def error(self, message: str, key: str | None = None) -> SceneError:
        entry = f"{self.where}.{key}" if key and self.where else (key or self.where)
        return SceneError(message, file=self.file, entry=entry or None)

    def child(self, key: str, data: Any) -> Entry:
        return Entry(data, file=self.file, where=f"{self.where}.{key}" if self.where else key)

    def raw(self, key: str, default: Any = MISSING) -> Any:
        self.used.add(key)
        if key not in self.data:
            if default is MISSING:
                raise self.error("missing required field", key)
            return default
        return self.data[key]

    def number(self, key: str, default: Any = MISSING) -> float:
        value = self.raw(key, default)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.error(f"must be a number, got {_show(value)}", key)
        if not math.isfinite(value):
            raise self.error(f"must be finite, got {value}", key)
        return float(value)

    def length(self, key: str, units: Units, *, positive: bool = True, default: Any = MISSING) -> float:
        value = self.number(key, default)
        if positive and value <= 0.0:
            raise self.error(f"length must be positive, got {value}", key)
        return value * units.length

    def angle(self, key: str, units: Units, default: Any = MISSING) -> float:
        return self.number(key, default) * units.angle

    def name(self, key: str, default: Any = MISSING) -> str:
        value = self.raw(key, default)
        if not isinstance(value, str) or not value.strip():
            raise self.error(f"must be a name, got {_show(value)}", key)
        return value

    def names(self, key: str, count: int | None = None, default: Any = MISSING) -> tuple[str, ...]:
        value = self.raw(key, default)
        if not isinstance(value, (list, tuple)) or not all(isinstance(v, str) for v in value):
            raise self.error(f"must be a list of names, got {_show(value)}", key)
        if count is not None and len(value) != count:
            raise self.error(f"must name exactly {count} points, got {len(value)}", key)
        return tuple(value)

    def mode(self, key: str = "M") -> int:
        value = self.raw(key)
        if isinstance(value, bool) or value not in (1, -1):
            raise self.error(f"assembly mode must be +1 or -1, got {_show(value)}", key)
        return int(value)

    def done(self) -> None:
        unknown = sorted(set(self.data) - self.used)
        if unknown:
            raise self.error(f"unknown field(s): {', '.join(unknown)}")


def _show(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."
