"""A robot model file as plain data: rigid bodies, joints, loop closures and couplings in 3-D.

Each file format's reader (solver.models.mjcf, solver.models.urdf) fills a :class:`SpatialModel`
at one pose; solver.models.planar checks that it is a planar mechanism and lays it into its plane.
Everything here is in the model's world frame, SI units (m, rad, kg, kg·m²).

* A :class:`Body` is a rigid body after welding: a model body and every descendant fixed to it
  (no joint between them) are one body, named after the first. ``points`` are its sites
  (MJCF) and the origins of its model bodies (named after them; ``origins``), where the scene
  may want to read them; a site's name wins over an origin's at one place.
* A :class:`Joint` is a hinge or a slide between two bodies (``parent`` — ``child``), with its
  world ``anchor`` and unit ``axis`` at the pose, its ``value`` there and its ``reference`` (the
  value at which the model was written: MJCF qpos0, URDF 0).
* A :class:`Closure` joins two bodies at one world point (MJCF ``<connect>``, onshape-to-robot's
  ``closing_*`` frame pairs, URDF+ ``<constraint type="loop">``): a pin, in the plane.
* A :class:`Coupling` ties joint ``joint`` to joint ``source``: value = ``offset`` + ``ratio``·source
  (MJCF ``<joint>`` equality with a linear polycoef, URDF ``<mimic>``).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Body", "Joint", "Closure", "Coupling", "SpatialModel", "GROUND_BODY"]

#: The name of the frame (MJCF's world body and everything welded to it; a URDF's root link).
GROUND_BODY = "world"


@dataclass(frozen=True)
class Body:
    name: str
    points: Mapping[str, np.ndarray]  # model body origins, world
    mass: float = 0.0
    com: np.ndarray = field(default_factory=lambda: np.zeros(3))  # world
    inertia: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))  # about the com, world axes
    #: the names among ``points`` that are only model bodies' origins (the rest: sites, frames)
    origins: frozenset[str] = frozenset()


@dataclass(frozen=True)
class Joint:
    name: str
    kind: str  # "hinge" | "slide"
    parent: str
    child: str
    anchor: np.ndarray
    axis: np.ndarray  # unit
    value: float  # at the pose
    reference: float  # the model's reference value (qpos0)
    range: tuple[float, float] | None = None


@dataclass(frozen=True)
class Closure:
    name: str
    body1: str
    body2: str
    point: np.ndarray  # world, on body1
    gap: float  # |point on body1 − point on body2| at the pose, m


@dataclass(frozen=True)
class Coupling:
    joint: str
    source: str
    ratio: float
    offset: float
    what: str  # where it comes from, for messages: "equality joint[2]", "mimic of 'x'"


@dataclass(frozen=True)
class SpatialModel:
    name: str
    file: str
    kind: str  # "MJCF" | "URDF"
    bodies: Mapping[str, Body]  # the ground first
    joints: tuple[Joint, ...]
    closures: tuple[Closure, ...]
    couplings: tuple[Coupling, ...]
    actuated: tuple[str, ...]  # joints the model's actuators drive
    gravity: np.ndarray
    pose: str  # "qpos0", "keyframe 'name'", "zero"
    provenance: str = ""
    notes: tuple[str, ...] = ()
