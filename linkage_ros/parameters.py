"""mechanism_node's parameters without rclpy: their specs, their checks and their coercion.

:data:`PARAMETERS` is what the node (:mod:`linkage_ros.node`) declares, with descriptors built
from each :class:`ParameterSpec`; :func:`validate_parameter` is the one check every value goes
through, at start (:func:`initial_settings`) and at run time (:func:`checked_changes`), before
:class:`~linkage_ros.runtime.Runtime` acts on it. Each rejection is one line naming the parameter
and the reason.

Several inputs (a scene with ``scene.inputs`` = (q1, …, qk), docs/inputs.md): ``omega``,
``epsilon`` and ``phi0`` apply to every input unless the double arrays ``input_omegas``,
``input_epsilons``, ``input_phi0s`` (:data:`PER_INPUT`) give one value per input, in the order of
``scene.inputs`` (empty: the scalar; another length is rejected by :func:`per_input_reason` with
a reason naming the inputs); :func:`per_input` reads the value that applies.

A scene driven by an actuator (a stroke input, docs/inputs.md): ``omega``, ``epsilon`` and
``phi0`` are then m/s, m/s² and m — :func:`for_scene` gives the parameters' descriptions as the
node declares them for its start scene, and :func:`scene_defaults` the start values a stroke
needs (its closed length, STROKE_RATE) where none is given. A ``phi0`` outside the stroke cannot
be assembled: the change is rejected with the reason and the node keeps its state.

Dynamic mode (issue 22, :mod:`linkage_ros.dynamic`): ``mode`` (kinematic | dynamic), ``drive``
(auto | motor | effort | free), ``effort_timeout`` and ``dynamics_tolerance``; ``phi0`` and
``omega`` (or the per-input arrays) then give the initial state, ``epsilon`` is not used.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import solver
from solver.errors import SolverError

from .dynamic import (
    DEFAULT_EFFORT_TIMEOUT,
    DEFAULT_TOLERANCE,
    DRIVES,
    EFFORT_TIMEOUT_RANGE,
    MODES,
    TOLERANCE_RANGE,
)
from .engine import ON_UNASSEMBLABLE
from .relay import DEFAULT_MAX_GAP, EPSILON_RULES, EPSILON_ZERO

__all__ = [
    "INPUT_SOURCES",
    "MAX_EPSILON",
    "MAX_GAP_RANGE_S",
    "MAX_OMEGA",
    "MAX_RATE_HZ",
    "MIN_RATE_HZ",
    "PARAMETERS",
    "PER_INPUT",
    "SPECS",
    "ParameterSpec",
    "STROKE_RATE",
    "checked_changes",
    "for_scene",
    "initial_settings",
    "inputs_of",
    "per_input",
    "per_input_reason",
    "points_of",
    "scene_defaults",
    "start_scene",
    "validate_parameter",
]

#: Largest |ω| (rad/s), |ε| (rad/s²) and rate (Hz) the node accepts.
MAX_OMEGA = 1.0e4
MAX_EPSILON = 1.0e6
MAX_RATE_HZ = 1.0e4
MIN_RATE_HZ = 1.0e-3
#: Accepted values of ``input_source``.
INPUT_SOURCES = ("clock", "topic")
#: Topic mode: the range of ``topic_max_gap`` (s).
MAX_GAP_RANGE_S = (1.0e-3, 60.0)

_FRAME_ID = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_./-]*\Z")
_POINT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_JOINT = re.compile(r"[^\s]+\Z")


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
        constraints="empty, the scene's input joint, a URDF-style revolute joint of the scene, or the URDF's "
                    "prismatic joint of the input actuator (<actuator>_rod_joint)",
    ),
    ParameterSpec(
        "input_joints", "string_array", (),
        "Topic mode: the joint of the incoming JointState that drives each input, in the order of the "
        "scene's inputs (\"\" for one: its own name or its URDF joint); empty: every input read under "
        "the scene's input joint or, for an actuator, the URDF's <actuator>_rod_joint.",
        constraints="empty, or one name per input: \"\", the input joint, or a joint of the URDF that drives it",
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
    # dynamic mode (issue 22, linkage_ros.dynamic; docs/ros.md "Dynamic mode")
    ParameterSpec(
        "mode", "string", MODES[0],
        "kinematic: phi(t) from omega and epsilon (or the input topic); dynamic: phi(t) from the "
        "equation of motion, from phi0 and omega, under the drive. A change restarts the run at phi0.",
        constraints=" or ".join(MODES),
    ),
    ParameterSpec(
        "drive", "string", DRIVES[0],
        "Dynamic mode: what drives the inputs. motor: the scene's motor; effort: the commands on "
        "effort_commands (std_msgs/Float64MultiArray, one value per input); free: nothing; auto: "
        "the motor if the scene has one, else the effort commands.",
        constraints=" or ".join(DRIVES),
    ),
    ParameterSpec(
        "effort_timeout", "double", DEFAULT_EFFORT_TIMEOUT,
        "Dynamic mode: an effort command older than this (s) counts as zero.",
        float_range=EFFORT_TIMEOUT_RANGE,
    ),
    ParameterSpec(
        "dynamics_tolerance", "double", DEFAULT_TOLERANCE,
        "Dynamic mode: the integrator's relative and absolute tolerance (DOP853 steps; the state "
        "at a tick from its dense output). A change restarts the run at phi0.",
        float_range=TOLERANCE_RANGE,
    ),
)

SPECS: Mapping[str, ParameterSpec] = {spec.name: spec for spec in PARAMETERS}
#: The per-input double arrays and the scalar each one stands in for when empty.
PER_INPUT = {"input_omegas": "omega", "input_epsilons": "epsilon", "input_phi0s": "phi0"}

#: The start rate of an actuator's stroke (m/s) when ``omega`` is not given.
STROKE_RATE = 0.1

#: The words of the input parameters that name a unit, for an angle and for a stroke.
_ANGLE_WORDS = (("Angular velocity", "Velocity"), ("Angular acceleration", "Acceleration"), ("rad/s^2", "m/s^2"),
                ("rad/s", "m/s"), ("Input angle", "Input stroke (length of the actuator)"),
                ("angular velocity", "velocity"), ("angular acceleration", "acceleration"),
                ("angle of each input", "stroke of each input"), (", rad.", ", m."), (", rad,", ", m,"))


def for_scene(spec: ParameterSpec, units: Sequence[str]) -> ParameterSpec:
    """``spec`` as declared for a scene whose inputs have ``units`` ("rad" or "m" each): the
    descriptions of ``omega``, ``epsilon``, ``phi0`` and their arrays in m/s, m/s² and m when
    every input is an actuator's stroke, in both units when they are mixed."""
    if spec.name not in ("omega", "epsilon", "phi0", *PER_INPUT) or "m" not in units:
        return spec
    text = spec.description
    if "rad" in units:  # cranks and actuators: each input in its own unit
        text += " (rad, rad/s, rad/s^2 for a crank's angle; m, m/s, m/s^2 for an actuator's stroke)"
    else:
        for angle, stroke in _ANGLE_WORDS:
            text = text.replace(angle, stroke)
    return ParameterSpec(spec.name, spec.kind, spec.default, text, spec.float_range, spec.constraints)


def scene_defaults(scene: Any) -> dict[str, Any]:
    """Start values for a scene driven by actuators, for the parameters not given: the stroke
    starts at its closed length (``phi0``; ``input_phi0s`` with several inputs) and extends at
    :data:`STROKE_RATE` m/s (``omega``; with several inputs ``input_phi0s`` and ``input_omegas``,
    a crank's entries the scalar defaults); empty for a scene of cranks."""
    ranges = tuple(getattr(scene, "input_ranges", ()))
    if not any(r is not None for r in ranges):
        return {}
    if len(ranges) == 1:
        return {"phi0": float(ranges[0][0]), "omega": STROKE_RATE}
    return {"input_phi0s": [0.0 if r is None else float(r[0]) for r in ranges],
            "input_omegas": [SPECS["omega"].default if r is None else STROKE_RATE for r in ranges]}


def _finite_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def validate_parameter(name: str, value: Any) -> str | None:
    """Why ``value`` is not acceptable for parameter ``name``, or None if it is.

    Parameters that are not the node's own (``use_sim_time``, ...) are always accepted.
    """
    spec = SPECS.get(name)
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
        if name == "input_joints":
            bad = [v for v in value if v and not _JOINT.match(v)]
            return f"input_joints: {', '.join(map(repr, bad))} cannot be a joint name (no spaces)" if bad else None
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
            reason = getattr(error, "reason", error)  # (the message without the file, named here)
            if Path(value).is_dir():
                return f"scene {value!r}: {reason}"
            return f"unknown scene {value!r}: {reason}"
    elif name == "frame_id":
        if not _FRAME_ID.match(value):
            return f"frame_id must be non-empty (letters, digits, _ . / -), got {value!r}"
    elif name == "on_unassemblable" and value not in ON_UNASSEMBLABLE:
        return f"on_unassemblable must be one of {', '.join(ON_UNASSEMBLABLE)}, got {value!r}"
    elif name == "input_source" and value not in INPUT_SOURCES:
        return f"input_source must be one of {', '.join(INPUT_SOURCES)}, got {value!r}"
    elif name == "topic_epsilon" and value not in EPSILON_RULES:
        return f"topic_epsilon must be one of {', '.join(EPSILON_RULES)}, got {value!r}"
    elif name == "mode" and value not in MODES:
        return f"mode must be one of {', '.join(MODES)}, got {value!r}"
    elif name == "drive" and value not in DRIVES:
        return f"drive must be one of {', '.join(DRIVES)}, got {value!r}"
    return None


def points_of(value: Any) -> tuple[str, ...]:
    """The point names of a ``points`` value, without the empty ones (``[""]``: none)."""
    return tuple(p for p in (value or ()) if p)


def inputs_of(scene: Any) -> tuple[str, ...]:
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
    values: Sequence[float] = settings.get(array) or ()
    if len(inputs) == 1:
        return float(values[0]) if len(values) else float(settings[scalar])
    if len(values):
        return tuple(float(v) for v in values)
    return (float(settings[scalar]),) * len(inputs)


def initial_settings(values: Mapping[str, Any]) -> dict[str, Any]:
    """The node's settings at start: ``values`` of its own parameters (None: not given) over the
    defaults of :data:`PARAMETERS`, each checked, the per-input arrays as tuples of floats.

    Raises ValueError with the reason of the first value that is not acceptable.
    """
    settings = {spec.name: spec.default for spec in PARAMETERS}
    settings.update({k: v for k, v in values.items() if k in SPECS and v is not None})
    for name, value in settings.items():
        if value is None:
            continue
        reason = validate_parameter(name, value)
        if reason:
            raise ValueError(reason)
    for name in PER_INPUT:
        settings[name] = tuple(float(v) for v in settings[name] or ())
    settings["input_joints"] = tuple(str(v) for v in settings["input_joints"] or ())
    return settings


def checked_changes(changes: Mapping[str, Any]) -> tuple[dict[str, Any], str | None]:
    """The node's own parameters among ``changes`` (others, such as ``use_sim_time``, are left
    out), the per-input arrays as tuples of floats; or ``({}, reason)`` for the first value that
    is not acceptable."""
    ours = {k: v for k, v in changes.items() if k in SPECS}
    for name, value in ours.items():
        reason = validate_parameter(name, value)
        if reason:
            return {}, reason
    return {k: tuple(float(x) for x in v) if k in PER_INPUT else tuple(v) if k == "input_joints" else v
            for k, v in ours.items()}, None


def start_scene(name: Any) -> tuple[tuple[str, ...], dict[str, Any]]:
    """The start scene's input units and start values (:func:`scene_defaults`) for the scene
    parameter's value ``name`` (None: the default); ``("rad",)`` and none where it cannot be
    loaded (the node's Runtime then says why)."""
    try:
        scene = solver.load_scene(SPECS["scene"].default if name is None else name)
    except (SolverError, OSError, TypeError):
        return ("rad",), {}
    return tuple(scene.input_units), scene_defaults(scene)
