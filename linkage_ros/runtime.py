"""What mechanism_node does, without rclpy: its parameters, their checks, and the tick.

The node (:mod:`linkage_ros.node`) is a thin shell: it declares :data:`PARAMETERS`, forwards
parameter changes to :meth:`Runtime.update` and timer ticks to :meth:`Runtime.tick`, and
publishes the CDR bytes that come back (the recorder writes the same bytes). Everything here is
plain Python and tested without ROS.

Topic mode (``input_source: topic``, issue 12): the node answers every
``sensor_msgs/JointState`` on ``input_joint_states`` through :meth:`Runtime.answer` instead of
ticking (:mod:`linkage_ros.relay` reads the input state off the message, with the ε rule
``topic_epsilon`` and the gap ``topic_max_gap``); ``joint_states`` then leaves out the input
joint, which the driver publishes.

Several inputs (a scene with ``scene.inputs`` = (q1, …, qk), docs/inputs.md): ``omega``,
``epsilon`` and ``phi0`` apply to every input unless the double arrays ``input_omegas``,
``input_epsilons``, ``input_phi0s`` give one value per input, in the order of ``scene.inputs``
(empty: the scalar; another length is rejected with a reason naming the inputs); the engine then
runs a :class:`~linkage_ros.motion.Motions`. In topic mode every input joint is read from the
same message and joint_states leaves out all of them.

What a tick sends: every topic of :func:`~linkage_ros.messages.topic_types` except that
``diagnostics`` goes out on the first tick, whenever the status changes (ok / near singular /
unassemblable, or a new unassemblable event) and otherwise every :data:`DIAGNOSTICS_PERIOD_S`
of clock time; the markers carry the paths on the first tick and then once per
:data:`~linkage_ros.messages.PATH_PERIOD` of run time.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

import solver
from solver.errors import SolverError

from .engine import ON_UNASSEMBLABLE, STATUS_OK, STATUS_UNASSEMBLABLE, Engine, Frame
from .instant import FastPath
from .messages import DIAGNOSTICS, MessageBuilder, MessageTypes, topic_types
from .motion import SEGMENT_HOLD, Motion, Motions
from .relay import (
    ANSWER_DROPPED,
    ANSWER_FRAME,
    DEFAULT_MAX_GAP,
    EPSILON_RULES,
    EPSILON_ZERO,
    Answer,
    Reading,
    Relay,
)
from .serialize import Serializer

__all__ = [
    "DIAGNOSTICS_PERIOD_S",
    "INPUT_SOURCES",
    "PARAMETERS",
    "PER_INPUT",
    "RESUMING",
    "ParameterSpec",
    "Recorder",
    "RecorderFactory",
    "Runtime",
    "per_input",
    "per_input_reason",
    "validate_parameter",
]

NS_PER_S = 1_000_000_000
#: Largest |ω| (rad/s), |ε| (rad/s²) and rate (Hz) the node accepts.
MAX_OMEGA = 1.0e4
MAX_EPSILON = 1.0e6
MAX_RATE_HZ = 1.0e4
MIN_RATE_HZ = 1.0e-3
#: Clock seconds between two diagnostics messages while the status stays the same.
DIAGNOSTICS_PERIOD_S = 1.0
#: Accepted values of ``input_source``.
INPUT_SOURCES = ("clock", "topic")
#: Topic mode: the range of ``topic_max_gap`` (s).
MAX_GAP_RANGE_S = (1.0e-3, 60.0)
#: Parameters whose accepted set resumes an input held where the mechanism could not be
#: assembled (``on_unassemblable: stop``), even when the value does not change.
RESUMING = frozenset({"omega", "epsilon", "input_omegas", "input_epsilons", "on_unassemblable"})

#: The diagnostics key of an ordinary frame: the fast path runs while it is the last one sent.
_ORDINARY = (STATUS_OK, "")

_FRAME_ID = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_./-]*\Z")
_POINT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


@dataclass(frozen=True)
class ParameterSpec:
    """One node parameter: ``kind`` is ``"string"``, ``"double"``, ``"double_array"`` or
    ``"string_array"``;
    ``float_range`` is ``(from, to)`` for a FloatingPointRange."""

    name: str
    kind: str
    default: Any
    description: str
    float_range: tuple[float, float] | None = None
    constraints: str = ""


PARAMETERS: tuple[ParameterSpec, ...] = (
    ParameterSpec(
        "scene", "string", "harvester_finger",
        "Scene file (YAML), or the name of a shipped scene (four_bar, harvester_finger, ...).",
        constraints="an existing file or a shipped scene name",
    ),
    ParameterSpec(
        "omega", "double", 1.0,
        "Angular velocity of the input joint, rad/s. A change starts a new motion segment "
        "(phi continuous).",
        float_range=(-MAX_OMEGA, MAX_OMEGA),
    ),
    ParameterSpec(
        "epsilon", "double", 0.0,
        "Angular acceleration of the input joint, rad/s^2. A change starts a new motion segment "
        "(phi and omega continuous).",
        float_range=(-MAX_EPSILON, MAX_EPSILON),
    ),
    ParameterSpec(
        "phi0", "double", 0.0,
        "Input angle at the first tick, rad. A change restarts the motion there.",
        constraints="finite; the mechanism must be assemblable there",
    ),
    ParameterSpec(
        "input_omegas", "double_array", (),
        "Scenes with several inputs: angular velocity of each input, rad/s, in the order of the "
        "scene's inputs; empty: omega for every input. A change starts a new motion segment.",
        float_range=(-MAX_OMEGA, MAX_OMEGA),
        constraints="empty, or one finite value per input of the scene",
    ),
    ParameterSpec(
        "input_epsilons", "double_array", (),
        "Scenes with several inputs: angular acceleration of each input, rad/s^2, in the order of "
        "the scene's inputs; empty: epsilon for every input. A change starts a new motion segment.",
        float_range=(-MAX_EPSILON, MAX_EPSILON),
        constraints="empty, or one finite value per input of the scene",
    ),
    ParameterSpec(
        "input_phi0s", "double_array", (),
        "Scenes with several inputs: angle of each input at the first tick, rad, in the order of "
        "the scene's inputs; empty: phi0 for every input. A change restarts the motion there.",
        constraints="empty, or one finite value per input; the mechanism must be assemblable there",
    ),
    ParameterSpec(
        "rate_hz", "double", 100.0, "Publishing rate, Hz.",
        float_range=(MIN_RATE_HZ, MAX_RATE_HZ),
    ),
    ParameterSpec(
        "frame_id", "string", "world", "frame_id of every message header.",
        constraints="non-empty; letters, digits, _ . / -",
    ),
    ParameterSpec(
        "points", "string_array", None,
        "Points whose kinematics are published (points/<P>/...); default: the scene's outputs. "
        "Left at the outputs, it follows a change of scene.",
        constraints="names of points of the scene",
    ),
    ParameterSpec(
        "on_unassemblable", "string", "stop",
        "What the input does where the mechanism cannot be assembled: stop (hold the last valid "
        "state) or reverse (reverse the drive at the boundary).",
        constraints="stop or reverse",
    ),
    ParameterSpec(
        "record_mcap", "string", "",
        "MCAP file to record every published message to (rosbag2 profile); empty: off. "
        "The directory must exist.",
    ),
    ParameterSpec(
        "input_source", "string", "clock",
        "Where the input comes from: clock (phi(t) from omega and epsilon at rate_hz) or topic "
        "(every sensor_msgs/JointState on input_joint_states is answered under its stamp).",
        constraints="clock or topic",
    ),
    ParameterSpec(
        "input_joint", "string", "",
        "Topic mode: the joint of the incoming JointState that drives the mechanism; empty: the "
        "scene's input joint.",
        constraints="empty, the scene's input joint, or a URDF-style revolute joint of the scene",
    ),
    ParameterSpec(
        "topic_epsilon", "string", EPSILON_ZERO,
        "Topic mode: the input's angular acceleration. zero: 0 (positions and velocities exact, "
        "accelerations lack v_q*epsilon); difference: the difference of the velocities of two "
        "successive messages at most topic_max_gap apart (lags half a sample, amplifies noise).",
        constraints=" or ".join(EPSILON_RULES),
    ),
    ParameterSpec(
        "topic_max_gap", "double", DEFAULT_MAX_GAP,
        "Topic mode: two messages further apart than this (s) are not differenced (for omega when "
        "a message has no velocities, and for topic_epsilon: difference).",
        float_range=MAX_GAP_RANGE_S,
    ),
)

_SPECS = {spec.name: spec for spec in PARAMETERS}
#: The per-input double arrays and the scalar each one stands in for when empty.
PER_INPUT = {"input_omegas": "omega", "input_epsilons": "epsilon", "input_phi0s": "phi0"}


def _finite_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def validate_parameter(name: str, value: Any) -> str | None:
    """Why ``value`` is not acceptable for parameter ``name``, or None if it is.

    Parameters that are not the node's own (``use_sim_time``, ...) are always accepted.
    """
    spec = _SPECS.get(name)
    if spec is None:
        return None
    if spec.kind == "double":
        if not _finite_number(value):
            return f"{name} must be a finite number, got {value!r}"
        if name == "rate_hz" and value <= 0:
            return f"rate_hz must be > 0, got {value!r}"
        if spec.float_range is not None:
            lo, hi = spec.float_range
            if not lo <= value <= hi:
                return f"{name} must lie in [{lo:g}, {hi:g}], got {value!r}"
        return None
    if spec.kind == "double_array":
        if isinstance(value, (str, bytes)) or not isinstance(value, Sequence):
            return f"{name} must be a list of numbers, got {value!r}"
        bad = [v for v in value if not _finite_number(v)]
        if bad:
            return f"{name} must hold finite numbers, got {list(value)!r}"
        if spec.float_range is not None:
            lo, hi = spec.float_range
            if not all(lo <= v <= hi for v in value):
                return f"{name}: every value must lie in [{lo:g}, {hi:g}], got {list(value)!r}"
        return None
    if spec.kind == "string_array":
        if isinstance(value, str) or not all(isinstance(v, str) for v in value):
            return f"{name} must be a list of strings, got {value!r}"
        bad = [v for v in value if v and not _POINT.match(v)]
        if bad:
            return f"{name}: {', '.join(map(repr, bad))} cannot be part of a topic name"
        return None
    if not isinstance(value, str):
        return f"{name} must be a string, got {value!r}"
    if name == "scene":
        if not value:
            return "scene must name a scene file or a shipped scene"
        try:
            solver.find_scene(value)
        except SolverError as error:
            if Path(value).is_dir():
                return f"scene {value!r}: {getattr(error, 'reason', error)}"
            return f"unknown scene {value!r}: {error}"
    elif name == "frame_id":
        if not _FRAME_ID.match(value):
            return f"frame_id must be non-empty (letters, digits, _ . / -), got {value!r}"
    elif name == "on_unassemblable" and value not in ON_UNASSEMBLABLE:
        return f"on_unassemblable must be one of {', '.join(ON_UNASSEMBLABLE)}, got {value!r}"
    elif name == "input_source" and value not in INPUT_SOURCES:
        return f"input_source must be one of {', '.join(INPUT_SOURCES)}, got {value!r}"
    elif name == "topic_epsilon" and value not in EPSILON_RULES:
        return f"topic_epsilon must be one of {', '.join(EPSILON_RULES)}, got {value!r}"
    return None


class Recorder(Protocol):
    """What the runtime needs of a recorder (``linkage_ros.record.mcap.Recorder`` fits)."""

    def write_serialized(self, stamp_ns: int, messages: Sequence[tuple[str, bytes]]) -> None: ...

    def close(self) -> None: ...


#: ``factory(path, topics, engine=..., frame_id=...)`` opens a recorder for
#: ``[(topic, type name)]`` (``engine`` and ``frame_id`` for the file's scene metadata).
RecorderFactory = Callable[..., Recorder]


def _jazzy_typestore() -> Any:
    from rosbags.typesys import Stores, get_typestore

    return get_typestore(Stores.ROS2_JAZZY)


def _points_of(value: Any) -> tuple[str, ...]:
    return tuple(p for p in (value or ()) if p)


def _inputs_of(scene: Any) -> tuple[str, ...]:
    """The scene's input joints, in order (one for a single-input scene)."""
    return tuple(getattr(scene, "inputs", ()) or (scene.input_joint,))


def per_input_reason(settings: Mapping[str, Any], inputs: Sequence[str]) -> str | None:
    """Why the per-input arrays of ``settings`` do not fit a scene with ``inputs``, or None."""
    for name, scalar in PER_INPUT.items():
        values = settings.get(name) or ()
        if len(values) and len(values) != len(inputs):
            return (
                f"{name} needs {len(inputs)} value(s), one per input of the scene ({', '.join(inputs)}), "
                f"or none ({scalar} for every input); got {len(values)}: {list(values)!r}"
            )
    return None


def per_input(settings: Mapping[str, Any], scalar: str, inputs: Sequence[str]) -> Any:
    """The value of ``omega``, ``epsilon`` or ``phi0`` for a scene with ``inputs``: a float with
    one input, a k-tuple with several (the array's entries, or the scalar for every input)."""
    array = next(name for name, s in PER_INPUT.items() if s == scalar)
    values = settings.get(array) or ()
    if len(inputs) == 1:
        return float(values[0]) if len(values) else float(settings[scalar])
    if len(values):
        return tuple(float(v) for v in values)
    return (float(settings[scalar]),) * len(inputs)


class Runtime:
    """The node's state: settings, engine, message builder, run clock and optional recorder.

    ``values``: parameter values by name (defaults from :data:`PARAMETERS` fill the gaps).
    ``types`` and ``serialize(msg, typename)``: rosbags' message classes and CDR serialiser
    (default: rosbags' Jazzy type store); the ticks are rendered by
    :class:`~linkage_ros.serialize.Serializer` from templates the builder makes with them; ordinary
    instants take the fast path of :mod:`linkage_ros.instant` (no Frame, one pack per topic).
    ``recorder_factory``: opens the MCAP recorder when ``record_mcap`` is set.
    Raises :class:`solver.SolverError` (or ValueError) for unusable start values.
    """

    def __init__(
        self,
        values: Mapping[str, Any],
        types: Mapping[str, Any] | MessageTypes | None = None,
        *,
        serialize: Callable[[Any, str], Any] | None = None,
        recorder_factory: RecorderFactory | None = None,
    ) -> None:
        settings = {spec.name: spec.default for spec in PARAMETERS}
        settings.update({k: v for k, v in values.items() if k in _SPECS and v is not None})
        for name, value in settings.items():
            if value is None:
                continue
            reason = validate_parameter(name, value)
            if reason:
                raise ValueError(reason)
        for name in PER_INPUT:
            settings[name] = tuple(float(v) for v in settings[name] or ())
        if types is None or serialize is None:
            store = _jazzy_typestore()
            types = store.types if types is None else types
            serialize = store.serialize_cdr if serialize is None else serialize
        self.types = types if isinstance(types, MessageTypes) else MessageTypes(types)
        self._serialize = serialize
        self._diagnostics_key: tuple[str, str] | None = None
        self._diagnostics_ns = 0
        self._recorder_factory = recorder_factory
        self.settings = settings
        self.start_ns: int | None = None
        self._last_ns: int | None = None
        self._last_frame: Frame | FastPath | None = None
        self._fast_path: FastPath | None = None
        self._last_event = ""
        self.events: list[str] = []
        self.input_warnings: list[str] = []
        self.engine = self._engine(settings, t0=0.0)
        self.settings["points"] = list(self.engine.published_points)
        self.relay = self._relay(self.engine, settings)
        self.builder, self.wire = self._builder(self.engine, settings["frame_id"], self.relay)
        self.recorder: Recorder | None = None
        if settings["record_mcap"]:
            self.recorder = self._open_recorder(settings["record_mcap"], self.engine, settings["frame_id"])

    # ------------------------------------------------------------------ queries
    @property
    def topics(self) -> list[tuple[str, str]]:
        """``[(relative topic, type name)]`` published now."""
        return topic_types(self.engine)

    @property
    def topic_mode(self) -> bool:
        """Whether the input comes from ``input_joint_states`` (not from the clock)."""
        return self.relay is not None

    @property
    def period_s(self) -> float:
        return 1.0 / float(self.settings["rate_hz"])

    def run_time(self, now_ns: int) -> float:
        """Seconds since the first tick (0 before it)."""
        if self.start_ns is None:
            return 0.0
        return (int(now_ns) - self.start_ns) / NS_PER_S

    # ------------------------------------------------------------------ the tick
    def tick(self, now_ns: int) -> list[tuple[str, bytes]]:
        """Solve the frame at clock time ``now_ns`` and render its messages as CDR bytes
        (stamp = ``now_ns``); the recorder, if any, gets the same bytes.

        A clock at zero (simulated time before the first /clock message) gives no messages.
        A clock that jumps backwards restarts the run at ``phi0``.
        """
        now_ns = int(now_ns)
        if now_ns <= 0 or self.relay is not None:
            return []
        if self.start_ns is None:
            self.start_ns = now_ns
        elif self._last_ns is not None and now_ns < self._last_ns:
            self.events.append("clock jumped backwards: restarting the run at phi0")
            self.start_ns = now_ns
            self.engine = self._engine(self.settings, t0=0.0)
            self.builder, self.wire = self._builder(self.engine, self.settings["frame_id"], None)
        self._last_ns = now_ns
        t = self.run_time(now_ns)
        messages = self._fast(t, now_ns, None)
        if messages is None:  # the Frame path (linkage_ros.instant: when and why)
            frame = self.engine.frame(t)
            self.last_frame = frame
            if frame.status == STATUS_UNASSEMBLABLE and frame.message != self._last_event:
                self.events.append(frame.message)
            self._last_event = frame.message if frame.status == STATUS_UNASSEMBLABLE else ""
            messages = self.wire.render(frame, now_ns, paths=self.builder.wants_paths(frame.t),
                                        diagnostics=self._wants_diagnostics(frame, now_ns))
        if self.recorder is not None:
            self.recorder.write_serialized(now_ns, messages)
        return messages

    def answer(self, names: Sequence[str], positions: Sequence[float], velocities: Sequence[float],
               stamp_ns: int) -> list[tuple[str, bytes]]:
        """Topic mode: the messages that answer one incoming JointState, under its stamp (the
        recorder gets the same bytes); nothing in clock mode.

        A frame: every topic (joint_states without the input joint). Unassemblable: only
        diagnostics, level ERROR with the group and the φ interval (nothing non-finite, no
        joint_states). Dropped (no input joint, a non-finite value): nothing, and a line in
        :attr:`input_warnings`. The relay's own joint_states coming back: nothing.
        """
        if self.relay is None:
            return []
        reading = self.relay.read(names, positions, velocities, stamp_ns)
        if isinstance(reading, Answer):  # dropped, or the relay's own joint_states (ignored)
            if reading.kind == ANSWER_DROPPED:
                self.input_warnings.append(f"JointState dropped: {reading.reason}")
            return []
        stamp = reading.stamp_ns
        messages = self._fast(stamp / NS_PER_S, stamp, reading)
        if messages is None:  # the Frame path (linkage_ros.instant: when and why)
            answer = self.relay.solve(reading)
            if answer.kind == ANSWER_FRAME:
                frame = answer.frame
                assert frame is not None
                self.last_frame = frame
                messages = self.wire.render(frame, stamp, paths=self.builder.wants_paths(frame.t),
                                            diagnostics=self._wants_diagnostics(frame, stamp))
            else:  # ANSWER_UNASSEMBLABLE
                self.input_warnings.append(answer.reason)
                several = isinstance(answer.phi, tuple)  # several inputs: k-tuples as read
                state = Frame(t=stamp / NS_PER_S,
                              phi=answer.phi if several else float(answer.phi or 0.0),  # type: ignore[arg-type]
                              omega=answer.omega if several else float(answer.omega or 0.0),  # type: ignore[arg-type]
                              epsilon=answer.epsilon if several else float(answer.epsilon or 0.0),  # type: ignore[arg-type]
                              points={}, joints={},
                              status=STATUS_UNASSEMBLABLE, conditioning=0.0, message=answer.reason)
                self._diagnostics_key = None  # the next frame reports again
                messages = self.wire.generic(state, stamp, [DIAGNOSTICS])
        if self.recorder is not None:
            self.recorder.write_serialized(stamp, messages)
        return messages

    def take_input_warnings(self) -> list[str]:
        """Topic mode: dropped and unassemblable messages since the last call."""
        warnings, self.input_warnings = self.input_warnings, []
        return warnings

    def _fast(self, t: float, stamp_ns: int, reading: Reading | None) -> list[tuple[str, bytes]] | None:
        """The bytes of an ordinary instant from the fast path (:mod:`linkage_ros.instant`) when
        the status is ok and neither diagnostics nor the path markers are due; None: take the
        Frame path."""
        if (self._diagnostics_key != _ORDINARY or self.builder.wants_paths(t)
                or not 0 <= stamp_ns - self._diagnostics_ns < DIAGNOSTICS_PERIOD_S * NS_PER_S):
            return None
        fast = self._fast_path
        if fast is None or fast.serializer is not self.wire:
            fast = self._fast_path = FastPath(self.engine, self.builder, self.wire)
        if reading is None:
            messages = fast.tick(t, stamp_ns)
        else:
            messages = fast.answer(reading.phi, reading.omega, reading.epsilon, stamp_ns)
        if messages is not None:
            self._last_frame = fast
        return messages

    @property
    def last_frame(self) -> Frame | None:
        """The frame of the last tick or answer (the fast path's is solved when asked for)."""
        last = self._last_frame
        if isinstance(last, FastPath):
            last = self._last_frame = last.last_frame()
        return last

    @last_frame.setter
    def last_frame(self, frame: Frame | None) -> None:
        self._last_frame = frame

    def _wants_diagnostics(self, frame: Frame, now_ns: int) -> bool:
        """First tick, a change of status (or a new unassemblable event), or a period passed."""
        key = (frame.status, frame.message if frame.status == STATUS_UNASSEMBLABLE else "")
        if (key != self._diagnostics_key or self._diagnostics_key is None
                or not 0 <= now_ns - self._diagnostics_ns < DIAGNOSTICS_PERIOD_S * NS_PER_S):
            self._diagnostics_key, self._diagnostics_ns = key, now_ns
            return True
        return False

    def take_events(self) -> list[str]:
        """Unassemblable (and clock) events since the last call, each reported once."""
        events, self.events = self.events, []
        return events

    # ------------------------------------------------------------------ parameter changes
    def update(self, changes: Mapping[str, Any], now_ns: int) -> str | None:
        """Apply parameter changes atomically; the reason they are rejected, or None.

        ``omega`` / ``epsilon`` start a new motion segment at the current run time; ``scene``,
        ``points`` and ``phi0`` rebuild the engine (``scene`` and ``phi0`` restart the motion at
        ``phi0``); ``record_mcap`` closes the current recorder and opens the new one;
        ``input_source`` switches between clock and topic mode (back to clock, the run restarts
        at ``phi0`` on the next tick); ``input_joint`` is checked against the scene.
        ``input_omegas`` / ``input_epsilons`` act as ``omega`` / ``epsilon``, ``input_phi0s`` as
        ``phi0``; their lengths are checked against the (new) scene's inputs.
        While the input is held where the mechanism could not be assembled (``stop``), an
        accepted set of any of :data:`RESUMING` — also to the value it has — resumes the drive
        from the held φ with the (new) ω and ε. ``topic_epsilon`` / ``topic_max_gap`` make a new
        relay (the next message is not differenced with the one before).
        """
        ours = {k: v for k, v in changes.items() if k in _SPECS}
        for name, value in ours.items():
            reason = validate_parameter(name, value)
            if reason:
                return reason
        if not ours:
            return None
        ours = {k: tuple(float(x) for x in v) if k in PER_INPUT else v for k, v in ours.items()}
        new = {**self.settings, **ours}
        t = self.run_time(now_ns)
        changed = {k for k, v in ours.items() if v != self.settings[k]}
        engine = self.engine
        if changed & {"scene", "points", "phi0", "input_phi0s"}:
            if "scene" in changed and "points" not in ours and (
                _points_of(self.settings["points"]) == tuple(self.engine.scene.output_points)
            ):
                new["points"] = []  # follow the new scene's outputs
            try:
                engine = self._engine(new, t0=t, keep_motion=not changed & {"scene", "phi0", "input_phi0s"})
            except (SolverError, ValueError) as error:
                return str(error)
            new["points"] = list(engine.published_points)
        reason = per_input_reason(new, _inputs_of(engine.scene))
        if reason is not None:
            return reason
        if "input_source" in changed and new["input_source"] == "clock":
            engine = self._engine(new, t0=0.0)  # the run restarts at phi0
        relay = self.relay
        if new["input_source"] == "clock":
            relay = None
        elif (relay is None or engine is not self.engine
              or changed & {"input_joint", "topic_epsilon", "topic_max_gap"}):
            try:
                relay = self._relay(engine, new)
            except ValueError as error:
                return str(error)
        recorder = self.recorder
        if "record_mcap" in changed and new["record_mcap"]:
            try:
                recorder = self._open_recorder(new["record_mcap"], engine, new["frame_id"])
            except (OSError, ValueError, ImportError) as error:
                return f"cannot record to {new['record_mcap']!r}: {error}"
        # Nothing can fail from here on.
        if engine.motion is self.engine.motion:
            motion = engine.motion
            inputs = _inputs_of(engine.scene)
            resume = bool(ours.keys() & RESUMING) and motion.segment_at(t).tag == SEGMENT_HOLD
            if changed & {"omega", "input_omegas"} or resume:
                motion.set_omega(t, per_input(new, "omega", inputs), epsilon=per_input(new, "epsilon", inputs))
            elif changed & {"epsilon", "input_epsilons"}:
                motion.set_epsilon(t, per_input(new, "epsilon", inputs))
        engine.on_unassemblable = new["on_unassemblable"]
        if engine is not self.engine or "frame_id" in changed or relay is not self.relay:
            self.builder, self.wire = self._builder(engine, new["frame_id"], relay)
            self._diagnostics_key = None
        if "input_source" in changed and new["input_source"] == "clock":
            self.start_ns = self._last_ns = None
        self.relay = relay
        if recorder is not self.recorder or (not new["record_mcap"] and self.recorder):
            if self.recorder is not None:
                self.recorder.close()
            self.recorder = recorder if new["record_mcap"] else None
        elif self.recorder is not None and engine is not self.engine:
            add = getattr(self.recorder, "add_topic", None)
            if add is not None:
                for topic, typename in topic_types(engine):
                    add(topic, typename)
        self.engine = engine
        self.settings = new
        return None

    def close(self) -> None:
        """Close the recorder, if any."""
        if self.recorder is not None:
            self.recorder.close()
            self.recorder = None

    # ------------------------------------------------------------------ helpers
    def _engine(self, settings: Mapping[str, Any], *, t0: float, keep_motion: bool = False) -> Engine:
        points = _points_of(settings.get("points")) or None
        if keep_motion:
            motion = self.engine.motion
            scene: Any = self.engine.scene
        else:
            scene = solver.load_scene(settings["scene"])
            inputs = _inputs_of(scene)
            reason = per_input_reason(settings, inputs)
            if reason is not None:
                raise ValueError(reason)
            phi0, omega, epsilon = (per_input(settings, name, inputs) for name in ("phi0", "omega", "epsilon"))
            if len(inputs) == 1:
                motion = Motion(phi0=phi0, omega=omega, epsilon=epsilon, t0=t0)
            else:
                motion = Motions.of(len(inputs), phi0=phi0, omega=omega, epsilon=epsilon, t0=t0)
        return Engine(scene, motion, points=points, on_unassemblable=settings["on_unassemblable"])

    def _builder(self, engine: Engine, frame_id: str, relay: Relay | None) -> tuple[MessageBuilder, Serializer]:
        omit = () if relay is None else relay.input_joints
        builder = MessageBuilder(engine, self.types, frame_id=frame_id, omit_joints=omit)
        return builder, Serializer(builder, self._serialize)

    @staticmethod
    def _relay(engine: Engine, settings: Mapping[str, Any]) -> Relay | None:
        """The topic mode's relay (None in clock mode); ValueError for an unknown input_joint."""
        if settings["input_source"] != "topic":
            return None
        return Relay(engine, input_joint=settings["input_joint"] or None,
                     epsilon=settings["topic_epsilon"], max_gap=float(settings["topic_max_gap"]))

    def _open_recorder(self, path: str, engine: Engine, frame_id: str) -> Recorder:
        if self._recorder_factory is None:
            raise ValueError("this node has no MCAP recorder")
        folder = Path(path).parent
        if not folder.is_dir():
            raise ValueError(f"directory {str(folder)!r} does not exist (record_mcap does not create it)")
        return self._recorder_factory(path, topic_types(engine), engine=engine, frame_id=frame_id)
