"""Machine dynamics of one input: steady periodic motion, speed fluctuation, flywheel, run-up.

The steady motion is periodic over one cycle Φ of the load (one turn, or the longest table
period: 720° for a four-stroke engine): the ω₀ at φ₀ whose motion returns to ω₀ at φ₀ + Φ. Each
trial integrates the equation of motion in time (:func:`simulate`, stopped at φ₀ + Φ by its
event) and ``root_scalar`` (secant) closes the cycle, exact up to the integrator's tolerance. (The
energy equation in φ, dω/dφ = (Q_drive − h)/(J·ω), is the same equation; integrated in φ over a
piecewise-linear table it came out about 1000 times less accurate at the same tolerance here,
so time is the independent variable.) Its time-mean speed ω_m = Φ / ∫dφ/ω and δ = (ω_max − ω_min)/ω_m.

A flywheel J_F on the input adds J_F to J(φ) and nothing to h (its centre is the crank's pivot):
the classical estimate J_F ≈ ΔE_max/(δ·ω_m²) − J_min (ΔE_max the largest swing of the excess
work over the cycle at the mean speed) brackets the exact J_F, found by ``brentq`` on the
periodic solution's δ. The run-up is :func:`simulate` from rest until ω first enters the steady
cycle's band [ω_min, ω_max].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from scipy.optimize import brentq, root_scalar

from .._arguments import Arguments
from ..errors import DynamicsArgumentError, DynamicsError
from ..forces.spec import TableForce
from .drive import make_drive
from .integrate import simulate
from .reduced import ReducedModel, reduced_model

__all__ = ["SteadyState", "RunUp", "cycle_of", "steady_state", "flywheel_for", "run_up"]

#: The periodic ω₀ is searched to this, relative (secant steps) — ten times finer than the cycle
#: is accepted to (CYCLE_CLOSURE), both well above the runs' noise at rtol 1e-10 (≈ 1e-10·ω).
ROOT_STEP = 1e-9
#: A steady cycle closes when |ω(φ₀ + Φ) − ω₀| ≤ this, relative to ω₀.
CYCLE_CLOSURE = 1e-8
#: A table period is a whole number of turns within this, relative (degrees typed in a file).
WHOLE_TURNS = 1e-9
#: The flywheel found by brentq to this, relative to its bracket.
FLYWHEEL_STEP = 1e-9
#: The mean-balance speed is looked for over this range (rad/s), on a geometric grid.
SPEED_RANGE = (1e-3, 1e5)


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


def _one_input(scene: Any, function: str) -> ReducedModel:
    """The model of a machine of one input crank; one line where machine dynamics does not apply."""
    model: ReducedModel = reduced_model(scene)
    if model.k != 1:
        raise DynamicsError(f"{function}: machine dynamics is for one input; this scene has {model.k} "
                            f"({', '.join(scene.inputs)})", scene=scene.name)
    span = scene.input_ranges[0]
    if span is not None:
        raise DynamicsError(f"{function}: machine dynamics (steady state, flywheel, run-up) is for an input crank "
                            f"that turns through a load cycle; '{scene.inputs[0]}' is an actuator's stroke "
                            f"[{span[0]:g}, {span[1]:g}] m, which has none: run it with simulate (its force, N, "
                            "as the drive) instead", scene=scene.name)
    return model


def _arguments(function: str, scene: Any, *, phi0: Any, rtol: Any, atol: Any) -> tuple[Arguments, float, float,
                                                                                        float]:
    """The arguments every machine-dynamics function takes, checked: (checks, φ₀, rtol, atol)."""
    args = Arguments(function, scene=getattr(scene, "name", None), error=DynamicsArgumentError)
    return (args, args.number("phi0", phi0, unit="rad"), args.number("rtol", rtol, low=0.0, low_open=True),
            args.number("atol", atol, low=0.0, low_open=True))


def cycle_of(scene: Any) -> float:
    """The load cycle (rad): one turn, or the longest period of a table of an angle (720° for a
    four-stroke engine's gas force), when that is a whole number of turns."""
    model = reduced_model(scene)
    periods = [ld.period for ld in model.spec.loads if isinstance(ld, TableForce) and ld.period]
    cycle = max([2 * math.pi, *periods])
    turns = cycle / (2 * math.pi)
    if abs(turns - round(turns)) > WHOLE_TURNS * turns:
        raise DynamicsError(f"a table's period ({math.degrees(cycle):g}°) is not a whole number of turns: the "
                            "load has no cycle", scene=scene.name)
    return cycle


def with_flywheel(scene: Any, inertia: float) -> Any:
    """The scene with ``inertia`` (kg·m²) more flywheel on its input crank (a new Scene)."""
    if inertia == 0.0:
        return scene
    spec = reduced_model(scene).spec
    data = scene._data
    crank = next(g for g in data.groups if g.drives)
    bodies = tuple(replace(b, inertia=b.inertia + inertia) if b.link.name == crank.name else b for b in spec.bodies)
    flywheels = {**spec.flywheels, scene.inputs[0]: spec.flywheels.get(scene.inputs[0], 0.0) + inertia}
    return type(scene)(replace(data, forces=replace(spec, bodies=bodies, flywheels=flywheels)))


def _cycle(scene: Any, drive: Any, phi0: float, cycle: float, w0: float, rtol: float, atol: float) -> Any:
    """One load cycle in time from (φ₀, ω₀): the run up to φ₀ + cycle, or None where it stalls."""
    traj = simulate(scene, 1e6, phi0=phi0, omega0=w0, drive=drive, rtol=rtol, atol=atol, until_phi=phi0 + cycle,
                    events=[lambda t, phi, omega: float(omega)], on_singular="stop")
    if traj.status != "until" or not traj.phi[-1] >= phi0 + cycle * (1 - WHOLE_TURNS):
        return None
    return traj


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
    args, phi0, rtol, atol = _arguments("steady_state", scene, phi0=phi0, rtol=rtol, atol=atol)
    flywheel = args.number("flywheel", flywheel, low=0.0, unit="kg·m²")
    omega_guess = args.number("omega_guess", omega_guess, low=0.0, low_open=True, unit="rad/s", none=True)
    samples = args.integer("samples", samples, low=2)
    model = _one_input(scene, "steady_state")
    fn, kind = make_drive(drive, scene.inputs, model.motors, scene=scene.name)
    cycle = cycle_of(scene)
    guess = omega_guess if omega_guess is not None else _mean_balance(model, fn, phi0, cycle, scene.name)
    machine = with_flywheel(scene, flywheel)

    def miss(w0: float) -> float:
        traj = _cycle(machine, drive, phi0, cycle, w0, rtol, atol)
        if traj is None:  # stalled within the cycle
            return -w0
        return float(traj.omega[-1]) - w0

    # the miss is smooth and nearly linear in ω₀; its noise is the integrator's (≈ rtol·ω)
    root = root_scalar(miss, x0=guess, x1=guess * 1.01, method="secant", xtol=ROOT_STEP * abs(guess), maxiter=100)
    if not root.root > 0 or abs(miss(float(root.root))) > CYCLE_CLOSURE * abs(root.root):
        raise DynamicsError(f"no steady periodic motion found near ω = {guess:.6g} rad/s (the machine stalls or "
                            "runs away: is the drive able to carry the load?)", scene=scene.name)
    w0 = float(root.root)
    traj = _cycle(machine, drive, phi0, cycle, w0, rtol, atol)
    if traj is None:
        raise DynamicsError("the steady motion stops within a cycle (ω reaches 0)", scene=scene.name)
    period = float(traj.t[-1])
    t = np.linspace(0.0, period, samples)
    phi, omega = traj.at(t)
    lo, hi = _extremes(traj, t)
    mean = cycle / period
    return SteadyState(phi=phi, omega=omega, t=t, omega_mean=mean, omega_min=lo, omega_max=hi,
                       delta=(hi - lo) / mean, period=period, cycle=cycle, flywheel=flywheel,
                       method=f"periodic solution over one {math.degrees(cycle):.0f}° cycle: the equation of "
                              f"motion in time (DOP853, rtol {rtol:g}) from φ₀ to φ₀ + cycle, ω₀ with ω(end) = ω₀ by"
                              f" the secant method; drive: {kind}")


def _extremes(traj: Any, t: np.ndarray) -> tuple[float, float]:
    """ω's extremes over the cycle: the samples' refined on the dense output around each."""
    w = traj.at(t)[1]
    out = []
    for pick, best in ((np.argmin, np.min), (np.argmax, np.max)):
        i = int(pick(w))
        ts = np.linspace(t[max(i - 1, 0)], t[min(i + 1, t.size - 1)], 201)
        out.append(float(best(traj.at(ts)[1])))
    return out[0], out[1]


def _mean_balance(model: ReducedModel, drive: Any, phi0: float, cycle: float, scene: str) -> float:
    """The constant speed at which the drive's mean effort over a cycle equals the loads' (the
    classical first estimate of the mean speed)."""
    phi = np.linspace(phi0, phi0 + cycle, 721)[:-1]

    def excess(w: float) -> float:
        h = model.bias(phi, w)
        q = np.array([drive(0.0, (p,), (w,))[0] for p in phi])
        return float(np.mean(q) - np.mean(h))

    ws = np.geomspace(*SPEED_RANGE, 81)
    vals = [excess(w) for w in ws]
    for a, b, fa, fb in zip(ws, ws[1:], vals, vals[1:]):
        if fa > 0 >= fb:
            return float(brentq(excess, a, b, xtol=ROOT_STEP * b))
    raise DynamicsError(f"the drive's mean effort never balances the loads' over a cycle for {SPEED_RANGE[0]:g} ≤ "
                        f"ω ≤ {SPEED_RANGE[1]:g} rad/s "
                        "(no motor, or one too weak to run the machine)", scene=scene)


def flywheel_for(scene: Any, delta: float, *, drive: Any = None, phi0: float = 0.0, rtol: float = 1e-10,
                 atol: float = 1e-10) -> tuple[float, SteadyState, float]:
    """The flywheel inertia (kg·m²) on the input that gives the coefficient of speed fluctuation
    ``delta``, exact on the periodic solution; also that steady state and the classical estimate."""
    args, phi0, rtol, atol = _arguments("flywheel_for", scene, phi0=phi0, rtol=rtol, atol=atol)
    delta = args.number("delta", delta, low=0.0, high=2.0, low_open=True, high_open=True)
    model = _one_input(scene, "flywheel_for")
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

    hi = 2 * estimate if estimate > 0 else 2 * float(np.max(model.mass(phi)))
    while miss(hi) > 0:
        hi *= 4
    jf = float(brentq(miss, 0.0, hi, xtol=FLYWHEEL_STEP * hi))
    return jf, steady_state(scene, drive=drive, flywheel=jf, phi0=phi0, omega_guess=w, rtol=rtol, atol=atol), estimate


def run_up(scene: Any, *, drive: Any = None, phi0: float = 0.0, t_max: float = 600.0, rtol: float = 1e-9,
           atol: float = 1e-9) -> RunUp:
    """From rest at ``phi0`` under the motor: the time until ω first enters the steady cycle's
    band [ω_min, ω_max] (``t_max`` s at most)."""
    args, phi0, rtol, atol = _arguments("run_up", scene, phi0=phi0, rtol=rtol, atol=atol)
    t_max = args.number("t_max", t_max, low=0.0, low_open=True, unit="s")
    _one_input(scene, "run_up")
    steady = steady_state(scene, drive=drive, phi0=phi0)
    low = steady.omega_min

    def reached(t: float, phi: Any, omega: Any) -> float:
        return float(omega) - low

    traj = simulate(scene, t_max, phi0=phi0, omega0=0.0, drive=drive, rtol=rtol, atol=atol, events=[reached])
    if traj.status != "until":
        raise DynamicsError(f"does not reach its steady speed band (ω ≥ {low:.6g} rad/s) within {t_max:g} s",
                            scene=scene.name)
    return RunUp(time=float(traj.t[-1]), trajectory=traj, steady=steady)
