"""The rosbag2 side of the MCAP profile, as ROS 2 Jazzy's rosbag2 writes it: message definitions
in rosbag2's layout, the channels' QoS metadata, and the ``rosbag2`` metadata record.

References: ``rosbag2_storage_mcap`` (``mcap_storage.cpp``, ``message_definition_cache.cpp``) and
``rosbag2_storage`` (``qos.cpp``, ``yaml.hpp``) of Jazzy; see docs/recording.md.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import yaml

__all__ = [
    "CHUNK_INTERVAL_S",
    "CHUNK_SIZE",
    "METADATA_VERSION",
    "QOS_DEPTH",
    "ROS_DISTRO",
    "TopicInfo",
    "absolute_topic",
    "bag_metadata",
    "default_typestore",
    "library",
    "offered_qos_profiles",
    "ros2msg_definition",
]

CHUNK_INTERVAL_S = 1.0
"""Default: a chunk is closed and flushed at least this often (message time and wall clock)."""
CHUNK_SIZE = 768 * 1024
"""rosbag2's default chunk size (mcap's C++ ``DefaultChunkSize``), bytes."""
QOS_DEPTH = 10
ROS_DISTRO = "jazzy"
METADATA_VERSION = 9
"""rosbag2 metadata version written by Jazzy (QoS policies as strings)."""
DELIMITER = "=" * 80 + "\n"
RMW_DURATION_INFINITE = (9223372036, 854775807)


def library() -> str:
    from importlib.metadata import PackageNotFoundError, version

    def _v(dist: str) -> str:
        try:
            return version(dist)
        except PackageNotFoundError:
            return "unknown"

    return f"linkage_ros {_v('linkage_ros')} (mcap-python {_v('mcap')}, rosbags {_v('rosbags')})"


def absolute_topic(name: str, namespace: str = "/") -> str:
    """``joint_states`` in namespace ``/robot`` → ``/robot/joint_states``; absolute names stay."""
    if name.startswith("/"):
        return name
    ns = "/" + namespace.strip("/") if namespace.strip("/") else ""
    return f"{ns}/{name}"


def offered_qos_profiles(*, depth: int = QOS_DEPTH, reliability: str = "reliable",
                         durability: str = "volatile") -> str:
    """The channel metadata ``offered_qos_profiles`` as rosbag2 Jazzy serialises it (yaml-cpp
    ``Dump`` of a one-element sequence, no trailing newline). Unset durations are the
    ``RMW_DURATION_INFINITE`` that the middleware reports for a default publisher."""
    sec, nsec = RMW_DURATION_INFINITE
    dur = f"\n    sec: {sec}\n    nsec: {nsec}"
    return (
        f"- history: keep_last\n  depth: {depth}\n  reliability: {reliability}\n"
        f"  durability: {durability}\n  deadline:{dur}\n  lifespan:{dur}\n"
        f"  liveliness: automatic\n  liveliness_lease_duration:{dur}\n"
        "  avoid_ros_namespace_conventions: false"
    )


def _short(typename: str) -> str:
    """``std_msgs/msg/Header`` → ``std_msgs/Header`` (the form used inside definitions)."""
    pkg, _, name = typename.partition("/msg/")
    return f"{pkg}/{name}" if name else typename


def _sections(typestore: Any, typename: str) -> dict[str, str]:
    """Own text of ``typename`` and of every type it depends on, keyed by short name."""
    full, _ = typestore.generate_msgdef(typename, ros_version=2)
    parts = full.split(DELIMITER)
    out = {_short(typename): parts[0]}
    for part in parts[1:]:
        head, _, body = part.partition("\n")
        out[head.removeprefix("MSG: ").strip()] = body
    return out


def _dependencies(text: str) -> list[str]:
    deps = set()
    for line in text.splitlines():
        words = line.split()
        if len(words) >= 2 and "=" not in words[0]:
            base = words[0].split("[")[0]
            if "/" in base:
                deps.add(base)
    return sorted(deps)


def ros2msg_definition(typestore: Any, typename: str) -> str:
    """Complete ``ros2msg`` schema text in rosbag2's layout (see the module docstring)."""
    sections = _sections(typestore, typename)
    seen: set[str] = set()

    def walk(name: str) -> str:
        text = sections[name]
        for dep in _dependencies(text):
            if dep not in seen:
                seen.add(dep)
                text += "\n" + DELIMITER + f"MSG: {dep}\n" + walk(dep)
        return text

    return walk(_short(typename))


class _Dumper(yaml.SafeDumper):
    """yaml-cpp-like block style: sequences indented under their key, ``~`` for null."""

    def increase_indent(self, flow: bool = False, indentless: bool = False) -> None:
        super().increase_indent(flow, False)


_Dumper.add_representer(type(None), lambda d, _: d.represent_scalar("tag:yaml.org,2002:null", "~"))


@dataclass
class TopicInfo:
    name: str
    typename: str
    channel_id: int
    qos: str
    type_hash: str
    sequence: int = 0
    """Messages written on this topic (the MCAP sequence number of the last one)."""


def bag_metadata(topics: Iterable[TopicInfo], *, file_name: str, start_ns: int, end_ns: int,
                  count: int) -> str:
    """``serialized_metadata`` of the ``rosbag2`` metadata record (BagMetadata, version 9)."""
    duration = max(0, end_ns - start_ns)
    data = {
        "version": METADATA_VERSION,
        "storage_identifier": "mcap",
        "duration": {"nanoseconds": duration},
        "starting_time": {"nanoseconds_since_epoch": start_ns},
        "message_count": count,
        "topics_with_message_count": [
            {
                "topic_metadata": {
                    "name": t.name,
                    "type": t.typename,
                    "serialization_format": "cdr",
                    "offered_qos_profiles": yaml.safe_load(t.qos),
                    "type_description_hash": t.type_hash,
                },
                "message_count": t.sequence,
            }
            for t in topics
        ],
        "compression_format": "",
        "compression_mode": "",
        "relative_file_paths": [file_name],
        "files": [
            {
                "path": file_name,
                "starting_time": {"nanoseconds_since_epoch": start_ns},
                "duration": {"nanoseconds": duration},
                "message_count": count,
            }
        ],
        "custom_data": None,
        "ros_distro": ROS_DISTRO,
    }
    return yaml.dump(data, Dumper=_Dumper, sort_keys=False, default_flow_style=False).rstrip("\n")


def default_typestore() -> Any:
    from rosbags.typesys import Stores, get_typestore

    return get_typestore(Stores.ROS2_JAZZY)
