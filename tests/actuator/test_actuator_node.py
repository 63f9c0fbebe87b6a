"""The node's logic for a scene driven by actuators, without rclpy: parameter descriptions and
start values in m, joint_states of the prismatic input (m, m/s, N), a stroke outside the range
rejected with the reason (the state kept), topic mode reading the cylinder's prismatic joint."""

from __future__ import annotations

import pytest

rosbags = pytest.importorskip("rosbags", reason="the node's message types come from rosbags")

from rosbags.typesys import Stores, get_typestore  # noqa: E402

import solver  # noqa: E402
from linkage_ros._relay_rates import Rates  # noqa: E402
from linkage_ros.engine import Engine  # noqa: E402
from linkage_ros.motion import Motion, Motions  # noqa: E402
from linkage_ros.parameters import SPECS, STROKE_RATE, for_scene, scene_defaults, start_scene  # noqa: E402
from linkage_ros.relay import ANSWER_FRAME, ANSWER_UNASSEMBLABLE, Relay  # noqa: E402
from linkage_ros.runtime import Runtime  # noqa: E402

STORE = get_typestore(Stores.ROS2_JAZZY)
NS = 1_000_000_000
T0 = 1_700_000_000 * NS


def test_the_input_parameters_are_described_in_metres_for_a_stroke() -> None:
    units, defaults = start_scene("tipper")
    assert units == ("m",) and defaults == {"phi0": 0.74, "omega": STROKE_RATE}
    omega, epsilon, phi0 = (for_scene(SPECS[n], units).description for n in ("omega", "epsilon", "phi0"))
    assert omega.startswith("Velocity of the input joint, m/s.") and "rad" not in omega
    assert epsilon.startswith("Acceleration of the input joint, m/s^2.") and "rad" not in epsilon
    assert phi0.startswith("Input stroke (length of the actuator) at the first tick, m.")
    assert for_scene(SPECS["omega"], ("rad",)) is SPECS["omega"]
    mixed = for_scene(SPECS["input_omegas"], ("rad", "m")).description
    assert mixed.endswith("(rad, rad/s, rad/s^2 for a crank's angle; m, m/s, m/s^2 for an actuator's stroke)")
    assert scene_defaults(solver.load_scene("excavator")) == {"input_phi0s": [1.05, 1.3, 1.0],
                                                              "input_omegas": [STROKE_RATE] * 3}
    assert scene_defaults(solver.load_scene("five_bar")) == {}


def test_joint_states_carry_the_stroke_its_rate_and_the_cylinder_force() -> None:
    runtime = Runtime({"scene": "tipper", "phi0": 0.8, "omega": 0.1}, STORE.types)
    runtime.tick(T0)
    messages = dict(runtime.tick(T0 + NS // 2))
    js = STORE.deserialize_cdr(messages["joint_states"], "sensor_msgs/msg/JointState")
    k = solver.load_scene("tipper").solve(0.85, omega=0.1, epsilon=0.0)
    for name in ("stroke", "lift_rod_joint"):  # the scene's input joint and the URDF's prismatic joint
        i = js.name.index(name)
        assert js.position[i] == pytest.approx(0.85, abs=4e-16) and js.velocity[i] == pytest.approx(0.1, abs=4e-16)
        assert js.effort[i] == pytest.approx(k.effort("stroke"), rel=1e-12)  # N, extending positive


def test_a_stroke_outside_the_range_is_rejected_and_the_node_keeps_its_state() -> None:
    runtime = Runtime({"scene": "tipper", "phi0": 0.8, "omega": 0.1}, STORE.types)
    runtime.tick(T0)
    reason = runtime.update({"phi0": 1.5}, T0 + NS // 10)
    assert reason is not None and "group 'lift' is outside its stroke [0.74, 1.3] m" in reason
    assert runtime.settings["phi0"] == 0.8
    assert runtime.update({"phi0": 1.0}, T0 + NS // 5) is None and runtime.settings["phi0"] == 1.0


def test_topic_mode_reads_the_prismatic_joint_of_the_cylinder() -> None:
    relay = Relay(Engine("tipper", Motion(phi0=0.8)), input_joint="lift_rod_joint")
    assert relay.input_joint == "lift_rod_joint" and "lift_rod_joint" not in relay.published_joints
    first = relay.answer(["lift_rod_joint"], [0.9], [], T0)
    second = relay.answer(["lift_rod_joint"], [0.95], [], T0 + NS // 10)
    assert first.kind == second.kind == ANSWER_FRAME
    assert second.frame is not None and second.frame.phi == 0.95
    assert second.omega == pytest.approx(0.5, rel=1e-12)  # (0.95 − 0.9)/0.1 s, m/s
    out = relay.answer(["lift_rod_joint"], [1.5], [0.0], T0 + NS // 5)
    assert out.kind == ANSWER_UNASSEMBLABLE and out.frame is None
    assert out.reason == ("group 'lift' is outside its stroke [0.74, 1.3] m (closed and open lengths) for "
                          "s = 1.5 m (lift_rod_joint = 1.5)")
    with pytest.raises(ValueError, match=r"accepted: stroke, lift_rod_joint$"):
        Relay(Engine("tipper", Motion(phi0=0.8)), input_joint="lift_joint")


def test_strokes_are_differenced_without_wrapping() -> None:
    rates = Rates(rule="zero", max_gap_ns=NS, strokes=(True,))
    rates.one(T0, 0.0, None)
    omega, *_ = rates.one(T0 + NS // 2, 4.0, None)
    assert omega == 8.0  # an angle would have wrapped 4 rad to 4 − 2π


def test_several_actuators_are_read_by_their_input_names() -> None:
    engine = Engine("excavator", Motions.of(3, phi0=(1.3, 1.6, 1.2), omega=0.0, epsilon=0.0))
    relay = Relay(engine)
    answer = relay.answer(["boom_stroke", "arm_stroke", "bucket_stroke"], [1.3, 1.6, 1.2], [0.1, 0.0, -0.1], T0)
    assert answer.kind == ANSWER_FRAME and answer.frame is not None
    assert answer.frame.phi == (1.3, 1.6, 1.2)
    assert set(answer.frame.efforts) == {"boom_stroke", "arm_stroke", "bucket_stroke"}
