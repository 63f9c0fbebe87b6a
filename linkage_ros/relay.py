"""Topic mode without rclpy: a JointState in, the input state read off it, the frame solved.

The node's topic mode (``input_source: topic``) hands every ``sensor_msgs/JointState`` that
arrives on ``input_joint_states`` to :meth:`Relay.answer` and publishes what comes back. Nothing
here imports rclpy; the tests drive it with plain lists (``tests/relay``), the node with the
message's fields. See ``docs/relay.md`` for the graph and every decision.

API (kept stable for the node)::

    relay = Relay(engine, input_joint=None, epsilon="zero", max_gap=0.25)
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
    relay.joint_states(frame)             # (names, positions, velocities): tuples, in that order
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
* **Ignored**: a message without the input joint whose names are all joints this relay publishes:
  its own joint_states coming back (the driver and the node share ``/joint_states`` so that
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

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

from solver.errors import AssemblyError, format_intervals

from ._relay_joint import InputMap, input_map
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


class Relay:
    """Answers JointState messages with frames of ``engine``'s scene (see the module docstring)."""

    def __init__(
        self,
        engine: Engine,
        *,
        input_joint: str | None = None,
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
        if len(inputs) > 1:
            if input_joint:
                raise ValueError(
                    f"input_joint '{input_joint}': scene '{self.scene.name}' has {len(inputs)} inputs "
                    f"({', '.join(inputs)}), each read by its own name from the same message; "
                    "leave input_joint empty"
                )
            self._map = InputMap(inputs[0], 1.0, 0.0)
            self.input_joints: tuple[str, ...] = inputs
        else:
            self._map = input_map(self.scene, input_joint)
            self.input_joints = (self._map.name,)
        self.input_joint: str = self._map.name
        skip = frozenset(self.input_joints)
        self._tree = exportable_model(self.scene)
        tree_names = () if self._tree is None else tuple(self._tree.joint_names)
        self._scene_joints = tuple(n for n in engine.joint_names if n not in skip)
        self._tree_mask = tuple(n not in skip for n in tree_names)
        self.published_joints: tuple[str, ...] = (
            *self._scene_joints,
            *(n for n, keep in zip(tree_names, self._tree_mask) if keep),
        )
        self._own = frozenset(self.published_joints)
        units = dict(getattr(self.scene, "joint_units", {}))
        strokes = tuple(units.get(n, "rad") == "m" for n in (inputs if len(inputs) > 1 else (self.scene.input_joint,)))
        self._units = tuple("m" if m else "rad" for m in strokes)
        self._rates = Rates(rule=epsilon, max_gap_ns=self.max_gap_ns, strokes=strokes)

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
        name = self.input_joint
        try:
            i = names.index(name) if isinstance(names, (list, tuple)) else list(names).index(name)
        except ValueError:
            if len(names) and self._own.issuperset(names):
                return Answer(ANSWER_IGNORED, stamp_ns, reason="carries only joints this relay publishes")
            return Answer(ANSWER_DROPPED, stamp_ns, reason=f"no joint '{name}' in the message")
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
        m = self._map
        return Reading(stamp_ns, m.shift + m.sign * q, m.sign * omega_q, m.sign * eps_q, omega_from, eps_from, q)

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
        index = {n: i for i, n in enumerate(names)}
        missing = [n for n in self.input_joints if n not in index]
        if missing:
            if len(missing) == len(self.input_joints) and len(names) and self._own.issuperset(names):
                return Answer(ANSWER_IGNORED, stamp_ns, reason="carries only joints this relay publishes")
            listed = ", ".join(f"'{n}'" for n in missing)
            return Answer(
                ANSWER_DROPPED, stamp_ns,
                reason=f"no joint {listed} in the message (every input is needed: {', '.join(self.input_joints)})",
            )
        where = [index[n] for n in self.input_joints]
        if max(where) >= len(positions):
            short = ", ".join(f"'{n}'" for n, i in zip(self.input_joints, where) if i >= len(positions))
            return Answer(
                ANSWER_DROPPED, stamp_ns,
                reason=f"joint {short} has no position ({len(names)} names, {len(positions)} positions)",
            )
        q = tuple(float(positions[i]) for i in where)
        bad = [f"'{n}' position is {v}" for n, v in zip(self.input_joints, q) if not math.isfinite(v)]
        dq: tuple[float, ...] | None = None
        if len(velocities):
            if max(where) >= len(velocities):
                short = ", ".join(f"'{n}'" for n, i in zip(self.input_joints, where) if i >= len(velocities))
                return Answer(
                    ANSWER_DROPPED, stamp_ns,
                    reason=f"joint {short} has no velocity ({len(names)} names, {len(velocities)} velocities)",
                )
            dq = tuple(float(velocities[i]) for i in where)
            bad += [f"'{n}' velocity is {v}" for n, v in zip(self.input_joints, dq) if not math.isfinite(v)]
        if bad:
            return Answer(ANSWER_DROPPED, stamp_ns, reason="joint " + ", ".join(bad))
        omega, omega_from, eps, eps_from = self._rates.several(stamp_ns, q, dq)
        return Reading(stamp_ns, q, omega, eps, omega_from, eps_from, q)

    # ------------------------------------------------------------------ outgoing joints
    def joint_states(self, frame: Frame) -> tuple[tuple[str, ...], tuple[float, ...], tuple[float, ...]]:
        """``(names, positions, velocities)`` for joint_states in topic mode: the names of
        :attr:`published_joints`, in that order."""
        joints = frame.joints
        q = [joints[n].position for n in self._scene_joints]
        dq = [joints[n].velocity for n in self._scene_joints]
        if self._tree is not None:
            tree = frame_tree_joint_states(self._tree, frame)
            q += [v for v, keep in zip(tree.position, self._tree_mask) if keep]
            dq += [v for v, keep in zip(tree.velocity, self._tree_mask) if keep]
        return self.published_joints, tuple(q), tuple(dq)
