"""MCAP recording in the rosbag2 profile (as ROS 2 Jazzy's rosbag2 writes it; the rosbag2 parts
are in :mod:`.rosbag2`). Reading, including files cut short by a crash, and their recovery are in
:mod:`.mcap_read` (re-exported here: ``from linkage_ros.record.mcap import read_mcap`` works).

The layout follows ``rosbag2_storage_mcap``:

* header profile ``ros2``; schemas with encoding ``ros2msg`` holding the complete definition
  (the type's own text, then every dependency once, depth first in sorted order, each after a
  blank line, a line of 80 ``=`` and ``MSG: pkg/Name``); channels with message encoding ``cdr``
  and the metadata ``offered_qos_profiles`` (YAML, metadata version 9 strings) and
  ``topic_type_hash`` (RIHS01); messages with log time = publish time = the message stamp, ns;
* a metadata record ``rosbag2`` with key ``serialized_metadata`` (the bag's metadata, version 9)
  written when the file is opened and again when it is closed, as rosbag2's SequentialWriter does;
* uncompressed chunks. rosbag2 closes a chunk when it reaches 768 KiB; we also close it when
  ``chunk_interval_s`` of message time or of wall-clock time has passed, and flush the file, so a
  process killed with SIGKILL loses at most the open chunk.

Not reproduced byte for byte: the definitions carry no comments (rosbag2 copies the ``.msg``
files, comments included; rosbags' Jazzy type store has none), and the header's library string
names this package instead of ``libmcap``.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from functools import partial
from pathlib import Path
from typing import Any, BinaryIO

from mcap.writer import CompressionType, Writer

from .mcap_read import McapContents, RawMessage, iter_messages, read_mcap, recover
from .rosbag2 import (
    CHUNK_INTERVAL_S,
    CHUNK_SIZE,
    QOS_DEPTH,
    TopicInfo,
    absolute_topic,
    bag_metadata,
    default_typestore,
    library,
    offered_qos_profiles,
    ros2msg_definition,
)

__all__ = [
    "CHUNK_INTERVAL_S",
    "QOS_DEPTH",
    "McapContents",
    "RawMessage",
    "Recorder",
    "absolute_topic",
    "iter_messages",
    "offered_qos_profiles",
    "read_mcap",
    "recover",
    "ros2msg_definition",
]

NS_PER_S = 1_000_000_000


class Recorder:
    """Writes ``(topic, message)`` lists, one call per tick, into a rosbag2-profile MCAP file.

    ``topics``: ``(name, ros type)`` pairs, e.g. ``("joint_states", "sensor_msgs/msg/JointState")``;
    relative names are resolved in ``namespace``, or by ``resolve(name) -> absolute name`` when
    given (a live node passes its ``resolve_topic_name``, so that remapped topics are recorded
    under the names on the wire). Messages of other topics are accepted when they
    carry their type (rosbags messages have ``__msgtype__``). ``serialize(msg, typename) -> bytes``
    defaults to the rosbags type store's CDR serialiser, padded to 4 bytes as every producer of
    the node's messages writes them (:func:`linkage_ros.serialize.cdr_bytes`); a live rclpy node passes
    ``lambda m, _: rclpy.serialization.serialize_message(m)``. ``metadata``: extra metadata
    records written when the file is opened (name → string map), e.g. the ``linkage_ros`` scene
    description of :func:`linkage_ros.record.replay.scene_metadata` that names what the markers
    draw.
    """

    def __init__(self, path: str | os.PathLike[str], topics: Sequence[tuple[str, str]] = (), *,
                 typestore: Any = None, namespace: str = "/",
                 resolve: Callable[[str], str] | None = None,
                 serialize: Callable[[Any, str], bytes] | None = None,
                 chunk_interval_s: float = CHUNK_INTERVAL_S, chunk_size: int = CHUNK_SIZE,
                 qos_depth: int = QOS_DEPTH, fsync: bool = False,
                 metadata: Mapping[str, Mapping[str, str]] | None = None) -> None:
        if not chunk_interval_s > 0:
            raise ValueError(f"chunk_interval_s must be > 0, got {chunk_interval_s!r}")
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._ts = typestore if typestore is not None else default_typestore()
        if serialize is None:
            from linkage_ros.serialize import cdr_bytes

            serialize = partial(cdr_bytes, self._ts.serialize_cdr)
        self._serialize = serialize
        self._resolve = resolve or (lambda name: absolute_topic(name, namespace))
        self._interval_ns = int(round(chunk_interval_s * NS_PER_S))
        self._interval_s = chunk_interval_s
        self._qos = offered_qos_profiles(depth=qos_depth)
        self._fsync = fsync
        self._file: BinaryIO = open(self.path, "wb")
        self._writer = Writer(self._file, chunk_size=chunk_size, compression=CompressionType.NONE)
        self._writer.start(profile="ros2", library=library())
        self._schemas: dict[str, int] = {}
        self._topics: dict[str, TopicInfo] = {}
        self._start_ns: int | None = None
        self._end_ns = 0
        self._chunk_stamp: int | None = None
        self._chunk_wall = time.monotonic()
        self._lookup: dict[str, TopicInfo] = {}
        self.closed = False
        for name, typename in topics:
            self.add_topic(name, typename)
        self._writebag_metadata()
        for record_name, values in (metadata or {}).items():
            self._writer.add_metadata(record_name, dict(values))
        self._flush()

    # -- topics -------------------------------------------------------------------------------
    def add_topic(self, name: str, typename: str) -> str:
        """Declare a topic (schema and channel); returns its absolute name."""
        topic = self._resolve(name)
        if topic in self._topics:
            if self._topics[topic].typename != typename:
                raise ValueError(f"topic {topic} already recorded as {self._topics[topic].typename}")
            return topic
        schema_id = self._schemas.get(typename)
        if schema_id is None:
            data = ros2msg_definition(self._ts, typename).encode()
            schema_id = self._writer.register_schema(typename, "ros2msg", data)
            self._schemas[typename] = schema_id
        type_hash = self._ts.hash_rihs01(typename)
        channel_id = self._writer.register_channel(
            topic, "cdr", schema_id,
            {"offered_qos_profiles": self._qos, "topic_type_hash": type_hash},
        )
        self._topics[topic] = TopicInfo(topic, typename, channel_id, self._qos, type_hash)
        return topic

    @property
    def topics(self) -> dict[str, str]:
        """Absolute topic name → ROS type, in creation order."""
        return {t.name: t.typename for t in self._topics.values()}

    def _topic(self, name: str, msg: Any) -> TopicInfo:
        topic = self._lookup.get(name)
        if topic is None:
            topic = self._topics.get(self._resolve(name))
            if topic is None:
                typename = getattr(msg, "__msgtype__", None)
                if typename is None:
                    raise KeyError(f"topic {name!r} was not declared and its message has no type")
                topic = self._topics[self.add_topic(name, typename)]
            self._lookup[name] = topic
        return topic

    # -- writing ------------------------------------------------------------------------------
    def write(self, stamp_ns: int, messages: Iterable[tuple[str, Any]]) -> None:
        """Record one tick: every message gets log time = publish time = ``stamp_ns``."""
        stamp_ns = self._tick(stamp_ns)
        add = self._writer.add_message
        for name, msg in messages:
            topic = self._topic(name, msg)
            topic.sequence += 1
            add(topic.channel_id, stamp_ns, self._serialize(msg, topic.typename), stamp_ns,
                topic.sequence)
        self._maybe_close_chunk(stamp_ns)

    def write_serialized(self, stamp_ns: int, messages: Iterable[tuple[str, bytes]]) -> None:
        """Record one tick of already CDR-serialised messages of declared topics."""
        stamp_ns = self._tick(stamp_ns)
        add = self._writer.add_message
        for name, data in messages:
            topic = self._lookup.get(name) or self._topic(name, None)
            topic.sequence += 1
            add(topic.channel_id, stamp_ns, data, stamp_ns, topic.sequence)
        self._maybe_close_chunk(stamp_ns)

    def _tick(self, stamp_ns: int) -> int:
        if self.closed:
            raise ValueError(f"recorder for {self.path} is closed")
        stamp_ns = int(stamp_ns)
        if self._start_ns is None or stamp_ns < self._start_ns:
            self._start_ns = stamp_ns
        if stamp_ns > self._end_ns:
            self._end_ns = stamp_ns
        if self._chunk_stamp is None:
            self._chunk_stamp = stamp_ns
        return stamp_ns

    @property
    def message_count(self) -> int:
        """Messages written so far."""
        return sum(t.sequence for t in self._topics.values())

    def _maybe_close_chunk(self, stamp_ns: int) -> None:
        if self._chunk_stamp is None:
            return
        if (int(stamp_ns) - self._chunk_stamp >= self._interval_ns
                or time.monotonic() - self._chunk_wall >= self._interval_s):
            self.flush()

    def flush(self) -> None:
        """Close the open chunk (if it holds messages) and push everything to the OS."""
        self._writer.flush()
        self._flush()
        self._chunk_stamp = None
        self._chunk_wall = time.monotonic()

    def _flush(self) -> None:
        self._file.flush()
        if self._fsync:
            os.fsync(self._file.fileno())

    def _writebag_metadata(self) -> None:
        start = self._start_ns or 0
        self._writer.add_metadata("rosbag2", {"serialized_metadata": bag_metadata(
            self._topics.values(), file_name=self.path.name, start_ns=start,
            end_ns=max(self._end_ns, start), count=self.message_count)})

    def close(self) -> None:
        """Finish the file: last chunk, final ``rosbag2`` metadata, summary and footer."""
        if self.closed:
            return
        self._writer.flush()
        self._writebag_metadata()
        self._writer.finish()
        self._flush()
        self._file.close()
        self.closed = True

    def __enter__(self) -> Recorder:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
