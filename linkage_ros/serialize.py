"""One byte-template serialiser: the CDR bytes of the node's messages, for every producer.

The node's ticks, the relay's answers, ``linkage-run``'s whole runs and the MCAP recorder all
write the bytes made here. Within one engine, each topic's message has the same byte layout at
every tick (same names, same array lengths, same frame_id): only numbers change. So
:class:`Serializer` builds each topic's message once with
:class:`~linkage_ros.messages.MessageBuilder` from a *probe* frame whose every number is a
distinct sentinel (:mod:`linkage_ros._sentinels`), serialises it once with rosbags' CDR
serialiser, finds the byte offsets of the sentinels and keeps the message as a template: the
constant runs of bytes between the numbers, and which number goes where. Numbers are named by
*slots* (:data:`Slot`): ``("sec",)``, ``("nsec",)`` (the stamp), ``("p", P, c)``, ``("v", P, c)``,
``("a", P, c)`` (component c of the position, velocity, acceleration of point P), ``("j", J, i)``
(joint J: i = 0 position, 1 velocity, 2 acceleration), ``("tq", k)``, ``("tv", k)`` (the URDF tree
joints' positions and velocities on ``joint_states``), and in scenes with forces
(:mod:`linkage_ros.forces`) ``("e", J)`` (input J's effort), ``("l", key, i)`` (a load's
Fx, Fy, M) and ``("lt", k)`` (the load arrows' tips, x and y, flat); in scenes with friction
``("f", name)`` (the power friction dissipates: ``total``, then per element). Like the tree joints, the
tips are derived by the builder (``MessageBuilder.load_tips``), not copied from the frame.

Three ways to fill the templates, one set of templates:

* :meth:`Serializer.packer` binds the templates to a vector of numbers in any slot order (the
  flat output of a compiled instant, :mod:`linkage_ros.instant`): a tick is then one
  :class:`struct.Struct` ``pack`` per topic, no message objects and no dicts (the node's and
  the relay's hot path);
* :meth:`Serializer.render` fills them from an engine :class:`~linkage_ros.frame.Frame`
  (every tick that has a frame: the first, status changes, the path markers and diagnostics);
* :meth:`Serializer.render_block` fills one topic for a block of ticks at once with numpy
  (``linkage-run``'s whole runs).

The builder stays the single definition of the messages: a template is what the builder
writes. On the first frame every template is checked against the builder's ordinary output,
serialised (:meth:`Serializer.verify`); a topic whose rendering differs is built and serialised
the ordinary way from then on. Always built the ordinary way: ``diagnostics`` (numbers as text;
sent about once a second) and ``markers`` when they carry the paths (first frame, then
periodically).

The bytes are what rosbags' ``serialize_cdr`` writes (XCDR1, little endian), padded with zeros
to a multiple of 4 bytes (:func:`pad4`). Why that form: rclpy's ``serialize_message`` pads the
end to 8 bytes (236 bytes where rosbags writes 232 for the same JointState), which rosbags'
readers reject ("CDR message size mismatch": they accept at most 3 bytes of padding); Fast DDS
pads every payload it sends to 4 bytes, so unpadded bytes would arrive 1–3 bytes longer than
recorded. Padded to 4, the bytes that ``Publisher.publish(bytes)`` sends, the bytes a
subscriber receives and the bytes every recorder writes are the same, and rclpy, rosbags and
mcap_ros2 all read them.
"""

from __future__ import annotations

import struct
from collections.abc import Callable, Sequence
from operator import itemgetter
from types import MappingProxyType
from typing import Any, NamedTuple

import numpy as np

from ._sentinels import NSEC, SEC, find_all, sentinel
from .frame import STATUS_OK, Frame, JointState, PointState
from .messages import DIAGNOSTICS, MARKERS, NS_PER_S, MessageBuilder
from .urdf import TreeJointStates

__all__ = ["Packer", "Serializer", "Slot", "cdr_bytes", "pad4", "read_joint_state"]

#: The name of one number of a tick (see the module docstring).
Slot = tuple[Any, ...]
STAMP_SLOTS: tuple[Slot, Slot] = (("sec",), ("nsec",))
_SIZES = {"d": 8, "i": 4, "I": 4}


def pad4(data: Any) -> bytes:
    """``data`` with zero bytes appended up to a multiple of 4 (what Fast DDS sends)."""
    data = bytes(data)
    return data + bytes(-len(data) % 4)


def cdr_bytes(serialize: Callable[[Any, str], Any], message: Any, typename: str) -> bytes:
    """The ordinary path: ``serialize(message, typename)`` padded to 4 (:func:`pad4`)."""
    return pad4(serialize(message, typename))


class _Template(NamedTuple):
    """One topic's serialised probe: its bytes and, per number in it, its offset and slot index."""

    topic: str
    raw: bytes
    fields: tuple[tuple[int, str, int], ...]  # offset, struct code, slot index (sorted by offset)


class Packer:
    """Every per-tick topic's bytes (all but ``diagnostics``, markers without the paths) from
    one vector of numbers in the order :meth:`Serializer.packer` was given.

    ``packer(values)``: ``values`` is a tuple of exactly one number per slot of that order;
    returns ``[(topic, bytes)]`` in the builder's topic order. KeyError when the order lacks a
    slot the templates need."""

    __slots__ = ("_consts", "_getter", "_pack", "_parts", "_size", "_spans")

    def __init__(self, templates: Sequence[_Template], order: Sequence[Slot], slots: Sequence[Slot]) -> None:
        where = {slot: i for i, slot in enumerate(order)}
        index = [where[slot] for slot in slots]  # canonical slot index -> position in the vector
        consts: list[bytes] = []
        fmt, spans, start = ["<"], [], 0
        args: list[int] = []
        parts: list[tuple[str, str, tuple[int, ...]]] = []  # per topic: its format and arguments
        for tpl in templates:  # one struct for all the topics, cut into one message per topic
            pos = 0
            first = len(fmt), len(args)
            for off, code, j in tpl.fields:
                if off > pos:
                    fmt.append(f"{off - pos}s")
                    args.append(len(order) + len(consts))
                    consts.append(tpl.raw[pos:off])
                fmt.append(code)
                args.append(index[j])
                pos = off + _SIZES[code]
            if pos < len(tpl.raw):
                fmt.append(f"{len(tpl.raw) - pos}s")
                args.append(len(order) + len(consts))
                consts.append(tpl.raw[pos:])
            spans.append((tpl.topic, start, start + len(tpl.raw)))
            parts.append((tpl.topic, "<" + "".join(fmt[first[0]:]), tuple(args[first[1]:])))
            start += len(tpl.raw)
        self._consts = tuple(consts)
        self._parts, self._size = tuple(parts), len(order)
        self._getter = itemgetter(*args) if len(args) > 1 else _one(args[0])
        self._pack = struct.Struct("".join(fmt)).pack
        self._spans = tuple(spans)

    def source(self, read: Callable[[int], str], *, prefix: str = "_p") -> tuple[list[str], dict[str, Any]]:
        """The same packing as generated code: lines (no indentation) whose last returns what
        ``packer(values)`` returns, ``read(i)`` being the source text of ``values[i]`` (a local
        name, say); and the names they use (``{prefix}pack{t}``, the constant byte runs
        ``{prefix}k{i}``). One ``struct`` pack per topic straight from the named numbers (a call
        with a few tens of arguments, which CPython passes on its stack; one pack of everything
        would need a list built item by item, then slices): no vector, no getter."""
        n = self._size
        namespace: dict[str, Any] = {f"{prefix}k{i}": c for i, c in enumerate(self._consts)}
        messages = []
        for t, (topic, fmt, args) in enumerate(self._parts):
            namespace[f"{prefix}pack{t}"] = struct.Struct(fmt).pack
            items = ", ".join(read(a) if a < n else f"{prefix}k{a - n}" for a in args)
            messages.append(f"({topic!r}, {prefix}pack{t}({items}))")
        return [f"return [{', '.join(messages)}]"], namespace

    def reads(self) -> set[int]:
        """The positions in the vector that the templates read."""
        return {a for _, _, args in self._parts for a in args if a < self._size}

    def __call__(self, values: tuple[Any, ...]) -> list[tuple[str, bytes]]:
        data = self._pack(*self._getter(values + self._consts))
        return [(topic, data[a:b]) for topic, a, b in self._spans]


def _one(index: int) -> Callable[[Sequence[Any]], tuple[Any, ...]]:
    return lambda values: (values[index],)


class Serializer:
    """CDR bytes of every topic of ``builder``.

    ``builder`` must be built with rosbags' message classes and ``serialize(msg, typename)`` be
    the same type store's ``serialize_cdr``.
    """

    def __init__(self, builder: MessageBuilder, serialize: Callable[[Any, str], Any]) -> None:
        self.builder = builder
        self.serialize = serialize
        self.types = dict(builder.topics)
        engine = builder.engine
        scene = engine.scene
        dim = int(scene.dim)
        fixed = {k: tuple(float(x) for x in v) for k, v in scene.fixed_points.items()}
        self._moving = tuple(p for p in engine.point_names if p not in fixed)
        self._published = tuple(engine.published_points)
        self._joint_names = tuple(engine.joint_names)
        names = builder.tree_joint_names
        self._tree = bool(names)
        slots: list[Slot] = list(STAMP_SLOTS)
        slots += [("p", p, c) for p in self._moving for c in range(dim)]
        slots += [("v", p, c) for p in self._published for c in range(dim)]
        slots += [("a", p, c) for p in self._published for c in range(dim)]
        slots += [("j", j, i) for j in self._joint_names for i in range(3)]
        slots += [("tq", k) for k in range(len(names))] + [("tv", k) for k in range(len(names))]
        forces = bool(getattr(engine, "forces", False))  # efforts and loads (linkage_ros.forces)
        self._efforts = tuple(engine.inputs) if forces else ()
        self._loads = tuple(pair.key for pair in engine.load_pairs) if forces else ()
        slots += [("e", q) for q in self._efforts] + [("l", key, i) for key in self._loads for i in range(3)]
        slots += [("lt", k) for k in range(2 * len(self._loads))]
        self._friction = tuple(getattr(engine, "friction_names", ()))
        slots += [("f", name) for name in self._friction]
        #: The canonical order of a tick's numbers (:meth:`numbers`).
        self.slots: tuple[Slot, ...] = tuple(slots)
        probe = [float(SEC), float(NSEC)] + [sentinel(i) for i in range(2, len(slots))]
        value = dict(zip(slots, probe))

        def vec(kind: str, p: str) -> tuple[float, ...]:
            return tuple(value[(kind, p, c)] for c in range(dim))

        zeros = (0.0,) * dim
        points = {
            p: PointState(vec("p", p) if p not in fixed else fixed[p],
                          vec("v", p) if p in self._published else zeros,
                          vec("a", p) if p in self._published else zeros)
            for p in engine.point_names
        }
        joints = {j: JointState(*(value[("j", j, i)] for i in range(3))) for j in self._joint_names}
        tree = TreeJointStates(names, tuple(value[("tq", k)] for k in range(len(names))),
                               tuple(value[("tv", k)] for k in range(len(names)))) if names else None
        extra: dict[str, Any] = {}
        if forces:
            extra["efforts"] = MappingProxyType({q: value[("e", q)] for q in self._efforts})
            extra["loads"] = MappingProxyType({key: tuple(value[("l", key, i)] for i in range(3))
                                               for key in self._loads})
        if self._friction:
            extra["friction"] = MappingProxyType({name: value[("f", name)] for name in self._friction})
        frame = Frame(t=0.0, phi=0.0, omega=0.0, epsilon=0.0, points=MappingProxyType(points),
                      joints=MappingProxyType(joints), status=STATUS_OK, conditioning=1.0, message="",
                      **extra)
        candidates = [t for t, _ in builder.topics if t != DIAGNOSTICS]
        tips = {"load_tips": tuple(value[("lt", k)] for k in range(2 * len(self._loads)))} if forces else {}
        messages = dict(builder.build_topics(frame, SEC * NS_PER_S + NSEC, candidates,
                                             include_paths=False, tree=tree, **tips))
        self._templates: dict[str, _Template] = {}
        for topic in candidates:
            template = _compile(topic, cdr_bytes(serialize, messages[topic], self.types[topic]), len(slots))
            if template is not None:
                self._templates[topic] = template
        self._each = {t: Packer([tpl], self.slots, self.slots) for t, tpl in self._templates.items()}
        self.verified = False
        self._every_tick = self.packer(self.slots)

    # ------------------------------------------------------------------ public
    @property
    def template_topics(self) -> list[str]:
        """Topics rendered from templates (the others are built and serialised per tick)."""
        return list(self._templates)

    def packer(self, order: Sequence[Slot], topics: Sequence[str] | None = None) -> Packer | None:
        """The per-tick topics' bytes (or those of ``topics``) from a vector of numbers in slot
        ``order`` (which must hold every slot of :attr:`slots`); None when one of them has no
        template (those ticks take :meth:`render`)."""
        if topics is None:
            topics = [t for t in self.types if t != DIAGNOSTICS]
        if any(t not in self._templates for t in topics):
            return None
        return Packer([self._templates[t] for t in topics], order, self.slots)

    def numbers(self, frame: Frame, stamp_ns: int) -> tuple[Any, ...]:
        """The numbers of ``frame`` stamped ``stamp_ns`` in the order of :attr:`slots`."""
        sec, nanosec = divmod(int(stamp_ns), NS_PER_S)
        values: list[Any] = [sec, nanosec]
        add = values.extend  # (not +=: a whole run's rows are numpy arrays)
        points = frame.points
        for p in self._moving:
            add(points[p].position)
        for p in self._published:
            add(points[p].velocity)
        for p in self._published:
            add(points[p].acceleration)
        joints = frame.joints
        for j in self._joint_names:
            add(joints[j])
        if self._tree:
            tree = self.builder.tree_states(frame)
            assert tree is not None
            add(tree.position)
            add(tree.velocity)
        if self._efforts:
            efforts, loads = frame.efforts, frame.loads
            add([efforts[q] for q in self._efforts])
            for key in self._loads:
                add(loads[key])
            add(self.builder.load_tips(frame))
        if self._friction:
            friction = frame.friction
            add([friction[name] for name in self._friction])
        return tuple(values)

    def render(self, frame: Frame, stamp_ns: int, *, paths: bool = False,
               diagnostics: bool = True) -> list[tuple[str, bytes]]:
        """``[(topic, CDR bytes)]`` of ``frame`` stamped ``stamp_ns``, in the builder's topic
        order. ``markers`` carry the paths when ``paths``; ``diagnostics`` is left out unless
        ``diagnostics``."""
        if not self.verified:
            self.verify(frame, stamp_ns)
        values = self.numbers(frame, stamp_ns)
        if self._every_tick is not None and not paths and not diagnostics:  # most ticks
            return self._every_tick(values)
        out: list[tuple[str, bytes]] = []
        generic: list[str] = []
        packed = dict(self._pack_each(values, [t for t in self._templates if not (paths and t == MARKERS)]))
        for topic in self.types:
            data = packed.get(topic)
            if data is not None:
                out.append((topic, data))
            elif topic != DIAGNOSTICS or diagnostics:
                out.append((topic, b""))
                generic.append(topic)
        if generic:
            built = dict(self.generic(frame, stamp_ns, generic, paths=paths))
            out = [(t, data if data else built[t]) for t, data in out]
        return out

    def energies(self, values: Sequence[float]) -> bytes:
        """The CDR bytes of an ``energies`` row (:meth:`MessageBuilder.energies`)."""
        return cdr_bytes(self.serialize, self.builder.energies(values), "std_msgs/msg/Float64MultiArray")

    def generic(self, frame: Frame, stamp_ns: int, topics: Sequence[str], *,
                paths: bool = False) -> list[tuple[str, bytes]]:
        """``topics`` of ``frame`` built and serialised the ordinary way (e.g. the diagnostics of
        an input state that has no frame: ``frame`` may then carry no points or joints)."""
        built = self.builder.build_topics(frame, stamp_ns, topics, include_paths=paths)
        return [(t, cdr_bytes(self.serialize, m, self.types[t])) for t, m in built]

    def verify(self, frame: Frame, stamp_ns: int) -> list[str]:
        """Topics whose template rendering of ``frame`` differs from the builder's output (they
        are built the ordinary way from then on); empty when every template is exact."""
        self.verified = True
        ordinary = dict(self.generic(frame, stamp_ns, list(self._templates)))
        bad = [t for t, data in self._pack_each(self.numbers(frame, stamp_ns), list(self._templates))
               if data != ordinary[t]]
        for topic in bad:
            del self._templates[topic], self._each[topic]
        self._every_tick = self.packer(self.slots)
        return bad

    def render_block(self, topic: str, rows: np.ndarray) -> list[bytes]:
        """The bytes of ``topic`` for a block of ticks: ``rows`` is ``(n, len(slots))``, each row
        a tick's :meth:`numbers` (the stamp's sec and nanosec as floats, which hold them exactly)."""
        tpl = self._templates[topic]
        n = rows.shape[0]
        size = len(tpl.raw)
        out = np.empty((n, size), dtype=np.uint8)
        out[:] = np.frombuffer(tpl.raw, dtype=np.uint8)
        columns = {"d": "<f8", "i": "<i4", "I": "<u4"}
        for off, code, j in tpl.fields:
            column = np.ascontiguousarray(rows[:, j].astype(columns[code]))
            out[:, off: off + _SIZES[code]] = column.view(np.uint8).reshape(n, _SIZES[code])
        flat = out.tobytes()
        return [flat[i * size: (i + 1) * size] for i in range(n)]

    # ------------------------------------------------------------------ helpers
    def _pack_each(self, values: tuple[Any, ...], topics: Sequence[str]) -> list[tuple[str, bytes]]:
        """``topics`` (templated) packed from canonical ``values``, one template at a time."""
        return [self._each[t](values)[0] for t in topics]


_U32 = struct.Struct("<I").unpack_from
_STAMP_AND_FRAME_ID = struct.Struct("<iII").unpack_from
_CDR_LE = b"\x00\x01"


def read_joint_state(data: bytes) -> tuple[list[str], tuple[float, ...], tuple[float, ...], int] | None:
    """``(names, positions, velocities, stamp_ns)`` of the CDR bytes of a ``sensor_msgs/JointState``
    (what a raw subscription receives: XCDR1 little endian, as Fast DDS and rosbags write it),
    read straight off the bytes with ``struct`` instead of building the message object; None for
    anything else (another encapsulation, truncated or inconsistent bytes, names that are not
    UTF-8): the caller then deserialises the ordinary way. The effort array is not read."""
    if data[:2] != _CDR_LE:
        return None
    try:
        sec, nanosec, length = _STAMP_AND_FRAME_ID(data, 4)
        pos = 16 + length  # header.frame_id: length (with its NUL), characters
        pos += -pos & 3
        (count,) = _U32(data, pos)
        if count > (len(data) - pos) // 4:
            return None
        pos += 4
        names = []
        for _ in range(count):
            (length,) = _U32(data, pos)
            pos += 4
            if length < 1 or pos + length > len(data) or data[pos + length - 1] != 0:
                return None
            names.append(data[pos:pos + length - 1].decode())
            pos += length
            pos += -pos & 3
        positions, pos = _doubles(data, pos)
        velocities, pos = _doubles(data, pos)
    except (struct.error, UnicodeDecodeError):
        return None
    return names, positions, velocities, sec * NS_PER_S + nanosec


def _doubles(data: bytes, pos: int) -> tuple[tuple[float, ...], int]:
    """A ``float64[]`` at ``pos`` (length aligned to 4, elements to 8 after the 4-byte
    encapsulation header): its values and the position after it."""
    pos += -pos & 3
    (count,) = _U32(data, pos)
    pos += 4
    if not count:
        return (), pos
    pos += -(pos - 4) & 7
    if pos + 8 * count > len(data):
        raise struct.error("truncated float64[]")
    return struct.unpack_from(f"<{count}d", data, pos), pos + 8 * count


def _compile(topic: str, raw: bytes, count: int) -> _Template | None:
    """The template of one serialised probe message (None when its sentinels overlap)."""
    fields: list[tuple[int, str, int]] = []
    fields += [(off, "i", 0) for off in find_all(raw, struct.pack("<i", SEC))]
    fields += [(off, "I", 1) for off in find_all(raw, struct.pack("<I", NSEC))]
    for j in range(2, count):
        fields += [(off, "d", j) for off in find_all(raw, struct.pack("<d", sentinel(j)))]
    fields.sort()
    pos = 0
    for off, code, _ in fields:
        if off < pos:
            return None
        pos = off + _SIZES[code]
    return _Template(topic, raw, tuple(fields))
