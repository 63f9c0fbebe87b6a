"""MCAP recording in the rosbag2 profile (as ROS 2 Jazzy's rosbag2 writes it; the rosbag2 parts
are in :mod:`.rosbag2`), a reader that tolerates files cut short by a crash, and their recovery.

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

import io
import mmap
import os
import struct
import time
import zlib
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import Any, BinaryIO

from mcap.data_stream import ReadDataStream
from mcap.exceptions import EndOfFile
from mcap.opcode import Opcode
from mcap.records import Channel, Chunk, Footer, Header, Message, Metadata, Schema
from mcap.stream_reader import StreamReader
from mcap.writer import CompressionType, Writer

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

MAGIC = b"\x89MCAP0\r\n"
RECORD_HEADER = struct.Struct("<BQ")
OPCODE_FOOTER = 0x02
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


# -- reading ------------------------------------------------------------------------------------
@dataclass(frozen=True)
class RawMessage:
    topic: str
    typename: str
    log_time: int
    publish_time: int
    sequence: int
    data: bytes


@dataclass
class McapContents:
    """Everything readable in a file, up to its last complete record."""

    header: Header | None = None
    schemas: dict[int, Schema] = field(default_factory=dict)
    channels: dict[int, Channel] = field(default_factory=dict)
    metadata: list[Metadata] = field(default_factory=list)
    messages: list[RawMessage] = field(default_factory=list)
    complete: bool = False
    """True when the file ends with a footer (it was closed cleanly)."""
    valid_bytes: int = 0
    size: int = 0
    message_count: int = 0
    """Messages read (all topics, also those not collected)."""

    def topics(self) -> dict[str, str]:
        return {c.topic: self.schemas[c.schema_id].name for c in self.channels.values()
                if c.schema_id in self.schemas}


OPCODE_MESSAGE_INDEX = 0x07
OPCODE_MESSAGE = 0x05
MESSAGE_HEAD = struct.Struct("<HIQQ")  # channel id, sequence, log time, publish time


def _scan(buf: mmap.mmap) -> tuple[int, bool, list[tuple[int, int]]]:
    """End of the prefix made of whole records, whether a footer (and the closing magic) was
    reached, and the byte ranges of the records worth reading (message indexes left out: they
    only serve indexed access)."""
    if buf[: len(MAGIC)] != MAGIC:
        raise ValueError("not an MCAP file (bad magic)")
    pos, size = len(MAGIC), len(buf)
    keep: list[tuple[int, int]] = [(0, pos)]
    while pos + RECORD_HEADER.size <= size:
        opcode, length = RECORD_HEADER.unpack_from(buf, pos)
        end = pos + RECORD_HEADER.size + length
        if opcode == 0 or end > size:
            break
        if opcode != OPCODE_MESSAGE_INDEX:
            if keep[-1][1] == pos:
                keep[-1] = (keep[-1][0], end)
            else:
                keep.append((pos, end))
        pos = end
        if opcode == OPCODE_FOOTER:
            return pos, buf[pos: pos + len(MAGIC)] == MAGIC, keep
    return pos, False, keep


class _Ranges(io.RawIOBase):
    """Byte ranges of a buffer read one after the other, then ``tail``."""

    def __init__(self, buf: mmap.mmap, ranges: list[tuple[int, int]], tail: bytes) -> None:
        self._buf, self._ranges, self._tail, self._i, self._pos = buf, ranges, tail, 0, -1

    def readable(self) -> bool:
        return True

    def readinto(self, buffer: Any) -> int:
        view = memoryview(buffer)
        while self._i < len(self._ranges):
            start, stop = self._ranges[self._i]
            pos = start if self._pos < 0 else self._pos
            if pos < stop:
                n = min(len(view), stop - pos)
                view[:n] = self._buf[pos: pos + n]
                self._pos = pos + n
                return n
            self._i, self._pos = self._i + 1, -1
        n = min(len(view), len(self._tail))
        view[:n] = self._tail[:n]
        self._tail = self._tail[n:]
        return n


def _chunk_data(chunk: Chunk) -> bytes | None:
    """Uncompressed records of a chunk; None when its CRC does not match (a damaged chunk)."""
    if chunk.compression == "zstd":
        import zstandard

        data: bytes = zstandard.decompress(chunk.data, chunk.uncompressed_size)
    elif chunk.compression == "lz4":
        import lz4.frame

        data = lz4.frame.decompress(chunk.data)
    else:
        data = bytes(chunk.data)
    if chunk.uncompressed_crc and zlib.crc32(data) != chunk.uncompressed_crc:
        return None
    return data


def read_mcap(path: str | os.PathLike[str], *, topics: Iterable[str] | None = None,
              messages: bool = True,
              on_message: Callable[[Channel, Message], None] | None = None) -> McapContents:
    """Read a file with mcap's StreamReader, stopping at the last complete record: a file cut
    short by a crash gives every message of its complete chunks. Chunk CRCs are checked; a
    damaged chunk ends the readable part like a cut.

    Messages of ``topics`` (all by default) are collected in ``messages`` as :class:`RawMessage`,
    or handed to ``on_message(channel, message)`` instead when it is given."""
    wanted = set(topics) if topics is not None else None
    out = McapContents()

    def message(record: Message) -> None:
        out.message_count += 1
        channel = out.channels[record.channel_id]
        if not messages or (wanted is not None and channel.topic not in wanted):
            return
        if on_message is not None:
            on_message(channel, record)
            return
        schema = out.schemas.get(channel.schema_id)
        out.messages.append(RawMessage(channel.topic, schema.name if schema else "",
                                       record.log_time, record.publish_time, record.sequence,
                                       record.data))

    def other(record: Any) -> None:
        if isinstance(record, Schema):
            out.schemas.setdefault(record.id, record)
        elif isinstance(record, Channel):
            out.channels.setdefault(record.id, record)
        elif isinstance(record, Metadata):
            out.metadata.append(record)
        elif isinstance(record, Header):
            out.header = record

    with open(path, "rb") as fh:
        out.size = os.fstat(fh.fileno()).st_size
        if out.size == 0:
            raise ValueError(f"{path}: empty file")
        with mmap.mmap(fh.fileno(), 0, access=mmap.ACCESS_READ) as buf:
            end, out.complete, ranges = _scan(buf)
            out.valid_bytes = end
            reader = StreamReader(_Ranges(buf, ranges, MAGIC if out.complete else b""),
                                  emit_chunks=True)
            try:
                for record in reader.records:
                    if isinstance(record, Chunk):
                        data = _chunk_data(record)
                        if data is None:
                            out.complete = False
                            break
                        _chunk_records(data, message, other)
                    elif isinstance(record, Message):
                        message(record)
                    elif isinstance(record, Footer):
                        break
                    else:
                        other(record)
            except EndOfFile:
                pass  # no footer: the file was cut short; everything before the cut is read
    return out


def _chunk_records(data: bytes, message: Callable[[Message], None],
                   other: Callable[[Any], None]) -> None:
    """The records inside a chunk: messages parsed directly, schemas and channels by mcap."""
    pos, size = 0, len(data)
    head, mhead = RECORD_HEADER, MESSAGE_HEAD
    while pos + head.size <= size:
        opcode, length = head.unpack_from(data, pos)
        body = pos + head.size
        pos = body + length
        if opcode == OPCODE_MESSAGE:
            channel_id, sequence, log_time, publish_time = mhead.unpack_from(data, body)
            message(Message(channel_id=channel_id, sequence=sequence, log_time=log_time,
                            publish_time=publish_time, data=data[body + mhead.size: pos]))
        elif opcode in (Opcode.SCHEMA, Opcode.CHANNEL):
            stream = ReadDataStream(io.BytesIO(data[body:pos]))
            other(Schema.read(stream) if opcode == Opcode.SCHEMA else Channel.read(stream))


def iter_messages(path: str | os.PathLike[str], typestore: Any = None, *,
                  topics: Iterable[str] | None = None) -> Iterator[tuple[RawMessage, Any]]:
    """Decoded messages (rosbags' Jazzy type store), in file order."""
    ts = typestore if typestore is not None else default_typestore()
    for raw in read_mcap(path, topics=topics).messages:
        yield raw, ts.deserialize_cdr(raw.data, raw.typename)


def recover(broken: str | os.PathLike[str], fixed: str | os.PathLike[str], *,
            chunk_size: int = CHUNK_SIZE) -> McapContents:
    """Write every readable record of ``broken`` into a new, finished file ``fixed``: same
    header, schemas, channels (ids renumbered in order), messages and metadata; the ``rosbag2``
    metadata record is rewritten with the counts and times of what was recovered."""
    contents = read_mcap(broken)
    if Path(fixed).resolve() == Path(broken).resolve():
        raise ValueError("recover writes a new file; give FIXED a different path than BROKEN")
    with open(fixed, "wb") as fh:
        writer = Writer(fh, chunk_size=chunk_size, compression=CompressionType.NONE)
        header = contents.header or Header(profile="ros2", library=library())
        writer.start(profile=header.profile, library=header.library)
        schema_ids = {sid: writer.register_schema(s.name, s.encoding, s.data)
                      for sid, s in sorted(contents.schemas.items())}
        channel_ids: dict[str, int] = {}
        topic_info: dict[str, TopicInfo] = {}
        for _cid, c in sorted(contents.channels.items()):
            channel_ids[c.topic] = writer.register_channel(
                c.topic, c.message_encoding, schema_ids.get(c.schema_id, 0), dict(c.metadata))
            schema = contents.schemas.get(c.schema_id)
            topic_info[c.topic] = TopicInfo(
                c.topic, schema.name if schema else "", channel_ids[c.topic],
                c.metadata.get("offered_qos_profiles", ""), c.metadata.get("topic_type_hash", ""))
        rosbag2 = [m for m in contents.metadata if m.name == "rosbag2"]
        for record in contents.metadata:
            if record.name != "rosbag2":
                writer.add_metadata(record.name, dict(record.metadata))
        start = min((m.log_time for m in contents.messages), default=0)
        end = max((m.log_time for m in contents.messages), default=0)
        for m in contents.messages:
            topic_info[m.topic].sequence += 1
            writer.add_message(channel_ids[m.topic], m.log_time, m.data, m.publish_time,
                               m.sequence)
        if rosbag2:
            writer.add_metadata("rosbag2", {"serialized_metadata": bag_metadata(
                topic_info.values(), file_name=Path(fixed).name, start_ns=start, end_ns=end,
                count=len(contents.messages))})
        writer.finish()
    return contents
