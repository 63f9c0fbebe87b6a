"""What the inputs' actuators apply in forward dynamics: Q_drive(t, q, q̇) (docs/dynamics.md).

* the scene's ``motor`` of each input (a linear DC characteristic T = T_stall·(1 − ω/ω₀), valid in
  every quadrant: above ω₀ it brakes, below 0 it exceeds the stall torque; or a torque–speed
  table, linear between its entries and constant beyond them); an input without a motor is free;
* a constant effort per input, or a function ``f(t, q, qd)`` of the time and the state;
* ``"free"`` (or 0): nothing drives; the loads alone move the mechanism.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from ..errors import SolverError
from ..forces.spec import Motor

__all__ = ["Drive", "HELD", "motor_torque", "make_drive"]

#: Q_drive(t, q, qd) → one effort per input (N·m; N for a length input). With one input a drive
#: may carry ``one(t, q, w) → float``, the same effort on floats (the equation's per-step path).
Drive = Callable[[float, Sequence[float], Sequence[float]], Sequence[float]]


#: The pieces of motors' torque–speed tables held by the integrators between two of a table's
#: kinks (solver.dynamics._breaks, as solver.forces.frames.HELD for the loads' tables):
#: id(motor) → (ω_mid, T_mid, slope, 0.0), the line of one piece, extended beyond its ends.
HELD: dict[int, tuple[float, float, float, float]] = {}


def motor_torque(motor: Motor, omega: float) -> float:
    """The motor's torque (N·m) at the input rate ``omega`` (rad/s)."""
    if motor.linear:
        assert motor.stall is not None and motor.no_load is not None
        return motor.stall * (1.0 - omega / motor.no_load)
    if HELD:
        line = HELD.get(id(motor))
        if line is not None:
            return line[1] + line[2] * (omega - line[0])
    at, ts = motor.speeds, motor.torques
    if omega <= at[0]:
        return ts[0]
    if omega >= at[-1]:
        return ts[-1]
    i = bisect.bisect_right(at, omega) - 1
    return ts[i] + (omega - at[i]) / (at[i + 1] - at[i]) * (ts[i + 1] - ts[i])


def make_drive(spec: Any, inputs: Sequence[str], motors: Mapping[str, Motor], *, scene: str) -> tuple[Drive, str]:
    """The drive function for ``spec`` (see the module's docstring) and a word saying what it is:
    ``None`` — the scene's motors (free where an input has none); ``"free"`` or 0; a number or
    one number per input; a callable ``f(t, q, qd)`` returning a number or one per input."""
    k = len(inputs)
    if spec is None or spec == "motor":
        if not motors:
            if spec == "motor":
                raise SolverError(f"{scene}: drive='motor' but the scene has no 'motor:' (docs/dynamics.md)")
            return _constant((0.0,) * k), "free"
        chosen = [motors.get(j) for j in inputs]

        def by_motor(t: float, q: Sequence[float], qd: Sequence[float]) -> Sequence[float]:
            return [0.0 if m is None else motor_torque(m, qd[i]) for i, m in enumerate(chosen)]

        if k == 1 and chosen[0] is not None:
            motor = chosen[0]
            if motor.linear:
                stall, no_load = motor.stall, motor.no_load
                assert stall is not None and no_load is not None

                def one(t: float, q: float, w: float) -> float:
                    return stall * (1.0 - w / no_load)  # motor_torque's line, without the call
            else:
                def one(t: float, q: float, w: float) -> float:
                    return motor_torque(motor, w)

            by_motor.one = one  # type: ignore[attr-defined]
        return by_motor, "motor"
    if isinstance(spec, str):
        if spec != "free":
            raise SolverError(f"{scene}: drive must be 'motor', 'free', a number, {k} numbers or a function "
                              f"f(t, q, qd); got {spec!r}")
        return _constant((0.0,) * k), "free"
    if callable(spec):
        def by_function(t: float, q: Sequence[float], qd: Sequence[float]) -> Sequence[float]:
            out = spec(t, q[0] if k == 1 else q, qd[0] if k == 1 else qd)
            return _per_input(out, k, scene)

        return by_function, "function"
    return _constant(_per_input(spec, k, scene)), "effort"


def _per_input(value: Any, k: int, scene: str) -> list[float]:
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        out = [float(value)] * k if k == 1 else _fail(value, k, scene)
    elif isinstance(value, (str, bytes, bool)):
        return _fail(value, k, scene)
    else:
        try:
            out = [float(v) for v in value]
        except (TypeError, ValueError):
            return _fail(value, k, scene)
    if len(out) != k or not all(map(math.isfinite, out)):
        return _fail(value, k, scene)
    return out


def _fail(value: Any, k: int, scene: str) -> list[float]:
    raise SolverError(f"{scene}: the drive gives {value!r:.60} where it must give {k} effort(s), one per input, "
                      "each a finite number")


def _constant(values: Sequence[float]) -> Drive:
    fixed = list(values)

    def constant(t: float, q: Sequence[float], qd: Sequence[float]) -> Sequence[float]:
        return fixed

    if len(fixed) == 1:
        value = fixed[0]

        def one(t: float, q: float, w: float) -> float:
            return value

        constant.one = one  # type: ignore[attr-defined]
    return constant
