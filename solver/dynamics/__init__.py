"""Forward dynamics in the input coordinates and machine dynamics (docs/dynamics.md).

The effort of the kinetostatics is affine in the input accelerations, Q = M(q)·q̈ + h(q, q̇)
(solver.dynamics.reduced); forward dynamics integrates q̈ = M⁻¹(Q_drive − h) with DOP853 or a
fixed-step RK4, breakpoint to breakpoint (solver.dynamics.integrate, solver.dynamics.stepper);
machine dynamics (one input) finds the steady periodic motion under a motor and a cyclic load,
the coefficient of speed fluctuation, the flywheel for a requested one and the run-up time
(solver.dynamics.machine). ``Scene.simulate`` and ``Scene.reduced`` are doors into ``simulate``
and ``reduced_model`` (opened by ``solver/__init__``, imported on first use).
"""

from __future__ import annotations

from .drive import make_drive, motor_torque
from .integrate import Equation, Trajectory, simulate
from .machine import RunUp, SteadyState, flywheel_for, run_up, steady_state
from .reduced import ReducedModel, reduced_model
from .stepper import Stepper, fixed_step

__all__ = [
    "Equation",
    "ReducedModel",
    "RunUp",
    "SteadyState",
    "Stepper",
    "Trajectory",
    "fixed_step",
    "flywheel_for",
    "make_drive",
    "motor_torque",
    "reduced_model",
    "run_up",
    "simulate",
    "steady_state",
]
