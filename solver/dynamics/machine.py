"""Machine dynamics of one input: steady periodic motion, speed fluctuation, flywheel, run-up.

The energy method (docs/dynamics.md). With φ as the independent variable the equation of motion
J(φ)·ε + h(φ, ω) = Q_drive(ω), ε = ω·dω/dφ, becomes

    dω/dφ = (Q_drive(ω) − h(φ, ω)) / (J(φ)·ω)        (ω ≠ 0)

— the energy equation d(½Jω²)/dφ = Q_drive − Q_loads differentiated — integrated over one cycle
Φ of the load (one turn, or the longest table period: 720° for a four-stroke engine) by scipy's
``solve_ivp``; the steady motion is the ω₀ with ω(φ₀ + Φ) = ω₀ (``root_scalar``, secant), exact up
to the integrator's tolerance. Its time-mean speed ω_m = Φ / ∫dφ/ω and δ = (ω_max − ω_min)/ω_m.

A flywheel J_F on the input adds J_F to J(φ) and nothing to h (its centre is the crank's pivot):
the classical estimate J_F ≈ ΔE_max/(δ·ω_m²) − J_min (ΔE_max the largest swing of the excess
work over the cycle at the mean speed) brackets the exact J_F, found by ``brentq`` on the
periodic solution's δ. The run-up is :func:`simulate` from rest until ω first enters the steady
cycle's band [ω_min, ω_max].
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, root_scalar

from ..errors import DynamicsError
from ..forces.spec import TableForce
from .drive import make_drive
from .integrate import simulate
from .reduced import ReducedModel, reduced_model

__all__ = ["SteadyState", "RunUp", "cycle_of", "steady_state", "flywheel_for", "run_up"]


@dataclass(frozen=True)
class SteadyState:
    """The steady periodic motion over one load cycle: ``phi`` (rad, from ``phi0`` over the
    cycle), ``omega`` (rad/s) and ``t`` (s) along it; the time-mean speed, its extremes, δ, the
    cycle's period (s) and the method."""

    phi: np.ndarray
    omega: np.ndarray
    t: np.ndarray
    omega_mean: float
    omega_min: float
    omega_max: float
    delta: float
    period: float
    cycle: float
    flywheel: float
    method: str


@dataclass(frozen=True)
class RunUp:
    """Run-up from rest: the time (s) until ω first enters the steady band, and the run itself."""

    time: float
    trajectory: Any
    steady: SteadyState


def _one_input(scene: Any) -> ReducedModel:
    model: ReducedModel = reduced_model(scene)
    if model.k != 1:
        raise DynamicsError(f"machine dynamics is for one input; this scene has {model.k} ({', '.join(scene.inputs)})",
                            scene=scene.name)
    return model


def cycle_of(scene: Any) -> float:
    """The load cycle (rad): one turn, or the longest period of a table of an angle (720° for a
    four-stroke engine's gas force), when that is a whole number of turns."""
    model = reduced_model(scene)
    periods = [ld.period for ld in model.spec.loads if isinstance(ld, TableForce) and ld.period]
    cycle = max([2 * math.pi, *periods])
    turns = cycle / (2 * math.pi)
    if abs(turns - round(turns)) > 1e-9 * turns:
        raise DynamicsError(f"a table's period ({math.degrees(cycle):g}°) is not a whole number of turns: the "
                            "load has no cycle", scene=scene.name)
    return cycle


def _rhs(model: ReducedModel, drive: Any, flywheel: float) -> Any:
    def f(phi: float, y: np.ndarray) -> list[float]:
        w, t = float(y[0]), float(y[1])
        m, h, _ = model.instant((float(phi),), (w,))
        q = drive(t, (phi,), (w,))[0]
        return [(q - h[0]) / ((m + flywheel) * w), 1.0 / w]

    return f


def _cycle(model: ReducedModel, drive: Any, flywheel: float, phi0: float, cycle: float, w0: float,
           rtol: float, atol: float, dense: bool = False) -> Any:
    def stall(phi: float, y: np.ndarray) -> float:
        return float(y[0])

    stall.terminal = True  # type: ignore[attr-defined]
    return solve_ivp(_rhs(model, drive, flywheel), (phi0, phi0 + cycle), [w0, 0.0], method="DOP853", rtol=rtol,
                     atol=atol, events=[stall], dense_output=dense)


def steady_state(
    scene: Any,
    *,
    drive: Any = None,
    flywheel: float = 0.0,
    phi0: float = 0.0,
    omega_guess: float | None = None,
    rtol: float = 1e-10,
    atol: float = 1e-10,
    samples: int = 721,
) -> SteadyState:
    """The steady periodic motion of a one-input machine under its motor (or ``drive``) and
    cyclic loads, with an extra flywheel inertia ``flywheel`` (kg·m²) on the input."""
    model = _one_input(scene)
    fn, kind = make_drive(drive, scene.inputs, model.motors, scene=scene.name)
    cycle = cycle_of(scene)
    guess = omega_guess if omega_guess is not None else _mean_balance(model, fn, phi0, cycle, scene.name)

    def miss(w0: float) -> float:
        sol = _cycle(model, fn, flywheel, phi0, cycle, w0, rtol, atol)
        if sol.status == 1:  # stalled within the cycle
            return -w0
        return float(sol.y[0, -1]) - w0

    root = root_scalar(miss, x0=guess, x1=guess * 1.01, method="secant", xtol=atol + rtol * abs(guess))
    if not root.converged or not root.root > 0:
        raise DynamicsError(f"no steady periodic motion found near ω = {guess:.6g} rad/s (the machine stalls or "
                            "runs away: is the drive able to carry the load?)", scene=scene.name)
    w0 = float(root.root)
    sol = _cycle(model, fn, flywheel, phi0, cycle, w0, rtol, atol, dense=True)
    if sol.status == 1:
        raise DynamicsError("the steady motion stops within a cycle (ω reaches 0)", scene=scene.name)
    phi = np.linspace(phi0, phi0 + cycle, samples)
    y = sol.sol(phi)
    omega, t = y[0], y[1]
    # the extremes of ω between samples: where dω/dφ = 0, refined on the dense output
    lo, hi = _extremes(sol, phi)
    period = float(t[-1])
    mean = cycle / period
    return SteadyState(phi=phi, omega=omega, t=t, omega_mean=mean, omega_min=lo, omega_max=hi,
                       delta=(hi - lo) / mean, period=period, cycle=cycle, flywheel=flywheel,
                       method=f"energy method over one {math.degrees(cycle):.0f}° cycle (DOP853 in φ, rtol {rtol:g}),"
                              f" periodic ω₀ by the secant method; drive: {kind}")


def _extremes(sol: Any, phi: np.ndarray) -> tuple[float, float]:
    w = sol.sol(phi)[0]
    out = []
    for pick in (np.argmin, np.argmax):
        i = int(pick(w))
        a, b = phi[max(i - 1, 0)], phi[min(i + 1, phi.size - 1)]
        xs = np.linspace(a, b, 201)
        out.append(float((np.min if pick is np.argmin else np.max)(sol.sol(xs)[0])))
    return out[0], out[1]


def _mean_balance(model: ReducedModel, drive: Any, phi0: float, cycle: float, scene: str) -> float:
    """The constant speed at which the drive's mean effort over a cycle equals the loads' (the
    classical first estimate of the mean speed)."""
    phi = np.linspace(phi0, phi0 + cycle, 721)[:-1]

    def excess(w: float) -> float:
        h = model.bias(phi, w)
        q = np.array([drive(0.0, (p,), (w,))[0] for p in phi])
        return float(np.mean(q) - np.mean(h))

    ws = np.geomspace(1e-3, 1e5, 81)
    vals = [excess(w) for w in ws]
    for a, b, fa, fb in zip(ws, ws[1:], vals, vals[1:]):
        if fa > 0 >= fb:
            return float(brentq(excess, a, b, xtol=1e-12 * b))
    raise DynamicsError("the drive's mean effort never balances the loads' over a cycle for 1e-3 ≤ ω ≤ 1e5 rad/s "
                        "(no motor, or one too weak to run the machine)", scene=scene)


def flywheel_for(scene: Any, delta: float, *, drive: Any = None, phi0: float = 0.0, rtol: float = 1e-10,
                 atol: float = 1e-10) -> tuple[float, SteadyState, float]:
    """The flywheel inertia (kg·m²) on the input that gives the coefficient of speed fluctuation
    ``delta``, exact on the periodic solution; also that steady state and the classical estimate."""
    if not (0 < delta < 2):
        raise DynamicsError(f"delta must lie in (0, 2), got {delta!r}", scene=scene.name)
    model = _one_input(scene)
    bare = steady_state(scene, drive=drive, phi0=phi0, rtol=rtol, atol=atol)
    fn, _ = make_drive(drive, scene.inputs, model.motors, scene=scene.name)
    phi = bare.phi[:-1]
    w = bare.omega_mean
    excess = np.array([fn(0.0, (p,), (w,))[0] for p in phi]) - model.bias(phi, w)
    work = np.concatenate([[0.0], np.cumsum(0.5 * (excess[1:] + excess[:-1]) * np.diff(phi))])
    j_min = float(np.min(model.mass(phi)))
    estimate = max(float(np.ptp(work)) / (delta * w * w) - j_min, 0.0)
    if bare.delta <= delta:
        return 0.0, bare, estimate

    def miss(jf: float) -> float:
        return steady_state(scene, drive=drive, flywheel=jf, phi0=phi0, omega_guess=w, rtol=rtol,
                            atol=atol).delta - delta

    hi = max(estimate, 1e-9) * 2
    while miss(hi) > 0:
        hi *= 4
    jf = float(brentq(miss, 0.0, hi, xtol=1e-9 * hi, rtol=1e-10))
    return jf, steady_state(scene, drive=drive, flywheel=jf, phi0=phi0, omega_guess=w, rtol=rtol, atol=atol), estimate


def run_up(scene: Any, *, drive: Any = None, phi0: float = 0.0, t_max: float = 600.0, rtol: float = 1e-9,
           atol: float = 1e-9) -> RunUp:
    """From rest at ``phi0`` under the motor: the time until ω first enters the steady cycle's
    band [ω_min, ω_max] (``t_max`` s at most)."""
    steady = steady_state(scene, drive=drive, phi0=phi0)
    low = steady.omega_min

    def reached(t: float, phi: Any, omega: Any) -> float:
        return float(omega) - low

    traj = simulate(scene, t_max, phi0=phi0, omega0=0.0, drive=drive, rtol=rtol, atol=atol, events=[reached])
    if traj.status != "until":
        raise DynamicsError(f"does not reach its steady speed band (ω ≥ {low:.6g} rad/s) within {t_max:g} s",
                            scene=scene.name)
    return RunUp(time=float(traj.t[-1]), trajectory=traj, steady=steady)
