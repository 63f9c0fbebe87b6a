"""What a ROS user tripped on (issue 19), without rclpy: resuming a stopped input, the relay's ε
rule and gap as parameters, remapped names in the recording, a scene that is a directory, the
five-bar's singular corner."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from rosbags.typesys import Stores, get_typestore

import solver
from linkage_ros.motion import SEGMENT_HOLD
from linkage_ros.parameters import PARAMETERS, validate_parameter
from linkage_ros.runtime import Runtime

STORE = get_typestore(Stores.ROS2_JAZZY)
NS = 1_000_000_000
T0 = 1_700_000_000 * NS
TICK = NS // 100
ROCKING = Path(__file__).parent / "data" / "rocking_four_bar.yaml"  # swings in |φ| ≤ 78.585°


def stopped_runtime(**values: object) -> tuple[Runtime, int]:
    """The rocking four-bar driven at 1 rad/s into its gap, held there; the next tick's clock."""
    runtime = Runtime({"scene": str(ROCKING), "omega": 1.0, **values}, STORE.types)
    now = T0
    while not runtime.take_events():
        runtime.tick(now)
        now += TICK
        assert now < T0 + 5 * NS, "the input never reached the gap"
    return runtime, now


def holding(runtime: Runtime, now: int) -> bool:
    return runtime.engine.motion.segment_at(runtime.run_time(now)).tag == SEGMENT_HOLD


# ---------------------------------------------------------------------------------------- resume
def test_setting_omega_to_the_value_it_has_resumes_a_stopped_input() -> None:
    runtime, now = stopped_runtime()
    assert holding(runtime, now)
    assert runtime.update({"omega": 1.0}, now) is None  # unchanged value
    assert not holding(runtime, now)
    assert runtime.engine.motion.state(runtime.run_time(now))[1] == 1.0


def test_setting_reverse_while_stopped_swings_the_input_back() -> None:
    runtime, now = stopped_runtime()
    held = runtime.last_frame
    assert held is not None and held.omega == 0.0
    assert runtime.update({"on_unassemblable": "reverse"}, now) is None
    for _ in range(100):
        runtime.tick(now)
        now += TICK
    frame = runtime.last_frame
    assert frame is not None and frame.omega == pytest.approx(-1.0)
    assert frame.phi < held.phi - 0.5  # one second back from the boundary


def test_a_set_of_a_parameter_outside_the_drive_leaves_the_input_held() -> None:
    runtime, now = stopped_runtime()
    assert runtime.update({"frame_id": "odom", "rate_hz": 50.0}, now) is None
    assert holding(runtime, now)


def test_epsilon_set_while_stopped_resumes_with_omega_and_epsilon() -> None:
    runtime, now = stopped_runtime(omega=-1.0, phi0=0.0)
    assert runtime.update({"epsilon": 0.0, "omega": -1.0}, now) is None
    _, omega, eps = runtime.engine.motion.state(runtime.run_time(now))
    assert (omega, eps) == (-1.0, 0.0)


# ---------------------------------------------------------------------------------------- relay
def test_the_relay_rule_and_gap_are_declared_parameters_with_ranges() -> None:
    specs = {spec.name: spec for spec in PARAMETERS}
    assert specs["topic_epsilon"].default == "zero" and "difference" in specs["topic_epsilon"].constraints
    assert specs["topic_max_gap"].kind == "double" and specs["topic_max_gap"].float_range == (1e-3, 60.0)
    assert specs["topic_max_gap"].default == 0.25 and specs["topic_epsilon"].description
    assert validate_parameter("topic_epsilon", "central") == (
        "topic_epsilon must be one of zero, difference, got 'central'")
    assert "topic_max_gap must lie in [0.001, 60]" in (validate_parameter("topic_max_gap", 0.0) or "")
    assert validate_parameter("topic_max_gap", 2.0) is None


def test_epsilon_difference_and_max_gap_act_on_the_answers_and_change_at_run_time() -> None:
    runtime = Runtime({"scene": "four_bar", "input_source": "topic", "topic_epsilon": "difference"},
                      STORE.types)
    runtime.answer(["crank"], [0.5], [1.0], T0)
    runtime.answer(["crank"], [0.51], [1.5], T0 + TICK)  # ε = 0.5 / 0.01 s
    assert runtime.last_frame is not None and runtime.last_frame.epsilon == pytest.approx(50.0, rel=1e-12)
    assert runtime.update({"topic_max_gap": 0.005}, T0) is None  # now 10 ms is too far apart
    runtime.answer(["crank"], [0.52], [2.0], T0 + 2 * TICK)
    runtime.answer(["crank"], [0.53], [2.5], T0 + 3 * TICK)
    assert runtime.last_frame.epsilon == 0.0
    assert runtime.update({"topic_epsilon": "zero", "topic_max_gap": 1.0}, T0) is None
    runtime.answer(["crank"], [0.54], [3.0], T0 + 4 * TICK)
    runtime.answer(["crank"], [0.55], [3.5], T0 + 5 * TICK)
    assert runtime.last_frame.epsilon == 0.0
    assert runtime.relay is not None and runtime.relay.max_gap_ns == NS
    assert runtime.update({"topic_epsilon": "central"}, T0) == (
        "topic_epsilon must be one of zero, difference, got 'central'")


# ---------------------------------------------------------------------------------------- scene
def test_a_scene_that_is_a_directory_is_called_one(tmp_path: Path) -> None:
    (tmp_path / "mine.yaml").write_text("scene: mine\n")
    with pytest.raises(solver.SceneError, match=r"is a directory, not a scene file; scene files in it: mine\.yaml"):
        solver.find_scene(tmp_path)
    assert validate_parameter("scene", str(tmp_path)) == (
        f"scene '{tmp_path}': is a directory, not a scene file; scene files in it: mine.yaml")
    assert "no such scene file" in (validate_parameter("scene", str(tmp_path / "absent")) or "")


def test_a_directory_of_many_scenes_says_how_many_it_leaves_out(tmp_path: Path) -> None:
    for i in range(7):
        (tmp_path / f"s{i}.yaml").write_text("scene: s\n")
    with pytest.raises(solver.SceneError, match=r"scene files in it: s0\.yaml, .*, s4\.yaml and 2 more$"):
        solver.find_scene(tmp_path)


def test_an_unknown_scene_is_named_once() -> None:
    reason = validate_parameter("scene", "nope") or ""
    assert reason.startswith("unknown scene 'nope': no such scene file, and no shipped scene of that name")
    assert reason.count("nope") == 1


def test_the_five_bar_at_its_stretched_corner_is_a_singular_position_of_group_distal() -> None:
    """(q1, q2) = (π, 0): A1, P, A2 on one line, the distal links stretched: P exists, its
    velocities do not. The solve's group with conditioning 0 is named (docs/ros.md)."""
    with pytest.raises(solver.AssemblyError, match=(
            r"^group 'distal' is at a singular position \(conditioning 0\) at 1 sample\(s\) of "
            r"\(q1, q2\) = \(180\.0000°, 0\.0000°\)$")):
        Runtime({"scene": "five_bar", "input_phi0s": [math.pi, 0.0]}, STORE.types)
    runtime = Runtime({"scene": "five_bar", "input_source": "topic"}, STORE.types)
    assert runtime.answer(["q1", "q2"], [math.pi, 0.0], [1.0, 1.0], T0)  # diagnostics only
    assert runtime.take_input_warnings() == [
        "group 'distal' is at a singular position (conditioning 0) at (q1, q2) = (3.14159, 0) rad"]


# ---------------------------------------------------------------------------------------- recording
def test_remapped_topics_are_recorded_under_their_wire_names_and_replayed(tmp_path: Path) -> None:
    pytest.importorskip("rclpy", reason="linkage_ros.node needs rclpy")
    from linkage_ros.node import mcap_recorder
    from linkage_ros.record.mcap import read_mcap
    from linkage_ros.record.replay import run_data_from_mcap

    remaps = {"joint_states": "/robot/joint_states", "joint_kinematics": "/kin"}

    def resolve(name: str) -> str:  # what Node.resolve_topic_name does with -r ... and __ns:=/arm
        return remaps.get(name, f"/arm/{name}")

    target = tmp_path / "remapped.mcap"
    runtime = Runtime({"scene": "four_bar", "record_mcap": str(target)}, STORE.types,
                      recorder_factory=mcap_recorder(resolve))
    for k in range(20):
        runtime.tick(T0 + k * TICK)
    runtime.close()
    topics = read_mcap(target).topics()
    assert {"/robot/joint_states", "/kin", "/arm/points/B/position", "/arm/markers"} <= set(topics)
    assert not {"/arm/joint_states", "/joint_states", "/arm/joint_kinematics"} & set(topics)
    data, _ = run_data_from_mcap(target)  # found through the metadata record, not the endings
    assert data.n == 20 and "rocker" in data.joints and "B" in data.positions
    assert data.t[0] == 0.0 and data.t[-1] == pytest.approx(0.19) and data.start_ns == T0
