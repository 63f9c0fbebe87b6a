"""Per-tick CDR bytes of the node's messages: one serialisation for the wire and the MCAP.

Within one engine, each topic's message has the same byte layout at every tick (same names,
same array lengths, same frame_id): only numbers change. :class:`TickSerializer` builds each
topic's message once with :class:`~linkage_ros.messages.MessageBuilder` from a *probe* frame
whose every number is a distinct sentinel, serialises it once with rosbags' CDR serialiser, finds
the byte offsets of the sentinels and compiles the message into one :class:`struct.Struct`:
the constant runs of bytes between the numbers become ``Ns`` fields, the numbers ``d`` (and the
stamp ``i``/``I``). A tick is then one flat list of the frame's numbers and one ``pack`` per topic
(a few µs for all topics, against ~300 µs for building and serialising message objects).

The builder stays the single definition of the messages: a template is what the builder
writes. On the first frame every template is checked against the builder's ordinary output,
serialised; a topic whose rendering differs is built and serialised the ordinary way from then on.
Always built the ordinary way: ``diagnostics`` (numbers as text; the node sends it about once a
second) and ``markers`` when they carry the paths (first frame, then periodically).

The bytes are what rosbags' ``serialize_cdr`` writes (XCDR1, little endian), padded with zeros
to a multiple of 4 bytes (:func:`pad4`). Why that form: rclpy's ``serialize_message`` pads the
end to 8 bytes (236 bytes where rosbags writes 232 for the same JointState), which rosbags'
readers reject ("CDR message size mismatch": they accept at most 3 bytes of padding); Fast DDS
pads every payload it sends to 4 bytes, so unpadded bytes would arrive 1–3 bytes longer than
recorded. Padded to 4, the bytes that ``Publisher.publish(bytes)`` sends, the bytes a
subscriber receives and the bytes the recorder writes are the same, and rclpy, rosbags and
mcap_ros2 all read them.
"""

from __future__ import annotations

import struct
from collections.abc import Callable, Sequence
from operator import itemgetter
from types import MappingProxyType
from typing import Any, NamedTuple

from ._sentinels import NSEC, SEC, find_all, sentinel
from .engine import STATUS_OK, Frame, JointState, PointState
from .messages import DIAGNOSTICS, MARKERS, NS_PER_S, MessageBuilder
from .urdf import TreeJointStates

__all__ = ["TickSerializer", "pad4"]

_SIZES = {"d": 8, "i": 4, "I": 4}


def pad4(data: Any) -> bytes:
    """``data`` with zero bytes appended up to a multiple of 4 (what Fast DDS sends)."""
    data = bytes(data)
    return data + bytes(-len(data) % 4)


class _Template(NamedTuple):
    topic: str
    pack: Callable[..., bytes]
    args: Callable[[Sequence[Any]], tuple[Any, ...]]


class TickSerializer:
    """CDR bytes of every topic of ``builder`` for one frame.

    ``builder`` must be built with rosbags' message classes and ``serialize(msg, typename)`` be
    the same type store's ``serialize_cdr``.
    """

    def __init__(self, builder: MessageBuilder, serialize: Callable[[Any, str], Any]) -> None:
        self.builder = builder
        self.serialize = serialize
        self.types = dict(builder.topics)
        engine = builder.engine
        scene = engine.scene
        self._dim = dim = int(scene.dim)
        fixed = {k: tuple(float(x) for x in v) for k, v in scene.fixed_points.items()}
        self._moving = tuple(p for p in engine.point_names if p not in fixed)
        self._published = tuple(engine.published_points)
        self._joint_names = tuple(engine.joint_names)
        self._tree = bool(builder.tree_joint_names)
        counter = iter(range(2, 1 << 30))  # numbers 0 and 1 are the stamp's sec and nanosec

        def sentinels(n: int) -> tuple[float, ...]:
            return tuple(sentinel(next(counter)) for _ in range(n))

        # the same order as _numbers
        positions = {p: sentinels(dim) for p in self._moving}
        velocities = {p: sentinels(dim) for p in self._published}
        accelerations = {p: sentinels(dim) for p in self._published}
        joints = {j: JointState(*sentinels(3)) for j in self._joint_names}
        names = builder.tree_joint_names
        tree = TreeJointStates(names, sentinels(len(names)), sentinels(len(names))) if names else None
        self._count = next(counter)
        zeros = (0.0,) * dim
        points = {
            p: PointState(positions.get(p) or fixed[p], velocities.get(p, zeros), accelerations.get(p, zeros))
            for p in engine.point_names
        }
        probe = Frame(t=0.0, phi=0.0, omega=0.0, epsilon=0.0, points=MappingProxyType(points),
                      joints=MappingProxyType(joints), status=STATUS_OK, conditioning=1.0, message="")
        candidates = [t for t, _ in builder.topics if t != DIAGNOSTICS]
        messages = dict(builder.build_topics(probe, SEC * NS_PER_S + NSEC, candidates,
                                             include_paths=False, tree=tree))
        consts: list[bytes] = []
        self._templates: dict[str, _Template] = {}
        for topic in candidates:
            template = self._compile(topic, pad4(serialize(messages[topic], self.types[topic])), consts)
            if template is not None:
                self._templates[topic] = template
        self._consts = consts
        self._verified = False
        self._every_tick = self._fast_path()

    # ------------------------------------------------------------------ public
    @property
    def template_topics(self) -> list[str]:
        """Topics rendered from templates (the others are built and serialised per tick)."""
        return list(self._templates)

    def render(self, frame: Frame, stamp_ns: int, *, paths: bool = False,
               diagnostics: bool = True) -> list[tuple[str, bytes]]:
        """``[(topic, CDR bytes)]`` of ``frame`` stamped ``stamp_ns``, in the builder's topic
        order. ``markers`` carry the paths when ``paths``; ``diagnostics`` is left out unless
        ``diagnostics``."""
        if not self._verified:
            self.verify(frame, stamp_ns)
        values = self._numbers(frame, stamp_ns)
        if self._every_tick is not None and not paths and not diagnostics:  # most ticks
            return [(topic, pack(*args(values))) for topic, pack, args in self._every_tick]
        templates = self._templates
        out: list[tuple[str, bytes]] = []
        generic: list[str] = []
        for topic in self.types:
            tpl = templates.get(topic)
            if tpl is not None and not (paths and topic == MARKERS):
                out.append((topic, tpl.pack(*tpl.args(values))))
            elif topic != DIAGNOSTICS or diagnostics:
                out.append((topic, b""))
                generic.append(topic)
        if generic:
            built = dict(self.builder.build_topics(frame, stamp_ns, generic, include_paths=paths))
            out = [(t, data if data else pad4(self.serialize(built[t], self.types[t])))
                   for t, data in out]
        return out

    def generic(self, frame: Frame, stamp_ns: int, topics: Sequence[str]) -> list[tuple[str, bytes]]:
        """``topics`` of ``frame`` built and serialised the ordinary way (e.g. the diagnostics of
        an input state that has no frame: ``frame`` may then carry no points or joints)."""
        built = self.builder.build_topics(frame, stamp_ns, topics, include_paths=False)
        return [(t, pad4(self.serialize(m, self.types[t]))) for t, m in built]

    def verify(self, frame: Frame, stamp_ns: int) -> list[str]:
        """Topics whose template rendering of ``frame`` differs from the builder's output (they
        are built the ordinary way from then on); empty when every template is exact."""
        self._verified = True
        values = self._numbers(frame, stamp_ns)
        topics = list(self._templates)
        built = dict(self.builder.build_topics(frame, stamp_ns, topics, include_paths=False))
        bad = []
        for topic in topics:
            tpl = self._templates[topic]
            if tpl.pack(*tpl.args(values)) != pad4(self.serialize(built[topic], self.types[topic])):
                bad.append(topic)
        for topic in bad:
            del self._templates[topic]
        self._every_tick = self._fast_path()
        return bad

    # ------------------------------------------------------------------ helpers
    def _fast_path(self) -> list[_Template] | None:
        """The templates of a tick without paths and diagnostics, in topic order; None when some
        such topic has no template (those ticks take the general path of :meth:`render`)."""
        topics = [t for t in self.types if t != DIAGNOSTICS]
        if any(t not in self._templates for t in topics):
            return None
        return [self._templates[t] for t in topics]

    def _numbers(self, frame: Frame, stamp_ns: int) -> list[Any]:
        """The frame's numbers in sentinel order, then the templates' constant byte runs."""
        sec, nanosec = divmod(int(stamp_ns), NS_PER_S)
        values: list[Any] = [sec, nanosec]
        points = frame.points
        for p in self._moving:
            values += points[p].position
        for p in self._published:
            values += points[p].velocity
        for p in self._published:
            values += points[p].acceleration
        joints = frame.joints
        for j in self._joint_names:
            values += joints[j]
        if self._tree:
            tree = self.builder.tree_states(frame)
            assert tree is not None
            values += tree.position
            values += tree.velocity
        values += self._consts
        return values

    def _compile(self, topic: str, raw: bytes, consts: list[bytes]) -> _Template | None:
        """The template of one serialised probe message (None when its sentinels overlap)."""
        slots: list[tuple[int, str, int]] = []  # offset, struct code, index in _numbers
        slots += [(off, "i", 0) for off in find_all(raw, struct.pack("<i", SEC))]
        slots += [(off, "I", 1) for off in find_all(raw, struct.pack("<I", NSEC))]
        for j in range(2, self._count):
            slots += [(off, "d", j) for off in find_all(raw, struct.pack("<d", sentinel(j)))]
        slots.sort()
        fmt, args, pos = ["<"], [], 0
        for off, code, j in slots:
            if off < pos:
                return None
            if off > pos:
                fmt.append(f"{off - pos}s")
                args.append(self._count + len(consts))
                consts.append(raw[pos:off])
            fmt.append(code)
            args.append(j)
            pos = off + _SIZES[code]
        if pos < len(raw):
            fmt.append(f"{len(raw) - pos}s")
            args.append(self._count + len(consts))
            consts.append(raw[pos:])
        getter: Callable[[Sequence[Any]], tuple[Any, ...]]
        if len(args) == 1:
            index = args[0]
            getter = lambda values: (values[index],)
        else:
            getter = itemgetter(*args)
        return _Template(topic, struct.Struct("".join(fmt)).pack, getter)
