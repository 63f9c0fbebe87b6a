"""What the runtime adds in dynamic mode (issue 30): the drive state in diagnostics and the
energies in the recording.

* :class:`DriveState` gives the KeyValues every diagnostics status carries in dynamic mode
  (:attr:`~linkage_ros.messages.MessageBuilder.diagnostic_values`): ``drive`` (motor, effort or
  free), ``command_age`` (s since the last accepted effort command, node clock; ``none`` before
  the first), ``stale`` (``true`` while the drive is effort and there is no command younger than
  ``effort_timeout``: the efforts count as zero), ``efforts`` (the command in force) and
  ``real_time_factor``: run time advanced per second of wall-clock (monotonic) time since the
  previous diagnostics message — 1 while the node keeps up with its clock; under
  ``use_sim_time`` the ``/clock``'s rate; ``fixed_step`` (s, the RK4 step the law chose at its
  start) and ``step_error`` (that step's error over its first 50 ticks against the adaptive run,
  in units of ``dynamics_tolerance``: above 1 where the tick budget allowed no more steps — the
  tolerance is missed by that factor, said, never silently); ``ticks_late`` and
  ``ticks_skipped``: of the node's timer grid (:class:`~linkage_ros._tick_grid.TickGrid`), the
  ticks rendered a period or more after their grid time (periods rcl's timer skipped, caught up)
  and the periods beyond the catch-up bound, never ticked — both counted since the mode started.
* :func:`energy_values` gives the row of the ``energies`` topic (``std_msgs/Float64MultiArray``,
  recorded, not published): the kinetic energy ½q̇ᵀM(q)q̇, the potentials of gravity and of the
  springs, and their sum T + V (J), of the state a tick reached.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from solver.dynamics import reduced_model

from .topics import ENERGY_LABELS

__all__ = ["ENERGY_LABELS", "DriveState", "energy_values"]



def energy_values(scene: Any, phi: Any, omega: Any) -> tuple[float, ...]:
    """(T, V_gravity, V_springs, T + V) in J at the state (φ, ω) (floats, or k-tuples)."""
    model = reduced_model(scene)
    q = np.asarray([phi], dtype=np.float64)
    qd = np.asarray([omega], dtype=np.float64)
    kinetic = float(model.kinetic(q, qd)[0])
    potential = model.potential(q)
    gravity, springs = float(potential["gravity"][0]), float(potential["springs"][0])
    return kinetic, gravity, springs, kinetic + gravity + springs


class DriveState:
    """The drive-state KeyValues of one dynamic law (see the module docstring).

    ``motion``: the dynamic law (its ``kind``, ``timeout``, ``efforts``); ``run_time()``: the run
    time of the last tick (s); ``last_command()``: run time of the last accepted command, or None;
    ``grid()``: the node's :class:`~linkage_ros._tick_grid.TickGrid`, or None.
    """

    def __init__(self, motion: Any, run_time: Callable[[], float], last_command: Callable[[], float | None],
                 *, clock: Callable[[], float] = time.monotonic, grid: Callable[[], Any] | None = None) -> None:
        self.motion = motion
        self._grid = grid
        self._run_time = run_time
        self._last_command = last_command
        self._clock = clock
        self._previous: tuple[float, float] | None = None

    def __call__(self) -> list[tuple[str, str]]:
        motion = self.motion
        t = self._run_time()
        since = self._last_command()
        age = None if since is None else max(t - since, 0.0)
        kind = str(motion.kind)
        stale = kind == "effort" and (age is None or age > float(motion.timeout))
        wall = self._clock()
        factor = "none"
        if self._previous is not None and wall > self._previous[0]:
            factor = f"{(t - self._previous[1]) / (wall - self._previous[0]):.4g}"
        self._previous = (wall, t)
        return [("drive", kind), ("command_age", "none" if age is None else f"{age:.6f}"),
                ("stale", "true" if stale else "false"),
                ("efforts", " ".join(repr(float(v)) for v in motion.efforts)),
                ("real_time_factor", factor),
                ("fixed_step", f"{float(getattr(motion, 'step', math.nan)):.6g}"),
                ("step_error", f"{float(getattr(motion, 'step_error', math.nan)):.3g}"),
                *self._ticks()]

    def _ticks(self) -> list[tuple[str, str]]:
        grid = None if self._grid is None else self._grid()
        if grid is None:
            return []
        return [("ticks_late", str(grid.late)), ("ticks_skipped", str(grid.skipped))]
