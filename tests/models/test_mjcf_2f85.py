"""The Robotiq 2F-85 (tests/data/models/robotiq_2f85.xml, PROVENANCE.md) imported from MJCF,
against MuJoCo's own kinematics closed by a Newton solve (issue 31).

The reference knows nothing of groups: it sets the inputs in ``qpos``, takes the four passive
hinges as unknowns and drives both ``<connect>`` residuals (mj_kinematics, body1's anchor
minus body2's) to zero with scipy's Levenberg–Marquardt, continued sample to sample from qpos0.
Every joint of the model (the eight hinges) must agree with ours to ≤ 1e-9 rad over the drivers'
range [0, 0.8] rad, the spring links off the drivers by −0.1 … +0.05 rad (the left by half) and equal to them.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np
import pytest

import solver

mujoco = pytest.importorskip("mujoco")
optimize = pytest.importorskip("scipy.optimize")

MODEL = Path(__file__).resolve().parents[1] / "data" / "models" / "robotiq_2f85.xml"
INPUTS = ["right_driver_joint", "right_spring_link_joint", "left_spring_link_joint"]
PASSIVE = ["right_coupler_joint", "right_follower_joint", "left_coupler_joint", "left_follower_joint"]
#: agreement with the closed-loop Newton solve on MuJoCo's kinematics (issue 31)
JOINT_TOLERANCE = 1e-9


@pytest.fixture(scope="module")
def scene() -> solver.Scene:
    return solver.load_scene(MODEL, inputs=INPUTS)


class MuJoCoLoop:
    """The model's kinematics in MuJoCo, its loops closed by Newton on the connect residuals."""

    def __init__(self) -> None:
        self.m = mujoco.MjModel.from_xml_path(str(MODEL))
        self.d = mujoco.MjData(self.m)
        self.adr = {self.m.joint(n).name: int(self.m.joint(n).qposadr[0]) for n in range(self.m.njnt)}

    def set(self, qd: float, qsr: float, qsl: float, passive: np.ndarray) -> None:
        q = self.d.qpos
        q[self.adr["right_driver_joint"]] = q[self.adr["left_driver_joint"]] = qd  # the joint equality
        q[self.adr["right_spring_link_joint"]], q[self.adr["left_spring_link_joint"]] = qsr, qsl
        for name, v in zip(PASSIVE, passive):
            q[self.adr[name]] = v
        mujoco.mj_kinematics(self.m, self.d)

    def gaps(self) -> np.ndarray:
        out = []
        for e in range(self.m.neq):
            if int(self.m.eq_type[e]) != int(mujoco.mjtEq.mjEQ_CONNECT):
                continue
            b1, b2 = int(self.m.eq_obj1id[e]), int(self.m.eq_obj2id[e])
            p1 = self.d.xpos[b1] + self.d.xmat[b1].reshape(3, 3) @ self.m.eq_data[e][0:3]
            p2 = self.d.xpos[b2] + self.d.xmat[b2].reshape(3, 3) @ self.m.eq_data[e][3:6]
            out.append(p1 - p2)
        return np.concatenate(out)

    def close(self, qd: float, qsr: float, qsl: float, start: np.ndarray) -> np.ndarray:
        def residual(x: np.ndarray) -> np.ndarray:
            self.set(qd, qsr, qsl, x)
            return self.gaps()

        sol = optimize.least_squares(residual, start, method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15)
        assert np.max(np.abs(sol.fun)) < 1e-15
        return np.asarray(sol.x)


def test_import_reads_the_model(scene: solver.Scene) -> None:
    assert scene.inputs == tuple(INPUTS)
    assert set(scene.output_joints) == {*INPUTS, *PASSIVE, "left_driver_joint"}
    assert scene.model.kind == "MJCF" and scene.model.pose == "qpos0"
    np.testing.assert_allclose(scene.model.plane.normal, [1.0, 0.0, 0.0], atol=1e-15)
    k = scene.solve((0.0, 0.0, 0.0))
    for j in scene.output_joints:  # qpos0 reproduced: the model's own convention
        assert abs(k.joint(j).position) < 1e-15


@pytest.mark.parametrize("delta", [-0.1, 0.0, 0.05])
def test_every_joint_against_mujoco_newton(scene: solver.Scene, delta: float) -> None:
    ref = MuJoCoLoop()
    drivers = np.linspace(0.0, 0.8, 41)
    q = np.column_stack([drivers, drivers + delta, drivers + delta / 2])
    k = scene.solve(q)
    x = np.zeros(4)
    # continue from qpos0 (closed) to the first sample in small steps, then sample to sample
    for t in np.linspace(0.0, 1.0, 11)[1:]:
        x = ref.close(q[0, 0] * t, q[0, 1] * t, q[0, 2] * t, x)
    worst = 0.0
    for i, (qd, qsr, qsl) in enumerate(q):
        x = ref.close(qd, qsr, qsl, x)
        ours = [k.joint(n).position[i] for n in PASSIVE]
        worst = max(worst, float(np.max(np.abs(np.subtract(ours, x)))))
        assert k.joint("left_driver_joint").position[i] == qd
    print(f"worst joint difference against MuJoCo + Newton: {worst:.3g} rad")
    assert worst <= JOINT_TOLERANCE, worst


def test_our_joint_values_close_mujocos_loops(scene: solver.Scene) -> None:
    """Our joint values put into MuJoCo's qpos: both connects closed to round-off."""
    ref = MuJoCoLoop()
    for qd, qsr, qsl in [(0.2, 0.25, 0.1), (0.8, 0.7, 0.75), (0.05, 0.0, 0.02)]:
        k = scene.solve((qd, qsr, qsl))
        ref.set(qd, qsr, qsl, np.array([k.joint(n).position for n in PASSIVE]))
        assert np.max(np.abs(ref.gaps())) < 1e-16 * 1e3  # m: a few ulps of the 0.1 m model


def test_bodies_and_gravity_from_the_compiled_model(scene: solver.Scene) -> None:
    names = {b.name for b in scene.bodies if b.mass > 0}
    assert {"right_driver", "right_coupler", "right_spring_link", "right_follower"} <= names
    follower = next(b for b in scene.bodies if b.name == "right_follower")
    assert follower.mass == pytest.approx(0.0125222 + 0.0035, rel=1e-15)  # the pad is welded to it
    k = scene.solve((0.4, 0.4, 0.4))
    assert all(math.isfinite(k.effort(j)) for j in INPUTS)


def test_import_is_fast() -> None:
    """Issue 31 asks ≤ 1 s for the 2F-85's import; a unit test only keeps it from growing tenfold."""
    solver.load_scene(MODEL, inputs=INPUTS)  # modules imported
    t = time.perf_counter()
    solver.load_scene(MODEL, inputs=INPUTS)
    assert time.perf_counter() - t < 10.0


def test_default_inputs_are_the_actuated_joints_completed_by_the_free_hinges() -> None:
    """The actuators drive the two (coupled) drivers: one input; the mobility is 3, so the
    default adds the hinges on the ground in model order: the two spring links."""
    assert solver.load_scene(MODEL).inputs == tuple(INPUTS)


def test_explicit_inputs_are_counted_against_the_mobility() -> None:
    with pytest.raises(solver.SceneError, match=(
        r"robotiq_2f85.xml: inputs: the model has 3 freedoms \(8 moving bodies, 8 hinges, 2 loop closures, "
        r"1 coupling\(s\): F = 3·8 − 2·10 − 1 = 3\) but 1 input\(s\) \(right_driver_joint\); name 3 inputs: "
        r"hinges on the ground not yet inputs: right_spring_link_joint, left_spring_link_joint")):
        solver.load_scene(MODEL, inputs=["right_driver_joint"])


def test_linkage_import_writes_the_imported_scene(tmp_path: Path, scene: solver.Scene) -> None:
    from solver.structure_cli import import_main

    out = tmp_path / "gripper.yaml"
    assert import_main([str(MODEL), "-o", str(out)]) == 0
    written = solver.load_scene(out)
    q = np.column_stack([np.linspace(0.0, 0.8, 9)] * 3)
    a, b = scene.solve(q), written.solve(q)
    for j in scene.output_joints:
        assert np.array_equal(a.joint(j).position, b.joint(j).position)
    for j in INPUTS:
        assert np.array_equal(a.effort(j), b.effort(j))
