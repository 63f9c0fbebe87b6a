"""What the structure finder's steps share (solver.structure.decompose, and the triad's step
beside it): a :class:`Step` of the decomposition, the plane's products of complex numbers, and
the refusal of a group drawn at its toggle."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..tolerances import SINGULAR

#: A slide's point farther than this from its line, relative to the drawing's size, is off it
#: (the drawn form's slides and the slider triad's guide).
ON_LINE = 1e-9

__all__ = ["ON_LINE", "Step", "cross", "dot", "refuse_toggle"]


def cross(a: complex, b: complex) -> float:
    return a.real * b.imag - a.imag * b.real


def dot(a: complex, b: complex) -> float:
    return a.real * b.real + a.imag * b.imag


@dataclass(frozen=True)
class Step:
    """One group of the decomposition: ``kind`` (a group type of the scene files), its ``name``,
    the drawn bodies it places (``links``), the points it provides, its ``fields`` as a group
    entry in the file's units (without ``type`` and ``name``), its assembly mode and its
    conditioning at the drawn pose (1 well conditioned, 0 a toggle), where it has them."""

    kind: str
    name: str
    links: tuple[str, ...]
    provides: tuple[str, ...]
    fields: dict[str, Any]
    mode: int | None = None
    conditioning: float | None = None
    #: the input's value at the drawn pose (rad for a crank, file length unit for an actuator)
    drawn: float | None = None

    def entry(self) -> dict[str, Any]:
        """The group entry of a scene file: ``{type, name, **fields}``."""
        return {"type": self.kind, "name": self.name, **self.fields}


def refuse_toggle(st: Any, cond: float, entry: str, what: str) -> None:
    """A group drawn within ``tolerances.SINGULAR`` of its toggle has no mode: one line."""
    if not cond >= SINGULAR:
        raise st.d.error(f"{what}: its assembly mode is undefined there (conditioning {cond:.2g}); draw it in the "
                         "assembly it is meant to run in", entry)
