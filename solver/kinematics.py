"""The result of a solve: positions, velocity and acceleration analogs, and real motion.

Real motion follows from the analogs for any input law φ(t) (seed 000, eq. 11–12):
    v = v_q·ω,   a = a_q·ω² + v_q·ε,
with v_q = dr/dφ and a_q = d²r/dφ². With ω = 1 and ε = 0 the velocities and accelerations
returned are the analogs themselves.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, NamedTuple

import numpy as np

from .errors import SolverError
from .jet import Jet

__all__ = ["Kinematics", "Motion", "MotionRows", "empty_motion", "fill_motion", "motion_rows"]


class Motion(NamedTuple):
    """Position, velocity and acceleration of one point ((N, dim) arrays) or joint ((N,) arrays).

    For a scalar φ the leading axis is dropped: (dim,) and () respectively.
    """

    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray


def empty_motion(n: int, width: int | None) -> Motion:
    """Uninitialised (N, width) arrays, or (N,) for a joint (``width=None``).

    Planar points (width 2) are allocated as complex (N,) arrays and viewed as float (N, 2), so
    that filling them from complex jets is a contiguous copy.
    """
    if width == 2:
        return Motion(*(np.empty(n, complex).view(np.float64).reshape(n, 2) for _ in range(3)))
    shape = (n,) if width is None else (n, width)
    return Motion(np.empty(shape), np.empty(shape), np.empty(shape))


class MotionRows(NamedTuple):
    """Where :func:`fill_motion` writes one output: planar points as complex (N,) views of their
    (N, 2) arrays, so that a complex jet is copied contiguously; ``spatial`` for (N, 3) points,
    whose rows take ω and ε as a column."""

    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    spatial: bool


def motion_rows(out: Motion, *, planar: bool) -> MotionRows:
    """The arrays of ``out`` that :func:`fill_motion` writes (once per solve, not per block)."""
    if planar:
        pos, vel, acc = (x.view(np.complex128)[:, 0] for x in out)
        return MotionRows(pos, vel, acc, False)
    return MotionRows(out.position, out.velocity, out.acceleration, out.position.ndim == 2)


def fill_motion(out: MotionRows, rows: slice, jet: Jet, omega: Any, epsilon: Any) -> None:
    """Write the real motion of ``jet`` for the samples ``rows`` into ``out``:
    v = z'·ω, a = z''·ω² + z'·ε.

    Planar points are complex jets (written as x, y columns); spatial points (…, 3) real jets;
    joints real jets. ``omega`` and ``epsilon`` are floats or the rows' (n,) arrays.
    """
    z0, z1, z2 = jet
    w, e = omega, epsilon
    if out.spatial:  # spatial points: ω, ε per row
        w = omega[:, None] if np.ndim(omega) else omega
        e = epsilon[:, None] if np.ndim(epsilon) else epsilon
    out.position[rows] = z0
    np.multiply(z1, w, out=out.velocity[rows])
    acc = out.acceleration[rows]
    np.multiply(z2, w * w, out=acc)
    if type(e) is not float or e != 0.0:
        acc += z1 * e


class Kinematics:
    """Motion of the requested points and joints over the sampled crank angles."""

    def __init__(
        self,
        *,
        phi: np.ndarray,
        omega: np.ndarray,
        epsilon: np.ndarray,
        motions: Mapping[str, Motion],
        points: tuple[str, ...],
        joints: tuple[str, ...],
        conditioning: Mapping[str, Any],
        valid: np.ndarray | None = None,
        floats: Mapping[str, tuple[Any, Any, Any]] | None = None,
    ) -> None:
        self.phi = phi
        self.omega = omega
        self.epsilon = epsilon
        self.points = points
        self.joints = joints
        self._motions = dict(motions)
        self._floats = floats
        self._conditioning = conditioning
        self._valid = valid
        self._conditioning_arrays: dict[str, Any] | None = None

    def point(self, name: str) -> Motion:
        """Position, velocity and acceleration of point ``name``: (N, 2) or (N, 3) arrays."""
        if name not in self.points:
            raise SolverError(f"point '{name}' was not requested; requested points: {list(self.points)}")
        return self._motions.get(name) or self._from_floats(name)

    def joint(self, name: str) -> Motion:
        """Coordinate, velocity and acceleration of joint ``name`` (rad or m): (N,) arrays."""
        if name not in self.joints:
            raise SolverError(f"joint '{name}' was not requested; requested joints: {list(self.joints)}")
        return self._motions.get(name) or self._from_floats(name)

    def floats(self, name: str) -> tuple[Any, Any, Any]:
        """For a scalar φ: (position, velocity, acceleration) of a point (tuples of dim floats) or a
        joint (floats) as plain Python numbers — the per-tick path, which avoids numpy entirely."""
        if self._floats is None:
            raise SolverError("floats() is for a solve at a single φ; use point() or joint() for sweeps")
        if name not in self._floats:
            raise SolverError(f"'{name}' was not requested; requested: {[*self.points, *self.joints]}")
        return self._floats[name]

    def _from_floats(self, name: str) -> Motion:
        assert self._floats is not None
        m = Motion(*(np.array(x, dtype=float) for x in self._floats[name]))
        self._motions[name] = m
        return m

    @property
    def valid(self) -> np.ndarray:
        """False where a sample could not be assembled (only with ``mask=True``; else all True)."""
        if self._valid is None:
            self._valid = np.ones(self.phi.shape, bool)
        return self._valid

    @property
    def conditioning(self) -> dict[str, Any]:
        """Per group, its dimensionless conditioning per sample: 1 well conditioned, 0 singular.

        (N,) arrays for a sweep; plain floats for a scalar φ."""
        if self.phi.ndim == 0:  # a scalar solve: its floats as they are
            return self._conditioning  # type: ignore[return-value]
        if self._conditioning_arrays is None:
            shape = self.phi.shape
            self._conditioning_arrays = {
                k: np.broadcast_to(np.asarray(v, float), shape) for k, v in self._conditioning.items()
            }
        return self._conditioning_arrays

    @property
    def min_conditioning(self) -> np.ndarray:
        """The worst conditioning over all groups, per sample (1 where no group reports one)."""
        values = list(self.conditioning.values())
        return np.minimum.reduce(values) if values else np.ones(self.phi.shape)

    @property
    def singular(self) -> np.ndarray:
        """True at the samples where some group is singular (conditioning < tolerances.SINGULAR).

        Positions are exact there; the analogs are their limit along the branch where it exists,
        else NaN (see solver.singular).
        """
        from .tolerances import SINGULAR

        return self.min_conditioning < SINGULAR
