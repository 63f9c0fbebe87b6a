"""What mechanism_node does, without rclpy: its state, the tick, the answer and parameter updates.

The node (:mod:`linkage_ros.node`) is a thin shell: it declares the parameters of
:mod:`linkage_ros.parameters`, forwards parameter changes to :meth:`Runtime.update` and timer
ticks to :meth:`Runtime.tick`, and publishes the CDR bytes that come back (the recorder writes
the same bytes). Everything here is plain Python and tested without ROS.

Topic mode (``input_source: topic``, issue 12): the node answers every
``sensor_msgs/JointState`` on ``input_joint_states`` through :meth:`Runtime.answer` instead of
ticking (:mod:`linkage_ros.relay` reads the input state off the message, with the ε rule
``topic_epsilon`` and the gap ``topic_max_gap``); ``joint_states`` then leaves out the input
joint, which the driver publishes.

Parameters: :mod:`linkage_ros.parameters` holds their specs, checks and coercion. Several
inputs (docs/inputs.md) take ``omega``, ``epsilon`` and ``phi0`` per input from the arrays of
:data:`~linkage_ros.parameters.PER_INPUT`, and the engine then runs a
:class:`~linkage_ros.motion.Motions`. In topic mode every input joint is read from the same
message and joint_states leaves out all of them.

Dynamic mode (``mode: dynamic``, issue 22): the engine's time law is a
:class:`~linkage_ros.dynamic.DynamicMotion` (or ``DynamicMotions``) that integrates the equation of
motion tick by tick; :meth:`Runtime.command_efforts` takes the effort commands, and a command
that timed out is reported among :attr:`Runtime.events`. Everything after the time law is the
clock mode's.

What a tick sends: every topic of :func:`~linkage_ros.topics.topic_types` except that
``diagnostics`` goes out on the first tick, whenever the status changes (ok / near singular /
unassemblable, or a new unassemblable event) and otherwise every :data:`DIAGNOSTICS_PERIOD_S`
of clock time; the markers carry the paths on the first tick and then once per
:data:`~linkage_ros.messages.PATH_PERIOD` of run time.
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Mapping, Sequence
from pathlib import Path
from typing import Any, Protocol

import solver
from solver.errors import SolverError

from ._runtime_dynamic import DriveState, energy_values
from ._runtime_topic import DIAGNOSTICS_PERIOD_S, TopicAnswers
from ._tick_grid import TickGrid, grid_for
from .dynamic import RESTARTING, drive_reason, dynamic_law, mode_reason
from .engine import Engine
from .frame import STATUS_BEHIND, STATUS_OK, STATUS_UNASSEMBLABLE, Frame
from .instant import FastPath
from .messages import MessageBuilder, MessageTypes
from .motion import SEGMENT_HOLD, Motion, Motions
from .parameters import (
    checked_changes,
    initial_settings,
    inputs_of,
    per_input,
    per_input_reason,
    points_of,
)
from .relay import Reading, Relay
from .serialize import Serializer, cdr_bytes, pad4
from .topics import ENERGIES, INPUT_TYPES, MARKERS, ROBOT_DESCRIPTION, topic_types

__all__ = [
    "DIAGNOSTICS_PERIOD_S",
    "RESUMING",
    "Recorder",
    "RecorderFactory",
    "Runtime",
]

NS_PER_S = 1_000_000_000
#: Parameters whose accepted set resumes an input held where the mechanism could not be
#: assembled (``on_unassemblable: stop``), even when the value does not change.
RESUMING = frozenset({"omega", "epsilon", "input_omegas", "input_epsilons", "on_unassemblable"})

#: The diagnostics keys of an ordinary frame: the fast path runs while one of them is the last
#: one sent. ``behind`` (a dynamic law slower than real time) changes the diagnostics only, not a
#: tick's other bytes: its ticks keep the fast path — on the Frame path every tick (2–3× the
#: cost) a law just behind real time fell further behind (issue 32) — and the change back to ok,
#: as the change to behind, shows in the next periodic diagnostics (at most a second later; the
#: law's own window is a second of run time).
_ORDINARY = frozenset({(STATUS_OK, ""), (STATUS_BEHIND, "")})


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


class Runtime(TopicAnswers):
    """The node's state: settings, engine, message builder, run clock and optional recorder.

    ``values``: parameter values by name (defaults from
    :data:`~linkage_ros.parameters.PARAMETERS` fill the gaps).
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
        settings = initial_settings(values)
        reason = mode_reason(settings)
        if reason is not None:
            raise ValueError(reason)
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
        #: the topics somebody reads (:meth:`publish_only`; None: every topic)
        self._wanted: frozenset[str] | None = None
        self._last_event = ""
        self.events: list[str] = []
        self.input_warnings: list[str] = []
        self.engine = self._engine(settings, t0=0.0)
        #: dynamic mode: the timer's period grid, whose skipped periods the node catches up
        #: (:mod:`linkage_ros._tick_grid`); None in the other modes
        self.grid: TickGrid | None = grid_for(settings)
        self.settings["points"] = list(self.engine.published_points)
        self.relay = self._relay(self.engine, settings)
        self._command_t: float | None = None
        self._description: tuple[tuple[int, str], str | None] | None = None
        self._recorded_inputs: set[str] = set()
        self._views: dict[tuple[str, ...], tuple[MessageBuilder, Serializer, FastPath | None]] = {}
        self._view: tuple[str, ...] = ()
        self.builder: MessageBuilder
        self.wire: Serializer
        self._set_builder(self.engine, settings["frame_id"], self.relay)
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
            self.engine = self._engine(self.settings, t0=0.0, scene=self.engine.scene)
            self._set_builder(self.engine, self.settings["frame_id"], None)
        self._last_ns = now_ns
        t = self.run_time(now_ns)
        messages = self._fast(t, now_ns, None)
        if messages is None:  # the Frame path (linkage_ros.instant: when and why)
            frame = self.engine.frame(t)
            self.last_frame = frame
            if frame.status == STATUS_UNASSEMBLABLE and frame.message != self._last_event:
                self.events.append(frame.message)
            self._last_event = frame.message if frame.status == STATUS_UNASSEMBLABLE else ""
            messages = self.wire.render(frame, now_ns, paths=self._paths_due(frame.t),
                                        diagnostics=self._wants_diagnostics(frame, now_ns))
        notes = getattr(self.engine.motion, "events", None)  # dynamic mode: a command timed out
        if notes:
            self.events += self.engine.motion.take_events()  # type: ignore[union-attr]
        if self.recorder is not None:
            self.recorder.write_serialized(now_ns, messages)
            if notes is not None:  # dynamic mode
                self._record_energies(now_ns, t)
        return messages

    def publish_only(self, topics: Collection[str] | None) -> None:
        """The topics the caller publishes (those with a subscriber; None: every topic): an
        ordinary tick renders only those (and joint_states), unless a recording is open, which
        gets every topic (:meth:`linkage_ros.instant.FastPath.want`). The ticks of the Frame path
        (the first, a change of status, the path markers and diagnostics about once a second)
        render every topic."""
        self._wanted = None if topics is None else frozenset(topics)

    def command_efforts(self, values: Sequence[float], now_ns: int) -> str | None:
        """Dynamic mode: an effort command (``effort_commands``, one value per input) from clock
        time ``now_ns`` on; the one-line reason it is refused (the last good command stays in
        force), or None (:meth:`linkage_ros.dynamic.DynamicMotion.command`)."""
        command = getattr(self.engine.motion, "command", None)
        if command is None:
            return "effort command ignored: mode is kinematic (set mode to dynamic)"
        t = self.run_time(now_ns)
        reason: str | None = command(values, t)
        if reason is None:
            self._command_t = t
        return reason

    def record_input(self, topic: str, stamp_ns: int, data: bytes) -> None:
        """Write a message the node received (``input_joint_states``, ``effort_commands``: its CDR
        bytes as they came) to the recording, if any, beside what the node publishes."""
        recorder = self.recorder
        if recorder is None:
            return
        if topic not in self._recorded_inputs:
            add = getattr(recorder, "add_topic", None)
            if add is not None:
                add(topic, INPUT_TYPES[topic])
            self._recorded_inputs.add(topic)
        recorder.write_serialized(int(stamp_ns), [(topic, data if not len(data) % 4 else pad4(data))])

    def _record_energies(self, now_ns: int, t: float) -> None:
        """Dynamic mode, while recording: the ``energies`` row of the state the tick reached."""
        phi, omega, _ = self.engine.motion.state(t)
        values = energy_values(self.engine.scene, phi, omega)
        self.record_input(ENERGIES, now_ns, self.wire.energies(values))

    def _fast(self, t: float, stamp_ns: int, reading: Reading | None) -> list[tuple[str, bytes]] | None:
        """The bytes of an ordinary instant from the fast path (:mod:`linkage_ros.instant`) when
        the status is ok and neither diagnostics nor the path markers are due; None: take the
        Frame path."""
        if (self._diagnostics_key not in _ORDINARY or self._paths_due(t)
                or not 0 <= stamp_ns - self._diagnostics_ns < DIAGNOSTICS_PERIOD_S * NS_PER_S):
            return None
        fast = self._fast_path
        if fast is None or fast.serializer is not self.wire:
            fast = self._fast_path = FastPath(self.engine, self.builder, self.wire)
        fast.want(self._wanted if self.recorder is None else None)
        if reading is None:
            messages = fast.tick(t, stamp_ns)
        else:
            messages = fast.answer(reading.phi, reading.omega, reading.epsilon, stamp_ns)
        if messages is not None:
            self._last_frame = fast
        return messages

    def _paths_due(self, t: float) -> bool:
        """Whether a tick at ``t`` draws the paths into ``markers`` (its builder's period) —
        never while nobody reads ``markers`` and nothing records (:meth:`publish_only`): the path
        markers, serialised the generic way, took 2–6 ms once a second, more than a 1 kHz period
        (issue 32); a reader matched later gets them on its next tick."""
        wanted = self._wanted
        if wanted is not None and MARKERS not in wanted and self.recorder is None:
            return False
        return self.builder.wants_paths(t)

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
        ours, reason = checked_changes(changes)
        if reason:
            return reason
        if not ours:
            return None
        new = {**self.settings, **ours}
        t = self.run_time(now_ns)
        changed = {k for k, v in ours.items() if v != self.settings[k]}
        engine = self.engine
        restart = False
        reason = mode_reason(new)
        if reason is not None:
            return reason
        if changed & {"scene", "points", "phi0", "input_phi0s", *RESTARTING}:
            if "scene" in changed and "points" not in ours and (
                points_of(self.settings["points"]) == tuple(self.engine.scene.output_points)
            ):
                new["points"] = []  # follow the new scene's outputs
            try:
                restart = bool(changed & {"scene", "phi0", "input_phi0s", *RESTARTING})
                same = None if "scene" in changed else self.engine.scene  # reused: compiled once
                engine = self._engine(new, t0=0.0 if restart else t, keep_motion=not restart, scene=same)
            except (SolverError, ValueError) as error:
                return str(error)
            new["points"] = list(engine.published_points)
        reason = per_input_reason(new, inputs_of(engine.scene))
        if reason is not None:
            return reason
        if "input_source" in changed and new["input_source"] == "clock":
            engine = self._engine(new, t0=0.0, scene=engine.scene)  # the run restarts at phi0
        dynamic = getattr(engine.motion, "set_kind", None)  # dynamic mode: drive from the state reached
        if dynamic is not None and "drive" in changed and engine.motion is self.engine.motion:
            reason = drive_reason(engine.scene, new["drive"])
            if reason is not None:
                return reason
        relay = self.relay
        if new["input_source"] == "clock":
            relay = None
        elif (relay is None or engine is not self.engine
              or changed & {"input_joint", "input_joints", "topic_epsilon", "topic_max_gap"}):
            try:
                relay = self._relay(engine, new)
            except ValueError as error:
                return str(error)
        if relay is None and (new["input_joint"] or new["input_joints"]) and (
                engine is not self.engine or changed & {"input_joint", "input_joints"}):
            try:  # clock mode: the names are checked now, not at the switch to topic mode
                self._relay(engine, {**new, "input_source": "topic"})
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
            inputs = inputs_of(engine.scene)
            resume = bool(ours.keys() & RESUMING) and motion.segment_at(t).tag == SEGMENT_HOLD
            if changed & {"omega", "input_omegas"} or resume:
                motion.set_omega(t, per_input(new, "omega", inputs), epsilon=per_input(new, "epsilon", inputs))
            elif changed & {"epsilon", "input_epsilons"}:
                motion.set_epsilon(t, per_input(new, "epsilon", inputs))
        engine.on_unassemblable = new["on_unassemblable"]
        if dynamic is not None and engine.motion is self.engine.motion:
            if "drive" in changed:
                dynamic(new["drive"])
            engine.motion.timeout = float(new["effort_timeout"])  # type: ignore[union-attr]
        if engine is not self.engine or "frame_id" in changed or relay is not self.relay:
            self._set_builder(engine, new["frame_id"], relay)
            self._diagnostics_key = None
        if restart or ("input_source" in changed and new["input_source"] == "clock"):
            self.start_ns = self._last_ns = None  # a new run: its first tick is at t = 0, at phi0
        self.relay = relay
        if recorder is not self.recorder:
            self._recorded_inputs = set()
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
        if changed & {"mode", "rate_hz"}:
            self.grid = grid_for(new)
        self.settings = new
        return None

    def robot_description(self) -> str | None:
        """The URDF of the scene's tree (``linkage-urdf``, root link ``frame_id``) for the node's
        latched ``robot_description``; None for a scene the URDF export cannot open. Built once
        per scene and frame_id."""
        key = (id(self.engine.scene), self.settings["frame_id"])
        if self._description is None or self._description[0] != key:
            from .urdf import exportable_model, generate_urdf

            text = (generate_urdf(self.engine.scene, frame_id=self.settings["frame_id"])
                    if exportable_model(self.engine.scene) is not None else None)
            self._description = (key, text)
        return self._description[1]

    def record_description(self, now_ns: int) -> None:
        """Write :meth:`robot_description` to the recording, if any (the node calls it when it
        publishes the description and when a new recording starts)."""
        text = self.robot_description()
        if self.recorder is not None and text is not None:
            message = self.types.classes["std_msgs/msg/String"](data=text)
            self.record_input(ROBOT_DESCRIPTION, now_ns, cdr_bytes(self._serialize, message, "std_msgs/msg/String"))

    def close(self) -> None:
        """Close the recorder, if any."""
        if self.recorder is not None:
            self.recorder.close()
            self.recorder = None

    # ------------------------------------------------------------------ helpers
    def _engine(self, settings: Mapping[str, Any], *, t0: float, keep_motion: bool = False,
                scene: Any = None) -> Engine:
        """A new engine for ``settings``: the current motion (``keep_motion``), or a new one
        from ``phi0`` at run time ``t0``; ``scene``: the loaded scene to reuse (its compiled
        instant is built once), else ``settings["scene"]`` is loaded."""
        points = points_of(settings.get("points")) or None
        if keep_motion:
            motion = self.engine.motion
            scene = self.engine.scene
        else:
            scene = solver.load_scene(settings["scene"]) if scene is None else scene
            inputs = inputs_of(scene)
            reason = per_input_reason(settings, inputs)
            if reason is not None:
                raise ValueError(reason)
            phi0, omega, epsilon = (per_input(settings, name, inputs) for name in ("phi0", "omega", "epsilon"))
            if settings.get("mode") == "dynamic":  # phi(t) from the equation of motion (linkage_ros.dynamic)
                motion = dynamic_law(scene, settings, phi0=phi0, omega=omega, t0=t0)
            elif len(inputs) == 1:
                motion = Motion(phi0=phi0, omega=omega, epsilon=epsilon, t0=t0)
            else:
                motion = Motions.of(len(inputs), phi0=phi0, omega=omega, epsilon=epsilon, t0=t0)
        return Engine(scene, motion, points=points, on_unassemblable=settings["on_unassemblable"])

    def _set_builder(self, engine: Engine, frame_id: str, relay: Relay | None) -> None:
        """A new builder and serializer (a new engine, frame_id or relay); the views of topic mode
        start again from the relay's first choice of input joints."""
        self._view = () if relay is None else relay.input_joints
        self._views = {}
        self.builder, self.wire = self._builder(engine, frame_id, self._view)
        if hasattr(engine.motion, "command"):  # dynamic mode: the drive state in diagnostics
            if engine.motion is not getattr(getattr(self, "engine", None), "motion", None):
                self._command_t = None
            self.builder.diagnostic_values = DriveState(
                engine.motion, lambda: self.run_time(self._last_ns or 0), lambda: self._command_t,
                grid=lambda: self.grid)

    def _builder(self, engine: Engine, frame_id: str, omit: tuple[str, ...]) -> tuple[MessageBuilder, Serializer]:
        """The builder and serializer of ``engine``'s messages, joint_states without ``omit``
        (topic mode: the joints the driver publishes)."""
        builder = MessageBuilder(engine, self.types, frame_id=frame_id, omit_joints=omit)
        return builder, Serializer(builder, self._serialize)

    def _open_recorder(self, path: str, engine: Engine, frame_id: str) -> Recorder:
        if self._recorder_factory is None:
            raise ValueError("this node has no MCAP recorder")
        folder = Path(path).parent
        if not folder.is_dir():
            raise ValueError(f"directory {str(folder)!r} does not exist (record_mcap does not create it)")
        return self._recorder_factory(path, topic_types(engine), engine=engine, frame_id=frame_id)
