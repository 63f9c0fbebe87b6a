"""EXUDYN as an oracle from the field on four_bar_pendulum (bench/dynamics_exudyn.py).

EXUDYN integrates the bodies' absolute coordinates with the pins as constraints (a DAE, no closed
form, no reduced inertia): that its φ(t) converges to ours at second order in its step, and that
its total energy stays constant, checks both the EXUDYN model of the bench (the same bodies,
masses and pins as the scene) and our equation of motion. Skipped without exudyn.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

import solver  # noqa: E402
from bench import dynamics_exudyn  # noqa: E402

PHI0 = 0.3
TRAPEZOIDAL_AT_100_US = 1e-5
"""φ(t) of EXUDYN's trapezoidal rule at h = 0.1 ms against ours over 2 s: measured 5.5e-6 rad
(its O(h²) error); a wrong mass, centre or pin is off by far more."""
ENERGY_AT_100_US = 1e-5
"""The trapezoidal rule's swing of T + V over 2 s at h = 0.1 ms, relative to the kinetic energy's
swing (0.74 J): measured 2.0e-6."""


@pytest.fixture(scope="module")
def scene() -> Any:
    pytest.importorskip("exudyn")
    return solver.load_scene("four_bar_pendulum")


def test_exudyn_follows_our_motion_and_keeps_its_energy(scene: Any) -> None:
    import exudyn as exu
    import exudyn.itemInterface as ei

    t_end, step = 2.0, 1e-4
    sc, model = dynamics_exudyn.build_four_bar(scene, PHI0)
    kinds = (exu.OutputVariableType.Coordinates, exu.OutputVariableType.Coordinates_t)
    sensors = {name: tuple(model.mbs.AddSensor(ei.SensorNode(nodeNumber=n, writeToFile=False, storeInternal=True,
                                                             outputVariableType=k)) for k in kinds)
               for name, n in model.nodes.items()}
    model.mbs.Assemble()
    settings = exu.SimulationSettings()
    ti = settings.timeIntegration
    ti.endTime, ti.numberOfSteps, ti.verboseMode = t_end, int(round(t_end / step)), 0
    settings.solution.file.write = False
    settings.solution.sensors.writePeriod = 1e-2
    assert model.mbs.SolveDynamic(settings, solverType=exu.DynamicSolverType.TrapezoidalIndex2)

    spec = scene.reduced().spec
    energy, kinetic = 0.0, 0.0
    for body in spec.bodies:
        q, v = (model.mbs.GetSensorStoredData(s) for s in sensors[body.name])
        ref = model.mbs.GetNodeParameter(model.nodes[body.name], "referenceCoordinates")
        t_body = 0.5 * body.mass * (v[:, 1] ** 2 + v[:, 2] ** 2) + 0.5 * body.inertia * v[:, 3] ** 2
        kinetic = kinetic + t_body
        energy = energy + t_body - body.mass * (spec.gravity.real * (q[:, 1] + ref[0])
                                                + spec.gravity.imag * (q[:, 2] + ref[1]))
        if body.name == "crank":
            t, phi = q[:, 0], q[:, 3] + ref[2]
    ours = scene.simulate(t_end, phi0=PHI0, rtol=1e-12, atol=1e-12)
    want = np.array([ours.at(float(ti_))[0] for ti_ in t])
    assert np.ptp(phi) > 0.5  # it swings
    assert np.abs(phi - want).max() < TRAPEZOIDAL_AT_100_US
    assert np.ptp(energy) < ENERGY_AT_100_US * np.ptp(kinetic)
    del sc


def test_generalized_alpha_converges_to_ours_at_second_order_with_its_loop_closed(scene: Any) -> None:
    t_end = 1.0
    want = float(scene.simulate(t_end, phi0=PHI0, rtol=1e-12, atol=1e-12).phi[-1])
    runs = [dynamics_exudyn.run_four_bar(scene, PHI0, t_end, solver="GeneralizedAlpha", step=h) for h in (4e-4, 2e-4)]
    coarse, fine = (abs(r.phi - want) for r in runs)
    assert 3.0 < coarse / fine < 5.0  # O(h²) towards our φ: the same equation of motion
    assert fine < 5e-5  # measured 2.1e-5 at h = 0.2 ms
    assert max(r.gap for r in runs) < 1e-10  # index 3: the pins are solved at every step


def test_trapezoidal_index_2_lets_the_loop_drift(scene: Any) -> None:
    run = dynamics_exudyn.run_four_bar(scene, PHI0, 1.0, solver="TrapezoidalIndex2", step=1e-3)
    assert 1e-9 < run.gap < 1e-5  # velocity constraints only: the positions drift, O(h²)


def test_explicit_solvers_refuse_the_joints_and_the_rows_say_so(scene: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    assert "constraints" in dynamics_exudyn._refusal(scene, PHI0, "RK44")
    monkeypatch.setitem(sys.modules, "exudyn", None)  # as if not installed
    assert dynamics_exudyn._exudyn_rows(scene, phi0=PHI0, t_end=1.0, want=0.0) == ["| EXUDYN | not installed | | |"]
