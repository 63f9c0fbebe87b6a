"""The message builder: every topic, real Jazzy field names through a CDR round trip, one stamp
and frame_id per tick, valid markers; the same builder with rclpy's generated classes."""

from __future__ import annotations

import array
import math
from pathlib import Path

import numpy as np
import pytest
from rosbags.typesys import Stores, get_typestore

from linkage_ros.engine import Engine
from linkage_ros.frame import STATUS_UNASSEMBLABLE
from linkage_ros.messages import MessageBuilder, MessageTypes, build_messages
from linkage_ros.motion import Motion
from linkage_ros.topics import FIXED_TOPIC_TYPES, point_topics, stamp_parts, topic_types
from linkage_ros.urdf import exportable_model, frame_tree_joint_states

STAMP = 1_700_000_123_456_789_012
FRAME_ID = "mechanism"
STORE = get_typestore(Stores.ROS2_JAZZY)
ROCKING = Path(__file__).parent / "data" / "rocking_four_bar.yaml"


@pytest.fixture(scope="module")
def harvester() -> Engine:
    return Engine("harvester_finger", Motion(phi0=0.3, omega=2.0, epsilon=0.1))


def round_trip(messages: list[tuple[str, object]]) -> dict[str, object]:
    out = {}
    for topic, message in messages:
        typename = type(message).__msgtype__  # type: ignore[attr-defined]
        out[topic] = STORE.deserialize_cdr(STORE.serialize_cdr(message, typename), typename)
    return out


def test_every_topic_is_built_in_the_declared_order(harvester: Engine) -> None:
    messages = build_messages(harvester.frame(1.0), STORE.types, frame_id=FRAME_ID, stamp=STAMP, engine=harvester)
    declared = topic_types(harvester)
    assert [t for t, _ in messages] == [t for t, _ in declared]
    assert [type(m).__msgtype__ for _, m in messages] == [ty for _, ty in declared]  # type: ignore[attr-defined]
    # the harvester finger has bodies and loads: a wrench topic per pin and slide (issue 17)
    assert len(declared) == len(FIXED_TOPIC_TYPES) + 3 * len(harvester.published_points) + len(harvester.load_pairs)
    assert point_topics("C") == ("points/C/position", "points/C/velocity", "points/C/acceleration")


def test_cdr_round_trip_keeps_names_and_values(harvester: Engine) -> None:
    frame = harvester.frame(1.0)
    back = round_trip(build_messages(frame, STORE.types, frame_id=FRAME_ID, stamp=STAMP, engine=harvester))
    joints = list(harvester.scene.joint_names)
    tree = frame_tree_joint_states(exportable_model(harvester.scene), frame)
    js = back["joint_states"]
    # the scene's joints, then the URDF tree's joints for robot_state_publisher (issue 8)
    assert js.name == joints + list(tree.names)  # type: ignore[attr-defined]
    np.testing.assert_array_equal(js.position, [*(frame.joints[j].position for j in joints), *tree.position])  # type: ignore[attr-defined]
    np.testing.assert_array_equal(js.velocity, [*(frame.joints[j].velocity for j in joints), *tree.velocity])  # type: ignore[attr-defined]
    # bodies and loads (issue 17): the input's effort, on the tree's drum joint too, 0 elsewhere
    effort = dict(zip(js.name, js.effort))  # type: ignore[attr-defined]
    assert effort.pop("drum") == effort.pop("drum_joint") == frame.efforts["drum"]
    assert set(effort.values()) == {0.0}
    jk = back["joint_kinematics"]
    assert jk.joint_names == joints and len(jk.points) == 1  # type: ignore[attr-defined]
    (point,) = jk.points  # type: ignore[attr-defined]
    np.testing.assert_array_equal(point.positions, [frame.joints[j].position for j in joints])
    np.testing.assert_array_equal(point.velocities, [frame.joints[j].velocity for j in joints])
    np.testing.assert_array_equal(point.accelerations, [frame.joints[j].acceleration for j in joints])
    assert (point.time_from_start.sec, point.time_from_start.nanosec) == (0, 0)
    for name in harvester.published_points:
        pos, vel, acc = point_topics(name)
        state = frame.points[name]
        p = back[pos].point  # type: ignore[attr-defined]
        assert (p.x, p.y, p.z) == (state.position[0], state.position[1], 0.0)
        v = back[vel].vector  # type: ignore[attr-defined]
        assert (v.x, v.y, v.z) == (state.velocity[0], state.velocity[1], 0.0)
        a = back[acc].vector  # type: ignore[attr-defined]
        assert (a.x, a.y, a.z) == (state.acceleration[0], state.acceleration[1], 0.0)
    diag = back["diagnostics"].status[0]  # type: ignore[attr-defined]
    assert diag.level == 0 and diag.message == "ok"
    values = {kv.key: kv.value for kv in diag.values}
    assert float(values["phi"]) == frame.phi
    assert float(values["conditioning"]) == pytest.approx(frame.conditioning, rel=1e-5)
    assert values["status"] == "ok"


def test_all_messages_of_a_tick_carry_one_stamp_and_frame_id(harvester: Engine) -> None:
    back = round_trip(
        build_messages(harvester.frame(2.0), STORE.types, frame_id=FRAME_ID, stamp=STAMP, engine=harvester)
    )
    sec, nanosec = stamp_parts(STAMP)
    headers = [m.header for t, m in back.items() if hasattr(m, "header")]  # type: ignore[attr-defined]
    headers += [m.header for m in back["markers"].markers]  # type: ignore[attr-defined]
    assert len(headers) == len(back) - 1 + len(back["markers"].markers)  # type: ignore[attr-defined]
    for header in headers:
        assert (header.stamp.sec, header.stamp.nanosec, header.frame_id) == (sec, nanosec, FRAME_ID)


def test_stamps_split_into_seconds_and_nanoseconds() -> None:
    assert stamp_parts(STAMP) == (1_700_000_123, 456_789_012)
    assert stamp_parts(-1) == (-1, 999_999_999)


def test_markers_draw_links_joints_fixed_pivots_and_paths(harvester: Engine) -> None:
    frame = harvester.frame(0.5)
    back = round_trip(build_messages(frame, STORE.types, frame_id=FRAME_ID, stamp=STAMP, engine=harvester))
    M = STORE.types["visualization_msgs/msg/Marker"]
    markers = {(m.ns, m.id): m for m in back["markers"].markers}  # type: ignore[attr-defined]
    assert set(markers) == {("links", 0), ("joints", 0), ("fixed_pivots", 0), *(("paths", i) for i in range(3)),
                            *((ns, i) for ns in ("loads", "load_labels") for i in range(len(harvester.load_pairs)))}
    for i, pair in enumerate(harvester.load_pairs):  # each arrow labelled with its pin, at its tip (issue 24)
        arrow, label = markers[("loads", i)], markers[("load_labels", i)]
        assert label.type == M.TEXT_VIEW_FACING and label.text == f"R_{pair.key}"
        assert (label.pose.position.x, label.pose.position.y) == (arrow.points[1].x, arrow.points[1].y)
    links = markers[("links", 0)]
    assert links.type == M.LINE_LIST and len(links.points) % 2 == 0
    segments = sum(len(link.points) - 1 for link in harvester.scene.links)
    assert len(links.points) == 2 * segments
    joints = markers[("joints", 0)]
    assert joints.type == M.SPHERE_LIST
    moving = [p for p in harvester.scene.point_names if p not in harvester.scene.fixed_points]
    assert [(q.x, q.y) for q in joints.points] == [tuple(frame.points[p].position) for p in moving]
    fixed = markers[("fixed_pivots", 0)]
    assert fixed.type == M.CUBE_LIST and len(fixed.points) == len(harvester.scene.fixed_points)
    assert (fixed.color.r, fixed.color.g, fixed.color.b) != (joints.color.r, joints.color.g, joints.color.b)
    for i, name in enumerate(harvester.published_points):
        path = markers[("paths", i)]
        assert path.type == M.LINE_STRIP
        np.testing.assert_array_equal([(q.x, q.y) for q in path.points], harvester.paths[name])
    for m in markers.values():
        assert m.action == M.ADD
        assert m.pose.orientation.w == 1.0
        assert m.scale.x > 0 and m.color.a > 0
        assert all(math.isfinite(c) for q in m.points for c in (q.x, q.y, q.z))


def test_paths_are_sent_first_and_then_once_per_period(harvester: Engine) -> None:
    builder = MessageBuilder(harvester, STORE.types, frame_id=FRAME_ID, path_period=1.0)
    carried = []
    for k in range(0, 250):
        t = k / 100.0
        messages = dict(builder.build(harvester.frame(t), STAMP + k))
        carried.append(any(m.ns == "paths" for m in messages["markers"].markers))  # type: ignore[attr-defined]
    assert [k for k, c in enumerate(carried) if c] == [0, 100, 200]
    every = MessageBuilder(harvester, STORE.types, frame_id=FRAME_ID, path_period=0.0)
    assert all(
        any(m.ns == "paths" for m in dict(every.build(harvester.frame(k / 100), STAMP))["markers"].markers)  # type: ignore[attr-defined]
        for k in range(5)
    )


def test_spatial_scenes_publish_three_coordinates() -> None:
    engine = Engine("spherical_converter", Motion(phi0=0.2, omega=1.0))
    frame = engine.frame(0.7)
    back = round_trip(build_messages(frame, STORE.types, frame_id=FRAME_ID, stamp=STAMP, engine=engine))
    p = back["points/K/position"].point  # type: ignore[attr-defined]
    np.testing.assert_array_equal((p.x, p.y, p.z), frame.points["K"].position)


def test_diagnostics_report_an_unassemblable_input_as_error() -> None:
    engine = Engine(ROCKING, Motion(phi0=0.0, omega=1.0))
    frame = next(f for f in (engine.frame(k / 100) for k in range(400)) if f.status == STATUS_UNASSEMBLABLE)
    back = round_trip(build_messages(frame, STORE.types, frame_id=FRAME_ID, stamp=STAMP, engine=engine))
    status = back["diagnostics"].status[0]  # type: ignore[attr-defined]
    S = STORE.types["diagnostic_msgs/msg/DiagnosticStatus"]
    assert status.level == S.ERROR
    assert "cannot be assembled for φ in (78.58" in status.message
    assert {kv.key for kv in status.values} >= {"phi", "omega", "epsilon", "conditioning", "status", "t"}


def test_the_same_builder_serves_rclpy_classes(harvester: Engine) -> None:
    from rclpy.serialization import serialize_message

    from linkage_ros.node import message_classes

    types = MessageTypes(message_classes())
    assert types.flavour == "rclpy"
    frame = harvester.frame(1.0)
    messages = dict(build_messages(frame, types, frame_id=FRAME_ID, stamp=STAMP, engine=harvester))
    js = messages["joint_states"]
    assert isinstance(js.position, array.array) and js.position.typecode == "d"
    n = len(harvester.scene.joint_names)
    assert list(js.position)[:n] == [frame.joints[j].position for j in harvester.scene.joint_names]
    status = messages["diagnostics"].status[0]
    assert status.level == b"\x00"  # rclpy's byte fields are bytes
    # the same content as the rosbags build: rclpy's CDR decodes to the same values
    reference = round_trip(build_messages(frame, STORE.types, frame_id=FRAME_ID, stamp=STAMP, engine=harvester))
    for topic, message in messages.items():
        typename = dict(topic_types(harvester))[topic]
        decoded = STORE.deserialize_cdr(_unpadded(serialize_message(message), typename), typename)
        assert repr(decoded) == repr(reference[topic]), topic


def _unpadded(data: bytes, typename: str) -> bytes:
    """rclpy's CDR without the trailing padding rosbags does not accept."""
    for end in range(len(data), len(data) - 8, -1):
        try:
            STORE.deserialize_cdr(data[:end], typename)
        except Exception:
            continue
        return data[:end]
    raise AssertionError(f"no unpadded prefix of rclpy's {typename} decodes")


def test_missing_message_classes_are_named() -> None:
    partial = dict(STORE.types)
    del partial["visualization_msgs/msg/Marker"]
    with pytest.raises(KeyError, match="visualization_msgs/msg/Marker"):
        MessageTypes(partial)


def test_the_topic_table_is_still_importable_from_the_messages_module() -> None:
    from linkage_ros import messages, topics

    for name in topics.__all__:
        assert getattr(messages, name) is getattr(topics, name)
        assert name in messages.__all__
