"""CDR bytes from templates (linkage_ros.serialize): byte for byte what the message builder
and rosbags' serialiser give, for every shipped scene; readable by rclpy's deserialiser."""

from __future__ import annotations

from pathlib import Path

import pytest
from rosbags.typesys import Stores, get_typestore

import solver
from linkage_ros.engine import Engine
from linkage_ros.messages import DIAGNOSTICS, MARKERS, MessageBuilder
from linkage_ros.motion import Motion
from linkage_ros.serialize import Serializer, pad4

STORE = get_typestore(Stores.ROS2_JAZZY)
STAMP = 1_700_000_000_123_456_789
ROOT = Path(__file__).resolve().parents[2]
SCENES = sorted(
    p for p in (ROOT / "config" / "scenes").rglob("*.yaml")
    if len(getattr(solver.load_scene(p), "inputs", (None,))) == 1  # the node drives one input
)


def ordinary(engine: Engine, frame: object, stamp: int, *, paths: bool) -> list[tuple[str, bytes]]:
    builder = MessageBuilder(engine, STORE.types, frame_id="world")
    types = dict(builder.topics)
    return [(t, pad4(STORE.serialize_cdr(m, types[t])))
            for t, m in builder.build(frame, stamp, include_paths=paths)]  # type: ignore[arg-type]


@pytest.mark.parametrize("scene", SCENES, ids=lambda p: p.stem)
def test_templates_give_the_builders_bytes(scene: Path) -> None:
    span = solver.load_scene(scene).input_ranges[0]  # an actuator's stroke: from its closed length, m/s
    engine = Engine(scene, Motion(phi0=0.1, omega=2.0, epsilon=0.3) if span is None else Motion(
        phi0=span[0] + 0.01, omega=0.2, epsilon=0.3))
    wire = Serializer(MessageBuilder(engine, STORE.types, frame_id="world"), STORE.serialize_cdr)
    first = engine.frame(0.0)
    assert wire.verify(first, STAMP) == []
    assert set(wire.template_topics) == {t for t, _ in engine_topics(engine)} - {DIAGNOSTICS}
    assert wire.render(first, STAMP, paths=True) == ordinary(engine, first, STAMP, paths=True)
    later = engine.frame(0.037)
    expected = [(t, b) for t, b in ordinary(engine, later, STAMP + 37_000_000, paths=False) if t != DIAGNOSTICS]
    assert wire.render(later, STAMP + 37_000_000, diagnostics=False) == expected


def engine_topics(engine: Engine) -> list[tuple[str, str]]:
    from linkage_ros.messages import topic_types

    return topic_types(engine)


def test_rclpy_reads_the_bytes() -> None:
    from rclpy.serialization import deserialize_message

    from linkage_ros.node import message_classes

    engine = Engine("four_bar", Motion(omega=2.0))
    builder = MessageBuilder(engine, STORE.types, frame_id="world")
    wire = Serializer(builder, STORE.serialize_cdr)
    frame = engine.frame(0.25)
    classes = message_classes(sorted(set(dict(builder.topics).values())))
    for topic, data in wire.render(frame, STAMP, paths=True):
        message = deserialize_message(data, classes[dict(builder.topics)[topic]])
        header = message.markers[0].header if topic == MARKERS else message.header
        assert (header.stamp.sec, header.stamp.nanosec) == divmod(STAMP, 1_000_000_000), topic
    for topic, data in wire.render(frame, STAMP, paths=True):  # rosbags reads the padded bytes too
        assert len(data) % 4 == 0
        STORE.deserialize_cdr(data, dict(builder.topics)[topic])
    js = deserialize_message(dict(wire.render(frame, STAMP))["joint_states"], classes["sensor_msgs/msg/JointState"])
    assert js.position[0] == frame.joints["crank"].position
