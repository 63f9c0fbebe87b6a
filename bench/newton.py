"""A generic Newton–Raphson loop-closure solver: the approach of general multibody tools.

Unknowns are the coordinates of the moving points (natural coordinates); the mechanism is a list
of scalar constraints Φ(q, φ) = 0, each knowing its value, its gradient in q and φ, and its
second derivative along the motion. Positions come from Newton iterations warm-started from the
previous angle of the sweep; the analogs from the constraint Jacobian Φ_q:

    Φ_q q' = −Φ_φ,        Φ_q q'' = −γ,   γ = d²Φ/dφ² along (q', 1) with q'' = 0.

Nothing here knows the closed forms; only the first configuration of a sweep is assembled from
bench.alternatives (as a multibody tool is given an initial assembly).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from .alternatives import TAN_ALPHA, position_functions

__all__ = ["TOLERANCES", "Model", "models", "solve_sweep"]

TOLERANCES = (1e-6, 1e-10, 1e-14)
MAX_ITERATIONS = 50

Point = int | tuple[float, float]  # index of a moving point in q, or a fixed point


def _xy(q: np.ndarray, p: Point) -> tuple[float, float]:
    if isinstance(p, tuple):
        return p
    return q[2 * p], q[2 * p + 1]


@dataclass(frozen=True)
class Constraint:
    """One scalar constraint: value, ({q index: ∂Φ/∂q}, ∂Φ/∂φ), and γ along direction (v, 1)."""

    value: Callable[[np.ndarray, float], float]
    gradient: Callable[[np.ndarray, float], tuple[dict[int, float], float]]
    gamma: Callable[[np.ndarray, float, np.ndarray], float]


def driver(point: int, center: tuple[float, float], radius: float, axis: int) -> Constraint:
    """Crank driving constraint: coordinate ``axis`` of the point = centre + r (cos φ, sin φ)."""
    c = center[axis]
    trig, dtrig = (math.cos, lambda f: -math.sin(f)) if axis == 0 else (math.sin, math.cos)
    i = 2 * point + axis
    return Constraint(
        lambda q, f: q[i] - c - radius * trig(f),
        lambda q, f: ({i: 1.0}, -radius * dtrig(f)),
        lambda q, f, v: radius * trig(f),  # −r·trig'' = +r·trig
    )


def distance(a: Point, b: Point, length: float) -> Constraint:
    """|a − b|² − L² = 0 (either end may be fixed)."""

    def value(q: np.ndarray, f: float) -> float:
        (ax, ay), (bx, by) = _xy(q, a), _xy(q, b)
        return (ax - bx) ** 2 + (ay - by) ** 2 - length * length

    def gradient(q: np.ndarray, f: float) -> tuple[dict[int, float], float]:
        (ax, ay), (bx, by) = _xy(q, a), _xy(q, b)
        g: dict[int, float] = {}
        for p, sign in ((a, 2.0), (b, -2.0)):
            if not isinstance(p, tuple):
                g[2 * p] = g.get(2 * p, 0.0) + sign * (ax - bx)
                g[2 * p + 1] = g.get(2 * p + 1, 0.0) + sign * (ay - by)
        return g, 0.0

    def gamma(q: np.ndarray, f: float, v: np.ndarray) -> float:
        (vax, vay), (vbx, vby) = _velocity(v, a), _velocity(v, b)
        return 2.0 * ((vax - vbx) ** 2 + (vay - vby) ** 2)

    return Constraint(value, gradient, gamma)


def _velocity(v: np.ndarray, p: Point) -> tuple[float, float]:
    return (0.0, 0.0) if isinstance(p, tuple) else (v[2 * p], v[2 * p + 1])


def coordinate(point: int, axis: int, value: float) -> Constraint:
    """A point on a fixed line parallel to an axis: q[axis] = value."""
    i = 2 * point + axis
    return Constraint(lambda q, f: q[i] - value, lambda q, f: ({i: 1.0}, 0.0), lambda q, f, v: 0.0)


def collinear(point: int, pivot: tuple[float, float], through: int) -> Constraint:
    """(P − A) × (B − A) = 0: P on the line from the fixed pivot A through the moving point B."""
    ax, ay = pivot
    i, j = 2 * point, 2 * through

    def value(q: np.ndarray, f: float) -> float:
        return (q[i] - ax) * (q[j + 1] - ay) - (q[i + 1] - ay) * (q[j] - ax)

    def gradient(q: np.ndarray, f: float) -> tuple[dict[int, float], float]:
        return {i: q[j + 1] - ay, i + 1: -(q[j] - ax), j: -(q[i + 1] - ay), j + 1: q[i] - ax}, 0.0

    def gamma(q: np.ndarray, f: float, v: np.ndarray) -> float:
        return 2.0 * (v[i] * v[j + 1] - v[i + 1] * v[j])

    return Constraint(value, gradient, gamma)


def groove(point: int, tan_alpha: float) -> Constraint:
    """Seed 001: K = (y, z) in the cage plane with tan α · y − sin φ · z = 0 (ψ = atan(sin φ/tan α))."""
    i = 2 * point

    def value(q: np.ndarray, f: float) -> float:
        return tan_alpha * q[i] - math.sin(f) * q[i + 1]

    def gradient(q: np.ndarray, f: float) -> tuple[dict[int, float], float]:
        return {i: tan_alpha, i + 1: -math.sin(f)}, -math.cos(f) * q[i + 1]

    def gamma(q: np.ndarray, f: float, v: np.ndarray) -> float:
        return math.sin(f) * q[i + 1] - 2.0 * math.cos(f) * v[i + 1]

    return Constraint(value, gradient, gamma)


@dataclass(frozen=True)
class Model:
    """Constraints of one scene, its moving points (q order) and how to read the outputs."""

    points: tuple[str, ...]
    constraints: tuple[Constraint, ...]
    scale: float
    dim: int = 2


def models() -> dict[str, Model]:
    origin = (0.0, 0.0)
    a_finger = (0.04, -0.03)
    return {
        "four_bar": Model(
            ("A", "B"),
            (driver(0, origin, 0.1, 0), driver(0, origin, 0.1, 1), distance(0, 1, 0.4), distance(1, (0.4, 0.0), 0.3)),
            0.4,
        ),
        "harvester_finger": Model(
            ("B", "C", "E"),
            (
                driver(0, origin, 0.2, 0),
                driver(0, origin, 0.2, 1),
                distance(1, a_finger, 0.30),
                collinear(1, a_finger, 0),
                distance(2, a_finger, 0.22),
                collinear(2, a_finger, 0),
            ),
            0.3,
        ),
        "slider_crank": Model(
            ("A", "B"),
            (driver(0, origin, 0.05, 0), driver(0, origin, 0.05, 1), coordinate(1, 1, 0.01), distance(0, 1, 0.2)),
            0.2,
        ),
        # K = (0, y, z): the unknowns are (y, z) of K in the cage plane x = 0.
        "spherical_converter": Model(("K",), (distance(0, origin, 0.05), groove(0, TAN_ALPHA)), 0.05, dim=3),
    }


def _jacobian(model: Model, q: np.ndarray, f: float) -> tuple[np.ndarray, np.ndarray]:
    n = len(q)
    jac = np.zeros((n, n))
    dphi = np.empty(n)
    for row, c in enumerate(model.constraints):
        grad, dphi[row] = c.gradient(q, f)
        for col, value in grad.items():
            jac[row, col] = value
    return jac, dphi


def solve_sweep(
    scene: str, phi: Sequence[float] | np.ndarray, tol: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """(q, q', q'') of shape (N, n) over the sweep, and the mean Newton iterations per angle.

    Stops iterating after the first update with max |Δq| ≤ tol · scale.
    """
    model = models()[scene]
    start = position_functions[scene](np.asarray([phi[0]], float))[0]
    q = np.concatenate([start[p][0][-2:] for p in model.points])
    n = len(q)
    out = np.empty((3, len(phi), n))
    iterations = 0
    limit = tol * model.scale
    for k, f in enumerate(phi):
        f = float(f)
        for _ in range(MAX_ITERATIONS):
            residual = np.array([c.value(q, f) for c in model.constraints])
            jac, _ = _jacobian(model, q, f)
            step = np.linalg.solve(jac, -residual)
            q = q + step
            iterations += 1
            if np.max(np.abs(step)) <= limit:
                break
        else:
            raise ArithmeticError(f"{scene}: Newton did not converge in {MAX_ITERATIONS} iterations at phi={f!r}")
        jac, dphi = _jacobian(model, q, f)
        v = np.linalg.solve(jac, -dphi)
        gamma = np.array([c.gamma(q, f, v) for c in model.constraints])
        a = np.linalg.solve(jac, -gamma)
        out[0, k], out[1, k], out[2, k] = q, v, a
    return out[0], out[1], out[2], iterations / len(phi)


def outputs(scene: str, q: np.ndarray, v: np.ndarray, a: np.ndarray) -> tuple[dict, dict]:
    """The scene's output points and joints (value, d/dφ, d²/dφ²) from the natural coordinates."""
    model = models()[scene]
    pts = {}
    for i, name in enumerate(model.points):
        cols = [x[:, 2 * i : 2 * i + 2] for x in (q, v, a)]
        if model.dim == 3:
            cols = [np.column_stack([np.zeros(len(c)), c]) for c in cols]
        pts[name] = tuple(cols)

    def point(i: int) -> list[np.ndarray]:
        return [x[:, 2 * i : 2 * i + 2] for x in (q, v, a)]

    def fixed(xy: tuple[float, float]) -> list[np.ndarray]:
        zero = np.zeros_like(q[:, :2])
        return [zero + np.asarray(xy), zero, zero]

    def angle(tail: list[np.ndarray], head: list[np.ndarray]) -> tuple[np.ndarray, ...]:
        return _angle_of(*(h - t for h, t in zip(head, tail, strict=True)))

    if scene == "four_bar":
        joints = {"coupler": angle(point(0), point(1)), "rocker": angle(fixed((0.4, 0.0)), point(1))}
    elif scene == "harvester_finger":
        joints = {"finger": angle(fixed((0.04, -0.03)), point(1))}
    elif scene == "slider_crank":
        joints = {"slider": (q[:, 2], v[:, 2], a[:, 2])}
    else:  # cage angle ψ = atan2(y, z) of K = (0, y, z)
        joints = {"cage": _angle_of(*(x[:, 1::-1] for x in (q, v, a)))}
    return pts, joints


def _angle_of(q: np.ndarray, v: np.ndarray, a: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    x, y, vx, vy, ax, ay = q[:, 0], q[:, 1], v[:, 0], v[:, 1], a[:, 0], a[:, 1]
    r2 = x * x + y * y
    w = (x * vy - y * vx) / r2
    return np.arctan2(y, x), w, (x * ay - y * ax) / r2 - 2.0 * w * (x * vx + y * vy) / r2
