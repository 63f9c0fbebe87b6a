"""Kinetostatics: input efforts and pin reactions from masses and loads, exact (docs/forces.md).

A scene's optional ``bodies``, ``gravity`` and ``loads`` (solver.forces.parse) name the links
that the groups make (solver.forces.structure). ``Scene.solve`` then also gives
``k.effort(joint)``, ``k.reaction(point, on=body)`` and ``k.slide_reaction(block)``: route 2, the
groups' equilibria solved in reverse plan order on the jets the kinematics has just computed
(one module per group kind: crank, rrr, rrp, slotted, triad). Route 1, the virtual power of the
analogs (solver.forces.virtual), is the independent cross-check of the efforts.
"""

from __future__ import annotations

from .model import ForceModel
from .result import ForceBuffers, ForceResult, SlideReaction
from .spec import Body, ForceSpec, PointForce, Spring, TableForce, Torque
from .structure import GROUND, Link, Pin, Slide

__all__ = [
    "GROUND",
    "Body",
    "ForceBuffers",
    "ForceModel",
    "ForceResult",
    "ForceSpec",
    "Link",
    "Pin",
    "PointForce",
    "Slide",
    "SlideReaction",
    "Spring",
    "TableForce",
    "Torque",
]
