"""``linkage-run SCENE --dynamics`` (issue 22): the run's input law from the equation of motion.

The scene's forward dynamics are integrated once, sampled at the run's ticks
(:meth:`solver.Scene.simulate` with ``dt = 1/rate``: DOP853, dense output); :class:`TrajectoryLaw`
hands its samples to the engine as a time law, so the recording, the rerun view and the summary
are those of a kinematic run (:func:`~linkage_ros.record.run.run_standalone`), plus the energy
plots (:mod:`.energy`) and the lines of :func:`dynamics_lines`. Where the motion reaches a toggle
or an assembly limit the run ends there (the message says when, where and which group).

The summary (:func:`dynamics_lines`): the drive, the run-up time from rest (a motor on one input:
:func:`solver.dynamics.run_up`, to the band of the steady cycle), the inputs' mean / min / max ω
over the run and δ = (ω_max − ω_min)/ω_mean over the last full cycle of the load
(:func:`solver.dynamics.machine.cycle_of`: a turn, or 720° for a four-stroke engine), the drive's
peak effort and power, and the energy balance's largest error.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..motion import Motion, Motions, Segment

__all__ = ["DEFAULT_DURATION", "TrajectoryLaw", "TrajectoryLaws", "dynamics_lines", "parse_drive", "simulate_ticks"]

#: Seconds simulated when ``--duration`` is not given.
DEFAULT_DURATION = 5.0
SEGMENT_DYNAMICS = "dynamics"
#: A tick time and a sample time this close (s, relative to 1 + t) are the same instant.
_SAME_TIME = 1e-9


def parse_drive(text: str | None, inputs: Sequence[str]) -> Any:
    """``--drive``: None (the scene's motor, else free), ``free``, ``motor``, a number (N·m or N)
    or, with several inputs, one number per input separated by commas. ValueError: one line."""
    if text is None or text in ("free", "motor"):
        return text
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise ValueError(f"--drive {text!r}: give free, motor, an effort (N·m) or one per input "
                         f"({', '.join(inputs)}) separated by commas") from None
    if not all(math.isfinite(v) for v in values) or len(values) not in (1, len(inputs)):
        raise ValueError(f"--drive {text!r}: give one finite effort, or {len(inputs)} (one per input: "
                         f"{', '.join(inputs)})")
    return values[0] if len(values) == 1 else values


def simulate_ticks(scene: Any, *, duration: float, rate: float, phi0: Any, omega0: Any, drive: Any,
                   tolerance: float = 1e-9) -> Any:
    """The scene's forward dynamics sampled at every tick ``k / rate`` up to ``duration`` (ending
    early at a toggle or an assembly limit: ``status``, ``message``)."""
    return scene.simulate(duration, phi0=phi0, omega0=omega0, drive=drive, rtol=tolerance, atol=tolerance,
                          dt=1.0 / rate, on_singular="stop")


class _Samples:
    """The law of a :class:`solver.dynamics.Trajectory` at its sample times."""

    def _setup(self, trajectory: Any) -> None:
        self.trajectory = trajectory
        self.k = len(trajectory.scene.inputs)
        t = trajectory.t
        phi, omega, epsilon = (self._row(a, 0) for a in (trajectory.phi, trajectory.omega, trajectory.epsilon))
        self._origin = Segment(float(t[0]), phi, omega, epsilon, SEGMENT_DYNAMICS)

    def _row(self, values: Any, i: int) -> Any:
        row = values[i]
        return float(row) if self.k == 1 else tuple(float(v) for v in row)

    def _index(self, times: ArrayLike) -> np.ndarray | None:
        """The sample of each time, or None when one of them is not a sample."""
        t = self.trajectory.t
        times = np.asarray(times, dtype=np.float64).reshape(-1)
        i = np.clip(np.searchsorted(t, times), 1, t.size - 1) if t.size > 1 else np.zeros(times.size, int)
        if t.size > 1:
            i = np.where(np.abs(t[i - 1] - times) <= np.abs(t[i] - times), i - 1, i)
        if np.any(np.abs(t[i] - times) > _SAME_TIME * (1.0 + np.abs(times))):
            return None
        return i  # type: ignore[no-any-return]

    def states(self, t: ArrayLike) -> Any:
        """The samples at the run's ticks; elsewhere (the engine's sweep for the drawn paths, with
        several inputs) φ and ω from the dense output within the run and ε = 0."""
        i = self._index(t)
        tr = self.trajectory
        if i is not None:
            return tr.phi[i], tr.omega[i], tr.epsilon[i]
        times = np.clip(np.asarray(t, dtype=np.float64), tr.t[0], tr.t[-1])
        phi, omega = tr.at(times)
        return phi, omega, np.zeros_like(phi)

    def state(self, t: float) -> Any:
        i = self._index([t])
        if i is None:
            raise ValueError(f"t = {t!r} s is not a tick of the simulated run")
        tr = self.trajectory
        return self._row(tr.phi, int(i[0])), self._row(tr.omega, int(i[0])), self._row(tr.epsilon, int(i[0]))

    def moving_state(self, t: float) -> Any:
        return self.state(t)

    def segment_at(self, t: float) -> Segment:
        return self._origin

    @property
    def segments(self) -> tuple[Segment, ...]:
        return (self._origin,)

    def crossing(self, phi: float, t_lo: float, t_hi: float) -> float | None:
        return None

    def hold(self, t: float) -> Segment:
        """Nothing to hold: the trajectory ends where the dynamics stop."""
        return self._origin

    def reverse(self, t: float) -> Segment:
        return self._origin

    def snapshot(self) -> Any:
        return None

    def restore(self, segments: Any) -> None:
        """Nothing: the trajectory is fixed."""


class TrajectoryLaw(_Samples, Motion):
    """A one-input trajectory as the engine's time law (the interface of :class:`Motion`)."""

    def __init__(self, trajectory: Any) -> None:
        self._setup(trajectory)


class TrajectoryLaws(_Samples, Motions):
    """A several-input trajectory as the engine's time law (the interface of :class:`Motions`)."""

    def __init__(self, trajectory: Any) -> None:
        self._setup(trajectory)

    def __len__(self) -> int:
        return self.k

    def start(self) -> tuple[float, tuple[float, ...], tuple[float, ...], tuple[float, ...]]:
        s = self._origin
        return s.t0, s.phi0, s.omega0, s.epsilon  # type: ignore[return-value]


def law_of(trajectory: Any) -> TrajectoryLaw | TrajectoryLaws:
    """The engine's time law of ``trajectory``."""
    return TrajectoryLaw(trajectory) if len(trajectory.scene.inputs) == 1 else TrajectoryLaws(trajectory)


def _input_units(scene: Any, joint: str) -> tuple[str, str, str, str]:
    """(effort's name, its unit, the coordinate's unit, the rate's unit) of an input: a torque in
    N·m of an angle (rad, rad/s), a force in N of an actuator's stroke (m, m/s)."""
    if scene.joint_units.get(joint, "rad") == "m":
        return "force", "N", "m", "m/s"
    return "torque", "N·m", "rad", "rad/s"


def _drive_text(scene: Any, trajectory: Any) -> str:
    if trajectory.drive == "motor":
        from solver.dynamics import reduced_model

        motors = reduced_model(scene).motors
        parts = []
        for q, m in motors.items():
            effort, unit, _, rate = _input_units(scene, q)
            if m.linear:
                parts.append(f"{q}: stall {effort} {m.stall:g} {unit}, no-load speed {m.no_load:g} {rate}")
            else:
                parts.append(f"{q}: a {effort}–speed table of {len(m.speeds)} entries")
        return "the scene's motor (" + "; ".join(parts) + ")"
    if trajectory.drive == "effort":
        values = np.atleast_1d(trajectory.effort[0])
        shown = [f"{v:g} {_input_units(scene, q)[1]}" for q, v in zip(scene.inputs, values)]
        if len(shown) == 1:
            return f"constant effort {shown[0]}"
        return "constant effort " + ", ".join(f"{q} {v}" for q, v in zip(scene.inputs, shown))
    return "free (the loads alone)"


#: Samples of the dense output over the last cycle for ω's extremes (between the ticks).
CYCLE_SAMPLES = 4001


def _last_cycle(trajectory: Any, cycle: float) -> tuple[float, float, float] | None:
    """(t_start, ω_min, ω_max) over the last full load cycle of a one-input run (|Δφ| = cycle):
    its start found on the integrator's dense output (brentq), ω's extremes on that output too,
    not only at the ticks (a 720° cycle at 200 rad/s spans a handful of 100 Hz ticks)."""
    from scipy.optimize import brentq

    t = np.asarray(trajectory.t, float)
    phi = np.asarray(trajectory.phi, float)
    if t.size < 2 or abs(phi[-1] - phi[0]) < cycle:
        return None
    target = phi[-1] - math.copysign(cycle, phi[-1] - phi[0])
    crossed = np.flatnonzero((phi[:-1] - target) * (phi[1:] - target) <= 0.0)
    if not crossed.size:
        return None
    i = int(crossed[-1])
    t0 = float(brentq(lambda s: float(trajectory.at(s)[0]) - target, t[i], t[i + 1], xtol=1e-15))
    w = trajectory.at(np.linspace(t0, t[-1], CYCLE_SAMPLES))[1]
    return t0, float(np.min(w)), float(np.max(w))


def dynamics_lines(scene: Any, trajectory: Any, *, phi0: Any, run_up: bool = True) -> list[str]:
    """The summary lines of a dynamic run (see the module docstring)."""
    from solver.dynamics import run_up as run_up_of
    from solver.dynamics.machine import cycle_of
    from solver.errors import SolverError

    tr = trajectory
    k = len(scene.inputs)
    lines = [f"dynamics: drive {_drive_text(scene, tr)}; {tr.method}, rtol {tr.rtol:g}, atol {tr.atol:g}, "
             f"{tr.evaluations} evaluations"]
    if tr.status not in ("done", "until"):
        lines.append(f"  stopped: {tr.message}")
    lines += [f"  {line}" for line in getattr(tr, "messages", ())]  # (friction: each stick and slip)
    span = scene.input_ranges[0] if k == 1 else None
    if run_up and tr.drive == "motor" and k == 1 and span is not None:
        lines.append(f"  run-up: does not apply ('{scene.inputs[0]}' is an actuator's stroke [{span[0]:g}, "
                     f"{span[1]:g}] m: no load cycle, so no steady speed to run up to)")
    elif run_up and tr.drive == "motor" and k == 1 and tr.status in ("runaway", "steps"):
        lines.append("  run-up: not sought (the run itself did not end: see above)")
    elif run_up and tr.drive == "motor" and k == 1:
        try:
            ru = run_up_of(scene, phi0=float(phi0))
            lines.append(f"  run-up from rest at φ0: {ru.time:.4g} s to the steady band ω ≥ {ru.steady.omega_min:.6g} "
                         f"rad/s (steady: {ru.steady.method})")
        except SolverError as error:
            lines.append(f"  run-up: none ({getattr(error, 'reason', error)})")
    omega = np.asarray(tr.omega, dtype=float).reshape(tr.t.size, k)
    effort = np.asarray(tr.effort, dtype=float).reshape(tr.t.size, k)
    span = float(tr.t[-1] - tr.t[0])
    lengths = [scene.joint_units.get(q, "rad") == "m" for q in scene.inputs]
    for i, q in enumerate(scene.inputs):
        w = omega[:, i]
        mean = float(np.trapezoid(w, tr.t) / span) if span > 0 else float(w[0])
        rate, unit = ("ṡ", "m/s") if lengths[i] else ("ω", "rad/s")
        lines.append(f"  {q}: {rate} mean {mean:.6g}, min {float(np.min(w)):.6g}, max {float(np.max(w)):.6g} {unit} "
                     f"over the run (time mean)")
    if k == 1 and not lengths[0]:  # (a stroke has no cycle to fluctuate over)
        try:
            cycle = cycle_of(scene)
        except SolverError:
            cycle = 2 * math.pi
        last = _last_cycle(tr, cycle)
        if last is None:
            lines.append(f"  δ: no full cycle ({math.degrees(cycle):.0f}°) of the input in the run")
        else:
            t0, lo, hi = last
            mean = cycle / (float(tr.t[-1]) - t0)
            lines.append(f"  δ = (ω_max − ω_min)/ω_mean = {(hi - lo) / mean:.6g} over the last full "
                         f"{math.degrees(cycle):.0f}° cycle (t = {t0:.6g} … {float(tr.t[-1]):.6g} s, ω_mean {mean:.6g} "
                         "rad/s, on the integrator's dense output)")
    if tr.drive != "free":
        who = "motor" if tr.drive == "motor" else "drive"
        for i, q in enumerate(scene.inputs):
            e, p = effort[:, i], effort[:, i] * omega[:, i]
            je, jp = int(np.argmax(np.abs(e))), int(np.argmax(np.abs(p)))
            unit = "N" if scene.joint_units.get(q, "rad") == "m" else "N·m"
            lines.append(f"  {q}: peak {who} effort {float(e[je]):.6g} {unit} at t = {float(tr.t[je]):.6g} s, "
                         f"peak {who} power {float(p[jp]):.6g} W at t = {float(tr.t[jp]):.6g} s")
    energy = tr.energy()
    kinetic_swing = float(np.ptp(energy["kinetic"]))
    worst = float(np.max(np.abs(energy["balance"])))
    relative = f" ({worst / kinetic_swing:.2g} of the kinetic energy's swing)" if kinetic_swing > 0 else ""
    if "work_friction" in energy:
        lines.append(f"  friction: {-float(energy['work_friction'][-1]):.6g} J dissipated")
        lines.append(f"  energy balance: |T + V − W_drive − W_other − W_friction − its start| ≤ {worst:.3g} J"
                     f"{relative}")
    else:
        lines.append(f"  energy balance: |T + V − W_drive − W_other − its start| ≤ {worst:.3g} J{relative}")
    return lines
