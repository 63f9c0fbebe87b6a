"""Whole-run CDR serialisation by templates taken from the message builder.

Building and serialising ~13 messages per tick through Python objects costs ~300 µs; a
10-minute run at 100 Hz has 60 000 ticks. Within a run, each topic's message has the same byte
layout at every tick (same names, same array lengths, same frame_id): only numbers change. So
each topic's message is built once by :class:`~linkage_ros.messages.MessageBuilder` from a
*probe* frame whose every number is a distinct sentinel, serialised once by the type store, and
the byte offsets of the sentinels are found; a block of ticks is then one numpy array per topic,
the template repeated and the numbers written into their columns.

The builder stays the single definition of the messages: what it writes is what the template
holds. Topics whose layout changes from tick to tick (``diagnostics``: numbers as text; the
``markers`` that carry the paths, sent periodically) are built and serialised the ordinary way.
:meth:`TemplateSerializer.verify` compares the two paths on a real frame; the run falls back to
the ordinary path if they differ.
"""

from __future__ import annotations

import struct
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._sentinels import NSEC, SEC, find_all, sentinel

__all__ = ["Block", "TemplateSerializer", "GENERIC_TOPICS"]

GENERIC_TOPICS = ("diagnostics",)
"""Topics always built and serialised per tick; :meth:`TemplateSerializer.demote` adds those
whose numbers the builder derives (instead of copying them from the frame)."""
NS_PER_S = 1_000_000_000


@dataclass
class Block:
    """Numbers of a block of n ticks, the inputs of :meth:`TemplateSerializer.render`."""

    stamps: NDArray[np.int64]  # (n,) ns
    positions: dict[str, NDArray[np.float64]]  # (n, dim), every moving point
    velocities: dict[str, NDArray[np.float64]]  # (n, dim)
    accelerations: dict[str, NDArray[np.float64]]  # (n, dim)
    joints: dict[str, tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]]


@dataclass
class _Template:
    data: NDArray[np.uint8]  # (size,)
    floats: list[tuple[int, Callable[[Block], NDArray[np.float64]]]]  # offset, column
    secs: list[int]
    nsecs: list[int]


class TemplateSerializer:
    """Templates for every topic of ``builder`` except :data:`GENERIC_TOPICS`.

    ``serialize(msg, typename) -> bytes`` is the ordinary serialiser (rosbags' ``serialize_cdr``).
    """

    def __init__(self, builder: Any, serialize: Callable[[Any, str], bytes]) -> None:
        self.builder = builder
        self.serialize = serialize
        engine = builder.engine
        self.types = dict(builder.topics)
        self.topics = [t for t, _ in builder.topics if t not in GENERIC_TOPICS]
        self.generic = [t for t, _ in builder.topics if t in GENERIC_TOPICS]
        dim = int(engine.scene.dim)
        columns: list[Callable[[Block], NDArray[np.float64]]] = []

        def column(fn: Callable[[Block], NDArray[np.float64]]) -> float:
            columns.append(fn)
            return sentinel(len(columns) - 1)

        def component(kind: str, name: str, c: int) -> Callable[[Block], NDArray[np.float64]]:
            return lambda b: getattr(b, kind)[name][:, c]

        def joint(name: str, i: int) -> Callable[[Block], NDArray[np.float64]]:
            return lambda b: b.joints[name][i]

        def vec(kind: str, name: str) -> NDArray[np.float64]:
            return np.array([column(component(kind, name, c)) for c in range(dim)])

        published = set(engine.published_points)
        zeros = np.zeros(dim)
        points = {}
        fixed = {k: np.asarray(v, dtype=np.float64) for k, v in engine.scene.fixed_points.items()}
        for name in engine.point_names:
            pos = fixed[name] if name in fixed else vec("positions", name)
            vel = vec("velocities", name) if name in published else zeros
            acc = vec("accelerations", name) if name in published else zeros
            points[name] = _point_state(engine, pos, vel, acc)
        joints = {}
        for name in engine.joint_names:
            p, v, a = (column(joint(name, i)) for i in range(3))
            joints[name] = _joint_state(engine, p, v, a)
        probe = _frame(engine, points, joints)
        stamp = SEC * NS_PER_S + NSEC
        messages = dict(builder.build_topics(probe, stamp, self.topics, include_paths=False))
        self._templates: dict[str, _Template] = {}
        for topic in self.topics:
            raw = bytes(self.serialize(messages[topic], self.types[topic]))
            floats = [(off, columns[i]) for i in range(len(columns))
                      for off in find_all(raw, struct.pack("<d", sentinel(i)))]
            self._templates[topic] = _Template(
                np.frombuffer(raw, dtype=np.uint8).copy(), floats,
                find_all(raw, struct.pack("<i", SEC)), find_all(raw, struct.pack("<I", NSEC)))

    def render(self, topic: str, block: Block) -> list[bytes]:
        """The serialised messages of ``topic`` for every tick of ``block``."""
        tpl = self._templates[topic]
        n = block.stamps.size
        size = tpl.data.size
        rows = np.empty((n, size), dtype=np.uint8)
        rows[:] = tpl.data
        for off, col in tpl.floats:
            rows[:, off: off + 8] = np.ascontiguousarray(col(block), dtype="<f8").view(
                np.uint8).reshape(n, 8)
        sec, nsec = np.divmod(block.stamps.astype(np.int64), NS_PER_S)
        sec_b = sec.astype("<i4").view(np.uint8).reshape(n, 4)
        nsec_b = nsec.astype("<u4").view(np.uint8).reshape(n, 4)
        for off in tpl.secs:
            rows[:, off: off + 4] = sec_b
        for off in tpl.nsecs:
            rows[:, off: off + 4] = nsec_b
        flat = rows.tobytes()
        return [flat[i * size: (i + 1) * size] for i in range(n)]

    def demote(self, topics: Sequence[str]) -> None:
        """Build and serialise ``topics`` per tick from now on (their templates are not exact:
        the builder computes some of their numbers, e.g. the URDF tree joints on joint_states)."""
        self.topics = [t for t in self.topics if t not in topics]
        self.generic = [t for t, _ in self.builder.topics if t in self.generic or t in topics]

    def verify(self, frame: Any, stamp: int, block: Block) -> list[str]:
        """Topics whose rendering of the first tick of ``block`` (which must be ``frame``)
        differs from the builder's ordinary output; empty when the templates are exact."""
        messages = dict(self.builder.build_topics(frame, stamp, self.topics, include_paths=False))
        one = _first(block)
        return [t for t in self.topics
                if self.render(t, one)[0] != bytes(self.serialize(messages[t], self.types[t]))]


def _first(block: Block) -> Block:
    return Block(block.stamps[:1], {k: v[:1] for k, v in block.positions.items()},
                 {k: v[:1] for k, v in block.velocities.items()},
                 {k: v[:1] for k, v in block.accelerations.items()},
                 {k: (p[:1], v[:1], a[:1]) for k, (p, v, a) in block.joints.items()})


def _point_state(engine: Any, pos: Any, vel: Any, acc: Any) -> Any:
    from linkage_ros.engine import PointState

    return PointState(pos, vel, acc)


def _joint_state(engine: Any, p: float, v: float, a: float) -> Any:
    from linkage_ros.engine import JointState

    return JointState(p, v, a)


def _frame(engine: Any, points: dict[str, Any], joints: dict[str, Any]) -> Any:
    from linkage_ros.engine import STATUS_OK, Frame

    return Frame(t=0.0, phi=0.0, omega=0.0, epsilon=0.0, points=MappingProxyType(points),
                 joints=MappingProxyType(joints), status=STATUS_OK, conditioning=1.0, message="")


def stack_block(stamps: Sequence[int] | NDArray[np.int64], data: Any, start: int, stop: int) -> Block:
    """A :class:`Block` of ticks ``start:stop`` of a :class:`~linkage_ros.record.rerun.RunBuilder`."""
    sl = slice(start, stop)
    return Block(
        np.asarray(stamps[sl], dtype=np.int64),
        {k: v[sl] for k, v in data.pos.items()},
        {k: v[sl] for k, v in data.vel.items()},
        {k: v[sl] for k, v in data.acc.items()},
        {k: (p[sl], v[sl], a[sl]) for k, (p, v, a) in data.jnt.items()},
    )
