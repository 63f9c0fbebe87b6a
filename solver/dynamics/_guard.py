"""Bounds that end a run of forward dynamics that would not end (docs/dynamics.md, "Runs that end").

An adaptive integrator keeps its local error within the tolerance by shrinking its step, so a
motion it cannot follow does not fail: it crawls. Three such motions are ended here, each with one
line naming the time, the inputs' coordinates and rates, and the cause, and all three limits count
steps and rates, never the wall clock (a run ends at the same place on any machine):

* **a runaway**: a rate beyond :data:`MAX_RATE` (rad/s, or m/s for a stroke) — a drive that
  feeds on the speed, an effort with nothing to balance it. A terminal event on
  ``MAX_RATE − max|q̇ᵢ|``, located like any other.
* **a crawl**: the steps have become so small that the rest of the run would take more than
  ``max_steps`` of them at the mean step of the last :data:`WINDOW` (or the last step, where it
  is larger: steps that grow after a transient) — projected, so it stops after :data:`PATIENCE`
  steps (after one window where trial stages were refused), not at the end of a budget. The
  cause is named: the motion pressing against an assembly limit that it reaches only in the
  limit of ever smaller steps (the trial stages beyond it are refused), or a step at the
  round-off of the time.
* **a stiff equation**: the step is held by the explicit method's stability, not its accuracy —
  a motor or damper much stiffer than the inertia it drives (the decaying eigenvalue λ of
  ∂(q̇, q̈)/∂(q, q̇) with h̄·|λ| ≥ 1) — and more than :data:`STIFF_STEPS` steps remain: the run
  stops and says which time constant, and that ``method="Radau"`` integrates it. (The
  eigenvalues are taken by forward differences of the equation, for the message and this test
  only; nothing the run integrates is differentiated numerically.)

``RunGuard.accept(t, y)`` is called once per accepted step (``simulate`` through a terminal event
of solve_ivp, :class:`~solver.dynamics.Stepper` directly) and returns the reason the run must
stop, or None.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable
from typing import Any

import numpy as np

from ..errors import AssemblyError

__all__ = ["MAX_RATE", "MAX_STEPS", "PATIENCE", "STEPPER_STIFF_STEPS", "STIFF_STEPS", "WINDOW", "RunGuard",
           "rates_text"]

#: A rate beyond this (rad/s; m/s for a stroke) is a runaway: 10⁵ rad/s is ~10⁶ rpm, beyond any
#: machine (a turbocharger turns at ~2·10⁴ rad/s).
MAX_RATE: float = 1e5
#: A run that would need more steps than this to reach its end stops (``max_steps`` of simulate).
#: The engine over 2 s at rtol 1e-13 takes ~9·10³ steps (its smallest mean step over 64 steps is
#: ~2·10⁻⁵ s); 10⁶ steps of DOP853 take several minutes of Python.
MAX_STEPS: int = 1_000_000
#: A stiff run (see the module docstring) stops when more steps than this remain; one advance of
#: a Stepper (a tick of the node) when more than STEPPER_STIFF_STEPS do. A Stepper has no step
#: budget otherwise: a tick that covers a long interval (a node fallen behind) takes the steps it
#: needs, the pathological crawls (pressed, round-off, stiff) end it.
STIFF_STEPS: int = 10_000
STEPPER_STIFF_STEPS: int = 1_000
#: A step within this many units in the last place of the time is at its round-off.
ROUND_OFF_STEPS: int = 1_000
#: The mean step is taken over this many accepted steps, or this few where trial stages beyond an
#: assembly limit were refused (each such step costs several rejected ones: ~0.5 ms per step for
#: the excavator's three inputs).
WINDOW: int = 64
SHORT_WINDOW: int = 8
#: Pressed against an assembly limit: the mean step of a window with refused trial stages below
#: this, relative to max(|t|, 1 s) — the limit is then within ~10⁻¹² s of motion (a creep reaches
#: steps of 10⁻¹⁶ s; the engine's smallest step at rtol 1e-12 is 3·10⁻⁸ s).
PRESSED_STEP: float = 1e-12
#: A crawl is judged after this many steps: a fast transient resolved to the tolerance (an
#: implicit method's first microseconds of a stiff motor: ~1500 steps of ~1e-9 s) takes small
#: steps that grow afterwards.
PATIENCE: int = 2_000
#: The forward-difference step of the stiffness test, relative to a coordinate (and at least this).
_DIFF = 1e-7


def rates_text(scene: Any, y: Any) -> str:
    """The inputs' rates at state ``y`` as text: ``ω = 8 rad/s`` (one input) or ``ω = (1, 2)``."""
    k = len(scene.inputs)
    units = [scene.joint_units.get(j, "rad") for j in scene.inputs]
    parts = [f"{float(y[k + i]):.6g} {'rad' if u == 'rad' else u}/s" for i, u in enumerate(units)]
    return f"ω = {parts[0]}" if k == 1 else f"ω = ({', '.join(parts)})"


class RunGuard:
    """The three bounds of the module docstring for one run (or one advance of a Stepper).

    ``equation``: the run's :class:`~solver.dynamics.Equation`; ``t_end``: where the run ends (its
    projection's horizon; :meth:`aim` moves it); ``max_steps`` (None: no budget, only the
    pathological crawls end the run); ``max_rate``; ``stiff``: whether the stiffness test applies
    (an explicit method), with ``stiff_steps`` steps left at least; ``limit_text``: the run's one
    text for the assembly limit it is pressed against, from the equation's last fault (the same
    text as the stroke's event and the rejected step), else a generic one."""

    def __init__(self, equation: Any, *, t_end: float, max_steps: float | None = MAX_STEPS,
                 max_rate: float = MAX_RATE, stiff: bool = True, stiff_steps: float = STIFF_STEPS,
                 limit_text: Callable[[Any], str] | None = None) -> None:
        self.eq, self.k = equation, equation.k
        self.limit_text = limit_text
        self.t_end, self.max_steps, self.max_rate, self.stiff = float(t_end), max_steps, max_rate, stiff
        self.stiff_steps = stiff_steps
        self.steps = 0
        self._times: deque[float] = deque(maxlen=WINDOW + 1)
        self._faults = 0  # the equation's unassemblable trial stages when the window began
        #: why the run stops (set by :meth:`accept`), and where (t, y)
        self.reason: str | None = None
        #: what stopped it: "runaway", "assembly" (pressed against an assembly limit) or "steps"
        self.kind = ""
        self.where: tuple[float, np.ndarray] | None = None

    def aim(self, t_end: float) -> None:
        """A new horizon (the next tick): the steps are counted from here."""
        self.t_end, self.steps = float(t_end), 0
        last = self._times[-1] if self._times else None
        self._times.clear()
        if last is not None:
            self._times.append(last)

    def rate_event(self) -> Callable[[float, np.ndarray], float]:
        """A terminal event of solve_ivp at max|q̇ᵢ| = max_rate."""
        k, bound = self.k, self.max_rate

        def runaway(t: float, y: Any) -> float:
            return bound - max(abs(float(v)) for v in y[k:2 * k])

        runaway.terminal = True  # type: ignore[attr-defined]
        runaway.plain = True  # type: ignore[attr-defined]  # takes y as a list (the own step loop's)
        runaway.direction = -1  # type: ignore[attr-defined]
        return runaway

    def runaway(self, y: Any) -> str | None:
        """The runaway's reason at state ``y``, or None."""
        k = self.k
        rates = [abs(float(v)) for v in y[k:2 * k]]
        if not all(map(math.isfinite, rates)) or max(rates) > self.max_rate:
            return self.runaway_text()
        return None

    def runaway_text(self) -> str:
        return (f"runs away: a rate reaches {self.max_rate:g} (rad/s or m/s; max_rate) — a drive that grows with "
                "the speed, or an effort that nothing balances")

    def step_event(self) -> Callable[[float, np.ndarray], float]:
        """A terminal event of solve_ivp that is called once per accepted step (solve_ivp evaluates
        every event at each step's end) and changes sign at the step where :meth:`accept` trips."""
        state: dict[str, float] = {}

        def steps(t: float, y: np.ndarray) -> float:
            if "trip" in state:  # the root search on the tripping step: the sign changes at its end
                return 1.0 if t < state["trip"] else -1.0
            if self.accept(t, y) is not None:
                state["trip"] = t
                return -1.0
            return 1.0

        steps.terminal = True  # type: ignore[attr-defined]
        steps.plain = True  # type: ignore[attr-defined]
        steps.direction = -1  # type: ignore[attr-defined]
        return steps

    def accept(self, t: float, y: Any) -> str | None:
        """Record one accepted step ending at (t, y); the reason the run must stop, or None."""
        times = self._times
        if times and t <= times[-1]:
            return self.reason  # the same step end again
        if not times:
            self._faults = self.eq.faults
        times.append(float(t))
        self.steps += 1
        reason = self.runaway(y)
        self.kind = "runaway" if reason is not None else self.kind
        pressed = self.eq.faults > self._faults  # trial stages beyond an assembly limit in this window
        if reason is None and (len(times) > WINDOW or (pressed and len(times) > SHORT_WINDOW)):
            reason = self._crawl(float(t), y)
        if reason is not None and self.reason is None:
            self.reason, self.where = reason, (float(t), np.array(y, dtype=float))
        return self.reason

    def _crawl(self, t: float, y: Any) -> str | None:
        times = self._times
        # the mean step of the window, or its last step where the steps grow (a transient resolved,
        # not a crawl: the projection of its first steps would stop a run that is about to speed up)
        mean = max((times[-1] - times[0]) / (len(times) - 1), times[-1] - times[-2])
        faults, self._faults = self.eq.faults - self._faults, self.eq.faults
        remaining = max(self.t_end - t, 0.0)
        todo = remaining / mean if mean > 0 else math.inf
        times.clear()
        times.append(t)
        if faults and mean <= PRESSED_STEP * max(abs(t), 1.0):
            self.kind = "assembly"
            if self.limit_text is not None:
                return self.limit_text(self.eq.fault)
            group, why = (self.eq.fault or ("?", ""))[:2]
            return (f"stops at an assembly limit of group '{group}' ({why}): pressed against it, the steps beyond it "
                    f"refused, the step has fallen to {mean:.3g} s")
        if mean <= ROUND_OFF_STEPS * math.ulp(max(abs(t), 1.0)):
            self.kind = "steps"
            return f"the step has fallen to the round-off of the time ({mean:.3g} s): the motion cannot go on"
        if self.max_steps is not None and self.steps >= PATIENCE and self.steps + todo > self.max_steps:
            self.kind = "steps"
            return (f"the mean step has fallen to {mean:.3g} s{self._stiffness(t, y, mean)}; the run would need about "
                    f"{self.steps + todo:.3g} steps to reach t = {self.t_end:g} s, more than max_steps = "
                    f"{self.max_steps:g}")
        if self.stiff and todo > self.stiff_steps:
            text = self._stiffness(t, y, mean)
            if text:
                self.kind = "steps"
                return (f"stiff{text}; {todo:.3g} more steps of the explicit method to reach t = {self.t_end:g} s "
                        "— method='Radau' (implicit) integrates it")
        return None

    def _stiffness(self, t: float, y: Any, mean: float) -> str:
        """'' or, where the step is held by stability (h̄·|λ| ≥ 1 for a decaying eigenvalue λ), the
        time constant: ``: the step 5.9e-07 s is held by stability, not accuracy (…)``."""
        rate = self._decay_rate(t, y)
        if rate is None or mean * rate < 1.0:
            return ""
        return (f": the step {mean:.3g} s is held by the integrator's stability, not its accuracy — a decaying "
                f"mode of time constant {1 / rate:.3g} s (a motor or damper much stiffer than the inertia it drives)")

    def _decay_rate(self, t: float, y: Any) -> float | None:
        """The largest −Re λ over the eigenvalues λ of ∂(q̇, q̈)/∂(q, q̇) that decay more than they
        turn (|Im λ| < −Re λ), by forward differences of the equation; None where it cannot be had."""
        k = self.k
        base = [float(v) for v in y[:2 * k]]
        try:
            a0 = self.eq.accelerations(t, base[:k], base[k:])[0]
            jac = np.zeros((2 * k, 2 * k))
            jac[:k, k:] = np.eye(k)
            for j in range(2 * k):
                step = _DIFF * max(abs(base[j]), 1.0)
                moved = list(base)
                moved[j] += step
                a1 = self.eq.accelerations(t, moved[:k], moved[k:])[0]
                jac[k:, j] = (np.asarray(a1) - np.asarray(a0)) / step
        except (AssemblyError, ArithmeticError, ValueError):
            return None
        if not np.all(np.isfinite(jac)):
            return None
        lam = np.linalg.eigvals(jac)
        decaying = [-z.real for z in lam if z.real < 0 and abs(z.imag) < -z.real]
        return max(decaying) if decaying else None
