"""One summary of a sweep or a run, read at a glance by a mechanism engineer (pure: numpy only).

``linkage-solve`` (a sweep over φ) and ``linkage-run`` (ticks on simulated time) both describe
their outputs with :func:`summary_lines`, in one vocabulary:

* **position**, **velocity**, **acceleration** for points and joints alike;
* angles (φ, joint angles) in degrees, everything else SI (m, m/s, m/s², rad/s, rad/s²);
* a joint angle is unwrapped over the samples: a joint that turns a whole revolution is said to
  make a "full turn" (with the net angle), one that swings back and forth gives its range;
* a quantity that does not change over the samples is said to be "constant" (never "a maximum at
  an arbitrary φ"); a maximum that does vary is given with the φ (and t) where it occurs;
* every point and joint carries its one-line description from the scene (``descriptions:``).

The CSV and the API are unchanged (SI, rad): this is text for people.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["Output", "Sweep", "summary_lines", "motion_line", "format_phi", "CONSTANT_RTOL"]

TWO_PI = 2.0 * math.pi
AXES = "xyz"
#: A quantity whose spread over the samples is at most this fraction of its magnitude (plus
#: rounding) is "constant": 1e-9 is ~10⁷ ulps, far above rounding and far below any real variation.
CONSTANT_RTOL = 1e-9
#: A net joint rotation within this of a whole number of turns (relative) is that many full turns.
TURN_RTOL = 1e-6


@dataclass(frozen=True)
class Output:
    """One output over the samples: a point ((N, dim) arrays) or a joint ((N,) arrays)."""

    name: str
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    unit: str = "m"  # a joint's unit: "rad" or "m"; points are "m"
    description: str = ""


@dataclass(frozen=True)
class Sweep:
    """The samples to summarise.

    ``phi`` in rad; ``t`` in s for a run on time (None for a sweep over φ); ``periodic`` when the
    samples are one whole turn of the input with the last wrapping to the first (linkage-solve's
    default grid), so a joint's net rotation over the turn includes the closing step.
    """

    phi: np.ndarray
    points: Sequence[Output] = ()
    joints: Sequence[Output] = ()
    t: np.ndarray | None = None
    periodic: bool = False
    extra: Mapping[str, str] = field(default_factory=dict)


def format_phi(phi: Any) -> str:
    """φ as an angle in the turn, degrees in [0, 360); several inputs as a tuple of them."""
    if np.ndim(phi):
        return "(" + ", ".join(format_phi(p) for p in np.asarray(phi, float).reshape(-1)) + ")"
    deg = math.degrees(float(phi)) % 360.0
    return f"{0.0 if round(deg, 2) == 360.0 else deg:.2f}°"


def motion_line(omega: float, epsilon: float) -> str:
    """What ω and ε mean for the numbers that follow."""
    text = f"ω = {omega:g} rad/s, ε = {epsilon:g} rad/s²"
    if omega == 1.0 and epsilon == 0.0:
        text += " (velocities and accelerations are the analogs d/dφ, d²/dφ², per rad of the input)"
    elif omega != 0.0 and epsilon == 0.0:
        text += f" ({abs(omega) / TWO_PI:.4g} turn/s)"
    return text + "; angles in degrees, everything else SI"


def _where(sweep: Sweep, i: int) -> str:
    if sweep.t is not None:
        return f"at t = {float(sweep.t[i]):.4g} s (φ = {format_phi(sweep.phi[i])})"
    return f"at φ = {format_phi(sweep.phi[i])}"


def _constant(values: np.ndarray) -> bool:
    if values.size == 0:
        return True
    lo, hi = float(values.min()), float(values.max())
    scale = max(abs(lo), abs(hi))
    return hi - lo <= CONSTANT_RTOL * scale + 1e-300


def _magnitude_line(sweep: Sweep, label: str, symbol: str, values: np.ndarray, unit: str) -> str:
    """``velocity  max |v| = … at φ = …`` or ``velocity  |v| constant …``."""
    if values.size == 0 or not np.isfinite(values).any():
        return f"    {label}: no finite value"
    finite = np.where(np.isfinite(values), values, -np.inf)
    if _constant(values[np.isfinite(values)]):
        v = float(np.nanmax(values))
        return f"    {label}: {'zero' if v == 0.0 else f'{symbol} constant {v:.6g} {unit}'}"
    i = int(np.argmax(finite))
    return f"    {label}: max {symbol} = {float(values[i]):.6g} {unit} {_where(sweep, i)}"


def _range(values: np.ndarray, unit: str, fmt: str = ".6g") -> str:
    lo, hi = float(np.nanmin(values)) + 0.0, float(np.nanmax(values)) + 0.0
    if _constant(values):
        return f"constant {lo:{fmt}} {unit}"
    return f"{lo:{fmt}} … {hi:{fmt}} {unit}"


def _title(kind: str, out: Output) -> str:
    return f"  {kind} {out.name}" + (f" — {out.description}" if out.description else "")


def _point_lines(sweep: Sweep, p: Output) -> list[str]:
    pos = np.asarray(p.position, float)
    dim = pos.shape[1] if pos.ndim == 2 else 1
    coords = ", ".join(f"{a} {_range(pos[:, i], 'm')}" for i, a in enumerate(AXES[:dim]))
    return [
        _title("point", p),
        f"    position: {coords}",
        _magnitude_line(sweep, "velocity", "speed |v|", np.linalg.norm(np.asarray(p.velocity, float), axis=-1), "m/s"),
        _magnitude_line(
            sweep, "acceleration", "|a|", np.linalg.norm(np.asarray(p.acceleration, float), axis=-1), "m/s²"
        ),
    ]


def _turns(sweep: Sweep, q: np.ndarray) -> tuple[float, np.ndarray]:
    """The net rotation over the samples (rad; over the whole turn when periodic) and q unwrapped."""
    u = np.unwrap(q)
    net = float(u[-1] - u[0])
    if sweep.periodic and q.size > 1:
        net += math.remainder(float(q[0] - q[-1]), TWO_PI)
    return net, u


def _angle_position(sweep: Sweep, q: np.ndarray) -> str:
    if _constant(q):
        return f"constant {math.degrees(float(q[0])):.4f}°"
    net, u = _turns(sweep, q)
    lo, hi = math.degrees(float(u.min())), math.degrees(float(u.max()))
    k = round(net / TWO_PI)
    if k != 0 and abs(net - k * TWO_PI) <= TURN_RTOL * abs(net):
        per = " per turn of the input" if sweep.periodic else " over the run" if sweep.t is not None else ""
        what = "a full turn" if abs(k) == 1 else f"{abs(k)} full turns"
        return f"makes {what}{per} ({math.degrees(net):+.1f}°; unwrapped {lo:.2f}° … {hi:.2f}°)"
    if abs(net) >= TWO_PI:
        return f"turns {math.degrees(net):+.1f}° over the samples (unwrapped {lo:.2f}° … {hi:.2f}°)"
    return f"swings {lo:.2f}° … {hi:.2f}° (a range of {hi - lo:.2f}°)"


def _joint_lines(sweep: Sweep, j: Output) -> list[str]:
    q = np.asarray(j.position, float)
    if j.unit == "rad":
        position = _angle_position(sweep, q)
        rate, acc = "rad/s", "rad/s²"
    else:
        position = _range(q, j.unit)
        rate, acc = f"{j.unit}/s", f"{j.unit}/s²"
    return [
        _title("joint", j),
        f"    position: {position}",
        _magnitude_line(sweep, "velocity", "|velocity|", np.abs(np.asarray(j.velocity, float)), rate),
        _magnitude_line(sweep, "acceleration", "|acceleration|", np.abs(np.asarray(j.acceleration, float)), acc),
    ]


def summary_lines(sweep: Sweep) -> list[str]:
    """Per point: position ranges, velocity and acceleration magnitudes; per joint: its motion."""
    if np.asarray(sweep.phi).size == 0:
        return ["  no samples"]
    lines: list[str] = []
    for p in sweep.points:
        lines += _point_lines(sweep, p)
    for j in sweep.joints:
        lines += _joint_lines(sweep, j)
    return lines
