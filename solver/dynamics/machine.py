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
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from scipy.optimize import brentq

from .._arguments import Arguments
from ..errors import DynamicsArgumentError, DynamicsError
from ..forces.spec import TableForce
from ._cycle import CycleMap
from ._guard import MAX_RATE
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
#: The flywheel found by brentq to this, relative to the machine's inertia with it (δ is good to
#: about 1e-8 relative: a finer step only chases its noise).
FLYWHEEL_STEP = 1e-7
#: The mean-balance speed is looked for over this range (rad/s), on a geometric grid.
SPEED_RANGE = (1e-3, 1e5)
#: The periodic ω₀ is bracketed from its guess by steps of this (relative), doubling.
BRACKET_STEP = 0.01
#: The secant method's second point, relative to the guess.
SECANT_STEP = 1e-4
#: A cycle map whose miss and slope (per relative change of ω₀) are below this is neutral: every
#: ω₀ is periodic (the engine's slope is ~1e-2, the runs' noise ~1e-10).
NEUTRAL = 1e-6


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
    if model.friction is not None:
        raise DynamicsError(f"{function}: names friction: machine dynamics (steady state, flywheel, run-up) does not "
                            "model Coulomb friction; run it with simulate (docs/dynamics.md#friction)",
                            scene=scene.name)
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


class _Neutral(Exception):
    """The cycle closes at every ω₀ near the guess: a machine without losses."""


def _secant(miss: Callable[[float], float], guess: float, *, iterations: int = 6) -> float | None:
    """The root of the (nearly linear) miss by the secant method from ``guess`` and a point
    SECANT_STEP above it, when it gets there within ``iterations`` without a stall (+1) on the
    way; None otherwise (then the bracket and Brent's method take over)."""
    x0, x1 = guess, guess * (1 + SECANT_STEP)
    f0, f1 = miss(x0), miss(x1)
    if 1.0 not in (f0, f1) and abs(f1 - f0) < NEUTRAL * SECANT_STEP and abs(f0) < NEUTRAL:
        raise _Neutral(guess)
    for _ in range(iterations):
        if f0 == 1.0 or f1 == 1.0 or f1 == f0:  # a stall: not smooth there
            return None
        x0, f0, x1 = x1, f1, x1 - f1 * (x1 - x0) / (f1 - f0)
        if not (SPEED_RANGE[0] < x1 < MAX_RATE):
            return None
        f1 = miss(x1)
        if abs(f1) <= ROOT_STEP and abs(x1 - x0) <= 1e3 * ROOT_STEP * x1:
            return x1
    return None


def _bracket(miss: Callable[[float], float], guess: float, *, step: float = BRACKET_STEP,
             limit: float = MAX_RATE) -> tuple[float, float, float, float] | None:
    """(a, b, miss(a), miss(b)) with miss(a) ≥ 0 ≥ miss(b), a ≤ b, searched from ``guess`` by steps
    growing ×2 (the miss falls across its root: a faster start loses more to the brake, and a
    stall counts as +1); None where none is found within the speed range."""
    here = miss(guess)
    if here == 0.0:
        return guess, guess, 0.0, 0.0
    up = here > 0  # too slow at the guess: look above it
    a, fa, factor = guess, here, step
    while True:
        b = a * (1 + factor) if up else a / (1 + factor)
        if not (SPEED_RANGE[0] < b < limit):
            return None
        fb = miss(b)
        if (fb > 0) != up or fb == 0.0:
            return (a, b, fa, fb) if up else (b, a, fb, fa)
        a, fa, factor = b, fb, factor * 2


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
    cyclic loads, with an extra flywheel inertia ``flywheel`` (kg·m²) on the input: the ω₀ at
    ``phi0`` whose cycle returns to it, bracketed and found by Brent's method on the cycle map
    (solver.dynamics._cycle), each cycle integrated in φ from kink to kink of the load."""
    args, phi0, rtol, atol = _arguments("steady_state", scene, phi0=phi0, rtol=rtol, atol=atol)
    flywheel = args.number("flywheel", flywheel, low=0.0, unit="kg·m²")
    omega_guess = args.number("omega_guess", omega_guess, low=0.0, low_open=True, unit="rad/s", none=True)
    samples = args.integer("samples", samples, low=2)
    model = _one_input(scene, "steady_state")
    fn, kind = make_drive(drive, scene.inputs, model.motors, scene=scene.name)
    cycle = cycle_of(scene)
    guess = omega_guess if omega_guess is not None else _mean_balance(model, fn, phi0, cycle, scene.name)
    runs = CycleMap(model, fn, phi0=phi0, cycle=cycle, flywheel=flywheel, rtol=rtol, atol=atol)

    def miss(w0: float) -> float:
        run = runs.run(w0)
        if run is None:  # stalled within the cycle: too slow
            return 1.0
        return (run.omega_end - w0) / w0

    neutral = DynamicsError(f"no isolated steady motion: the cycle closes at every ω₀ near {guess:.6g} rad/s — a "
                            "machine without losses (no brake, damper or motor characteristic) has a periodic motion "
                            "at every speed that carries it round", scene=scene.name)
    try:
        w0 = _secant(miss, guess)
    except _Neutral:
        raise neutral from None
    if w0 is None:
        found = _bracket(miss, guess)
        if found is None:
            raise DynamicsError(_no_steady_reason(guess, miss), scene=scene.name)
        a, b, fa, fb = found
        w0 = a if fa == 0.0 else b if fb == 0.0 else float(brentq(miss, a, b, xtol=ROOT_STEP * b, rtol=ROOT_STEP))
        if abs(miss(w0 * (1 + BRACKET_STEP))) < NEUTRAL:  # closes above the root too: no isolated one
            raise DynamicsError(f"no isolated steady motion: the cycle closes at every ω₀ from {w0:.6g} rad/s up — a "
                                "machine without losses (no brake, damper or motor characteristic) has a periodic "
                                "motion at every speed that carries it round", scene=scene.name)
    run = runs.run(w0, keep=True)
    if run is None or abs(run.omega_end - w0) > CYCLE_CLOSURE * w0:
        # the miss jumps from a stall (+) to a loss (−) at w0: no cycle closes
        raise DynamicsError(f"no steady periodic motion: from ω₀ below {w0:.6g} rad/s at φ₀ = {phi0:g} rad the machine "
                            "stalls within the cycle, from above it ends the cycle slower than it began — too little "
                            "inertia to carry it through the cycle at its mean speed (a flywheel: flywheel_for)",
                            scene=scene.name)
    phi = np.linspace(phi0, phi0 + cycle, samples)
    omega, t = run.at(phi)
    lo, hi = run.extreme(np.argmin), run.extreme(np.argmax)
    mean = cycle / run.period
    return SteadyState(phi=phi, omega=omega, t=t, omega_mean=mean, omega_min=lo, omega_max=hi,
                       delta=(hi - lo) / mean, period=run.period, cycle=cycle, flywheel=flywheel,
                       method=f"periodic solution over one {math.degrees(cycle):.0f}° cycle: the equation of "
                              f"motion in φ (u = ω², DOP853 rtol {rtol:g} from kink to kink of the load), ω₀ with "
                              f"ω(end) = ω₀ bracketed and found by Brent's method in {runs.runs} cycles; drive: "
                              f"{kind}")


def _no_steady_reason(guess: float, miss: Callable[[float], float]) -> str:
    """Why there is no steady motion (one line)."""
    if miss(MAX_RATE / 2) > 0:
        return (f"no steady periodic motion: the machine gains speed over a cycle from every ω₀ up to "
                f"{MAX_RATE / 2:g} rad/s, or stalls within it: nothing brakes the drive enough")
    return (f"no steady periodic motion near ω = {guess:.6g} rad/s: the cycle's miss never changes sign (the "
            "drive cannot carry the load)")


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
    ``delta``, exact on the periodic solution; also that steady state and the classical estimate.

    The classical estimate J_F ≈ ΔE_max/(δ·ω_m²) − J_min is taken at the mean-balance speed (no
    steady state is needed for it: the bare machine may have none); the exact J_F is bracketed
    around it and found by Brent's method on δ(J_F) (decreasing; a flywheel too small for any
    steady motion counts as too small), each steady state started from the last one's ω₀."""
    args, phi0, rtol, atol = _arguments("flywheel_for", scene, phi0=phi0, rtol=rtol, atol=atol)
    delta = args.number("delta", delta, low=0.0, high=2.0, low_open=True, high_open=True)
    model = _one_input(scene, "flywheel_for")
    fn, _ = make_drive(drive, scene.inputs, model.motors, scene=scene.name)
    cycle = cycle_of(scene)
    w = _mean_balance(model, fn, phi0, cycle, scene.name)
    phi = np.linspace(phi0, phi0 + cycle, 1441)
    excess = np.array([fn(0.0, (p,), (w,))[0] for p in phi]) - model.bias(phi, w)
    work = np.concatenate([[0.0], np.cumsum(0.5 * (excess[1:] + excess[:-1]) * np.diff(phi))])
    j_min = float(np.min(model.mass(phi)))
    estimate = max(float(np.ptp(work)) / (delta * w * w) - j_min, 0.0)
    last = {"w0": w}
    states: dict[float, SteadyState] = {}

    def state(jf: float) -> SteadyState | None:
        try:
            s = steady_state(scene, drive=drive, flywheel=jf, phi0=phi0, omega_guess=last["w0"], rtol=rtol, atol=atol)
        except DynamicsError:
            return None
        last["w0"] = float(s.omega[0])
        states[jf] = s
        return s

    seen: dict[float, float] = {}

    def miss(jf: float) -> float:
        if jf not in seen:
            s = state(jf)
            seen[jf] = 1.0 if s is None else s.delta / delta - 1.0
        return seen[jf]

    # the machine as it is, unless the estimate says a flywheel well beyond its own inertia is
    # needed (then it may have no steady motion at all, and finding that out costs most)
    bare = state(0.0) if estimate <= j_min else None
    if bare is not None and bare.delta <= delta:
        return 0.0, bare, estimate
    # 1/δ grows nearly linearly with J_F (classically (J + J_F)·ω_m²/ΔE_max): predict J_F from the
    # bare machine (or the estimate), then bracket it by steps growing ×2 around the prediction
    slope = w * w / max(float(np.ptp(work)), 1e-300)
    guess = (1 / delta - 1 / bare.delta) / slope if bare is not None else max(estimate, 1e-6 * j_min)
    lo, hi = 0.0, guess
    step = 0.05
    if miss(guess) > 0:
        while True:
            lo, hi = hi, hi * (1 + step)
            if miss(hi) <= 0:
                break
            step *= 2
            if hi > 1e9 * max(guess, j_min):
                raise DynamicsError(f"no flywheel up to {hi:g} kg·m² brings δ to {delta:g}", scene=scene.name)
    else:
        while True:
            lo = hi / (1 + step)
            if lo < 1e-12 * guess:  # down to no flywheel at all: the machine as it is may do
                lo = 0.0
                if miss(0.0) <= 0:
                    return 0.0, states[0.0], estimate
                break
            if miss(lo) > 0:
                break
            hi, step = lo, step * 2
    jf = float(brentq(miss, lo, hi, xtol=FLYWHEEL_STEP * (hi + j_min), rtol=FLYWHEEL_STEP))
    final = states[jf] if jf in states else state(jf)
    if final is None:
        raise DynamicsError(f"no steady motion with the flywheel found ({jf:g} kg·m²)", scene=scene.name)
    return jf, final, estimate


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
