"""The equation of motion advanced tick by tick (the node's dynamic mode; docs/dynamics.md).

:class:`Stepper` steps the compiled instant (M, h) on the own step loop
(solver.dynamics._stepping), breakpoint to breakpoint across the tables' kinks:

* ``method="RK4"`` (real time): a fixed step ``step`` (s), the steps landing on every time asked
  for — a bounded cost per tick, four evaluations a step (more only where a kink falls in it).
  :func:`fixed_step` chooses the step for a tick period from a tolerance;
* ``method="DOP853"`` (accurate): the adaptive steps go across the ticks and a tick reads the
  step's dense output.

``set_drive`` changes the drive (an effort command) at the current time, so that no step
straddles the change. An ``advance`` that would not end — pressed against an assembly limit, a
step at the time's round-off, a stiff equation with more than ``stiff_steps`` adaptive steps to
go, a rate beyond ``max_rate`` — raises one DynamicsError line (solver.dynamics._guard): a tick
always ends; ``interrupted()``, asked between steps, ends it early (the node's SIGINT during a
long tick).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from .._arguments import Arguments
from ..errors import AssemblyError, DynamicsArgumentError, DynamicsError
from ..tolerances import DYNAMICS_TOGGLE
from ._breaks import breaks_of
from ._guard import MAX_RATE, STEPPER_STIFF_STEPS, RunGuard, rates_text
from ._rk import Dense
from ._stepping import Integrator, StepFailure
from .drive import make_drive
from .integrate import OWN_METHODS, Equation, _checked, _initial, _limit_message, _start, _stroke_end, _strokes, _where
from .reduced import reduced_model

__all__ = ["ADAPTIVE_BELOW", "FIXED_HORIZON", "MAX_SUBSTEPS", "Stepper", "fixed_step"]

#: RK4: under this conditioning of the groups (1 well conditioned, DYNAMICS_TOGGLE a toggle) the
#: stepper takes DOP853's adaptive steps, which resolve where the threshold is crossed
ADAPTIVE_BELOW = 0.1
#: :func:`fixed_step`: the most steps per tick it allows (the node's cost per tick is bounded)
MAX_SUBSTEPS = 16
#: :func:`fixed_step`: the run (in ticks) over which the error of a step size is estimated
FIXED_HORIZON = 50


class Stepper:
    """``advance(t)`` → the state y = (q, q̇, W_drive, W_other) at ``t`` (numpy, as the run's
    samples); ``works=False``: the work integrals stay 0 (with several inputs one force pass
    fewer per evaluation)."""

    def __init__(
        self, scene: Any, *, phi0: Any = None, omega0: Any = 0.0, drive: Any = None, rtol: float = 1e-9,
        atol: float = 1e-9, method: str = "DOP853", t0: float = 0.0, works: bool = True, step: float | None = None,
        stiff_steps: float = STEPPER_STIFF_STEPS, max_rate: float = MAX_RATE,
        interrupted: Callable[[], bool] | None = None,
    ) -> None:
        args = Arguments("Stepper", scene=scene.name, error=DynamicsArgumentError)
        rtol, atol, method = _checked(args, rtol=rtol, atol=atol, method=method, methods=OWN_METHODS)
        t0 = args.number("t0", t0, unit="s")
        works = args.flag("works", works)
        step = args.number("step", step, low=0.0, low_open=True, unit="s", none=True)
        if method == "RK4" and step is None:
            args.fail("step", step, "must be given with method 'RK4': the fixed step, a positive number of seconds")
        self.scene = scene
        self.model = reduced_model(scene)
        if self.model.friction is not None:
            raise DynamicsError("names friction: the fixed-step Stepper (the node's dynamic mode) does not model "
                                "Coulomb friction; scene.simulate does (docs/dynamics.md#friction)", scene=scene.name)
        k = self.k = self.model.k
        q0 = _start(scene) if phi0 is None else _initial(args, phi0, k, "phi0")
        w0 = _initial(args, omega0, k, "omega0")
        fn, self.kind = make_drive(drive, scene.inputs, self.model.motors, scene=scene.name)
        self.works = works
        self.eq = Equation(self.model, fn, works=works)
        self.rtol, self.atol, self.method, self.step = rtol, atol, method, step
        self.t = float(t0)
        self.y = np.array([*q0, *w0, 0.0, 0.0])
        self._strokes = _strokes(scene)
        self._breaks = breaks_of(self.model)
        try:
            self.eq.accelerations(self.t, q0, w0)
        except AssemblyError as exc:
            raise DynamicsError(f"cannot be assembled at the initial state ({exc.reason})", scene=scene.name,
                                time=self.t, at=_where(scene, self.y), group=exc.group) from None
        #: asked between steps: True ends an ``advance`` with a DynamicsError (the node's SIGINT)
        self.interrupted = interrupted
        # the stiffness test is for the adaptive steps (a fixed step's cost per tick is bounded)
        self.guard = RunGuard(self.eq, t_end=self.t, max_steps=None, max_rate=max_rate, stiff=method != "RK4",
                              stiff_steps=stiff_steps,
                              limit_text=lambda fault: _limit_message(scene, fault, "pressed against it"))
        if self.guard.runaway(self.y) is not None:
            raise DynamicsError(f"omega0 is beyond max_rate = {max_rate:g}", scene=scene.name, time=self.t,
                                at=f"{_where(scene, self.y)}, {rates_text(scene, self.y)}")
        self._restart()

    def _integrator(self, method: str, t: float, y: list[float]) -> Integrator:
        return Integrator(self.eq.rates, t, y, k=self.k, method=method, rtol=self.rtol, atol=self.atol,
                          step=self.step, breaks=self._breaks, conditioning=self._last_conditioning)

    def _restart(self) -> None:
        self._integ = self._integrator(self.method, self.t, self.y.tolist())
        self._dense: Dense | None = None
        #: y' at the last state returned, where the integrator evaluated it there (else None)
        self._fy: list[float] | None = self._integ.fy

    def _last_conditioning(self) -> float:
        return float(self.eq.last_conditioning)

    @property
    def evaluations(self) -> int:
        """Evaluations of (M, h) by the integrator since the last (re)start."""
        return self._integ.nfev

    def set_drive(self, drive: Any) -> None:
        fn, self.kind = make_drive(drive, self.scene.inputs, self.model.motors, scene=self.scene.name)
        self.eq = self.guard.eq = Equation(self.model, fn, works=self.works)
        self._restart()

    def advance(self, t: float) -> np.ndarray:
        """The state at time ``t`` ≥ the last one; DynamicsError where the motion reaches a
        toggle or an assembly limit on the way. RK4 hands over to DOP853 (at rtol, atol) while
        the conditioning is under ADAPTIVE_BELOW — near a toggle, whose threshold a fixed step
        could jump across — and takes over again at the first tick above it."""
        guard = self.guard
        guard.aim(t)
        while self._integ.t < t:
            integ = self._integ
            adaptive = integ.method == "DOP853"
            if self.method == "RK4" and not adaptive and self.eq.last_conditioning < ADAPTIVE_BELOW:
                self._integ = self._integrator("DOP853", integ.t, integ.y)
                continue
            try:
                self._dense = integ.step(math.inf if adaptive else t)
            except StepFailure as failure:
                fault = self.eq.fault or (failure.group, failure.reason, list(failure.y[:self.k]))
                raise DynamicsError(_limit_message(self.scene, fault, failure.reason), scene=self.scene.name,
                                    time=failure.t, at=_where(self.scene, np.array(failure.y)), group=None) from None
            self._check(integ.t, integ.y)
            stop = guard.accept(integ.t, integ.y)
            if stop is None and self.interrupted is not None and self.interrupted():
                stop = "interrupted (the process is asked to stop)"
            if stop is not None:
                y_now = np.array(integ.y)
                at = _where(self.scene, y_now)
                raise DynamicsError(stop, scene=self.scene.name, time=integ.t,
                                    at=at if guard.kind == "assembly" else f"{at}, {rates_text(self.scene, y_now)}")
        integ = self._integ
        if integ.t == t or self._dense is None:
            y = np.array(integ.y)
            self._fy = integ.fy if integ.t == t else None
        else:
            y = np.array(self._dense(t))
            self._fy = None
        if self.method == "RK4" and integ.method == "DOP853" and self.eq.last_conditioning >= ADAPTIVE_BELOW:
            self._integ = self._integrator("RK4", t, y.tolist())
            self._dense = None
            self._fy = self._integ.fy
        self.t, self.y = t, y
        return y

    def _check(self, t: float, y: list[float]) -> None:
        for i, lo, hi, name in self._strokes:
            if not lo <= y[i] <= hi:
                raise DynamicsError(_stroke_end(lo, hi, name, open_end=y[i] > hi), scene=self.scene.name, time=t,
                                    at=_where(self.scene, np.array(y)), group=None)
        if self.eq.last_conditioning < DYNAMICS_TOGGLE:  # of the step's last evaluation: its end
            arr = np.array(y)
            raise DynamicsError("reaches a singular position (a toggle: the inputs cannot drive through it)",
                                scene=self.scene.name, time=t, at=_where(self.scene, arr),
                                group=self.eq.worst_group(arr))

    def accelerations(self) -> tuple[list[float], list[float]]:
        """(q̈, Q_drive) at the last state returned."""
        k = self.k
        state = self.y.tolist()
        q, qd = state[:k], state[k:2 * k]
        fy = self._fy
        if fy is not None and all(map(math.isfinite, fy[k:2 * k])):  # the step's own last evaluation
            return list(fy[k:2 * k]), list(self.eq.drive(self.t, q, qd))
        qdd, qdrive, _ = self.eq.accelerations(self.t, q, qd)
        return qdd, qdrive


def fixed_step(
    scene: Any, *, period: float, tolerance: float, phi0: Any = None, omega0: Any = 0.0, drive: Any = None,
    max_substeps: int = MAX_SUBSTEPS, horizon: int = FIXED_HORIZON, budget: float | None = None,
) -> tuple[float, float]:
    """(step, error): the RK4 step for ticks of ``period`` s — period/n, n = 1, 2, 4 … up to
    ``max_substeps`` — whose error over ``horizon`` ticks from the initial state, against the
    adaptive DOP853 at a hundredth of ``tolerance``, is within ``tolerance``·(1 + |q|, |q̇|) (the
    error's size in those units, > 1 where the n taken misses it). (Not n against 2n: the kinks
    of a table cut the steps of both alike.) ``budget`` (s): the wall time a tick may take here;
    an n whose ticks took longer is not taken (real time before the tolerance: the error says by
    how much it is missed). A run that stops on the way (a toggle, an assembly limit) is
    compared up to where both reached."""
    k = len(scene.inputs)
    fine = tolerance / 100.0
    reference = Stepper(scene, phi0=phi0, omega0=omega0, drive=drive, rtol=fine, atol=fine, works=False)
    ticks = []
    for i in range(1, horizon + 1):
        try:
            ticks.append(reference.advance(i * period)[:2 * k].copy())
        except DynamicsError:
            break
    n = 1
    best = (period, math.inf)
    while ticks:
        stepper = Stepper(scene, phi0=phi0, omega0=omega0, drive=drive, method="RK4", step=period / n, works=False)
        worst = 0.0
        start = time.perf_counter()
        for i, expected in enumerate(ticks, start=1):
            try:
                got = stepper.advance(i * period)[:2 * k]
            except DynamicsError:
                worst = math.inf
                break
            worst = max(worst, float(np.max(np.abs(got - expected) / (tolerance * (1.0 + np.abs(expected))))))
        per_tick = (time.perf_counter() - start) / len(ticks)
        if budget is not None and per_tick > budget and n > 1:
            break  # the last n that kept within the budget
        best = (period / n, worst)
        if worst <= 1.0 or 2 * n > max_substeps:
            break
        n *= 2
    return best
