"""The structural check of a scene's inputs (docs/inputs.md): do they determine the mechanism?

A group-based scene is built of driving groups (one per input) and Assur groups (rrr, rrp,
slotted, attached, …), each of which determines its points from points already known and adds
no freedom of its own. Its mobility is therefore the number of inputs, and the inputs fail to
determine it in exactly three ways, each reported with the groups concerned:

* **too many inputs (over-determined)**: an input moves a point that another group also
  determines (e.g. a crank on a four-bar's rocker beside the dyad that places the rocker's end):
  the point is defined twice, by the crank and by the other group;
* **too few inputs (under-determined)**: a group needs a point that nothing provides — no input
  moves it and no group determines it (``solver.plan.order_groups`` reports it, naming the group);
* **an input that moves none of the outputs**: with several inputs, an input joint on which no
  declared output depends adds a dimension that nothing reads (a zero column of every Jacobian).
  Checked for the scene's declared outputs; ``Scene.with_outputs`` may ask for fewer.

Several inputs are supported for ``crank`` and ``actuator`` groups (a driven length, whose
input is its stroke in m), in any mix; the spherical converter's shaft and the vector-loop input
(seed 004) stay single-input drivers. An RRR dyad with ``through_change_points: continuous``
follows change points in one input angle: it is single-input, and driven by a crank.
An actuator pushes a link about a pivot: the pivot and the cylinder's base must be points of
the mechanism's links (fixed points or points a group places), not joints.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

from ._fields import Entry
from .groups import Actuator, CoupledCrank, Crank, Group

__all__ = ["check_actuators", "check_coupled", "check_drivers", "check_outputs_move", "input_joints"]


def input_joints(groups: Iterable[Group]) -> tuple[str, ...]:
    """The input joints of the driving groups, in scene order."""
    return tuple(str(g.input_joint()) for g in groups if g.drives)


def _label(g: Group) -> str:
    return f"{g.kind} '{g.name}'"


def check_drivers(top: Entry, groups: Sequence[Group]) -> None:
    """With several inputs: every driver is a crank or an actuator, no input over-determines a
    point, no group follows change points in φ. A single-input scene is left to the checks that
    follow."""
    drivers = [g for g in groups if g.drives]
    if len(drivers) < 2:
        return
    names = ", ".join(f"{_label(g)} (input '{g.input_joint()}')" for g in drivers)
    for g in drivers:
        if not isinstance(g, (Crank, Actuator)):
            raise top.error(
                f"several inputs are cranks and actuators only, found {names}: {_label(g)} drives a single-input scene",
                "groups",
            )
    by: dict[str, Group] = {}
    for g in groups:
        for n in g.provides():
            other = by.get(n)
            named_twice = n in g.joints() or (other is not None and n in other.joints())
            if other is not None and (other.drives or g.drives) and not named_twice:  # a point, not a name clash
                crank = other if other.drives else g
                rest = g if crank is other else other
                raise top.error(
                    f"'{n}' is defined twice: by {_label(other)} and by {_label(g)}: too many inputs "
                    f"(over-determined) — input '{crank.input_joint()}' of {_label(crank)} moves a point "
                    f"that {_label(rest)} also determines",
                    "groups",
                )
            by.setdefault(n, g)
    for g in groups:
        if getattr(g, "continuous", False):
            raise top.error(
                f"{_label(g)}: through_change_points: continuous follows change points in one input "
                f"angle; with several inputs ({names}) use 'keep'",
                "groups",
            )


def check_outputs_move(
    groups: Sequence[Group], fixed: Iterable[str], outputs: Sequence[str], *, file: str | None
) -> None:
    """With several inputs, every input joint must move at least one of ``outputs``."""
    from .errors import SceneError

    drivers = [g for g in groups if g.drives]
    if len(drivers) < 2:
        return
    provider: dict[str, Any] = {n: g for g in groups for n in g.provides()}
    fixed = set(fixed)
    reached: set[str] = set()
    stack = [o for o in outputs if o not in fixed]
    seen: set[str] = set()
    while stack:
        name = stack.pop()
        if name in seen or name not in provider:
            continue
        seen.add(name)
        g = provider[name]
        if g.drives:
            reached.add(g.name)
        stack.extend(r for r in g.requires() if r not in fixed)
    idle = [g for g in drivers if g.name not in reached]
    if idle:
        raise SceneError(
            "too many inputs: "
            + ", ".join(f"input '{g.input_joint()}' of {_label(g)}" for g in idle)
            + f" moves none of the outputs {list(outputs)}",
            file=file,
            entry="outputs",
        )


def check_actuators(top: Entry, fixed: Iterable[str], groups: Sequence[Group]) -> None:
    """Every actuator's base and pivot are points of links (fixed, or placed by a group), and a
    scene driven by an actuator has no branch followed through change points (an angle's)."""
    actuators = [g for g in groups if isinstance(g, Actuator)]
    if not actuators:
        return
    joints = {n for g in groups for n in (*g.joints(), *g.hidden())}
    points = set(fixed) | {n for g in groups for n in g.provides() if n not in joints}
    for a in actuators:
        for role, name in (("pivot", a.pivot), ("base", a.base)):
            if name not in points:
                what = "a joint" if name in joints else "no fixed point nor a point any group places"
                shown = ", ".join(sorted(points)[:12])
                raise top.error(
                    f"{_label(a)}: {role} '{name}' is not on a link ({what}); give a fixed point or a "
                    f"point of a link: {shown}",
                    "groups",
                )
    for g in groups:
        if getattr(g, "continuous", False):
            raise top.error(
                f"{_label(g)}: through_change_points: continuous follows change points in a crank "
                f"angle; a scene driven by {_label(actuators[0])} uses 'keep'",
                "groups",
            )


def check_coupled(top: Entry, groups: Sequence[Group]) -> None:
    """A coupled crank (``follows:``) follows the joint of an input crank of the scene."""
    inputs = {str(g.input_joint()): g for g in groups if g.drives}
    for g in groups:
        if isinstance(g, CoupledCrank):
            src = inputs.get(g.source)
            if not isinstance(src, Crank):
                what = f"the {_label(src)}'s stroke" if src is not None else "no input joint"
                cranks = ", ".join(j for j, d in inputs.items() if isinstance(d, Crank)) or "none"
                raise top.error(
                    f"crank '{g.name}' follows '{g.source}', {what}: a coupled crank follows an input crank's "
                    f"joint (input cranks: {cranks})",
                    "groups",
                )
