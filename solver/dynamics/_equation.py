"""The right-hand side of the equation of motion per instant, y = (q, q̇, W_drive, W_other)
(docs/dynamics.md): q̈ = M(q)⁻¹·(Q_drive − h(q, q̇)) from the reduced model's compiled instant."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..errors import AssemblyError
from .drive import Drive
from .reduced import ReducedModel

__all__ = ["Equation"]


class Equation:
    """The right-hand side of the first-order system y = (q, q̇, W_drive, W_other), per instant."""

    def __init__(self, model: ReducedModel, drive: Drive, *, works: bool = True) -> None:
        self.model, self.drive, self.k = model, drive, model.k
        #: (group, reason, q) of the last call that could not be assembled
        self.fault: tuple[str, str, list[float]] | None = None
        self.faults = 0  # how many calls were unassemblable (trial stages beyond an assembly limit)
        self.last_conditioning = 1.0  # of the last state :meth:`rates` was called at
        #: whether the two work integrals are integrated (False: their rates are 0, no pass for the
        #: other loads with several inputs)
        self.works = works
        #: one input: (compiled unit, its size, the efforts' start, other loads?, the drive's ``one``)
        self._layout: tuple[Any, int, int, bool, Any] | None = None

    def accelerations(
        self, t: float, q: Sequence[float], qd: Sequence[float]
    ) -> tuple[list[float], list[float], float]:
        """(q̈, Q_drive, conditioning) at one state; raises AssemblyError where it cannot be assembled."""
        qdd, qdrive, _, cond = self._solve(t, q, qd)
        return qdd, qdrive, cond

    def _solve(self, t: float, q: Sequence[float], qd: Sequence[float]) -> tuple[list, list, list, float]:
        m, h, other, cond = self.model.state(q, qd, other=self.works)
        qdrive = list(self.drive(t, q, qd))
        if self.k == 1:
            return [(qdrive[0] - h[0]) / m], qdrive, other, cond
        rhs = np.subtract(qdrive, h)
        return list(np.linalg.solve(np.asarray(m), rhs)), qdrive, other, cond

    def __call__(self, t: float, y: np.ndarray) -> np.ndarray:
        k = self.k
        state = y.tolist()  # Python floats (one call, not one float() per entry)
        q, qd = state[:k], state[k:2 * k]
        if not all(map(math.isfinite, state)):  # a trial stage after a rejected one: rejected too
            return np.full(y.shape, math.nan)
        try:
            qdd, qdrive, other, _ = self._solve(float(t), q, qd)
        except AssemblyError as exc:  # a trial step beyond an assembly limit: rejected (NaN)
            self.fault = (exc.group, exc.reason, q)
            self.faults += 1
            return np.full(y.shape, math.nan)
        if not self.works:
            return np.array([*qd, *qdd, 0.0, 0.0])
        if k == 1:
            w = qd[0]
            return np.array((w, qdd[0], qdrive[0] * w, other[0] * w))
        return np.array([*qd, *qdd, sum(a * b for a, b in zip(qdrive, qd)), sum(a * b for a, b in zip(other, qd))])

    def rates(self, t: float, y: list[float]) -> list[float]:
        """y' at (t, y) on plain lists (solver.dynamics._stepping); AssemblyError where the state
        cannot be assembled (kept in ``fault`` with the state's coordinates, and counted, as
        :meth:`__call__` does), NaN where it is not finite (a trial stage of a step that overflowed).
        Keeps the state's conditioning in ``last_conditioning``."""
        k = self.k
        if not all(map(math.isfinite, y[:2 * k])):  # a trial stage beyond an overflowing one: rejected too
            return [math.nan] * len(y)
        try:
            if k != 1:
                return self._several(t, y, k)
            # one input: the stacked compiled pass read in place (ReducedModel.state's layout), inline
            layout = self._layout
            if layout is None:
                unit = self.model._stacked_unit
                size = unit.size
                layout = self._layout = (unit, size, size + len(unit.conditioning), self.model.other is not None,
                                         getattr(self.drive, "one", None))
            unit, size, start, has_other, one = layout
            phi, w = y[0], y[1]
            flat = unit.function(phi, w, 0.0)  # (its ``function`` is replaced on the first call: read it each time)
            self.last_conditioning = min(flat[size:start]) if start > size else 1.0
            effort = one(t, phi, w) if one is not None else self.drive(t, y[:1], y[1:2])[0]
            accel = (effort - flat[start]) / flat[start + 1]
            if not self.works:
                return [w, accel, 0.0, 0.0]
            return [w, accel, effort * w, (-flat[start + 2] * w) if has_other else 0.0]
        except AssemblyError as exc:
            self.fault = (exc.group, exc.reason, list(y[:k]))
            self.faults += 1
            raise

    def _several(self, t: float, y: list[float], k: int) -> list[float]:
        """:meth:`rates` with k > 1 inputs, at a finite state."""
        q, qd = y[:k], y[k:2 * k]
        qdd, qdrive, other, self.last_conditioning = self._solve(t, q, qd)
        if not self.works:
            return [*qd, *qdd, 0.0, 0.0]
        return [*qd, *qdd, sum(a * b for a, b in zip(qdrive, qd)), sum(a * b for a, b in zip(other, qd))]

    def conditioning(self, t: float, y: np.ndarray) -> float:
        k = self.k
        state = y.tolist()
        try:
            return self.model.instant(state[:k], state[k:2 * k])[2]
        except AssemblyError:
            return 0.0

    def worst_group(self, y: np.ndarray) -> str:
        """The group with the worst conditioning at state ``y`` (for the message)."""
        scene = self.model.full
        k = self.k
        q = float(y[0]) if k == 1 else tuple(float(v) for v in y[:k])
        try:
            cond = scene.solve(q).conditioning
        except AssemblyError as exc:
            return exc.group
        return min(cond, key=lambda g: float(np.min(cond[g]))) if cond else "?"
