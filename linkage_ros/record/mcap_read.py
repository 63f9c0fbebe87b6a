"""Reading MCAP files, also those cut short by a crash, and their recovery (the writer:
:mod:`.mcap`).

:func:`read_mcap` reads with mcap's StreamReader up to the last complete record: a file killed
mid-write gives every message of its complete chunks (a chunk whose CRC does not match ends the
readable part like a cut). :func:`recover` writes what is readable into a new, finished file
with the ``rosbag2`` metadata rewritten to match.
"""

from __future__ import annotations

import io
import mmap
import os
import struct
import zlib
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from mcap.data_stream import ReadDataStream
from mcap.exceptions import EndOfFile
from mcap.opcode import Opcode
from mcap.records import Channel, Chunk, Footer, Header, Message, Metadata, Schema
from mcap.stream_reader import StreamReader
from mcap.writer import CompressionType, Writer

from .rosbag2 import CHUNK_SIZE, TopicInfo, bag_metadata, default_typestore, library

__all__ = ["McapContents", "RawMessage", "iter_messages", "read_mcap", "recover"]

MAGIC = b"\x89MCAP0\r\n"
RECORD_HEADER = struct.Struct("<BQ")
OPCODE_FOOTER = 0x02


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
