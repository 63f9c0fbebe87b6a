"""Which joint the relay reads, and φ from it: the driver joint's map (:mod:`linkage_ros.relay`).

The driver publishes either the scene's input joint (φ = q) or a URDF-style ``revolute`` joint of
the scene (``docs/scenes.md``) whose child link is the input crank and whose parent link is fixed:
then φ = θ_parent + sign·(q − offset), minus π when the child line runs point → centre, and
ω = sign·q̇, ε = sign·q̈. A scene driven by an actuator also reads the prismatic joint that
``linkage-urdf`` writes for its cylinder (``<name>_rod_joint``): its coordinate is the stroke,
s = q (m). Any other name is a ValueError that lists the accepted ones.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

__all__ = ["InputMap", "input_map"]


@dataclass(frozen=True, slots=True)
class InputMap:
    """φ = shift + sign·q for the joint the driver publishes (q its coordinate)."""

    name: str
    sign: float
    shift: float


def input_map(scene: Any, input_joint: str | None) -> InputMap:
    """How φ follows from the joint the driver publishes (see :class:`~linkage_ros.relay.Relay`)."""
    own = str(scene.input_joint)
    if not input_joint or input_joint == own:  # None or "" (a ROS parameter's empty default)
        return InputMap(own, 1.0, 0.0)
    mapped = _revolute_input(scene, input_joint)
    if mapped is not None:
        return mapped
    rods = _rod_inputs(scene)
    if input_joint in rods:  # the prismatic joint of the URDF tree: its coordinate is the stroke
        return InputMap(input_joint, 1.0, 0.0)
    accepted = [own, *_revolute_inputs(scene), *rods]
    raise ValueError(
        f"input_joint '{input_joint}' does not drive scene '{scene.name}': the driver's joint must be "
        f"the scene's input joint, a revolute joint of the input crank against the frame or the "
        f"prismatic joint of the input actuator (linkage-urdf); accepted: {', '.join(accepted)}"
    )


def _rod_inputs(scene: Any) -> list[str]:
    """The URDF tree's prismatic joint of the driving actuator (``<name>_rod_joint``, linkage-urdf)."""
    return [f"{g.name}_rod_joint" for g in scene.ordered
            if getattr(g, "kind", "") == "actuator" and g.input_joint() == scene.input_joint]


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
