"""The error hierarchy of the solver.

Every message carries its inputs: the scene file and entry for a :class:`SceneError`, the group
and the crank angles for an :class:`AssemblyError`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

__all__ = [
    "SolverError", "SceneError", "AssemblyError", "SampleAssemblyError", "DynamicsError", "SynthesisError",
    "ArgumentError", "DynamicsArgumentError", "SynthesisArgumentError", "format_intervals",
]


class SolverError(ValueError):
    """Base of every error the solver raises on purpose."""


class SceneError(SolverError):
    """A scene file (or scene data) that cannot be turned into a mechanism.

    One line: ``FILE:LINE: ENTRY: fault`` — the line where the YAML parser knows it (else
    ``FILE: ENTRY: fault``), the entry as a path into the file (``groups[1].lengths``).
    """

    def __init__(
        self, message: str, *, file: str | None = None, entry: str | None = None, line: int | None = None
    ) -> None:
        self.file = file
        self.entry = entry
        self.line = line
        self.reason = message
        head = f"{file}:{line}" if file and line is not None else file
        where = ": ".join(part for part in (head, entry) if part)
        text = f"{where}: {message}" if where else message
        super().__init__(" ".join(text.split()))


def format_intervals(intervals: Sequence[tuple[float, float]], unit: str = "rad") -> str:
    """``[(lo, hi), ...]`` in rad as text in degrees with 4 decimals (in m: metres, 6 digits)."""
    return ", ".join(f"({show_input(lo, unit)}, {show_input(hi, unit)})" for lo, hi in intervals)


def show_input(x: float, unit: str = "rad") -> str:
    """An input's value in a message: an angle in degrees, a stroke (``unit`` "m") in metres."""
    return f"{x:.6g} m" if unit == "m" else f"{math.degrees(x):.4f}°"


class AssemblyError(SolverError):
    """A group cannot be assembled at some crank angles.

    ``intervals`` lists the open intervals of φ (rad) where it cannot be assembled, exact to
    rounding (closed form or root-finding, solver.assembly): ``(lo, hi)`` with ``0 ≤ lo < 2π``
    and ``lo < hi < lo + 2π`` (one through φ = 0 ends past 2π); the pattern repeats every turn.
    ``phi`` holds the requested angles that fall inside. ``unit`` "m": the input is a stroke
    (an actuator's length, m), and the message says so in metres.
    """

    def __init__(
        self,
        *,
        group: str,
        phi: Sequence[float] = (),
        intervals: Sequence[tuple[float, float]] = (),
        reason: str = "cannot be assembled",
        scene: str | None = None,
        unit: str = "rad",
    ) -> None:
        self.group = group
        self.unit = unit
        self.phi = tuple(float(p) for p in phi)
        self.intervals = tuple((float(lo), float(hi)) for lo, hi in intervals)
        self.reason = reason
        self.scene = scene
        head = f"{scene}: " if scene else ""
        text = f"{head}group '{group}' {reason}"
        label = "s" if unit == "m" else "φ"
        if self.intervals:
            text += f" for {label} in {format_intervals(self.intervals, unit)}"
        if self.phi:
            shown = ", ".join(show_input(p, unit) for p in self.phi[:5])
            more = f" and {len(self.phi) - 5} more" if len(self.phi) > 5 else ""
            text += f"; requested {label} = {shown}{more}"
        super().__init__(text)


class SampleAssemblyError(AssemblyError):
    """A group cannot be assembled at some samples of several inputs.

    ``samples`` is an (M, k) array of the failing input vectors (rad or m, in the order of
    ``inputs``, each shown in its ``units``: "rad" or "m"); ``phi`` the same as a tuple of
    k-tuples; ``intervals`` is empty (the
    unassemblable set is a region of the k-dimensional input space, see :func:`assemblable`).
    """

    def __init__(
        self,
        *,
        group: str,
        samples: Any,
        inputs: Sequence[str],
        reason: str = "cannot be assembled",
        scene: str | None = None,
        units: Sequence[str] | None = None,
    ) -> None:
        rows = np.asarray(samples, float).reshape(-1, len(inputs))
        units = tuple(units) if units is not None else ("rad",) * len(inputs)
        self.unit = "rad"
        self.group = group
        self.samples = rows
        self.inputs = tuple(inputs)
        self.phi = tuple(tuple(float(x) for x in r) for r in rows)  # type: ignore[assignment,misc]
        self.intervals = ()
        self.reason = reason
        self.scene = scene
        head = f"{scene}: " if scene else ""
        text = f"{head}group '{group}' {reason}"
        if len(rows):
            shown = ", ".join("(" + ", ".join(show_input(x, u) for x, u in zip(r, units)) + ")" for r in rows[:5])
            more = f" and {len(rows) - 5} more" if len(rows) > 5 else ""
            text += f" at {len(rows)} sample(s) of ({', '.join(inputs)}) = {shown}{more}"
        SolverError.__init__(self, text)


class DynamicsError(SolverError):
    """Forward dynamics cannot go on, or cannot start (solver.dynamics): the scene, and where the
    run stands — the time (s), the inputs' coordinates (``at``, as text) and the group — when the motion reached
    a position the inputs cannot drive through (a toggle, an assembly limit)."""

    def __init__(
        self,
        message: str,
        *,
        scene: str | None = None,
        time: float | None = None,
        at: str | None = None,
        group: str | None = None,
    ) -> None:
        self.scene, self.time, self.at, self.group, self.reason = scene, time, at, group, message
        parts = [scene] if scene else []
        if time is not None:
            parts.append(f"t = {time:.6g} s")
        if at:
            parts.append(at)
        if group:
            parts.append(f"group '{group}'")
        super().__init__(f"{', '.join(parts)}: {message}" if parts else message)


class SynthesisError(SolverError):
    """A synthesis task that cannot be posed or has no feasible answer (solver.synthesis): the
    message names the argument (``through[3]``, ``pairs``) or the constraint that no design met."""


class ArgumentError(SolverError):
    """An argument of a public function of the wrong type, not finite or out of range (checked by
    solver._arguments, as a scene file's entries are). One line: ``SCENE: FUNCTION: ARGUMENT
    fault, got VALUE``; ``function``, ``argument``, ``value`` and ``reason`` (the fault) are kept."""

    def __init__(self, reason: str, *, function: str, argument: str, value: Any, scene: str | None = None) -> None:
        self.function, self.argument, self.value, self.scene, self.reason = function, argument, value, scene, reason
        shown = repr(value.item() if isinstance(value, np.generic) else value)
        if len(shown) > 60:
            shown = shown[:57] + "..."
        if not isinstance(value, (int, float, np.number, list, tuple, np.ndarray, type(None))) or \
                isinstance(value, (bool, np.bool_)):
            shown += f" (a {type(value).__name__})"
        where = ": ".join(part for part in (scene, function) if part)
        SolverError.__init__(self, f"{where}: {argument} {reason}, got {shown}")  # (not a subclass's own)


class DynamicsArgumentError(ArgumentError, DynamicsError):
    """A bad argument of solver.dynamics (simulate, steady_state, flywheel_for, run_up, Stepper):
    both an :class:`ArgumentError` and a :class:`DynamicsError`."""

    time = at = group = None


class SynthesisArgumentError(ArgumentError, SynthesisError):
    """A bad argument of ``synthesize``: both an :class:`ArgumentError` and a :class:`SynthesisError`."""
