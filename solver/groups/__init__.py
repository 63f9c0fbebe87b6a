"""Structural groups: one module per kind, each solving its points in closed form with exact analogs."""

from __future__ import annotations

from typing import Any

from .actuator import Actuator
from .attached import Attached
from .base import Context, Group
from .crank import CoupledCrank, CoupledCrankEntry, Crank
from .joints import JOINT_KINDS, JointExpression
from .rrp import RRP
from .rrr import RRR
from .slider_triad import SliderTriad
from .slotted import Slotted
from .spherical import SphericalCrankSlider
from .triad import Triad

__all__ = [
    "Actuator",
    "Attached",
    "Context",
    "CoupledCrank",
    "Crank",
    "Group",
    "GROUP_TYPES",
    "JOINT_KINDS",
    "JointExpression",
    "RRP",
    "RRR",
    "SliderTriad",
    "Slotted",
    "SphericalCrankSlider",
    "Triad",
]

#: The group types a scene's ``groups:`` list may name, by their ``type:`` key.
GROUP_TYPES: dict[str, Any] = {
    cls.kind: cls for cls in (Crank, Actuator, Attached, Slotted, RRR, RRP, SphericalCrankSlider, Triad, SliderTriad)
}
GROUP_TYPES[CoupledCrankEntry.kind] = CoupledCrankEntry  # the drawn form's coupled input (solver.structure)
