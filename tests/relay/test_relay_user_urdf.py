"""The user's own URDF: config/urdf/gripper_finger.urdf (hand-written, not from linkage-urdf) posed
by yourdfpy with the driver's ``finger_joint`` and the relay's passive joints closes its loop.

The scene config/scenes/gripper_finger.yaml names and measures the URDF's joints the URDF's way
(``{revolute: {parent, child, offset, sign}}``); the driver publishes ``finger_joint`` only.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yourdfpy

import solver
from linkage_ros.engine import Engine
from linkage_ros.motion import Motion
from linkage_ros.relay import ANSWER_FRAME, Relay

ROOT = Path(__file__).resolve().parents[2]
URDF = ROOT / "config" / "urdf" / "gripper_finger.urdf"
#: The two frames of the cut pin B, and the fingertip, against the solver (m).
CLOSURE_TOL = 1e-12
NS = 1_000_000_000


@pytest.fixture(scope="module")
def robot() -> yourdfpy.URDF:
    return yourdfpy.URDF.load(str(URDF), load_meshes=False, build_scene_graph=True)


@pytest.fixture(scope="module")
def relay() -> Relay:
    return Relay(Engine("gripper_finger", Motion()), input_joint="finger_joint")


def test_the_hand_written_urdf_is_valid_and_its_movable_joints_are_the_scenes(robot: yourdfpy.URDF) -> None:
    assert robot.validate()
    scene = solver.load_scene("gripper_finger")
    assert set(robot.actuated_joint_names) == {"finger_joint", "distal_joint", "follower_joint"}
    assert set(robot.actuated_joint_names) <= set(scene.joint_names)


def test_topic_mode_publishes_the_passive_urdf_joints_but_not_the_drivers(relay: Relay) -> None:
    assert relay.input_joint == "finger_joint"
    assert "finger_joint" not in relay.published_joints
    assert {"distal_joint", "follower_joint"} <= set(relay.published_joints)


@pytest.mark.parametrize("step", [0.1, 10.0], ids=["0.1deg", "10deg"])
def test_driver_angle_plus_relay_joints_close_the_loop_of_the_users_urdf(
    robot: yourdfpy.URDF, relay: Relay, step: float
) -> None:
    urdf_joints = set(robot.actuated_joint_names)
    worst = 0.0
    for i, q_driver in enumerate(np.arange(-200.0, 200.0, step)):
        q = math.radians(float(q_driver))
        answer = relay.answer(["finger_joint"], [q], [0.8], (i + 1) * NS // 100)
        assert answer.kind == ANSWER_FRAME and answer.frame is not None, answer.reason
        names, positions, _ = relay.joint_states(answer.frame)
        cfg = {n: v for n, v in zip(names, positions) if n in urdf_joints}
        cfg["finger_joint"] = q  # what the driver publishes
        assert set(cfg) == urdf_joints
        robot.update_cfg(cfg)
        on_distal = robot.get_transform("pin_b_on_distal", "palm")[:3, 3]
        on_follower = robot.get_transform("pin_b_on_follower", "palm")[:3, 3]
        tip = robot.get_transform("fingertip", "palm")[:3, 3]
        b = answer.frame.points["B"].position
        t = answer.frame.points["T"].position
        worst = max(
            worst,
            float(np.max(np.abs(on_distal - on_follower))),
            abs(on_distal[0] - b[0]), abs(on_distal[1] - b[1]),
            abs(tip[0] - t[0]), abs(tip[1] - t[1]),
        )
    assert worst <= CLOSURE_TOL


def test_the_driver_joint_maps_to_phi_by_the_scenes_offset_and_sign(relay: Relay) -> None:
    # finger_joint = 90° − φ (zero pointing up, positive clockwise)
    answer = relay.answer(["finger_joint"], [math.radians(30.0)], [2.0], NS)
    assert answer.phi == pytest.approx(math.radians(60.0), abs=1e-15)
    assert answer.omega == -2.0
    assert answer.frame is not None
    finger = answer.frame.joints["finger_joint"]
    assert finger.position == pytest.approx(math.radians(30.0), abs=1e-15)
    assert finger.velocity == pytest.approx(2.0, rel=1e-15)


def test_rates_of_the_driver_joint_turn_with_its_sign() -> None:
    relay = Relay(Engine("gripper_finger", Motion()), input_joint="finger_joint", epsilon="difference")
    relay.answer(["finger_joint"], [0.10], [1.0], NS)
    answer = relay.answer(["finger_joint"], [0.11], [1.5], NS + NS // 100)
    assert answer.omega == -1.5 and answer.epsilon == pytest.approx(-50.0, rel=1e-12)
    from_positions = Relay(Engine("gripper_finger", Motion()), input_joint="finger_joint")
    from_positions.answer(["finger_joint"], [0.10], [], NS)
    later = from_positions.answer(["finger_joint"], [0.11], [], NS + NS // 100)
    assert later.omega == pytest.approx(-1.0, rel=1e-9)
