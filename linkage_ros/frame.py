"""One solved instant of a mechanism: :class:`Frame`, its points and joints, and its status.

:class:`~linkage_ros.engine.Engine` makes frames (one tick, or whole runs); the message builder,
the serialiser, the relay and the recorders read them. A frame's ``status`` is
:data:`STATUS_OK`, :data:`STATUS_NEAR_SINGULAR` (a group's conditioning under the threshold, named
in ``message``) or :data:`STATUS_UNASSEMBLABLE` (the input held or reversed where the mechanism
cannot be assembled; ``message`` says where).
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "NO_VALUES",
    "STATUS_BEHIND",
    "STATUS_INPUT_DROPPED",
    "STATUS_NEAR_SINGULAR",
    "STATUS_OK",
    "STATUS_UNASSEMBLABLE",
    "Angles",
    "Frame",
    "JointState",
    "PointState",
    "finite_sum",
    "with_status",
]

STATUS_OK = "ok"
STATUS_NEAR_SINGULAR = "near_singular"
STATUS_UNASSEMBLABLE = "unassemblable"
#: A dynamic law that does not keep up with real time (diagnostics WARN with its real-time factor).
STATUS_BEHIND = "behind"
#: Topic mode only, in diagnostics (level WARN): an incoming JointState that could not be read
#: (none of the input joints, a non-finite value, short arrays); its ``message`` says why.
STATUS_INPUT_DROPPED = "input_dropped"
#: The efforts and loads of a frame without forces (read only).
NO_VALUES: Mapping[str, Any] = MappingProxyType({})


class PointState(NamedTuple):
    """Position, velocity and acceleration of one point, each ``dim`` floats (m, m/s, m/s²).

    A tuple of Python floats on the per-tick path (:meth:`Engine.frame`, no numpy per tick), a
    ``(dim,)`` array row in whole runs (:meth:`Engine.frames`); index them, or ``tuple()`` them.
    """

    position: Sequence[float] | NDArray[np.float64]
    velocity: Sequence[float] | NDArray[np.float64]
    acceleration: Sequence[float] | NDArray[np.float64]


class JointState(NamedTuple):
    """Position (rad or m), velocity and acceleration of one joint."""

    position: float
    velocity: float
    acceleration: float


#: One input value per input joint: a float, or a k-tuple with several inputs.
Angles = float | tuple[float, ...]


@dataclass(frozen=True, slots=True)
class Frame:
    """The mechanism at one instant ``t`` (s of run time)."""

    t: float
    #: The input state (rad, rad/s, rad/s²; m for a slide): floats, or k-tuples in input order
    #: with several inputs (docs/inputs.md).
    phi: Angles
    omega: Angles
    epsilon: Angles
    points: Mapping[str, PointState]
    joints: Mapping[str, JointState]
    status: str
    conditioning: float
    message: str
    #: Scenes with forces (:mod:`linkage_ros.forces`): input joint → effort (N·m or N), and
    #: load key → (Fx, Fy, M) (N, N, N·m); empty otherwise.
    efforts: Mapping[str, float] = field(default_factory=lambda: NO_VALUES)
    loads: Mapping[str, tuple[float, float, float]] = field(default_factory=lambda: NO_VALUES)
    #: Scenes with friction (:func:`linkage_ros.forces.friction_names`): the power (W) friction
    #: dissipates, ``total`` then per element; empty otherwise.
    friction: Mapping[str, float] = field(default_factory=lambda: NO_VALUES)


def finite_sum(frame: Frame) -> float:
    """A sum of every number of the frame: finite exactly when all of them are (barring overflow,
    which is as unusable). One ``sum`` over the chained numbers: it runs every tick."""
    chain = itertools.chain.from_iterable
    total = sum(chain(chain(frame.points.values()))) + sum(chain(frame.joints.values()))
    if frame.efforts:
        total += sum(frame.efforts.values()) + sum(chain(frame.loads.values()))
    if frame.friction:
        total += sum(frame.friction.values())
    return total


def with_status(frame: Frame, status: str, message: str) -> Frame:
    """``frame`` with another status and message."""
    return Frame(
        t=frame.t,
        phi=frame.phi,
        omega=frame.omega,
        epsilon=frame.epsilon,
        points=frame.points,
        joints=frame.joints,
        status=status,
        conditioning=frame.conditioning,
        message=message,
        efforts=frame.efforts,
        loads=frame.loads,
        friction=frame.friction,
    )
