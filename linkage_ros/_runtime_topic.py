"""Topic mode of :class:`~linkage_ros.runtime.Runtime` (issue 12, issue 30): the answer to one
incoming ``sensor_msgs/JointState``.

:meth:`TopicAnswers.answer` reads the input state off the message (:mod:`linkage_ros.relay`) and
renders the same topics as a clock tick under the message's stamp. The driver may name an input
by the scene's joint or by the URDF's (an actuator's ``<name>_rod_joint``): joint_states leaves
out exactly the joints the message named, with one builder per naming, kept (a *view*). A message
that cannot be read gets diagnostics WARN (the first one, then at most one per
:data:`~linkage_ros.runtime.DIAGNOSTICS_PERIOD_S` of stamps) and a line in ``input_warnings``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from .engine import Engine
from .frame import STATUS_INPUT_DROPPED, STATUS_UNASSEMBLABLE, Frame
from .instant import FastPath
from .messages import MessageBuilder
from .relay import ANSWER_DROPPED, ANSWER_FRAME, Answer, Reading, Relay
from .serialize import Serializer
from .topics import DIAGNOSTICS, NS_PER_S

__all__ = ["DIAGNOSTICS_PERIOD_S", "TopicAnswers"]

#: Clock seconds between two diagnostics messages while the status stays the same.
DIAGNOSTICS_PERIOD_S = 1.0


class TopicAnswers:
    """The topic-mode half of the runtime (a mixin of :class:`~linkage_ros.runtime.Runtime`)."""

    relay: Relay | None
    engine: Engine
    settings: dict[str, Any]
    builder: MessageBuilder
    wire: Serializer
    recorder: Any
    input_warnings: list[str]
    _fast_path: FastPath | None
    _views: dict[tuple[str, ...], tuple[MessageBuilder, Serializer, FastPath | None]]
    _view: tuple[str, ...]
    _diagnostics_key: tuple[str, str] | None
    _diagnostics_ns: int

    def _fast(self, t: float, stamp_ns: int, reading: Reading | None) -> list[tuple[str, bytes]] | None:
        raise NotImplementedError

    def _wants_diagnostics(self, frame: Frame, now_ns: int) -> bool:
        raise NotImplementedError

    def _paths_due(self, t: float) -> bool:
        raise NotImplementedError

    def _builder(self, engine: Engine, frame_id: str, omit: tuple[str, ...]) -> tuple[MessageBuilder, Serializer]:
        raise NotImplementedError

    last_frame: Frame | None

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
            if reading.kind != ANSWER_DROPPED:
                return []
            self.input_warnings.append(f"JointState dropped: {reading.reason}")
            messages = self._dropped(reading)
        else:
            if reading.joints != self._view:
                self._switch_view(reading.joints)
            messages = self._reading(reading)
        if messages and self.recorder is not None:
            self.recorder.write_serialized(int(stamp_ns), messages)
        return messages

    def _reading(self, reading: Reading) -> list[tuple[str, bytes]]:
        """The messages of one input state read off a JointState (:meth:`answer`)."""
        assert self.relay is not None
        stamp = reading.stamp_ns
        messages = self._fast(stamp / NS_PER_S, stamp, reading)
        if messages is None:  # the Frame path (linkage_ros.instant: when and why)
            answer = self.relay.solve(reading)
            if answer.kind == ANSWER_FRAME:
                frame = answer.frame
                assert frame is not None
                self.last_frame = frame
                messages = self.wire.render(frame, stamp, paths=self._paths_due(frame.t),
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
        return messages

    def _dropped(self, answer: Answer) -> list[tuple[str, bytes]]:
        """Diagnostics WARN for a JointState that could not be read (under its stamp): on the first
        one and then at most once per :data:`DIAGNOSTICS_PERIOD_S` of stamps while they go on."""
        stamp = answer.stamp_ns
        key = (STATUS_INPUT_DROPPED, "")
        if key == self._diagnostics_key and 0 <= stamp - self._diagnostics_ns < DIAGNOSTICS_PERIOD_S * NS_PER_S:
            return []
        self._diagnostics_key, self._diagnostics_ns = key, stamp
        k = len(self.engine.inputs)
        zero: Any = 0.0 if k == 1 else (0.0,) * k
        state = Frame(t=stamp / NS_PER_S, phi=zero, omega=zero, epsilon=zero, points={}, joints={},
                      status=STATUS_INPUT_DROPPED, conditioning=0.0, message=f"JointState dropped: {answer.reason}")
        return self.wire.generic(state, stamp, [DIAGNOSTICS])

    def _switch_view(self, joints: tuple[str, ...]) -> None:
        """Topic mode: the driver names the inputs by other joints than the last message did
        (the scene's or the URDF's): joint_states leaves out those; one builder per set, kept."""
        views = self._views
        views[self._view] = (self.builder, self.wire, self._fast_path)
        if joints in views:
            self.builder, self.wire, self._fast_path = views[joints]
        else:
            self.builder, self.wire = self._builder(self.engine, self.settings["frame_id"], joints)
            self._fast_path = None
        self._view = joints

    def take_input_warnings(self) -> list[str]:
        """Topic mode: dropped and unassemblable messages since the last call."""
        warnings, self.input_warnings = self.input_warnings, []
        return warnings

    @staticmethod
    def _relay(engine: Engine, settings: Mapping[str, Any]) -> Relay | None:
        """The topic mode's relay (None in clock mode); ValueError for an unknown input_joint."""
        if settings["input_source"] != "topic":
            return None
        return Relay(engine, input_joint=settings["input_joint"] or None,
                     input_joints=tuple(settings.get("input_joints") or ()),
                     epsilon=settings["topic_epsilon"], max_gap=float(settings["topic_max_gap"]))

