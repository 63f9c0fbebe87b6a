"""The MCAP writer follows the rosbag2 profile, survives SIGKILL, and recovers cut files."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest
import yaml

pytest.importorskip("mcap", reason="the record extra (mcap) is not installed")
pytest.importorskip("rosbags", reason="the record extra (rosbags) is not installed")
pytest.importorskip("mcap_ros2", reason="the record extra (mcap-ros2-support) is not installed")

from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_typestore

from linkage_ros.record.mcap import Recorder, absolute_topic, ros2msg_definition
from linkage_ros.record.mcap_read import read_mcap, recover

TS = get_typestore(Stores.ROS2_JAZZY)
T = TS.types
NS = 1_000_000_000
DT_NS = 10_000_000  # 100 Hz
TOPICS = [
    ("joint_states", "sensor_msgs/msg/JointState"),
    ("points/B/position", "geometry_msgs/msg/PointStamped"),
]
QOS_KEYS = ["history", "depth", "reliability", "durability", "deadline", "lifespan",
            "liveliness", "liveliness_lease_duration", "avoid_ros_namespace_conventions"]


def tick(k: int) -> list[tuple[str, object]]:
    ns = k * DT_NS
    header = T["std_msgs/msg/Header"](
        stamp=T["builtin_interfaces/msg/Time"](sec=ns // NS, nanosec=ns % NS), frame_id="world")
    js = T["sensor_msgs/msg/JointState"](
        header=header, name=["crank", "rocker"], position=np.array([0.01 * k, -0.02 * k]),
        velocity=np.array([1.0, 2.0]), effort=np.array([], dtype=float))
    pt = T["geometry_msgs/msg/PointStamped"](
        header=header, point=T["geometry_msgs/msg/Point"](x=float(k), y=0.5 * k, z=0.0))
    return [("joint_states", js), ("points/B/position", pt)]


def write(path: Path, n: int, **kw: object) -> None:
    with Recorder(path, TOPICS, typestore=TS, namespace="/mech", **kw) as rec:
        for k in range(n):
            rec.write(k * DT_NS, tick(k))


def test_topic_names_are_made_absolute_in_the_node_namespace() -> None:
    assert absolute_topic("joint_states", "/") == "/joint_states"
    assert absolute_topic("points/B/position", "/robot/arm/") == "/robot/arm/points/B/position"
    assert absolute_topic("/markers", "/robot") == "/markers"


def test_schema_text_is_the_complete_definition_in_rosbag2_layout() -> None:
    text = ros2msg_definition(TS, "geometry_msgs/msg/PointStamped")
    sep = "\n" + "=" * 80 + "\n"
    assert text == (
        "std_msgs/Header header\ngeometry_msgs/Point point\n"
        f"{sep}MSG: geometry_msgs/Point\nfloat64 x\nfloat64 y\nfloat64 z\n"
        f"{sep}MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id\n"
        f"{sep}MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n"
    )
    marker = ros2msg_definition(TS, "visualization_msgs/msg/MarkerArray")
    headers = [line for line in marker.splitlines() if line.startswith("MSG: ")]
    assert len(headers) == len(set(headers)), "each dependency appears once"
    assert "MSG: sensor_msgs/CompressedImage" in headers


def test_file_follows_the_rosbag2_profile(tmp_path: Path) -> None:
    path = tmp_path / "run.mcap"
    write(path, 50)
    with open(path, "rb") as fh:
        reader = make_reader(fh)
        assert reader.get_header().profile == "ros2"
        summary = reader.get_summary()
        assert summary is not None and summary.statistics.message_count == 100
        for schema in summary.schemas.values():
            assert schema.encoding == "ros2msg"
            assert schema.data.decode() == ros2msg_definition(TS, schema.name)
        topics = {}
        for channel in summary.channels.values():
            topics[channel.topic] = summary.schemas[channel.schema_id].name
            assert channel.message_encoding == "cdr"
            qos = yaml.safe_load(channel.metadata["offered_qos_profiles"])
            assert isinstance(qos, list) and list(qos[0]) == QOS_KEYS
            assert qos[0]["reliability"] == "reliable" and qos[0]["depth"] == 10
            assert qos[0]["deadline"] == {"sec": 9223372036, "nsec": 854775807}
            name = summary.schemas[channel.schema_id].name
            assert channel.metadata["topic_type_hash"] == TS.hash_rihs01(name)
        assert topics == {"/mech/joint_states": "sensor_msgs/msg/JointState",
                          "/mech/points/B/position": "geometry_msgs/msg/PointStamped"}
        for _, _, message in reader.iter_messages():
            stamp = TS.deserialize_cdr(
                message.data, topics[summary.channels[message.channel_id].topic]).header.stamp
            assert message.log_time == message.publish_time == stamp.sec * NS + stamp.nanosec
        bags = [m for m in reader.iter_metadata() if m.name == "rosbag2"]
    assert len(bags) == 2, "written at open and at close, as rosbag2's SequentialWriter does"
    final = yaml.safe_load(bags[-1].metadata["serialized_metadata"])
    assert final["version"] == 9 and final["ros_distro"] == "jazzy"
    assert final["storage_identifier"] == "mcap" and final["message_count"] == 100
    assert final["duration"]["nanoseconds"] == 49 * DT_NS
    counts = {t["topic_metadata"]["name"]: t["message_count"]
              for t in final["topics_with_message_count"]}
    assert counts == {"/mech/joint_states": 50, "/mech/points/B/position": 50}


def test_two_independent_readers_give_back_the_written_values(tmp_path: Path) -> None:
    path = tmp_path / "run.mcap"
    write(path, 30)
    with AnyReader([path], default_typestore=TS) as reader:
        rosbags_points = [reader.deserialize(raw, con.msgtype).point.x
                          for con, _, raw in reader.messages()
                          if con.topic == "/mech/points/B/position"]
    with open(path, "rb") as fh:
        decoded = make_reader(fh, decoder_factories=[DecoderFactory()])
        ros2_js = [msg.position for _, ch, _, msg in decoded.iter_decoded_messages()
                   if ch.topic == "/mech/joint_states"]
    assert rosbags_points == [float(k) for k in range(30)]
    np.testing.assert_array_equal(np.array(ros2_js), [[0.01 * k, -0.02 * k] for k in range(30)])


def test_a_chunk_is_closed_for_every_interval_of_message_time(tmp_path: Path) -> None:
    path = tmp_path / "run.mcap"
    write(path, 250, chunk_interval_s=0.5)  # 2.5 s of messages
    with open(path, "rb") as fh:
        summary = make_reader(fh).get_summary()
    assert summary is not None
    spans = [(c.message_end_time - c.message_start_time) for c in summary.chunk_indexes]
    assert len(spans) == 5 and max(spans) <= NS // 2


def test_recorder_refuses_writes_after_close(tmp_path: Path) -> None:
    rec = Recorder(tmp_path / "x.mcap", TOPICS, typestore=TS)
    rec.close()
    with pytest.raises(ValueError, match="is closed"):
        rec.write(0, tick(0))


def test_reader_refuses_a_file_that_is_not_mcap(tmp_path: Path) -> None:
    bad = tmp_path / "bad.mcap"
    bad.write_bytes(b"not an mcap file at all")
    with pytest.raises(ValueError, match="not an MCAP file"):
        read_mcap(bad)


CHILD = textwrap.dedent("""
    import sys, time
    sys.path.insert(0, {tests!r})
    from test_mcap import Recorder, TOPICS, TS, DT_NS, tick
    rec = Recorder(sys.argv[1], TOPICS, typestore=TS, chunk_interval_s=0.2)
    k = 0
    while True:
        rec.write(k * DT_NS, tick(k))
        print(k, flush=True)
        k += 1
        time.sleep(0.002)
""")


def test_sigkill_loses_at_most_the_open_chunk_and_the_file_can_be_recovered(
        tmp_path: Path) -> None:
    broken, fixed = tmp_path / "broken.mcap", tmp_path / "fixed.mcap"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD.format(tests=str(Path(__file__).parent)), str(broken)],
        stdout=subprocess.PIPE, text=True, env=env)
    assert child.stdout is not None
    last = -1
    deadline = time.monotonic() + 30
    while last < 120 and time.monotonic() < deadline:  # > 1.2 s of message time: 6 chunks
        last = int(child.stdout.readline())
    child.send_signal(signal.SIGKILL)
    child.wait()
    last = max([last, *(int(line) for line in child.stdout.read().split())])

    contents = read_mcap(broken)
    assert not contents.complete and contents.valid_bytes <= contents.size
    ks = [round(m.log_time / DT_NS) for m in contents.messages if m.topic == "/points/B/position"]
    assert ks == list(range(len(ks))), "every message before the cut, in order, none missing"
    assert last - ks[-1] <= 20, "lost at most the open chunk (0.2 s = 20 ticks)"

    recovered = recover(broken, fixed)
    assert len(recovered.messages) == 2 * len(ks)
    with open(fixed, "rb") as fh:
        summary = make_reader(fh).get_summary()
    assert summary is not None and summary.statistics.message_count == 2 * len(ks)
    with AnyReader([fixed], default_typestore=TS) as reader:
        assert sum(1 for _ in reader.messages()) == 2 * len(ks)
    bag = [m for m in read_mcap(fixed).metadata if m.name == "rosbag2"][-1]
    assert yaml.safe_load(bag.metadata["serialized_metadata"])["message_count"] == 2 * len(ks)


def test_recovering_a_finished_file_keeps_every_message(tmp_path: Path) -> None:
    path, copy = tmp_path / "run.mcap", tmp_path / "copy.mcap"
    write(path, 20)
    recover(path, copy)
    a, b = read_mcap(path), read_mcap(copy)
    assert b.complete and a.messages == b.messages and a.topics() == b.topics()
    with pytest.raises(ValueError, match="different path"):
        recover(path, path)


def test_mcap_cli_tells_a_cut_file_and_recovers_it(tmp_path: Path,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    from linkage_ros.cli import mcap_main

    path, cut, fixed = tmp_path / "run.mcap", tmp_path / "cut.mcap", tmp_path / "fixed.mcap"
    write(path, 200, chunk_interval_s=0.25)
    cut.write_bytes(path.read_bytes()[: int(path.stat().st_size * 0.7)])
    assert mcap_main(["info", str(cut)]) == 0
    out = capsys.readouterr().out
    assert "NOT finished" in out and "/mech/joint_states" in out
    assert mcap_main(["recover", str(cut), str(fixed)]) == 0
    assert "recovered" in capsys.readouterr().out
    assert mcap_main(["info", str(fixed)]) == 0
    assert f"{fixed}: finished;" in capsys.readouterr().out
    assert mcap_main(["info", str(tmp_path / "missing.mcap")]) == 2


def test_the_reader_is_still_importable_from_the_mcap_module() -> None:
    from linkage_ros.record import mcap, mcap_read

    for name in mcap_read.__all__:
        assert getattr(mcap, name) is getattr(mcap_read, name)
        assert name in mcap.__all__
