"""Topic mode's raw input (linkage_ros.serialize.read_joint_state): names, positions,
velocities and stamp read straight off a JointState's CDR bytes equal what rosbags' and rclpy's
deserialisers read, for any names, array lengths and frame_id; anything unusual is handed to
the ordinary deserialiser (None), never an exception."""

from __future__ import annotations

from typing import Any

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from rosbags.typesys import Stores, get_typestore

from linkage_ros.serialize import pad4, read_joint_state

STORE = get_typestore(Stores.ROS2_JAZZY)
TYPE = "sensor_msgs/msg/JointState"
JointState, Header, Time = (STORE.types[t] for t in (TYPE, "std_msgs/msg/Header", "builtin_interfaces/msg/Time"))

names = st.lists(st.text(max_size=12), max_size=4)
floats = st.lists(st.floats(allow_nan=False, width=64, min_value=-1e9, max_value=1e9), max_size=4)


def message(stamp: tuple[int, int], frame_id: str, name: list[str], position: list[float],
            velocity: list[float], effort: list[float]) -> Any:
    return JointState(header=Header(stamp=Time(sec=stamp[0], nanosec=stamp[1]), frame_id=frame_id), name=name,
                      position=np.array(position, dtype=float), velocity=np.array(velocity, dtype=float),
                      effort=np.array(effort, dtype=float))


@settings(max_examples=300, deadline=None)
@given(stamp=st.tuples(st.integers(0, 2**31 - 1), st.integers(0, 999_999_999)),
       frame_id=st.text(max_size=9), name=names, position=floats, velocity=floats, effort=floats)
def test_the_fields_read_off_the_bytes_are_the_deserialisers(stamp: tuple[int, int], frame_id: str, name: list[str],
                                                              position: list[float], velocity: list[float],
                                                              effort: list[float]) -> None:
    if any("\x00" in n for n in (*name, frame_id)):  # ROS strings end at their NUL
        return
    data = bytes(STORE.serialize_cdr(message(stamp, frame_id, name, position, velocity, effort), TYPE))
    for raw in (data, pad4(data), data + bytes(4)):  # as rosbags writes it, as Fast DDS sends it
        got = read_joint_state(raw)
        assert got is not None
        assert got == (name, tuple(position), tuple(velocity), stamp[0] * 1_000_000_000 + stamp[1])
    for cut in range(len(data)):  # truncated: read or handed back, never an exception
        read_joint_state(data[:cut])


def test_rclpys_bytes_are_read_and_odd_bytes_handed_back() -> None:
    from rclpy.serialization import serialize_message
    from sensor_msgs.msg import JointState as RclpyJointState

    msg = RclpyJointState(name=["crank", "coupler"], position=[0.25, -1.5], velocity=[2.0, 0.5])
    msg.header.stamp.sec, msg.header.stamp.nanosec, msg.header.frame_id = 17, 42, "world"
    assert read_joint_state(serialize_message(msg)) == (["crank", "coupler"], (0.25, -1.5), (2.0, 0.5),
                                                         17_000_000_042)
    data = bytes(STORE.serialize_cdr(message((1, 2), "w", ["crank"], [0.1], [], []), TYPE))
    assert read_joint_state(data)[2] == ()  # type: ignore[index]  # no velocities: an empty tuple
    assert read_joint_state(b"\x01\x01" + data[2:]) is None  # big endian: the ordinary deserialiser
    assert read_joint_state(data[:20]) is None
    bad_count = data[:20] + (10**6).to_bytes(4, "little") + data[24:]
    assert read_joint_state(bad_count) is None
    assert read_joint_state(b"") is None
