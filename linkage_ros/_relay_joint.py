"""Which joint the relay reads, and φ from it: the driver joint's map (:mod:`linkage_ros.relay`).

The driver publishes either the scene's input joint (φ = q) or a URDF-style ``revolute`` joint of
the scene (``docs/scenes.md``) whose child link is the input crank and whose parent link is fixed:
then φ = θ_parent + sign·(q − offset), minus π when the child line runs point → centre, and
ω = sign·q̇, ε = sign·q̈. A scene driven by an actuator also reads the prismatic joint that
``linkage-urdf`` writes for its cylinder (``<name>_rod_joint``): its coordinate is the stroke,
s = q (m). Any other name is a ValueError that lists the accepted ones.

Several inputs, and the URDF's names (issue 30): :func:`input_choices` gives, per input of the
scene, the joints the relay reads it from. By default (no name configured for it) the scene's
own input joint first, then the URDF tree's prismatic joint of an actuator's cylinder
(``boom_cylinder_rod_joint``: what a ros2_control driver of the generated URDF publishes); a
configured name (``input_joint``, or an entry of ``input_joints``) is the only one read.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

__all__ = ["InputMap", "input_choices", "input_map", "rod_joints"]


@dataclass(frozen=True, slots=True)
class InputMap:
    """φ = shift + sign·q for the joint the driver publishes (q its coordinate)."""

    name: str
    sign: float
    shift: float


def input_map(scene: Any, input_joint: str | None, *, own: str | None = None,
              parameter: str = "input_joint", model: Any = None) -> InputMap:
    """How the input ``own`` (default: the scene's input joint) follows from the joint the driver
    publishes (see :class:`~linkage_ros.relay.Relay`); ValueError naming ``parameter`` and the
    accepted names for any other. ``model``: the scene's URDF tree, if already built."""
    own = str(scene.input_joint) if own is None else own
    if not input_joint or input_joint == own:  # None or "" (a ROS parameter's empty default)
        return InputMap(own, 1.0, 0.0)
    single = len(getattr(scene, "inputs", ()) or (own,)) == 1
    mapped = _revolute_input(scene, input_joint) if single else None
    if mapped is not None:
        return mapped
    rods = rod_joints(scene, model).get(own, ())
    if input_joint in rods:  # the prismatic joint of the URDF tree: its coordinate is the stroke
        return InputMap(input_joint, 1.0, 0.0)
    accepted = [own, *(_revolute_inputs(scene) if single else ()), *rods]
    which = "" if single else f"input '{own}' of "
    raise ValueError(
        f"{parameter} '{input_joint}' does not drive {which}scene '{scene.name}': the driver's "
        f"joint must be the scene's input joint, a revolute joint of the input crank against the frame "
        f"or the prismatic joint of the input actuator (linkage-urdf); accepted: {', '.join(accepted)}"
    )


def input_choices(scene: Any, configured: Sequence[str], *, model: Any = None,
                  parameter: str = "input_joints") -> tuple[tuple[InputMap, ...], ...]:
    """Per input of the scene (``scene.inputs`` order), the joints it is read from, in the order
    they are tried: the configured name alone (an entry of ``configured``, one per input or none),
    else the scene's own input joint and then the URDF tree's rod joint of its cylinder.
    ValueError (one line) for a wrong length or a name that does not drive its input."""
    inputs = tuple(getattr(scene, "inputs", ()) or (scene.input_joint,))
    names = list(configured)
    if names and len(names) != len(inputs):
        raise ValueError(
            f"{parameter} needs {len(inputs)} name(s), one per input of scene '{scene.name}' "
            f"({', '.join(inputs)}; \"\" for the scene's own name or its URDF joint), or none; "
            f"got {len(names)}: {names!r}"
        )
    rods = rod_joints(scene, model)
    out: list[tuple[InputMap, ...]] = []
    for i, own in enumerate(inputs):
        name = names[i] if names else ""
        if name:
            out.append((input_map(scene, name, own=own, parameter=parameter, model=model),))
        else:
            out.append((InputMap(own, 1.0, 0.0), *(InputMap(r, 1.0, 0.0) for r in rods.get(own, ()))))
    return tuple(out)


def rod_joints(scene: Any, model: Any = None) -> dict[str, tuple[str, ...]]:
    """Input joint → the URDF tree's prismatic joint(s) whose coordinate is that input's stroke
    (an actuator's rod sliding in its barrel, ``linkage-urdf``: ``boom_cylinder_rod_joint``)."""
    if model is None:
        from .urdf import exportable_model

        model = exportable_model(scene)
    if model is None:
        return {}
    inputs = set(getattr(scene, "inputs", ()) or (scene.input_joint,))
    out: dict[str, tuple[str, ...]] = {}
    for joint in model.joints:
        data = joint.data
        if (joint.type == "prismatic" and model.bodies[joint.child].role == "rod" and len(data) > 2
                and data[2] in inputs):
            out[str(data[2])] = (*out.get(str(data[2]), ()), joint.name)
    return out


def _revolute_inputs(scene: Any) -> list[str]:
    return [g.name for g in scene.ordered if _revolute_input(scene, g.name) is not None]


def _revolute_input(scene: Any, name: str) -> InputMap | None:
    """The map of a URDF-style ``revolute`` scene joint whose child is the input crank (both its
    points) and whose parent is fixed, else None."""
    group = next((g for g in scene.ordered if g.name == name and getattr(g, "kind", "") == "joint"), None)
    if group is None or getattr(group, "expression", "") != "revolute":
        return None
    crank = next((g for g in scene.ordered if getattr(g, "drives", False)), None)
    center, point = getattr(crank, "center", None), getattr(crank, "point", None)
    if center is None or point is None:
        return None
    parent, child = group.points[:2], group.points[2:4]
    fixed = scene.fixed_points
    if not all(p in fixed for p in parent):
        return None
    if tuple(child) == (center, point):
        turn = 0.0
    elif tuple(child) == (point, center):
        turn = math.pi
    else:
        return None
    d = fixed[parent[1]] - fixed[parent[0]]
    theta_p = math.atan2(float(d[1]), float(d[0]))
    sign = float(group.sign)
    return InputMap(name, sign, theta_p - turn - sign * float(group.offset))
