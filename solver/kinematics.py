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

__all__ = ["Kinematics", "Motion"]


class Motion(NamedTuple):
    """Position, velocity and acceleration of one point ((N, dim) arrays) or joint ((N,) arrays).

    For a scalar φ the leading axis is dropped: (dim,) and () respectively.
    """

    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray


class Kinematics:
    """Motion of the requested points and joints over the sampled crank angles."""

    def __init__(
        self,
        *,
        phi: np.ndarray,
        omega: np.ndarray,
        epsilon: np.ndarray,
        values: Mapping[str, Jet],
        points: tuple[str, ...],
        joints: tuple[str, ...],
        conditioning: Mapping[str, Any],
        valid: np.ndarray | None = None,
        scalar: bool = False,
    ) -> None:
        self.phi = phi
        self.omega = omega
        self.epsilon = epsilon
        self.points = points
        self.joints = joints
        self._values = values
        self._scalar = scalar
        shape = phi.shape
        self.conditioning = {k: np.broadcast_to(np.asarray(v, float), shape) for k, v in conditioning.items()}
        #: False where a sample could not be assembled (only with ``mask=True``).
        self.valid = np.ones(shape, bool) if valid is None else np.broadcast_to(valid, shape)
        self._cache: dict[str, Motion] = {}

    def point(self, name: str) -> Motion:
        """Position, velocity and acceleration of point ``name``: (N, 2) or (N, 3) arrays."""
        if name not in self.points:
            raise SolverError(f"point '{name}' was not requested; requested points: {list(self.points)}")
        if name not in self._cache:
            self._cache[name] = self._motion(self._values[name], planar=None)
        return self._cache[name]

    def joint(self, name: str) -> Motion:
        """Coordinate, velocity and acceleration of joint ``name`` (rad or m): (N,) arrays."""
        if name not in self.joints:
            raise SolverError(f"joint '{name}' was not requested; requested joints: {list(self.joints)}")
        if name not in self._cache:
            self._cache[name] = self._motion(self._values[name], planar=False)
        return self._cache[name]

    @property
    def min_conditioning(self) -> np.ndarray:
        """The worst conditioning over all groups, per sample (1 where no group reports one)."""
        if not self.conditioning:
            return np.ones(self.phi.shape)
        return np.minimum.reduce(list(self.conditioning.values()))

    def _motion(self, jet: Jet, *, planar: bool | None) -> Motion:
        w, e = self.omega, self.epsilon
        z0, z1, z2 = jet
        is_complex = planar is None and np.iscomplexobj(np.asarray(z0))
        spatial = planar is None and not is_complex
        if spatial:  # (…, 3) arrays: broadcast ω, ε over the last axis
            w, e = w[..., None], e[..., None]
        v = z1 * w
        a = z2 * (w * w) + z1 * e
        shape = self.phi.shape + ((3,) if spatial else ())
        out = [_as(x, shape, complex if is_complex else float) for x in (z0, v, a)]
        if is_complex:
            out = [_planar(x) for x in out]
        return Motion(*out)


def _as(x: Any, shape: tuple[int, ...], dtype: type) -> np.ndarray:
    arr = np.asarray(x, dtype=dtype)
    if arr.shape != shape:
        arr = np.broadcast_to(arr, shape).copy()
    return arr


def _planar(z: np.ndarray) -> np.ndarray:
    """complex (…,) → float (…, 2) without a copy where the memory allows."""
    if z.ndim == 0:
        return np.array([z.real, z.imag])
    if not z.flags.c_contiguous:
        z = z.copy()
    return z.view(np.float64).reshape(z.shape + (2,))
