"""Forward dynamics: q̈ = M(q)⁻¹·(Q_drive − h(q, q̇)) integrated in time (docs/dynamics.md).

The state is (q, q̇) and two work integrals, W_drive = ∫Q_drive·q̇ dt and W_other = ∫Q_other·q̇ dt
(the loads other than gravity and springs: dampers, forces, torques, tables), so that the energy
balance T + V_gravity + V_springs − W_drive − W_other = const is checked on the run's own numbers.
Positions always come from the closed form, so the loop cannot open: nothing is stabilised.

``simulate`` integrates with DOP853 (adaptive, the accurate path) or RK4 (a fixed step) on the
own step loop (solver.dynamics._stepping: plain Python numbers, breakpoint to breakpoint across
the tables' kinks), or hands the equation to :func:`scipy.integrate.solve_ivp` (RK45, Radau);
:class:`~solver.dynamics.stepper.Stepper` advances it tick by tick (the node).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.integrate import DOP853, RK45, Radau, solve_ivp

from .._arguments import Arguments
from ..errors import AssemblyError, DynamicsArgumentError, DynamicsError
from ..tolerances import DYNAMICS_TOGGLE
from ._equation import Equation
from ._friction_multi_run import MultiFrictionEquation, run_with_friction_multi
from ._friction_run import FrictionEquation, run_with_friction
from ._guard import MAX_RATE, MAX_STEPS, RunGuard, rates_text
from ._run import Outcome, run
from .drive import make_drive
from .reduced import reduced_model

__all__ = ["Equation", "Trajectory", "simulate"]

#: scipy's methods (solve_ivp; the Stepper's adaptive one by name); DOP853 and RK4 run on the own
#: step loop (solver.dynamics._stepping: breakpoint to breakpoint, no per-step numpy overhead)
_METHODS = {"DOP853": DOP853, "RK45": RK45, "Radau": Radau}
OWN_METHODS = ("DOP853", "RK4")


@dataclass
class Trajectory:
    """A run of forward dynamics: samples of the time (s), the inputs' coordinates, rates and
    accelerations ((N,) for one input, (N, k) for several), the drive's effort and the two work
    integrals; ``status`` ``"done"`` (reached ``t_end``, its last sample), ``"until"`` (a
    requested angle or event), ``"toggle"`` / ``"assembly"`` (a position the inputs cannot drive
    through; ``message`` says when, where and which group), ``"runaway"`` (a rate beyond
    ``max_rate``) or ``"steps"`` (a run that would not end: its steps fallen so small, or held by
    stability, that the rest would take more than ``max_steps``; solver.dynamics._guard)."""

    scene: Any
    t: np.ndarray
    phi: np.ndarray
    omega: np.ndarray
    epsilon: np.ndarray
    effort: np.ndarray
    work_drive: np.ndarray
    work_other: np.ndarray
    status: str = "done"
    message: str = ""
    drive: str = "free"
    method: str = "DOP853"
    rtol: float = 0.0
    atol: float = 0.0
    evaluations: int = 0
    #: the friction's work since the start (J, ≤ 0; None without friction: docs/dynamics.md#friction)
    work_friction: np.ndarray | None = None
    #: one line per event of the run that did not end it: each stick and slip of a scene with friction
    messages: list[str] = field(default_factory=list)
    #: with friction: each stick and slip as (``"stick"`` / ``"slip"``, t (s), q) — the coordinate
    #: of the input that sticks or slips (``switch_inputs``) where it happened (in the order of ``messages``)
    switches: list[tuple[str, float, float]] = field(default_factory=list)
    #: with friction: the input of each entry of ``switches`` (several inputs stick and slip apart)
    switch_inputs: list[str] = field(default_factory=list)
    _dense: Callable[[Any], np.ndarray] | None = field(default=None, repr=False)

    def at(self, t: Any) -> tuple[np.ndarray, np.ndarray]:
        """(φ, ω) at time(s) ``t`` within the run, from the integrator's dense output."""
        if self._dense is None:
            raise DynamicsError("this trajectory keeps no dense output", scene=self.scene.name)
        y = self._dense(Arguments("Trajectory.at", scene=self.scene.name, error=DynamicsArgumentError).numbers("t", t))
        k = len(self.scene.inputs)
        if k == 1:
            return y[0], y[1]
        return np.moveaxis(y[:k], 0, -1), np.moveaxis(y[k:2 * k], 0, -1)

    def solve(self, *, mask: bool = False) -> Any:
        """Everything :meth:`Scene.solve` gives (points, joints, efforts, reactions) along the run."""
        return self.scene.solve(self.phi, omega=self.omega, epsilon=self.epsilon, mask=mask)

    def energy(self) -> dict[str, np.ndarray]:
        """Per sample (J): ``kinetic`` ½q̇ᵀMq̇, ``gravity`` and ``springs`` potentials, ``work_drive``
        and ``work_other`` done since the start (with friction ``work_friction`` too, ≤ 0), and
        ``balance`` = T + V − W_drive − W_other (− W_friction) minus its value at the start: zero up
        to the integrator's tolerance."""
        model = reduced_model(self.scene)
        kinetic = model.kinetic(self.phi, self.omega)
        pot = model.potential(self.phi)
        total = kinetic + pot["gravity"] + pot["springs"] - self.work_drive - self.work_other
        out = {
            "kinetic": kinetic,
            "gravity": pot["gravity"],
            "springs": pot["springs"],
            "work_drive": self.work_drive,
            "work_other": self.work_other,
        }
        if self.work_friction is not None:
            total = total - self.work_friction
            out["work_friction"] = self.work_friction
        out["balance"] = total - total[0]
        return out


def _start(scene: Any) -> list[float]:
    """The default initial coordinates: 0 for an angle, the closed length of an actuator's stroke."""
    spans = tuple(getattr(scene, "input_ranges", ())) or (None,) * len(scene.inputs)
    return [0.0 if span is None else float(span[0]) for span in spans]


def _initial(args: Arguments, value: Any, k: int, label: str) -> list[float]:
    """An initial coordinate or rate: a number (every input alike; None: 0) or one per input."""
    arr = args.numbers(label, 0.0 if value is None else value)
    if arr.ndim > 1 or (arr.ndim == 1 and arr.size != k):
        args.fail(label, value, "must be a finite number" if k == 1 else
                  f"must be a number or {k} numbers (one per input)")
    return [float(v) for v in np.broadcast_to(arr, (k,))]


def _checked(
    args: Arguments, *, rtol: Any, atol: Any, method: Any, methods: Sequence[str] = (*OWN_METHODS, *_METHODS)
) -> tuple[float, float, str]:
    """The integrator's tolerances and method, checked (simulate, Stepper)."""
    return (args.number("rtol", rtol, low=0.0, low_open=True), args.number("atol", atol, low=0.0, low_open=True),
            args.choice("method", method, tuple(dict.fromkeys(methods))))


def _where(scene: Any, y: np.ndarray) -> str:
    k = len(scene.inputs)
    parts = []
    for i, j in enumerate(scene.inputs):
        unit = scene.joint_units.get(j, "rad")
        v = float(y[i])
        parts.append(f"{j} = {v:.6g} rad ({math.degrees(v):.6g}°)" if unit == "rad" else f"{j} = {v:.6g} {unit}")
    return ", ".join(parts[:k])


def _strokes(scene: Any) -> list[tuple[int, float, float, str]]:
    """(input index, closed, open, group) of each length input with a stroke."""
    groups = {g.input_joint(): g.name for g in getattr(scene, "ordered", ()) if g.drives}
    spans = zip(scene.inputs, getattr(scene, "input_ranges", ()))
    return [(i, span[0], span[1], groups.get(joint, joint)) for i, (joint, span) in enumerate(spans)
            if span is not None]


def _stroke_end(lo: float, hi: float, group: str, *, open_end: bool) -> str:
    """The one message where a run reaches an end of a stroke, whichever way the integrator
    found it (the stroke's event, or a step beyond the end rejected: the two are the same limit)."""
    end, verb = ("open", "tops") if open_end else ("closed", "bottoms")
    return (f"reaches the {end} end of the stroke [{lo:g}, {hi:g}] m of group '{group}' (an assembly limit: "
            f"the cylinder {verb} out)")


def _limit_message(scene: Any, fault: tuple[str, str, list[float]] | None, detail: str) -> str:
    """The message where the integrator could not step on (a trial state it could not assemble):
    the stroke's end where that state lies beyond one (the same text as the stroke's event),
    else the group and its reason (``detail``: the integrator's own, without a fault)."""
    if fault is None:
        return f"stops at an assembly limit ({detail})"
    group, reason, q = fault
    for i, lo, hi, name in _strokes(scene):
        if not lo <= q[i] <= hi:
            return _stroke_end(lo, hi, name, open_end=q[i] > hi)
    return f"stops at an assembly limit of group '{group}' ({reason})"


def _stroke_events(scene: Any) -> list[Any]:
    """One terminal event per length input with a stroke: (s − closed)·(open − s) falls to 0 at
    either end, where the cylinder bottoms out or tops out (an assembly limit). ``message(y)``:
    the one text of :func:`_stroke_end` for the end ``y`` is at."""
    out = []
    for i, lo, hi, name in _strokes(scene):

        def end(t: float, y: np.ndarray, i: int = i, lo: float = lo, hi: float = hi) -> float:
            return float((y[i] - lo) * (hi - y[i]))

        def message(y: np.ndarray, i: int = i, lo: float = lo, hi: float = hi, name: str = name) -> str:
            return _stroke_end(lo, hi, name, open_end=abs(y[i] - hi) < abs(y[i] - lo))

        end.terminal = True  # type: ignore[attr-defined]
        end.plain = True  # type: ignore[attr-defined]  # takes y as a list (the own step loop's)
        end.direction = -1  # type: ignore[attr-defined]  # leaving the stroke (a run may start at an end)
        end.message = message  # type: ignore[attr-defined]
        out.append(end)
    return out


def simulate(
    scene: Any,
    t_end: float,
    *,
    phi0: Any = None,
    omega0: Any = 0.0,
    drive: Any = None,
    rtol: float = 1e-9,
    atol: float = 1e-9,
    method: str = "DOP853",
    dt: float | None = None,
    until_phi: float | None = None,
    events: Sequence[Callable[[float, Any, Any], float]] = (),
    on_singular: str = "raise",
    max_step: float = math.inf,
    max_steps: float = MAX_STEPS,
    max_rate: float = MAX_RATE,
    step: float | None = None,
) -> Trajectory:
    """Integrate the inputs from (``phi0``, ``omega0``) at t = 0 to ``t_end`` (s) under ``drive``
    (``phi0`` None: 0 for an angle, the closed length of an actuator's stroke)
    (solver.dynamics.drive: the scene's motors by default) and the scene's loads.

    Samples: the integrator's own steps, or every ``dt`` seconds; the last at exactly ``t_end``.
    ``until_phi`` (one input) stops the run where φ reaches it; each of ``events``, a function
    ``f(t, phi, omega)``, where it crosses zero. Where the motion reaches a toggle of a group
    (its conditioning falls to tolerances.DYNAMICS_TOGGLE: M is unbounded there) or an assembly
    limit, ``on_singular="raise"`` raises :class:`DynamicsError` naming the time, the angle and
    the group (the partial run on its ``trajectory``); ``"stop"`` returns the partial run with
    that ``status`` and ``message``. So does a run that would not end (solver.dynamics._guard): a
    rate beyond ``max_rate`` (rad/s or m/s), or steps so small (pressed against an assembly
    limit, at the round-off of the time, or a stiff equation for an explicit method) that the rest
    of the run would take more than ``max_steps``."""
    name = scene.name
    args = Arguments("simulate", scene=name, error=DynamicsArgumentError)
    t_end = args.number("t_end", t_end, low=0.0, low_open=True, unit="s")
    rtol, atol, method = _checked(args, rtol=rtol, atol=atol, method=method)
    on_singular = args.choice("on_singular", on_singular, ("raise", "stop"))
    dt = args.number("dt", dt, low=0.0, low_open=True, unit="s", none=True)
    until_phi = args.number("until_phi", until_phi, none=True)
    events = args.functions("events", events)
    max_step = args.number("max_step", max_step, low=0.0, low_open=True, unit="s", infinite=True)
    step = args.number("step", step, low=0.0, low_open=True, unit="s", none=True)
    if method == "RK4" and step is None:
        args.fail("step", step, "must be given with method 'RK4': the fixed step, a positive number of seconds")
    model = reduced_model(scene)
    k = model.k
    q0 = _start(scene) if phi0 is None else _initial(args, phi0, k, "phi0")
    w0 = _initial(args, omega0, k, "omega0")
    fn, kind = make_drive(drive, scene.inputs, model.motors, scene=name)
    friction = model.friction is not None
    if friction and method not in OWN_METHODS:
        args.fail("method", method, "must be 'DOP853' or 'RK4' for a scene with friction (its switches are segment "
                  "ends of the own step loop)")
    eq: Equation
    if friction:
        eq = FrictionEquation(model, fn) if k == 1 else MultiFrictionEquation(model, fn)
    else:
        eq = Equation(model, fn)
    y0 = np.array([*q0, *w0, 0.0, 0.0, *((0.0,) if friction else ())])
    try:
        eq.accelerations(0.0, q0, w0)
    except AssemblyError as exc:
        raise DynamicsError(f"cannot be assembled at the initial state ({exc.reason})", scene=name, time=0.0,
                            at=_where(scene, y0), group=exc.group) from None
    guard = RunGuard(eq, t_end=float(t_end), max_steps=max_steps, max_rate=max_rate, stiff=method != "Radau",
                     limit_text=lambda fault: _limit_message(scene, fault, "pressed against it"))
    if guard.runaway(y0) is not None:
        raise DynamicsError(f"omega0 is beyond max_rate = {max_rate:g}", scene=name, time=0.0,
                            at=f"{_where(scene, y0)}, {rates_text(scene, y0)}")

    def toggle(t: float, y: np.ndarray) -> float:
        return eq.conditioning(t, y) - DYNAMICS_TOGGLE

    toggle.terminal = True  # type: ignore[attr-defined]
    all_events: list[Any] = [toggle]
    strokes = _stroke_events(scene)
    all_events += [*strokes, guard.rate_event(), guard.step_event()]
    if until_phi is not None:
        if k != 1:
            raise DynamicsError("until_phi is for one input; pass events=[f(t, q, qd)] with several", scene=name)
        target = until_phi

        def reach(t: float, y: np.ndarray) -> float:
            return float(y[0]) - target

        reach.terminal = True  # type: ignore[attr-defined]
        all_events.append(reach)
    for f in events:
        def user(t: float, y: np.ndarray, f: Callable[..., float] = f) -> float:
            return float(f(t, y[0] if k == 1 else y[:k], y[1] if k == 1 else y[k:2 * k]))

        user.terminal = True  # type: ignore[attr-defined]
        all_events.append(user)
    t_eval = None
    if dt is not None:
        t_eval = np.append(np.arange(0.0, t_end, dt), t_end)
        if t_eval.size > 1 and t_eval[-2] >= t_end:
            t_eval = t_eval[:-1]
    messages: list[str] = []
    switches: list[tuple[str, float, float]] = []
    switch_inputs: list[str] = []
    if method in OWN_METHODS:
        own_events = [(ev, int(getattr(ev, "direction", 0))) for ev in all_events]
        out: Outcome
        if isinstance(eq, FrictionEquation):
            out = run_with_friction(eq, float(t_end), y0.tolist(), method=method, rtol=rtol, atol=atol, step=step,
                                    max_step=max_step, events=own_events, t_eval=t_eval,
                                    time_dependent=kind == "function")
            messages, switches = out.messages, out.switches
            switch_inputs = [scene.inputs[0]] * len(switches)
        elif isinstance(eq, MultiFrictionEquation):
            out = run_with_friction_multi(eq, float(t_end), y0.tolist(), method=method, rtol=rtol, atol=atol,
                                          step=step, max_step=max_step, events=own_events, t_eval=t_eval,
                                          time_dependent=kind == "function")
            messages, switches, switch_inputs = out.messages, out.switches, out.inputs
        else:
            out = run(eq, float(t_end), y0.tolist(), method=method, rtol=rtol, atol=atol, step=step,
                      max_step=max_step, events=own_events, t_eval=t_eval)
        ts, ys, sol_status, hit, dense, nfev = out.t, out.y, out.status, out.hit, out.sol, out.nfev
        known = out.rates
        if out.fault is not None and eq.fault is None:  # (the trial state's own, where a stage could not be assembled)
            eq.fault = out.fault
        last = dense.t_max
    else:
        sol = solve_ivp(eq, (0.0, float(t_end)), y0, method=method, rtol=rtol, atol=atol, dense_output=True,
                        events=all_events, t_eval=t_eval, max_step=max_step)
        ts, ys, sol_status, dense, nfev = sol.t, sol.y, sol.status, sol.sol, sol.nfev
        hit = None
        known = None
        if sol.status == 1:  # an event
            hit = next(i for i, te in enumerate(sol.t_events) if len(te))
            te, ye = sol.t_events[hit][0], sol.y_events[hit][0]
            if ts.size == 0 or ts[-1] < te:
                ts, ys = np.append(ts, te), np.column_stack([ys, ye])
        last = sol.sol.t_max if sol.sol is not None else ts[-1]
    status, message = "done", ""
    if sol_status == 1:  # an event
        ye = ys[:, -1]
        assert hit is not None
        if hit == 0:
            status = "toggle"
            message = (f"reaches a singular position of group '{eq.worst_group(ye)}' (a toggle: the inputs cannot "
                       f"drive through it, the reduced inertia grows without bound)")
        elif hit <= len(strokes):
            status = "assembly"
            message = strokes[hit - 1].message(ye)  # type: ignore[attr-defined]
        elif hit <= len(strokes) + 2:
            status = "runaway" if hit == len(strokes) + 1 else guard.kind
            message = guard.runaway_text() if status == "runaway" else guard.reason or ""
        else:
            status = "until"
    elif sol_status == -1:
        status = "assembly"
        message = _limit_message(scene, eq.fault, "the step size fell below the spacing of floats")
        if ts.size and last > ts[-1]:  # the last accepted step, past the last requested sample
            ts, ys = np.append(ts, last), np.column_stack([ys, dense(last)])
            known = None
    traj = _trajectory(scene, eq, ts, ys, dense, status=status, message=message, kind=kind, method=method,
                       rtol=rtol, atol=atol, nfev=nfev, known=known)
    traj.messages, traj.switches, traj.switch_inputs = messages, switches, switch_inputs
    if status in ("toggle", "assembly", "runaway", "steps"):
        at = _where(scene, ys[:, -1])
        if status in ("runaway", "steps"):
            at += f", {rates_text(scene, ys[:, -1])}"
        text = DynamicsError(message, scene=name, time=float(ts[-1]), at=at, group=None)
        traj.message = str(text)
        if on_singular == "raise":
            text.trajectory = traj  # type: ignore[attr-defined]
            raise text
    return traj


def _trajectory(
    scene: Any, eq: Equation, ts: np.ndarray, ys: np.ndarray, dense: Any, *, status: str, message: str, kind: str,
    method: str, rtol: float, atol: float, nfev: int, known: Sequence[Any] | None = None,
) -> Trajectory:
    """The run's samples; ``known``: per sample, y' where the integrator evaluated it (q̈ read
    from it, the drive's effort alone evaluated anew), or None."""
    k = eq.k
    n = ts.size
    eps = np.empty((n, k))
    eff = np.empty((n, k))
    known = known if known is not None and len(known) == n else [None] * n
    for i in range(n):
        q = [float(v) for v in ys[:k, i]]
        qd = [float(v) for v in ys[k:2 * k, i]]
        rates = known[i]
        if rates is not None and all(map(math.isfinite, rates[k:2 * k])):
            eps[i], eff[i] = rates[k:2 * k], list(eq.drive(float(ts[i]), q, qd))
            continue
        try:
            qdd, qdrive, _ = eq.accelerations(float(ts[i]), q, qd)
        except AssemblyError:
            qdd, qdrive = [math.nan] * k, [math.nan] * k
        eps[i], eff[i] = qdd, qdrive

    def shape(a: np.ndarray) -> np.ndarray:
        return a[:, 0].copy() if k == 1 else a

    return Trajectory(
        scene=scene, t=ts, phi=shape(ys[:k].T), omega=shape(ys[k:2 * k].T), epsilon=shape(eps), effort=shape(eff),
        work_drive=ys[2 * k].copy(), work_other=ys[2 * k + 1].copy(),
        work_friction=ys[2 * k + 2].copy() if ys.shape[0] > 2 * k + 2 else None, status=status, message=message,
        drive=kind, method=method, rtol=rtol, atol=atol, evaluations=nfev, _dense=dense,
    )
