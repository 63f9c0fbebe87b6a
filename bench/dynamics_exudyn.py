"""EXUDYN on the four-bar pendulum: the work–precision rows beside MuJoCo's (bench/dynamics.py).

EXUDYN (Gerstmayr, Multibody System Dynamics 2023; PyPI ``exudyn``) is a redundant-coordinate
multibody code: every link is a planar rigid body (``NodeRigidBody2D`` with x, y, θ at its centre
of mass, ``ObjectRigidBody2D`` with the scene's mass and inertia about the centre), every pin a
``ObjectJointRevolute2D`` between two ``MarkerBodyPosition`` markers (the ground's markers at the
fixed points), gravity a ``LoadMassProportional`` per body. The four-bar's loop is closed by the
pin at B between coupler and rocker like any other joint: nine coordinates, eight constraints, one
degree of freedom. The bodies start in the scene's assembled pose at φ₀ (reference coordinates),
at rest; φ is the crank node's rotation (reference + displacement).

Its solvers (``exudyn.DynamicSolverType``), fixed step h = t_end / numberOfSteps:

* ``GeneralizedAlpha`` — the generalized-α method (EXUDYN's default spectral radius ρ∞ = 0.9)
  on the index-3 DAE: the position constraints are solved by Newton at every step, so
  the loop stays closed to the Newton tolerance; second order, with numerical damping;
* ``TrapezoidalIndex2`` — the trapezoidal rule (Newmark β = ¼, γ = ½) with the constraints
  differentiated once (index 2, velocity level): no damping, but the positions drift off the
  constraint manifold by O(h²) per unit time;
* the explicit Runge–Kutta solvers (RK44, DOPRI5 with error control, …) take no constraints
  (EXUDYN refuses the revolute joints), so for them the pins are penalty springs
  (``ObjectConnectorCartesianSpringDamper`` of stiffness k): a different, compliant model whose
  error is O(1/k) and whose cost grows with √k.

Measured per run: the error of φ(t_end) against the reference, the wall time of
``SolveDynamic`` (after a short warm-up run; the model built beforehand, as MuJoCo's), and the
loop's largest opening, |B_coupler − B_rocker| sampled every min(10 h, 1 ms) by two
``SensorBody`` sensors stored internally.
"""

from __future__ import annotations

import cmath
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._common import assembled_points

__all__ = ["ExudynModel", "ExudynRun", "build_four_bar", "exudyn_version", "run_four_bar"]

#: (solver, step h in s, Newton tolerance, generalized-α's spectral radius ρ∞) of the implicit runs
_IMPLICIT: tuple[tuple[str, float, float, float | None], ...] = (
    ("GeneralizedAlpha", 1e-2, 1e-8, 0.9),
    ("GeneralizedAlpha", 1e-3, 1e-8, 0.9),
    ("GeneralizedAlpha", 1e-3, 1e-8, 0.99),
    ("GeneralizedAlpha", 1e-4, 1e-8, 0.9),
    ("GeneralizedAlpha", 1e-4, 1e-4, 0.9),
    ("GeneralizedAlpha", 1e-4, 1e-12, 0.9),
    ("GeneralizedAlpha", 5e-5, 1e-8, 0.9),
    ("TrapezoidalIndex2", 1e-2, 1e-8, None),
    ("TrapezoidalIndex2", 1e-3, 1e-8, None),
    ("TrapezoidalIndex2", 1e-4, 1e-8, None),
)
#: (solver, penalty stiffness N/m, rtol = atol) of the explicit runs with penalty pins
_EXPLICIT: tuple[tuple[str, float, float], ...] = (("DOPRI5", 1e5, 1e-6), ("DOPRI5", 1e6, 1e-6))
#: the largest step of the error-controlled explicit runs (s)
_EXPLICIT_MAX_STEP = 1e-3


@dataclass(frozen=True)
class ExudynRun:
    """One run: φ at the end (rad; NaN if it failed), wall time (s), the loop's largest opening (m),
    and the time the solver gave up at (None if it reached the end)."""

    phi: float
    wall: float
    gap: float
    failed_at: float | None = None


@dataclass(frozen=True)
class ExudynModel:
    """An assembled EXUDYN system of the scene: its MainSystem, each body's node (by body name) and
    the two sensors of B (on the coupler, on the rocker)."""

    mbs: Any
    nodes: dict[str, int]
    sensors: tuple[int, int]


def exudyn_version() -> str:
    import exudyn

    return str(exudyn.__version__)


def build_four_bar(scene: Any, phi0: float, *, penalty: float | None = None) -> tuple[Any, ExudynModel]:
    """The scene's bodies and pins as an EXUDYN system (SystemContainer, model), assembled at φ₀.

    ``penalty``: None — revolute joints (constraints); a stiffness k (N/m) — every pin a Cartesian
    spring of stiffness k in x and y instead (for the explicit solvers)."""
    import exudyn as exu
    import exudyn.itemInterface as ei

    spec = scene.reduced().spec
    pose = assembled_points(scene, phi0)
    fixed = set(scene._data.fixed)
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.AddObject(ei.ObjectGround())
    at: dict[str, list[int]] = {p: [mbs.AddMarker(ei.MarkerBodyPosition(bodyNumber=ground, localPosition=[
        pose[p].real, pose[p].imag, 0.0]))] for p in fixed}
    node: dict[str, int] = {}
    local: dict[tuple[str, str], tuple[int, list[float]]] = {}
    for body in spec.bodies:
        first, second = body.frame
        turn = cmath.exp(1j * cmath.phase(pose[second] - pose[first]))
        centre = pose[first] + body.center * turn
        node[body.name] = mbs.AddNode(ei.NodeRigidBody2D(referenceCoordinates=[
            centre.real, centre.imag, cmath.phase(turn)]))
        obj = mbs.AddObject(ei.ObjectRigidBody2D(mass=body.mass, inertia=body.inertia,
                                                 nodeNumber=node[body.name]))  # about the centre
        mass = mbs.AddMarker(ei.MarkerBodyMass(bodyNumber=obj))
        mbs.AddLoad(ei.LoadMassProportional(markerNumber=mass, loadVector=[
            spec.gravity.real, spec.gravity.imag, 0.0]))
        for p in body.link.points:
            r = (pose[p] - centre) / turn  # in the body frame, from the centre of mass
            local[body.name, p] = (obj, [r.real, r.imag, 0.0])
            at.setdefault(p, []).append(mbs.AddMarker(ei.MarkerBodyPosition(bodyNumber=obj, localPosition=[
                r.real, r.imag, 0.0])))
    for markers in at.values():  # a pin between the first body at a point (or the ground) and each other
        for other in markers[1:]:
            pair = [markers[0], other]
            mbs.AddObject(ei.ObjectJointRevolute2D(markerNumbers=pair) if penalty is None else
                          ei.ObjectConnectorCartesianSpringDamper(markerNumbers=pair,
                                                                  stiffness=[penalty, penalty, 0.0]))
    sensors = tuple(mbs.AddSensor(ei.SensorBody(bodyNumber=local[name, "B"][0], localPosition=local[name, "B"][1],
                                                writeToFile=False, storeInternal=True,
                                                outputVariableType=exu.OutputVariableType.Position))
                    for name in ("coupler", "rocker"))
    mbs.Assemble()
    return sc, ExudynModel(mbs, node, (sensors[0], sensors[1]))


@contextmanager
def _quiet() -> Iterator[None]:
    """EXUDYN's console output off (its banners around a failed solve), then as it was."""
    import exudyn as exu

    before = exu.config.printToConsole
    exu.config.printToConsole = False
    try:
        yield
    finally:
        exu.config.printToConsole = before


def run_four_bar(scene: Any, phi0: float, t_end: float, *, solver: str, step: float, newton: float = 1e-8,
                 rho: float | None = None, penalty: float | None = None,
                 tolerance: float | None = None) -> ExudynRun:
    """One EXUDYN run of ``t_end`` s from rest at φ₀ with ``solver`` (a ``DynamicSolverType`` name) at
    fixed step ``step`` (the largest step with ``tolerance``: error control, explicit solvers only);
    ``rho``: generalized-α's spectral radius ρ∞ (None: EXUDYN's default, 0.9)."""
    import exudyn as exu

    sc, model = build_four_bar(scene, phi0, penalty=penalty)
    settings = exu.SimulationSettings()
    ti = settings.timeIntegration
    ti.endTime, ti.numberOfSteps, ti.verboseMode = t_end, int(round(t_end / step)), 0
    ti.newton.relativeTolerance = ti.newton.absoluteTolerance = newton
    if rho is not None:
        ti.generalizedAlpha.spectralRadius = rho
    if tolerance is not None:
        ti.automaticStepSize, ti.relativeTolerance, ti.absoluteTolerance = True, tolerance, tolerance
    settings.solution.file.write = False
    settings.solution.sensors.writePeriod = min(10 * step, 1e-3)
    failed_at = None
    start = time.perf_counter()
    try:
        with _quiet():  # the solver's own failure banner: the failure is a row here
            model.mbs.SolveDynamic(settings, solverType=getattr(exu.DynamicSolverType, solver))
    except exu.SolverError:
        failed_at = float(model.mbs.sys["dynamicSolver"].it.currentTime)
    wall = time.perf_counter() - start
    b1, b2 = (model.mbs.GetSensorStoredData(s) for s in model.sensors)
    gap = float(np.linalg.norm(b1[:, 1:3] - b2[:, 1:3], axis=1).max())
    phi = float(model.mbs.GetNodeOutput(model.nodes["crank"], exu.OutputVariableType.Rotation)[2])
    del sc
    return ExudynRun(float("nan") if failed_at is not None else phi, wall, gap, failed_at)


def _refusal(scene: Any, phi0: float, solver: str) -> str:
    """What EXUDYN says when an explicit solver meets the revolute joints (its first line)."""
    import exudyn as exu

    sc, model = build_four_bar(scene, phi0)
    settings = exu.SimulationSettings()
    settings.timeIntegration.endTime, settings.timeIntegration.numberOfSteps = 1e-3, 1
    settings.solution.file.write = False
    try:
        with _quiet():
            model.mbs.SolveDynamic(settings, solverType=getattr(exu.DynamicSolverType, solver))
    except exu.ExudynError as err:
        return str(err).split("[")[0].strip().rstrip(";")
    finally:
        del sc
    return "accepted"


def _row(label: str, run: ExudynRun, want: float) -> str:
    if run.failed_at is not None:
        return (f"| {label} | fails at t = {run.failed_at:.2f} s (Newton does not converge) | "
                f"{run.wall:.3f} s | {run.gap:.1e} m |")
    return f"| {label} | {abs(run.phi - want):.1e} | {run.wall:.3f} s | {run.gap:.1e} m |"


def _exudyn_rows(scene: Any, *, phi0: float, t_end: float, want: float) -> list[str]:
    """The work–precision table's EXUDYN rows (a single "not installed" row without exudyn)."""
    try:
        import exudyn  # noqa: F401
    except ImportError:
        return ["| EXUDYN | not installed | | |"]
    name = f"EXUDYN {exudyn_version()}"
    run_four_bar(scene, phi0, 0.01, solver="GeneralizedAlpha", step=1e-3)  # warm
    rows = []
    for solver, step, newton, rho in _IMPLICIT:
        run = run_four_bar(scene, phi0, t_end, solver=solver, step=step, newton=newton, rho=rho)
        label = "trapezoidal index 2" if rho is None else f"generalized-α index 3 ρ∞={rho:g}"
        rows.append(_row(f"{name} {label} h={step:g} Newton tol={newton:g}", run, want))
    rows.append(f"| {name} RK44, DOPRI5 with the revolute joints | refused: “{_refusal(scene, phi0, 'RK44')}” | | |")
    for solver, stiffness, tol in _EXPLICIT:
        run = run_four_bar(scene, phi0, t_end, solver=solver, step=_EXPLICIT_MAX_STEP, penalty=stiffness,
                           tolerance=tol)
        rows.append(_row(f"{name} {solver} rtol=atol={tol:g}, penalty pins k={stiffness:g} N/m", run, want))
    return rows
