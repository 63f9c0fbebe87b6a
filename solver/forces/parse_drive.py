"""``motor``, ``flywheel`` and ``damping`` of a scene file: what drives and brakes its inputs.

    motor:    {INPUT: {stall_torque: T₀, no_load_speed: ω₀}}    T = T₀·(1 − ω/ω₀)   (N·m, rad/s;
              T₀ and ω₀ of one sign: the torque falls as the speed rises, never the other way)
              {INPUT: {speed: [ω…], torque: [T…]}}             linear between, constant beyond
              an actuator's stroke: stall_force and force (N) against speeds in m/s
    flywheel: {INPUT: I_F}       kg·m² about the crank's pivot, added to the crank's body
    damping:  {JOINT: c}         N·m·s/rad: a couple −c·q̇ between the joint's two bodies

A motor drives an input only in forward dynamics (solver.dynamics): the kinetostatic effort is
what the actuator must apply, whoever it is. A flywheel and a damper are part of the mechanism:
the efforts, the reactions and the equation of motion all carry them. Every fault is one
SceneError line naming the key (docs/dynamics.md).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import replace

from .._fields import Entry, show, suggest
from ..groups import Crank, Group, JointExpression
from .spec import Body, Damper, Motor
from .structure import GROUND

__all__ = ["DRIVE_KEYS", "parse_drive"]

#: The top-level keys of the drive layer (read with the force layer's).
DRIVE_KEYS = ("motor", "flywheel", "damping")

#: Largest stall torque (N·m), speed (rad/s), flywheel inertia (kg·m²), damping (N·m·s/rad).
DRIVE_MAX = 1e12


def parse_drive(
    top: Entry, groups: Sequence[Group], bodies: tuple[Body, ...]
) -> tuple[dict[str, Motor], dict[str, float], tuple[Body, ...], tuple[Damper, ...]]:
    """The motors, flywheels (with the bodies they enlarge) and dampers of a scene."""
    inputs = {g.input_joint(): g for g in groups if g.drives}
    motors = {j: _motor(top.child("motor", top.raw("motor")), j, inputs)
              for j in _keys(top, "motor")}
    flywheels: dict[str, float] = {}
    for j in _keys(top, "flywheel"):
        e = top.child("flywheel", top.raw("flywheel"))
        g = _input(e, j, inputs)
        if not isinstance(g, Crank):
            article = "an" if g.kind[:1] in "aeiou" else "a"
            raise e.error(f"a flywheel turns with a crank; '{j}' is {article} {g.kind}'s input", j)
        inertia = _bounded(e, j, "kg·m²")
        flywheels[j] = inertia
        bodies = tuple(replace(b, inertia=b.inertia + inertia) if b.link.name == g.name else b for b in bodies)
    dampers = tuple(_damper(top.child("damping", top.raw("damping")), j, groups, bodies)
                    for j in _keys(top, "damping"))
    return motors, flywheels, bodies, dampers


def _keys(top: Entry, key: str) -> list[str]:
    if key not in top.data:
        return []
    raw = top.raw(key)
    if not isinstance(raw, Mapping) or not raw:
        raise top.error(f"must map joint names to values (docs/dynamics.md), got {show(raw)}", key)
    return [str(k) for k in raw]


def _input(e: Entry, joint: str, inputs: Mapping[str | None, Group]) -> Group:
    g = inputs.get(joint)
    if g is None:
        names = [str(n) for n in inputs]
        near = suggest(joint, names)[:1]
        hint = f" (did you mean '{near[0]}'?)" if near else ""
        raise e.error(f"'{joint}' is not an input of the scene{hint}; inputs: {', '.join(names)}", joint)
    return g


def _bounded(e: Entry, key: str, unit: str, *, signed: bool = False) -> float:
    value = e.number(key)
    if not signed and value < 0.0:
        raise e.error(f"must not be negative, got {value:g} {unit}", key)
    if abs(value) > DRIVE_MAX:
        raise e.error(f"{value:g} {unit} is beyond {DRIVE_MAX:g}", key)
    return value


def _motor(top: Entry, joint: str, inputs: Mapping[str | None, Group]) -> Motor:
    """A motor's line or table: of a torque (N·m) against a speed (rad/s) on a crank, of a force
    (N) against a speed (m/s) on an actuator's stroke (``stall_force``, ``force``)."""
    stroke = _input(top, joint, inputs).input_range() is not None
    effort, unit, speed = ("force", "N", "m/s") if stroke else ("torque", "N·m", "rad/s")
    stall_key = f"stall_{effort}"
    e = top.child(joint, top.raw(joint))
    other = "torque" if stroke else "force"
    for key in (f"stall_{other}", other):
        if key in e.data:
            what = "an actuator's stroke: its motor gives a force (N)" if stroke else "a crank: its motor gives a " \
                "torque (N·m)"
            raise e.error(f"'{joint}' is {what}; write {key.replace(other, effort)}", key)
    e.expect((stall_key, "no_load_speed", "speed", effort))
    linear = [k for k in (stall_key, "no_load_speed") if k in e.data]
    table = [k for k in ("speed", effort) if k in e.data]
    if linear and table:
        raise e.error(f"a motor is a line ({stall_key}, no_load_speed) or a table (speed, {effort}), not both")
    if table:
        if len(table) != 2:
            raise e.error(f"a {effort}–speed table needs both 'speed' ({speed}) and '{effort}' ({unit})")
        speeds, torques = _numbers(e, "speed"), _numbers(e, effort)
        if len(speeds) != len(torques):
            raise e.error(f"has {len(torques)} {effort}s for {len(speeds)} speeds", effort)
        if any(b <= a for a, b in zip(speeds, speeds[1:])):
            raise e.error("speeds must increase strictly", "speed")
        e.done()
        return Motor(joint, speeds=speeds, torques=torques)
    if len(linear) != 2:
        raise e.error(f"a motor needs {stall_key} ({unit}) and no_load_speed ({speed}), or a table of speed and "
                      f"{effort}")
    stall = _bounded(e, stall_key, unit, signed=True)
    no_load = _bounded(e, "no_load_speed", speed, signed=True)
    if no_load == 0.0:
        raise e.error(f"must not be 0: the speed at which the motor's {effort} falls to zero", "no_load_speed")
    if stall * no_load < 0.0:
        raise e.error(f"{stall:g} {unit} against a no-load speed of {no_load:g} {speed}: a {effort} that grows "
                      f"with the speed it drives (the line's slope −{stall_key}/no_load_speed is positive) runs away; "
                      "a motor that turns backwards has both negative", stall_key)
    e.done()
    return Motor(joint, stall=stall, no_load=no_load)


def _numbers(e: Entry, key: str) -> tuple[float, ...]:
    raw = e.raw(key)
    if not isinstance(raw, (list, tuple)) or len(raw) < 2:
        raise e.error(f"must be a list of at least two numbers, got {show(raw)}", key)
    out = tuple(e.as_number(v, key) for v in raw)
    if any(abs(v) > DRIVE_MAX or not math.isfinite(v) for v in out):
        raise e.error(f"a value beyond ±{DRIVE_MAX:g}", key)
    return out


def _damper(e: Entry, joint: str, groups: Sequence[Group], bodies: tuple[Body, ...]) -> Damper:
    c = _bounded(e, joint, "N·m·s/rad")
    revolute = "; damping is modelled in revolute joints: an input crank, an angle of one link, a revolute joint"
    for g in groups:
        if isinstance(g, Crank) and g.joint == joint:
            return Damper(joint, _body_of(bodies, (g.center, g.point), e, joint), GROUND, c)
        if isinstance(g, JointExpression) and g.name == joint:
            if g.expression == "angle":
                return Damper(joint, _body_of(bodies, g.points, e, joint), GROUND, c)
            if g.expression == "revolute":
                parent = _body_of(bodies, g.points[:2], e, joint, ground_ok=True)
                child = _body_of(bodies, g.points[2:], e, joint)
                return Damper(joint, child, parent, c, g.sign)
            raise e.error(f"'{joint}' is a {g.expression} coordinate{revolute}", joint)
    joints = [n for g in groups for n in g.joints()]
    if joint in joints:
        raise e.error(f"'{joint}' is not a revolute joint{revolute}", joint)
    near = suggest(joint, joints)[:1]
    hint = f" (did you mean '{near[0]}'?)" if near else ""
    raise e.error(f"unknown joint '{joint}'{hint}; joints: {', '.join(joints)}", joint)


def _body_of(
    bodies: tuple[Body, ...], points: Sequence[str], e: Entry, joint: str, *, ground_ok: bool = False
) -> str:
    """The body that carries both ``points`` (``ground`` for fixed points when allowed)."""
    for b in bodies:
        if not b.link.block and set(points) <= set(b.points):
            return b.name
    if ground_ok:
        return GROUND
    raise e.error(f"'{joint}' does not measure one link ({', '.join(points)} are on no one body)", joint)
