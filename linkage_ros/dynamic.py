"""mechanism_node's dynamic mode: the inputs' time law from the equation of motion (issue 22).

In ``mode: dynamic`` (docs/ros.md, "Dynamic mode") the node does not prescribe φ(t): each tick
asks a :class:`DynamicMotion` (one input) or :class:`DynamicMotions` (several) for the input state
at the tick's run time, and that law advances the scene's forward dynamics
(:class:`solver.dynamics.Stepper` with RK4 at a fixed step landing on every tick, breakpoint to
breakpoint across a table's kinks; the step is chosen from ``dynamics_tolerance`` for the
``rate_hz`` at the start by :func:`solver.dynamics.fixed_step`: at most 16 steps a tick, and
only as many as fit in 15 % of a tick on this machine) from
``phi0`` / ``omega`` (``input_phi0s`` / ``input_omegas``). The
laws have the interface of :class:`~linkage_ros.motion.Motion` / :class:`~linkage_ros.motion.Motions`,
so the engine, the fast path, the messages and the recorder are those of the kinematic mode: a
tick publishes (φ, ω, ε) with ε = M⁻¹(Q_drive − h) from the equation of motion, and the efforts
on ``joint_states`` are the kinetostatics of that state, M·ε + h — the drive's effort, to
round-off.

What drives the inputs (``drive``): ``motor`` (the scene's ``motor:`` characteristic), ``effort``
(the last command on ``effort_commands``, one value per input, zero before the first and from
``effort_timeout`` seconds after the last), ``free`` (nothing), ``auto`` (the motor when the scene
has one, else the effort commands). A command of the wrong length, with a non-finite value, or
while the drive is not ``effort`` is refused (:meth:`DynamicMotion.command` gives the one-line
reason) and the last good command stays in force.

The law keeps count of the wall time its ticks take against the run time they advance: over each
second of run time, the real-time factor (run time / wall time computing it) and the share of the
ticks it was asked for (against ``rate_hz``). Below 1 or under 99 % it says so — once in the
node's log (``events``) and, while it lasts, in the frames' status ``behind`` (diagnostics WARN,
with the factor): it never falls behind silently. A command's ``effort_timeout`` is enforced at
its exact run time, whatever the ticks do (a late tick first advances to the moment the command
went stale, then on with zero).

Where the motion reaches a position the inputs cannot drive through (a toggle, an assembly
limit: :class:`solver.DynamicsError`) the law holds the last state it reached (φ frozen, ω = ε =
0): its segment is a hold, so the engine reports ``unassemblable`` with the error's message (the
time, the angle, the group) until a set of ``omega`` (any of
:data:`~linkage_ros.runtime.RESUMING`) or a new effort command restarts it from there.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from solver.dynamics import Stepper, fixed_step, reduced_model
from solver.errors import SolverError

from .motion import SEGMENT_HOLD, Motion, Motions, Segment

__all__ = [
    "DEFAULT_EFFORT_TIMEOUT",
    "DEFAULT_TOLERANCE",
    "DRIVES",
    "DynamicMotion",
    "DynamicMotions",
    "EFFORT_TIMEOUT_RANGE",
    "INTERRUPT",
    "MODES",
    "MODE_DYNAMIC",
    "RESTARTING",
    "SEGMENT_DYNAMICS",
    "TOLERANCE_RANGE",
    "drive_kind",
    "drive_reason",
    "dynamic_law",
    "mode_reason",
]

MODE_KINEMATIC, MODE_DYNAMIC = "kinematic", "dynamic"
#: Accepted values of ``mode`` and ``drive``.
MODES = (MODE_KINEMATIC, MODE_DYNAMIC)
DRIVES = ("auto", "motor", "effort", "free")
#: ``effort_timeout`` (s): a command older than this counts as zero; its default and range.
DEFAULT_EFFORT_TIMEOUT = 0.5
EFFORT_TIMEOUT_RANGE = (1.0e-3, 3600.0)
#: ``dynamics_tolerance``: the integrator's rtol = atol; its default and range.
DEFAULT_TOLERANCE = 1.0e-9
TOLERANCE_RANGE = (1.0e-13, 1.0e-3)
#: The run time (s) over which the law measures its real-time factor and the ticks it was asked for.
REALTIME_WINDOW = 1.0
#: Below this share of ``rate_hz`` ticks in a window the law says it falls behind.
TICKS_WANTED = 0.99
#: The share of a tick's period the law's steps may take (solver.dynamics.fixed_step's budget:
#: more steps a tick only while they fit, the tolerance second to real time). 15 %: with the
#: kinematic tick, the message build and the executor's publishing (≈ 0.25 ms at 1 kHz on the
#: project's machine), a node at 1 kHz stays under half a core, room for the jitter of a shared
#: machine (issue 32: at 25 % the calibration took 4–8 steps a tick, and the node 72–99 % of a
#: core, 84–98 % of the ticks).
TICK_BUDGET = 0.15
#: A tick advances the law by at most this many periods; a longer gap slips (the law falls
#: behind the clock instead of taking ever longer ticks to catch up with it).
MAX_GAP_TICKS = 20
#: Parameters whose change restarts a dynamic run at ``phi0`` (as ``scene`` does).
RESTARTING = frozenset({"mode", "dynamics_tolerance"})
#: The tag of a dynamic law's segment while it moves (a hold is SEGMENT_HOLD).
SEGMENT_DYNAMICS = "dynamics"
#: Set by the node on SIGINT / SIGTERM: a law's advance in progress ends between two steps (the
#: law holds, the tick is published and the recording finished), however long the tick would be.
INTERRUPT = threading.Event()


def drive_kind(scene: Any, drive: str) -> str:
    """What drives the inputs for the ``drive`` parameter: ``motor``, ``effort`` or ``free``
    (``auto``: the motor when the scene has one, else the effort commands). ValueError for
    ``motor`` on a scene without one."""
    motors = reduced_model(scene).motors
    if drive == "auto":
        return "motor" if motors else "effort"
    if drive == "motor" and not motors:
        raise ValueError(f"drive motor: scene '{scene.name}' has no 'motor:' (docs/dynamics.md); "
                         "use drive effort or free")
    return drive


def drive_reason(scene: Any, drive: str) -> str | None:
    """Why ``drive`` cannot drive ``scene`` (one line), or None."""
    try:
        drive_kind(scene, drive)
    except (ValueError, SolverError) as error:
        return str(error)
    return None


def mode_reason(settings: Mapping[str, Any]) -> str | None:
    """Why the settings' ``mode`` does not go with the rest (one line), or None."""
    if settings.get("mode") == MODE_DYNAMIC and settings.get("input_source") == "topic":
        return ("mode dynamic computes the input from the equation of motion: it needs input_source clock, "
                "not topic")
    return None


class _DynamicLaw:
    """The state and the tick of a dynamic law (one or several inputs); see the module docstring.

    Values are Python floats with one input and k-tuples with several (``self._pack``)."""

    def _setup(self, scene: Any, *, phi0: Any, omega: Any, drive: str, tolerance: float,
               timeout: float, t0: float, rate: float = 1000.0) -> None:
        self.scene = scene
        self.k = len(scene.inputs)
        #: what drives the inputs now: motor, effort or free
        self.kind = drive_kind(scene, drive)
        self.timeout = float(timeout)
        self.tolerance = float(tolerance)
        #: the effort command in force (zeros before the first and after a timeout)
        self.efforts: tuple[float, ...] = (0.0,) * self.k
        self._command_t: float | None = None
        #: messages for the node's log (a command timed out), taken by the runtime
        self.events: list[str] = []
        #: why the law holds (the DynamicsError's message), "" while it moves
        self.stop_message = ""
        self._held = False
        #: the drive's effort at the last state (a float, or a k-tuple), and that state (φ, ω, ε)
        self.effort: Any = 0.0
        self._state: tuple[Any, Any, Any] = (0.0, 0.0, 0.0)
        self.rate = float(rate)
        #: the RK4 step (s) and its error over 50 ticks in units of the tolerance (solver.dynamics.fixed_step)
        self.step, self.step_error = fixed_step(scene, period=1.0 / self.rate, tolerance=self.tolerance, phi0=phi0,
                                                omega0=omega, drive=self._drive(), budget=TICK_BUDGET / self.rate)
        self._stepper = self._new_stepper(phi0, omega, float(t0))
        #: run time over wall time of the last full window (inf before the first); "" or why it is behind
        self.realtime_factor = math.inf
        #: the share of the ``rate_hz`` ticks the node asked for over the last full window (nan
        #: before the first): its own count of ticks skipped, beside what a subscriber receives
        self.tick_share = math.nan
        self.behind = ""
        self._window = (float(t0), 0.0, 0)  # (run time at its start, wall seconds spent, ticks)
        self._counted = float(t0)  # the run time of the last tick counted
        #: the law's own time is the run time less ``_offset``: the time it let slip where a tick
        #: found it more than MAX_GAP_TICKS ticks behind (it never catches up by ever longer ticks)
        self._offset = 0.0
        self._max_gap = MAX_GAP_TICKS / self.rate
        self._command_wall: float | None = None  # the run time of the command in force
        self._t = float(t0)
        self._read()
        phi, w, e = self._state
        self._origin = Segment(float(t0), phi, w, e, SEGMENT_DYNAMICS)  # type: ignore[arg-type]

    # ------------------------------------------------------------------ the tick
    def state(self, t: float) -> Any:
        """(φ, ω, ε) at run time ``t``: the dynamics advanced to ``t`` (a time before the last
        one asked for gives the last state: the run cannot go back)."""
        if not self._held and t > self._t + self._offset:
            start = time.perf_counter()
            law = self._law_time(t)
            self._expire(law, t)
            self._advance(law)
            self._count(t, time.perf_counter() - start)
            self._counted = t
        elif self._held and t > self._counted:  # a hold's ticks count too (tick_share), at no cost
            self._count(t, 0.0)
            self._counted = t
        return self._state

    def _law_time(self, t: float) -> float:
        """The law's time for run time ``t``; where that is more than MAX_GAP_TICKS ticks ahead of
        the law, the rest slips (``_offset``): the law falls behind, it does not spiral."""
        law = t - self._offset
        if law - self._t > self._max_gap:
            self._offset += law - self._t - self._max_gap
            law = self._t + self._max_gap
        return law

    def _count(self, t: float, spent: float) -> None:
        """One tick's wall time into the window; at its end, the real-time factor and the ticks."""
        t_start, busy, ticks = self._window
        busy, ticks = busy + spent, ticks + 1
        span = t - t_start
        if span < REALTIME_WINDOW:
            self._window = (t_start, busy, ticks)
            return
        self._window = (t, 0.0, 0)
        self.realtime_factor = span / busy if busy > 0 else math.inf
        share = self.tick_share = ticks / (span * self.rate)
        if self.realtime_factor < 1.0 or share < TICKS_WANTED:
            factor = f"{self.realtime_factor:.2f}× real time, " if math.isfinite(self.realtime_factor) else ""
            behind = (f"dynamics fall behind real time: {factor}{100 * share:.1f} % "
                      f"of the {self.rate:g} Hz ticks over the last {span:.2f} s")
            if not self.behind:
                self.events.append(behind)
            self.behind = behind
        else:
            self.behind = ""

    def moving_state(self, t: float) -> Any:
        """:meth:`state`, or None while the law holds."""
        state = self.state(t)
        return None if self._held else state

    def segment_at(self, t: float) -> Segment:
        """The state of the last tick as a segment: a hold while the law holds."""
        phi, w, e = self._state
        return Segment(self._t, phi, w, e, SEGMENT_HOLD if self._held else SEGMENT_DYNAMICS)  # type: ignore[arg-type]

    @property
    def segments(self) -> tuple[Segment, ...]:
        """The start (what the engine reads its first frame from)."""
        return (self._origin,)

    def states(self, t: ArrayLike) -> Any:
        """The sweep the engine draws the paths over: φ0 + ω0·(t − t0), not the dynamics (which
        only move forward, tick by tick)."""
        start = self._origin
        dt = np.asarray(t, dtype=np.float64) - start.t0
        if self.k == 1:
            return start.phi0 + start.omega0 * dt, np.full(dt.shape, start.omega0), np.zeros(dt.shape)
        phi0, w0 = np.asarray(start.phi0), np.asarray(start.omega0)
        phi = phi0 + w0 * dt[..., None]
        return phi, np.broadcast_to(w0, phi.shape).copy(), np.zeros(phi.shape)

    def crossing(self, phi: float, t_lo: float, t_hi: float) -> float | None:
        return None

    # ------------------------------------------------------------------ changes
    def command(self, values: Sequence[float], t: float) -> str | None:
        """An effort command (one value per input) from run time ``t`` on; the reason it is
        refused (one line; the last good command stays in force), or None."""
        values = list(values)
        names = ", ".join(self.scene.inputs)
        if self.kind != "effort":
            return (f"effort command ignored: the drive is {self.kind}, not effort commands "
                    "(set drive to effort or auto)")
        if len(values) != self.k:
            return (f"effort command rejected: {len(values)} value(s) for {self.k} input(s) ({names}); "
                    f"keeping {list(self.efforts)}")
        if not all(isinstance(v, (int, float)) and math.isfinite(v) for v in values):
            return f"effort command rejected: non-finite value(s) {values}; keeping {list(self.efforts)}"
        wall, t = t, t - self._offset
        if self._held:
            self._resume(self._state[0], (0.0,) * self.k, max(t, self._t))
        elif t > self._t:
            t = self._law_time(wall)
            self._expire(t, wall)
            self._advance(t)
        self.efforts = tuple(float(v) for v in values)
        self._command_t, self._command_wall = max(t, self._t), wall
        self._restart_drive()
        return None

    def set_kind(self, drive: str) -> None:
        """Another ``drive`` from the last state on (checked beforehand: :func:`drive_reason`)."""
        self.kind = drive_kind(self.scene, drive)
        self._restart_drive()

    def set_omega(self, t: float, omega: Any, *, epsilon: Any = None) -> Segment:
        """From ``t`` on, the inputs' rates ``omega`` at the angle reached (φ continuous; a
        held law resumes there). ``epsilon`` is not used: the equation of motion gives it."""
        phi = self._state[0] if self._held else self.state(t)[0]
        self._resume(phi, omega, max(t - self._offset, self._t))
        return self.segment_at(t)

    def set_epsilon(self, t: float, epsilon: Any) -> Segment:
        """Nothing: ε follows from the equation of motion."""
        return self.segment_at(t)

    def hold(self, t: float) -> Segment:
        """Hold the last state (the engine's policy where a solve fails)."""
        self._freeze("")
        return self.segment_at(t)

    def reverse(self, t: float) -> Segment:
        """A dynamic law cannot be reversed: it holds (``on_unassemblable`` has no effect)."""
        return self.hold(t)

    def snapshot(self) -> Any:
        return None

    def restore(self, segments: Any) -> None:
        """Nothing to restore: the dynamics only move forward."""

    # ------------------------------------------------------------------ helpers
    def _drive(self) -> Any:
        if self.kind == "motor":
            return "motor"
        if self.kind == "effort":
            return list(self.efforts)
        return "free"

    def _restart_drive(self) -> None:
        self._stepper.set_drive(self._drive())
        self._read()

    def _expire(self, t: float, wall: float | None = None) -> None:
        """A command older than ``timeout`` at law time ``t`` (or at run time ``wall``, the node's
        clock, where the law let time slip): zero from the moment it went stale."""
        since = self._command_t
        if since is None or self.kind != "effort":
            return
        late = wall is not None and self._command_wall is not None and wall > self._command_wall + self.timeout
        if t <= since + self.timeout and not late:
            return
        stale = min(since + self.timeout, t)
        if stale > self._t:
            self._advance(stale)
            if self._held:
                return
        self.efforts = (0.0,) * self.k
        self._command_t = None
        self._restart_drive()
        self.events.append(f"effort command timed out ({self.timeout:g} s without one): efforts set to zero")

    def _advance(self, t: float) -> None:
        try:
            self._stepper.advance(t)
        except SolverError as error:  # DynamicsError: a toggle or an assembly limit on the way
            self._freeze(f"{error}; holding the last state")
            return
        self._t = t
        self._read()

    def _read(self) -> None:
        """The stepper's last state as (φ, ω, ε) and the drive's effort."""
        stepper = self._stepper
        y = stepper.y.tolist()
        k = self.k
        try:
            qdd, qdrive = stepper.accelerations()
        except SolverError as error:  # pragma: no cover - the stepper's state was assembled
            self._freeze(f"{error}; holding the last state")
            return
        if k == 1:
            self.effort = qdrive[0]
            self._state = (y[0], y[1], qdd[0])
        else:
            self.effort = tuple(qdrive)
            self._state = (tuple(y[:k]), tuple(y[k:2 * k]), tuple(float(v) for v in qdd))

    def _freeze(self, message: str) -> None:
        self._held = True
        self.stop_message = message
        phi = self._state[0]
        zero = self._pack((0.0,) * self.k)
        self._state = (phi, zero, zero)
        self.effort = zero

    def _new_stepper(self, phi0: Any, omega0: Any, t0: float) -> Stepper:
        return Stepper(self.scene, phi0=phi0, omega0=omega0, drive=self._drive(), method="RK4", step=self.step,
                       t0=t0, works=False, interrupted=INTERRUPT.is_set)

    def _resume(self, phi: Any, omega: Any, t: float) -> None:
        phis = [phi] if self.k == 1 else list(phi)
        rates = [float(omega)] * self.k if isinstance(omega, (int, float)) else [float(w) for w in omega]
        self._stepper = self._new_stepper(phis if self.k > 1 else phis[0], rates if self.k > 1 else rates[0], t)
        self._held, self.stop_message, self._t = False, "", t
        self._window = (t, 0.0, 0)
        self._read()

    def _pack(self, values: Any) -> Any:
        if self.k == 1:
            return float(values[0])
        return tuple(float(v) for v in values)

    def take_events(self) -> list[str]:
        events, self.events = self.events, []
        return events


class DynamicMotion(_DynamicLaw, Motion):
    """The dynamic law of a scene with one input (the interface of :class:`Motion`; floats)."""

    def __init__(self, scene: Any, *, phi0: float = 0.0, omega: float = 0.0, drive: str = "auto",
                 tolerance: float = DEFAULT_TOLERANCE, timeout: float = DEFAULT_EFFORT_TIMEOUT,
                 t0: float = 0.0, rate: float = 1000.0) -> None:
        self._setup(scene, phi0=phi0, omega=omega, drive=drive, tolerance=tolerance, timeout=timeout, t0=t0,
                    rate=rate)

    def __repr__(self) -> str:
        return f"DynamicMotion({self.scene.name}, drive {self.kind}, t = {self._t:g} s, state {self._state})"


class DynamicMotions(_DynamicLaw, Motions):
    """The dynamic law of a scene with several inputs (the interface of :class:`Motions`; k-tuples)."""

    def __init__(self, scene: Any, *, phi0: Sequence[float], omega: Sequence[float], drive: str = "auto",
                 tolerance: float = DEFAULT_TOLERANCE, timeout: float = DEFAULT_EFFORT_TIMEOUT,
                 t0: float = 0.0, rate: float = 1000.0) -> None:
        self._setup(scene, phi0=list(phi0), omega=list(omega), drive=drive, tolerance=tolerance,
                    timeout=timeout, t0=t0, rate=rate)

    def __len__(self) -> int:
        return self.k

    def start(self) -> tuple[float, tuple[float, ...], tuple[float, ...], tuple[float, ...]]:
        s = self._origin
        return s.t0, s.phi0, s.omega0, s.epsilon  # type: ignore[return-value]

    def __repr__(self) -> str:
        return f"DynamicMotions({self.scene.name}, drive {self.kind}, t = {self._t:g} s, state {self._state})"


def dynamic_law(scene: Any, settings: Mapping[str, Any], *, phi0: Any, omega: Any,
                t0: float) -> DynamicMotion | DynamicMotions:
    """The node's dynamic law for ``scene`` from its settings (``drive``, ``effort_timeout``,
    ``dynamics_tolerance``) and the initial state; :class:`solver.SolverError` (e.g. a scene
    without inertia) or ValueError (``drive: motor`` without a motor) when there is none."""
    options = {"drive": str(settings.get("drive", "auto")),
               "tolerance": float(settings.get("dynamics_tolerance", DEFAULT_TOLERANCE)),
               "timeout": float(settings.get("effort_timeout", DEFAULT_EFFORT_TIMEOUT)), "t0": t0,
               "rate": float(settings.get("rate_hz", 1000.0))}
    if len(scene.inputs) == 1:
        return DynamicMotion(scene, phi0=float(phi0), omega=float(omega), **options)  # type: ignore[arg-type]
    return DynamicMotions(scene, phi0=tuple(phi0), omega=tuple(omega), **options)  # type: ignore[arg-type]
