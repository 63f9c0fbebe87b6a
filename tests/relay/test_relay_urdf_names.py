"""The relay reads a cylinder under the URDF's own name (issue 30, must fix 2).

``linkage-urdf excavator`` writes a prismatic joint per cylinder (``boom_cylinder_rod_joint``,
...) whose coordinate is the stroke: what a ros2_control driver of that URDF publishes. The relay
reads every input under the scene's name or that joint (by default), or under the joint named per
input by ``input_joints``; joint_states then leaves out exactly the joints the driver publishes,
its own messages coming back are ignored under either naming, and a message without the inputs
is dropped with a reason that names what it carries (the runtime adds diagnostics WARN)."""

from __future__ import annotations

import pytest
from rosbags.typesys import Stores, get_typestore

from linkage_ros.engine import Engine
from linkage_ros.motion import Motion, Motions
from linkage_ros.relay import ANSWER_DROPPED, ANSWER_FRAME, ANSWER_IGNORED, Relay
from linkage_ros.runtime import Runtime

NS = 1_000_000_000
STORE = get_typestore(Stores.ROS2_JAZZY)
STROKES = ("boom_stroke", "arm_stroke", "bucket_stroke")
RODS = ("boom_cylinder_rod_joint", "arm_cylinder_rod_joint", "bucket_cylinder_rod_joint")
AT = [1.2, 1.5, 1.1]  # m, inside every stroke


def excavator() -> Engine:
    return Engine("excavator", Motions.of(3, phi0=(1.05, 1.3, 1.0), omega=(0.0, 0.0, 0.0), epsilon=(0.0,) * 3))


def test_the_urdf_rod_joints_drive_the_excavator_by_default() -> None:
    relay = Relay(excavator())
    answer = relay.answer(list(RODS), AT, [0.1, -0.1, 0.0], NS)
    assert answer.kind == ANSWER_FRAME and answer.frame is not None
    assert answer.phi == tuple(AT) and answer.omega == (0.1, -0.1, 0.0)
    names, q, _ = relay.joint_states(answer.frame, RODS)
    assert not set(RODS) & set(names) and set(STROKES) <= set(names)  # the driver has the rods
    assert [q[names.index(s)] for s in STROKES] == AT
    # the scene's names still work, and then the rods are published (robot_state_publisher needs them)
    scene_names = relay.answer(list(STROKES), AT, [], 2 * NS)
    assert scene_names.kind == ANSWER_FRAME and scene_names.frame is not None
    names, q, _ = relay.joint_states(scene_names.frame)
    assert set(RODS) <= set(names) and not set(STROKES) & set(names)
    assert [q[names.index(r)] for r in RODS] == pytest.approx(AT, abs=1e-15)


def test_its_own_joint_states_are_ignored_under_either_naming() -> None:
    relay = Relay(excavator())
    frame = relay.answer(list(RODS), AT, [0.0] * 3, NS).frame
    assert frame is not None
    for joints in (RODS, STROKES):
        names, q, dq = relay.joint_states(frame, joints)
        assert relay.answer(list(names), list(q), list(dq), 2 * NS).kind == ANSWER_IGNORED


def test_a_message_without_the_inputs_is_dropped_naming_both_names_and_what_it_carries() -> None:
    relay = Relay(excavator())
    answer = relay.answer(["swing_joint", "track_left"], [0.1, 0.2], [], NS)
    assert answer.kind == ANSWER_DROPPED
    assert answer.reason == (
        "no joint 'boom_stroke' or 'boom_cylinder_rod_joint', 'arm_stroke' or 'arm_cylinder_rod_joint', "
        "'bucket_stroke' or 'bucket_cylinder_rod_joint' in the message (every input is needed: boom_stroke, "
        "arm_stroke, bucket_stroke) (it carries: swing_joint, track_left)")
    mixed = relay.answer([RODS[0], STROKES[1]], [1.2, 1.5], [], NS)
    assert mixed.kind == ANSWER_DROPPED and mixed.reason.startswith(
        "no joint 'bucket_stroke' or 'bucket_cylinder_rod_joint' in the message")


def test_input_joints_maps_each_input_and_reads_only_that_name() -> None:
    relay = Relay(excavator(), input_joints=[RODS[0], "", "bucket_stroke"])
    assert relay.input_joints == (RODS[0], "arm_stroke", "bucket_stroke")
    assert relay.answer([RODS[0], RODS[1], "bucket_stroke"], AT, [], NS).kind == ANSWER_FRAME
    refused = relay.answer(list(STROKES), AT, [], NS)
    assert refused.kind == ANSWER_DROPPED and refused.reason.startswith(
        "no joint 'boom_cylinder_rod_joint' in the message")
    with pytest.raises(ValueError, match=r"input_joints needs 3 name\(s\), one per input of scene 'excavator' "
                                         r"\(boom_stroke, arm_stroke, bucket_stroke;"):
        Relay(excavator(), input_joints=[RODS[0]])
    with pytest.raises(ValueError, match="input_joints 'arm_cylinder_rod_joint' does not drive input 'boom_stroke' "
                                         "of scene 'excavator'.*accepted: boom_stroke, boom_cylinder_rod_joint"):
        Relay(excavator(), input_joints=[RODS[1], "", ""])


def test_one_cylinder_under_its_urdf_name_and_input_joint_against_input_joints() -> None:
    engine = Engine("tipper", Motion(phi0=0.9, omega=0.0))
    relay = Relay(engine)
    answer = relay.answer(["lift_rod_joint"], [0.95], [0.05], NS)
    assert answer.kind == ANSWER_FRAME and answer.phi == 0.95 and answer.omega == 0.05
    assert Relay(engine, input_joints=["lift_rod_joint"]).input_joint == "lift_rod_joint"
    with pytest.raises(ValueError, match="input_joint 'lift_rod_joint' and input_joints \\['stroke'\\] name different"):
        Relay(engine, input_joint="lift_rod_joint", input_joints=["stroke"])


def test_the_runtime_publishes_joint_states_without_the_joints_the_driver_names() -> None:
    runtime = Runtime({"scene": "excavator", "input_source": "topic", "input_phi0s": AT}, STORE.types)
    for stamp, names in ((NS, RODS), (2 * NS, STROKES), (3 * NS, RODS)):
        messages = dict(runtime.answer(list(names), AT, [0.0] * 3, stamp))
        js = STORE.deserialize_cdr(messages["joint_states"], "sensor_msgs/msg/JointState")
        assert not set(names) & set(js.name), names
        other = STROKES if names == RODS else RODS
        assert [js.position[list(js.name).index(n)] for n in other] == pytest.approx(AT, abs=1e-15)
    assert runtime.update({"input_joints": ["", "", "nope"]}, 4 * NS) == (
        "input_joints 'nope' does not drive input 'bucket_stroke' of scene 'excavator': the driver's joint must "
        "be the scene's input joint, a revolute joint of the input crank against the frame or the prismatic "
        "joint of the input actuator (linkage-urdf); accepted: bucket_stroke, bucket_cylinder_rod_joint")
    assert runtime.update({"input_joints": list(RODS)}, 4 * NS) is None
    assert runtime.relay is not None and runtime.relay.input_joints == RODS
    # clock mode checks the names too
    clock = Runtime({"scene": "excavator", "input_phi0s": AT}, STORE.types)
    assert "does not drive input 'boom_stroke'" in (clock.update({"input_joints": ["x", "", ""]}, NS) or "")
