"""Topic mode without rclpy: a JointState in, the input state read off it, the frame solved.

The node's topic mode (``input_source: topic``) hands every ``sensor_msgs/JointState`` that
arrives on ``input_joint_states`` to :meth:`Relay.answer` and publishes what comes back. Nothing
here imports rclpy; the tests drive it with plain lists (``tests/relay``), the node with the
message's fields. See ``docs/relay.md`` for the graph and every decision.

API (kept stable for the node)::

    relay = Relay(engine, input_joint=None, input_joints=(), epsilon="zero", max_gap=0.25)
    answer = relay.answer(names, positions, velocities, stamp_ns)
    answer.kind            # "frame" | "dropped" | "unassemblable" | "ignored"   (ANSWER_*)
    answer.frame           # engine.Frame at φ, ω, ε read off the message (kind "frame" only)
    answer.reason          # why dropped / why unassemblable (group and φ interval); "" for a frame
    answer.stamp_ns        # the message's stamp, to put on every message of the answer
    answer.phi, .omega, .epsilon          # the input state read (None when dropped)
    answer.omega_from      # "message" | "positions" | "none"        (OMEGA_* constants)
    answer.epsilon_from    # "zero" | "velocities"                    (EPSILON_FROM_* constants)
    answer.interval        # (lo, hi) rad of the gap containing φ (kind "unassemblable"), else None
    reading = relay.read(names, positions, velocities, stamp_ns)   # the input state (Reading), or
                                          # the Answer of a dropped / ignored message
    relay.solve(reading)                  # its Answer: answer() is read() then solve(); the node's
                                          # fast path solves a Reading itself (linkage_ros.instant)
    relay.published_joints                # joint_states names in topic mode (a tuple of str)
    relay.published_for(reading.joints)   # ... when the message named the inputs by those joints
    relay.joint_states(frame, joints=None)  # (names, positions, velocities): tuples, in that order
    relay.input_joint                     # the joint read from the messages
    relay.input_joints                    # every joint read: (input_joint,), or scene.inputs (k > 1)
    relay.reset()                         # forget the previous message (e.g. on a mode switch)

* ``engine``: a :class:`~linkage_ros.engine.Engine` (its motion law is not used; frames come from
  :meth:`Engine.frame_at <linkage_ros.engine.Engine.frame_at>`).
* ``input_joint``: the name the driver publishes. ``None`` or ``""``: the scene's input joint
  (φ itself).
  It may also be a URDF-style ``revolute`` joint of the scene (``docs/scenes.md``) whose child
  link is the input crank and whose parent link is fixed: then
  ``φ = θ_parent + sign·(q − offset)`` (minus π when the child line runs point → centre),
  ``ω = sign·q̇``, ``ε = sign·q̈``. Any other name is a :class:`ValueError` that says which names are accepted.
* The frame's ``t`` is the stamp in seconds; its φ is exactly the position read (not wrapped).

Decisions (``docs/relay.md`` states what each costs):

* **ω** is the input joint's velocity in the message. When the message has no velocities (an
  empty array, as joint_state_publisher_gui sends), ω is the backward difference of the last two
  positions (wrapped to (−π, π], over their stamps) when the previous accepted message is newer
  than ``max_gap`` s ago; otherwise ω = 0. ``omega_from`` says which.
* **ε** (``epsilon=``): ``"zero"`` (the default) — ε = 0: positions and velocities exact, the
  accelerations lack the term ``v_q·ε`` (exact at constant speed); no noise is amplified.
  ``"difference"`` — ε = (ω_k − ω_{k−1})/(t_k − t_{k−1}) from the velocities of two successive
  accepted messages (both from the message, stamps increasing, gap ≤ ``max_gap``), else 0: the
  term is there, but lags by half a sample (error ≈ ε̇·Δt/2) and velocity noise σ becomes
  ε noise ≈ √2·σ/Δt.
* **Dropped**: the input joint absent, no position for it, a non-finite position or velocity,
  arrays shorter than the names. A dropped message leaves the previous state as it was.
* **URDF names** (issue 30): by default each input is read under the scene's input joint or, when
  the message lacks it, the URDF tree's prismatic joint of its cylinder (``boom_cylinder_rod_joint``);
  ``input_joints`` (one name per input, ``""`` for the default) fixes the one name read for each
  (:func:`~linkage_ros._relay_joint.input_choices`). ``reading.joints`` says which were read, and
  joint_states leaves out exactly those.
* **Ignored**: a message whose names are exactly the names this relay publishes (under either
  naming of the inputs): its own joint_states coming back (the driver and the node share ``/joint_states`` so that
  robot_state_publisher hears both, ``docs/relay.md``). Publish nothing, warn about nothing.
* **Unassemblable**: no frame (nothing non-finite is ever returned); the reason names the group
  and the φ interval that contains the input. The next message is answered normally.
* **Joint states in topic mode**: every scene joint and every tree joint (``linkage-urdf``) but
  the one the driver publishes, so the two streams merge without a duplicate name.

Several inputs (``scene.inputs`` = (q1, …, qk), docs/inputs.md): every input joint is read, by
its own name, from the same message; ``input_joint`` must be left empty (a ValueError otherwise).
The message is dropped unless every input joint is present with a finite position (and, when the
message has velocities, a finite velocity); the reason names the missing ones. ω and ε follow the
rules above input by input (``omega_from`` is the same for all: the message has velocities or not).
``answer.phi``, ``.omega``, ``.epsilon`` and the frame's are then k-tuples; an unassemblable
message's reason names the group and the failing sample ``(q1, …, qk)`` (no φ interval:
``answer.interval`` is None). ``relay.input_joints`` lists the joints read (``(input_joint,)``
with one input); joint_states leaves out all of them.

Written in three parts: the message read and answered here; which joint is read and φ from it
in :mod:`linkage_ros._relay_joint`; the ω and ε rules in :mod:`linkage_ros._relay_rates` (its
names are imported from here).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

from solver.errors import AssemblyError, format_intervals

from ._relay_joint import input_choices
from ._relay_rates import (
    DEFAULT_MAX_GAP,
    EPSILON_DIFFERENCE,
    EPSILON_FROM_VELOCITIES,
    EPSILON_FROM_ZERO,
    EPSILON_RULES,
    EPSILON_ZERO,
    NS_PER_S,
    OMEGA_FROM_MESSAGE,
    OMEGA_FROM_NONE,
    OMEGA_FROM_POSITIONS,
    Rates,
)
from .engine import Engine, interval_containing
from .frame import Frame
from .urdf import exportable_model, frame_tree_joint_states

__all__ = [
    "ANSWER_DROPPED",
    "ANSWER_FRAME",
    "ANSWER_IGNORED",
    "ANSWER_UNASSEMBLABLE",
    "DEFAULT_MAX_GAP",
    "EPSILON_DIFFERENCE",
    "EPSILON_FROM_VELOCITIES",
    "EPSILON_FROM_ZERO",
    "EPSILON_RULES",
    "EPSILON_ZERO",
    "OMEGA_FROM_MESSAGE",
    "OMEGA_FROM_NONE",
    "OMEGA_FROM_POSITIONS",
    "Answer",
    "Reading",
    "Relay",
]

ANSWER_FRAME = "frame"
ANSWER_DROPPED = "dropped"
ANSWER_UNASSEMBLABLE = "unassemblable"
ANSWER_IGNORED = "ignored"


@dataclass(frozen=True, slots=True)
class Answer:
    """What one JointState message gets: a frame, or the reason it gets none."""

    kind: str
    stamp_ns: int
    frame: Frame | None = None
    reason: str = ""
    #: The input state read: floats, or k-tuples with several inputs; None when dropped.
    phi: float | tuple[float, ...] | None = None
    omega: float | tuple[float, ...] | None = None
    epsilon: float | tuple[float, ...] | None = None
    omega_from: str = OMEGA_FROM_NONE
    epsilon_from: str = EPSILON_FROM_ZERO
    #: The φ interval (rad) where the mechanism cannot be assembled, for kind "unassemblable".
    interval: tuple[float, float] | None = None


class Reading(NamedTuple):
    """The input state read off one JointState (:meth:`Relay.read`): φ, ω, ε (floats, or
    k-tuples with several inputs), where ω and ε came from, and the driver joint's value(s)."""

    stamp_ns: int
    phi: Any
    omega: Any
    epsilon: Any
    omega_from: str
    epsilon_from: str
    q: Any
    #: the joints read (one per input): they select the joint_states published (:meth:`Relay.published_for`)
    joints: tuple[str, ...]


class Relay:
    """Answers JointState messages with frames of ``engine``'s scene (see the module docstring)."""

    def __init__(
        self,
        engine: Engine,
        *,
        input_joint: str | None = None,
        input_joints: Sequence[str] = (),
        epsilon: str = EPSILON_ZERO,
        max_gap: float = DEFAULT_MAX_GAP,
    ) -> None:
        if epsilon not in EPSILON_RULES:
            raise ValueError(f"epsilon must be one of {', '.join(EPSILON_RULES)}; got {epsilon!r}")
        if not (isinstance(max_gap, (int, float)) and math.isfinite(max_gap) and max_gap > 0.0):
            raise ValueError(f"max_gap must be a finite number of seconds > 0; got {max_gap!r}")
        self.engine = engine
        self.scene = engine.scene
        self.epsilon_rule = epsilon
        self.max_gap_ns = int(round(float(max_gap) * NS_PER_S))
        inputs = tuple(getattr(engine, "inputs", ()) or (self.scene.input_joint,))
        configured = [str(n) for n in input_joints or ()]
        if input_joint:
            if len(inputs) > 1:
                raise ValueError(
                    f"input_joint '{input_joint}': scene '{self.scene.name}' has {len(inputs)} inputs "
                    f"({', '.join(inputs)}), each read by its own name from the same message; "
                    "leave input_joint empty (input_joints maps each input to a joint)"
                )
            if configured and configured[0] not in ("", input_joint):
                raise ValueError(f"input_joint '{input_joint}' and input_joints {configured!r} name different "
                                 "joints for the same input; set one of them")
            configured = [input_joint]
        self._tree = exportable_model(self.scene)
        #: per input, the joints it is read from, in the order they are tried (_relay_joint)
        self._choices = input_choices(self.scene, configured, model=self._tree,
                                      parameter="input_joints" if len(inputs) > 1 or not input_joint else "input_joint")
        self._map = self._choices[0][0]
        #: the joints read when the driver uses the first choice of every input
        self.input_joints: tuple[str, ...] = tuple(c[0].name for c in self._choices)
        self.input_joint: str = self._map.name
        self._single = len(inputs) == 1
        self._first = (tuple((m, self.input_joints if i == 0 else (m.name,)) for i, m in enumerate(self._choices[0]))
                       if self._single else ())
        tree_names = () if self._tree is None else tuple(self._tree.joint_names)
        self._all_names = (*engine.joint_names, *tree_names)
        self._n_scene = len(engine.joint_names)
        self._views: dict[tuple[str, ...], tuple[str, ...]] = {}
        self.published_joints: tuple[str, ...] = self.published_for(self.input_joints)
        own = {self.published_for(tuple(m.name for m in view)) for view in itertools.product(*self._choices)}
        #: joint_states of this relay under any of its views: its own messages coming back
        self._own = frozenset(own)
        self._own_lengths = frozenset(len(names) for names in own)
        self._accepted = tuple(" or ".join(f"'{m.name}'" for m in c) for c in self._choices)
        units = dict(getattr(self.scene, "joint_units", {}))
        strokes = tuple(units.get(n, "rad") == "m" for n in (inputs if len(inputs) > 1 else (self.scene.input_joint,)))
        self._units = tuple("m" if m else "rad" for m in strokes)
        self._rates = Rates(rule=epsilon, max_gap_ns=self.max_gap_ns, strokes=strokes)

    def published_for(self, joints: tuple[str, ...]) -> tuple[str, ...]:
        """joint_states' names in topic mode when the driver publishes ``joints``: every scene
        joint and every tree joint of the URDF but those."""
        names = self._views.get(joints)
        if names is None:
            skip = frozenset(joints)
            names = self._views[joints] = tuple(n for n in self._all_names if n not in skip)
        return names

    def is_own(self, names: Sequence[str]) -> bool:
        """Whether ``names`` are exactly the joint_states names of this relay (under any of its
        views): its own message coming back on a shared topic."""
        return len(names) in self._own_lengths and tuple(names) in self._own

    # ------------------------------------------------------------------ one message
    def answer(
        self,
        names: Sequence[str],
        positions: Sequence[float],
        velocities: Sequence[float],
        stamp_ns: int,
    ) -> Answer:
        """The answer to one JointState (its ``name``, ``position``, ``velocity`` and
        ``header.stamp`` in integer ns): :meth:`read`, then :meth:`solve`."""
        reading = self.read(names, positions, velocities, stamp_ns)
        return reading if isinstance(reading, Answer) else self.solve(reading)

    def read(
        self,
        names: Sequence[str],
        positions: Sequence[float],
        velocities: Sequence[float],
        stamp_ns: int,
    ) -> Reading | Answer:
        """The input state of one JointState, or the Answer of a dropped or ignored message.
        Remembers the message for the next one's differences (ω without velocities, ε)."""
        stamp_ns = int(stamp_ns)
        if len(self.input_joints) > 1:
            return self._read_inputs(names, positions, velocities, stamp_ns)
        if len(names) in self._own_lengths and tuple(names) in self._own:
            return Answer(ANSWER_IGNORED, stamp_ns, reason="carries only joints this relay publishes")
        seq = names if isinstance(names, (list, tuple)) else list(names)
        for m, read in self._first:  # noqa: B007 - read after the break
            try:
                i = seq.index(m.name)
                break
            except ValueError:
                continue
        else:
            return Answer(ANSWER_DROPPED, stamp_ns, reason=f"no joint {self._accepted[0]} in the message"
                          f"{_carried(seq)}")
        name = m.name
        if i >= len(positions):
            return Answer(
                ANSWER_DROPPED, stamp_ns,
                reason=f"joint '{name}' has no position ({len(names)} names, {len(positions)} positions)",
            )
        q = float(positions[i])
        if not math.isfinite(q):
            return Answer(ANSWER_DROPPED, stamp_ns, reason=f"joint '{name}' position is {q}")
        dq: float | None = None
        if len(velocities):
            if i >= len(velocities):
                return Answer(
                    ANSWER_DROPPED, stamp_ns,
                    reason=f"joint '{name}' has no velocity ({len(names)} names, {len(velocities)} velocities)",
                )
            dq = float(velocities[i])
            if not math.isfinite(dq):
                return Answer(ANSWER_DROPPED, stamp_ns, reason=f"joint '{name}' velocity is {dq}")
        omega_q, omega_from, eps_q, eps_from = self._rates.one(stamp_ns, q, dq)
        return Reading(stamp_ns, m.shift + m.sign * q, m.sign * omega_q, m.sign * eps_q, omega_from, eps_from, q,
                       read)

    def solve(self, reading: Reading) -> Answer:
        """The answer to an input state :meth:`read` gave: its frame, or why it has none."""
        stamp_ns, phi, omega, eps = reading.stamp_ns, reading.phi, reading.omega, reading.epsilon
        result = self.engine.frame_at(phi, omega, eps, t=stamp_ns / NS_PER_S)
        common = {
            "phi": phi, "omega": omega, "epsilon": eps, "omega_from": reading.omega_from,
            "epsilon_from": reading.epsilon_from,
        }
        if isinstance(result, AssemblyError):
            if isinstance(phi, tuple):  # several inputs: the failing sample, no φ interval
                sample = ", ".join(f"{v:.6g}" for v in phi)
                unit = "rad" if "m" not in self._units else "m" if "rad" not in self._units else "rad or m"
                reason = (f"group '{result.group}' {result.reason} at ({', '.join(self.input_joints)}) = "
                          f"({sample}) {unit}")
                return Answer(ANSWER_UNASSEMBLABLE, stamp_ns, reason=reason, **common)
            if self._units == ("m",):  # a stroke: the reason names its range; no wrap
                reason = (f"group '{result.group}' {result.reason} for s = {phi:.6g} m "
                          f"({self.input_joint} = {reading.q:.6g})")
                return Answer(ANSWER_UNASSEMBLABLE, stamp_ns, reason=reason, **common)
            interval = interval_containing(result.intervals, phi)
            where = f"φ in {format_intervals([interval])}" if interval is not None else f"φ = {phi:.6g} rad"
            reason = f"group '{result.group}' {result.reason} for {where} ({self.input_joint} = {reading.q:.6g})"
            return Answer(ANSWER_UNASSEMBLABLE, stamp_ns, reason=reason, interval=interval, **common)
        return Answer(ANSWER_FRAME, stamp_ns, frame=result, **common)

    def reset(self) -> None:
        """Forget the previous message (e.g. when the node switches back to topic mode)."""
        self._rates.reset()

    def _read_inputs(
        self, names: Sequence[str], positions: Sequence[float], velocities: Sequence[float], stamp_ns: int
    ) -> Reading | Answer:
        """:meth:`read` for a scene with several inputs (see the module docstring)."""
        if len(names) in self._own_lengths and tuple(names) in self._own:
            return Answer(ANSWER_IGNORED, stamp_ns, reason="carries only joints this relay publishes")
        index = {n: i for i, n in enumerate(names)}
        read: list[str] = []
        missing: list[str] = []
        for choices, accepted in zip(self._choices, self._accepted):
            found = next((m.name for m in choices if m.name in index), None)
            if found is None:
                missing.append(accepted)
            else:
                read.append(found)
        if missing:
            return Answer(
                ANSWER_DROPPED, stamp_ns,
                reason=f"no joint {', '.join(missing)} in the message (every input is needed: "
                       f"{', '.join(self.input_joints)}){_carried(names) if len(read) == 0 else ''}",
            )
        joints = tuple(read)
        where = [index[n] for n in joints]
        if max(where) >= len(positions):
            short = ", ".join(f"'{n}'" for n, i in zip(joints, where) if i >= len(positions))
            return Answer(
                ANSWER_DROPPED, stamp_ns,
                reason=f"joint {short} has no position ({len(names)} names, {len(positions)} positions)",
            )
        q = tuple(float(positions[i]) for i in where)
        bad = [f"'{n}' position is {v}" for n, v in zip(joints, q) if not math.isfinite(v)]
        dq: tuple[float, ...] | None = None
        if len(velocities):
            if max(where) >= len(velocities):
                short = ", ".join(f"'{n}'" for n, i in zip(joints, where) if i >= len(velocities))
                return Answer(
                    ANSWER_DROPPED, stamp_ns,
                    reason=f"joint {short} has no velocity ({len(names)} names, {len(velocities)} velocities)",
                )
            dq = tuple(float(velocities[i]) for i in where)
            bad += [f"'{n}' velocity is {v}" for n, v in zip(joints, dq) if not math.isfinite(v)]
        if bad:
            return Answer(ANSWER_DROPPED, stamp_ns, reason="joint " + ", ".join(bad))
        omega, omega_from, eps, eps_from = self._rates.several(stamp_ns, q, dq)
        return Reading(stamp_ns, q, omega, eps, omega_from, eps_from, q, joints)

    # ------------------------------------------------------------------ outgoing joints
    def joint_states(self, frame: Frame, joints: tuple[str, ...] | None = None
                     ) -> tuple[tuple[str, ...], tuple[float, ...], tuple[float, ...]]:
        """``(names, positions, velocities)`` for joint_states in topic mode when the driver
        publishes ``joints`` (default: :attr:`input_joints`): the names of :meth:`published_for`,
        in that order."""
        names = self.published_for(self.input_joints if joints is None else joints)
        values = {n: (j.position, j.velocity) for n, j in frame.joints.items()}
        if self._tree is not None:
            tree = frame_tree_joint_states(self._tree, frame)
            values.update(zip(self._tree.joint_names, zip(tree.position, tree.velocity)))
        return names, tuple(values[n][0] for n in names), tuple(values[n][1] for n in names)


def _carried(names: Sequence[str], most: int = 6) -> str:
    """`` (it carries: a, b, …)``: what a message without the inputs named instead."""
    if not len(names):
        return " (it names no joint)"
    shown = ", ".join(list(names)[:most])
    return f" (it carries: {shown}{', …' if len(names) > most else ''})"
