"""The result of a solve: positions, velocity and acceleration analogs, and real motion.

Real motion follows from the analogs for any input law φ(t) (seed 000, eq. 11–12):
    v = v_q·ω,   a = a_q·ω² + v_q·ε,
with v_q = dr/dφ and a_q = d²r/dφ². With ω = 1 and ε = 0 the velocities and accelerations
returned are the analogs themselves.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from functools import cached_property
from typing import Any, NamedTuple

import numpy as np

from .errors import SolverError
from .forces import ForceResult
from .jet import Jet

__all__ = [
    "Derivatives",
    "FlatFloats",
    "InstantKinematics",
    "InstantMotion",
    "Kinematics",
    "Motion",
    "OutputMotion",
    "MotionRows",
    "empty_motion",
    "fill_motion",
    "motion_rows",
]


class Motion(NamedTuple):
    """Position, velocity and acceleration of one point ((N, dim) arrays) or joint ((N,) arrays).

    For a scalar φ the leading axis is dropped: (dim,) and () respectively.
    """

    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray


class InstantMotion(NamedTuple):
    """Position, velocity and acceleration of one output at **one instant of a one-input scene**
    (``scene.solve(φ)`` with a float φ), as plain Python numbers: a point's are tuples of its
    ``dim`` floats (``(x, y)`` or ``(x, y, z)``, m, m/s, m/s²), a joint's are floats (rad or m).

    The per-tick object path: made from the solve's floats in two C calls, no numpy (a
    :class:`Motion` of (dim,) arrays costs a few µs a point). Wrap a field in ``np.asarray`` for
    array arithmetic (a tuple's ``+`` concatenates). Sweeps, and instants of scenes with several
    inputs, give :class:`OutputMotion` arrays with ``.jacobian`` and ``.hessian``; with one
    input those are the analogs, which a solve at ω = 1, ε = 0 gives as velocity and
    acceleration."""

    position: Any
    velocity: Any
    acceleration: Any


_new_tuple = tuple.__new__


class Derivatives:
    """The exact first and second partial derivatives of a solve's outputs in its inputs,
    evaluated on first use and kept: for every output at once (``compute() -> {name: (jacobian,
    hessian)}``, a sweep), or output by output (``each(name) -> (jacobian, hessian)``, one instant,
    where only the groups that output needs run)."""

    __slots__ = ("_compute", "_each", "_cache")

    def __init__(
        self,
        compute: Callable[[], Mapping[str, tuple[np.ndarray, np.ndarray]]] | None = None,
        *,
        each: Callable[[str], tuple[np.ndarray, np.ndarray]] | None = None,
    ) -> None:
        self._compute = compute
        self._each = each
        self._cache: dict[str, tuple[np.ndarray, np.ndarray]] | None = None

    def of(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        if self._cache is None:
            self._cache = {} if self._compute is None else dict(self._compute())
        if name not in self._cache and self._each is not None:
            self._cache[name] = self._each(name)
        return self._cache[name]


class OutputMotion(Motion):
    """A :class:`Motion` of one output of a solve, with its derivatives in the inputs.

    ``jacobian``: (N, dim, k) for a point, (N, k) for a joint; ``hessian``: (N, dim, k, k) and
    (N, k, k) — the leading N dropped for a single instant. Evaluated on first access (one more
    pass of the plan per input and per pair of inputs: for every output of a sweep at once, for
    one output at a time at a single instant);
    with one input they are the analogs d/dφ and d²/dφ² reshaped (docs/inputs.md).
    """

    _derivatives: Derivatives | None
    _name: str

    def __new__(cls, motion: Motion, name: str, derivatives: Derivatives | None) -> OutputMotion:
        self = super().__new__(cls, *motion)
        self._derivatives = derivatives
        self._name = name
        return self

    @property
    def jacobian(self) -> np.ndarray:
        return self._derived()[0]

    @property
    def hessian(self) -> np.ndarray:
        return self._derived()[1]

    def _derived(self) -> tuple[np.ndarray, np.ndarray]:
        if self._derivatives is None:
            raise SolverError(f"'{self._name}': this result carries no derivatives in the inputs")
        return self._derivatives.of(self._name)


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
        phi: Any,
        omega: Any,
        epsilon: Any,
        motions: Mapping[str, Motion],
        points: tuple[str, ...],
        joints: tuple[str, ...],
        conditioning: Mapping[str, Any],
        valid: np.ndarray | None = None,
        floats: Mapping[str, tuple[Any, Any, Any]] | None = None,
        derivatives: Derivatives | None = None,
        inputs: tuple[str, ...] | None = None,
        forces: Any = None,
    ) -> None:
        #: The input joints, in order (k of them); with several, ``phi`` is (N, k) — (k,) for
        #: one instant — and so are ``omega`` and ``epsilon``.
        self.inputs = inputs
        self._derivatives = derivatives
        # one instant may give φ, ω, ε as Python numbers (k-tuples with several inputs): made
        # arrays on first read only (the compiled per-tick path builds no array it is not asked for)
        if isinstance(phi, np.ndarray):
            self._samples = phi.shape if inputs is None or len(inputs) == 1 else phi.shape[:-1]
        else:
            self._samples = ()
        self._phi, self._omega, self._epsilon = phi, omega, epsilon
        self.points = points
        self.joints = joints
        self._motions = dict(motions)
        self._floats = floats
        self._conditioning = conditioning
        self._valid = valid
        self._conditioning_arrays: dict[str, Any] | None = None
        self._forces = forces  # solver.forces.ForceResult, for a scene with bodies, gravity or loads

    # -- forces (solver.forces, docs/forces.md) --------------------------------------------------
    def _force_result(self) -> Any:
        if self._forces is None:
            raise SolverError("this scene names no bodies, gravity or loads: it has no efforts or reactions")
        return self._forces

    def effort(self, joint: str) -> Any:
        """The effort of input ``joint``: the torque (N·m, about +z) its actuator applies to the
        crank; (N,) for a sweep, a float for one instant. NaN where ``singular``."""
        return self._force_result().effort(joint)

    def reaction(self, point: str, *, on: str, by: str | None = None) -> np.ndarray:
        """The force (N) on body ``on`` at pin ``point`` from the other body there (``by`` when three
        meet): (N, 2), or (2,) for one instant. Third law: ``reaction(P, on=Y) == -reaction(P, on=X)``."""
        return self._force_result().reaction(point, on=on, by=by)  # type: ignore[no-any-return]

    def slide_reaction(self, body: str) -> Any:
        """The whole reaction of slider block ``body``'s prismatic pair: ``.force`` (normal to the
        guide, on the block, at its pin) and ``.couple`` (N·m about +z), from ``.guide``."""
        return self._force_result().slide_reaction(body)

    #: the same as :meth:`slide_reaction`
    slide = slide_reaction

    # -- friction (solver.forces.friction, docs/forces.md#friction) -------------------------------
    def ideal_effort(self, joint: str) -> Any:
        """The effort of input ``joint`` without the scene's friction (Q₀)."""
        return self._force_result().ideal_effort(joint)

    def friction_loss(self, name: str) -> Any:
        """The power (W) friction dissipates at pin point / slider block / actuator ``name``."""
        return self._force_result().friction_loss(name)

    @property
    def friction_power(self) -> Any:
        """The power (W) all friction dissipates."""
        return self._force_result().friction_power

    @property
    def input_power(self) -> Any:
        """Σ Q·q̇ (W) of the inputs, friction included."""
        return self._force_result().input_power

    @property
    def efficiency(self) -> Any:
        """Instantaneous efficiency (solver.forces.result.ForceResult.efficiency)."""
        return self._force_result().efficiency

    @property
    def locked(self) -> Any:
        """True where the mechanism self-locks (friction: no finite effort drives it)."""
        return self._force_result().locked

    @property
    def locking_message(self) -> str:
        """One line naming the φ intervals where the mechanism self-locks; "" where it never does."""
        from .forces.friction import locking_message

        return locking_message(self.phi, self.locked)

    @property
    def phi(self) -> np.ndarray:
        """The input angle(s) solved at: (N,) — (N, k) with k inputs; 0-d — (k,) — for one instant."""
        if not isinstance(self._phi, np.ndarray):
            self._phi = np.array(self._phi, float)
        return self._phi

    @property
    def omega(self) -> np.ndarray:
        """ω as given, broadcast to ``phi``'s samples (rad/s, or m/s for a slide input)."""
        if not isinstance(self._omega, np.ndarray):
            self._omega = np.array(self._omega, float)
        return self._omega

    @property
    def epsilon(self) -> np.ndarray:
        """ε as given, broadcast to ``phi``'s samples."""
        if not isinstance(self._epsilon, np.ndarray):
            self._epsilon = np.array(self._epsilon, float)
        return self._epsilon

    def point(self, name: str) -> OutputMotion | InstantMotion:
        """Position, velocity and acceleration of point ``name``: (N, 2) or (N, 3) arrays
        (:class:`OutputMotion`); at one instant of a one-input scene, tuples of floats
        (:class:`InstantMotion`)."""
        if name not in self.points:
            raise SolverError(f"point '{name}' was not requested; requested points: {list(self.points)}")
        return self._output(name)

    def joint(self, name: str) -> OutputMotion | InstantMotion:
        """Coordinate, velocity and acceleration of joint ``name`` (rad or m): (N,) arrays
        (:class:`OutputMotion`); at one instant of a one-input scene, floats (:class:`InstantMotion`)."""
        if name not in self.joints:
            raise SolverError(f"joint '{name}' was not requested; requested joints: {list(self.joints)}")
        return self._output(name)

    def derivatives(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        """``(jacobian, hessian)`` of output ``name`` in the inputs — what an :class:`OutputMotion`'s
        ``.jacobian`` and ``.hessian`` give, also for one instant of a one-input scene (whose
        :class:`InstantMotion` has floats only): (dim, 1) and (dim, 1, 1) there, the analogs."""
        if name not in self.points and name not in self.joints:
            raise SolverError(f"'{name}' was not requested; requested: {[*self.points, *self.joints]}")
        if self._derivatives is None:
            raise SolverError(f"'{name}': this result carries no derivatives in the inputs")
        return self._derivatives.of(name)

    def _output(self, name: str) -> OutputMotion | InstantMotion:
        if self._floats is not None and (self.inputs is None or len(self.inputs) == 1) and not self._samples:
            return _new_tuple(InstantMotion, self._floats[name])  # type: ignore[no-any-return]
        m = self._motions.get(name) or self._from_floats(name)
        if type(m) is not OutputMotion:
            m = self._motions[name] = OutputMotion(m, name, self._derivatives)
        return m  # type: ignore[return-value]

    def floats(self, name: str) -> tuple[Any, Any, Any]:
        """For a scalar φ: (position, velocity, acceleration) of a point (tuples of dim floats) or a
        joint (floats) as plain Python numbers — the per-tick path, which avoids numpy entirely."""
        if self._floats is None:
            raise SolverError("floats() is for a solve at a single φ; use point() or joint() for sweeps")
        try:
            return self._floats[name]
        except KeyError:
            raise SolverError(f"'{name}' was not requested; requested: {[*self.points, *self.joints]}") from None

    def _from_floats(self, name: str) -> Motion:
        assert self._floats is not None
        m = Motion(*(np.array(x, dtype=float) for x in self._floats[name]))
        self._motions[name] = m
        return m

    @property
    def valid(self) -> np.ndarray:
        """False where a sample could not be assembled (only with ``mask=True``; else all True)."""
        if self._valid is None:
            self._valid = np.ones(self._samples, bool)
        return self._valid

    @property
    def conditioning(self) -> dict[str, Any]:
        """Per group, its dimensionless conditioning per sample: 1 well conditioned, 0 singular.

        (N,) arrays for a sweep; plain floats for a scalar φ."""
        if not self._samples:  # a scalar solve: its floats as they are
            return self._conditioning  # type: ignore[return-value]
        if self._conditioning_arrays is None:
            shape = self._samples
            self._conditioning_arrays = {
                k: np.broadcast_to(np.asarray(v, float), shape) for k, v in self._conditioning.items()
            }
        return self._conditioning_arrays

    @property
    def min_conditioning(self) -> np.ndarray:
        """The worst conditioning over all groups, per sample (1 where no group reports one)."""
        values = list(self.conditioning.values())
        return np.asarray(values).min(axis=0) if values else np.ones(self._samples)

    @property
    def singular(self) -> np.ndarray:
        """True at the samples where some group is singular (conditioning < tolerances.SINGULAR).

        Positions are exact there; the analogs are their limit along the branch where it exists,
        else NaN (see solver.singular).
        """
        from .tolerances import SINGULAR

        return self.min_conditioning < SINGULAR


class FlatFloats(Mapping[str, tuple[Any, Any, Any]]):
    """``Kinematics.floats`` read from a compiled instant's flat tuple (solver._codegen): a
    (position, velocity, acceleration) triple is made only for the output the caller asks for.
    ``index``: output name → (start in the tuple, point width, or 0 for a joint)."""

    __slots__ = ("_flat", "_index")

    def __init__(self, flat: tuple[Any, ...], index: Mapping[str, tuple[int, int]]) -> None:
        self._flat = flat
        self._index = index

    def __iter__(self) -> Iterator[str]:
        return iter(self._index)

    def __len__(self) -> int:
        return len(self._index)

    def __contains__(self, name: object) -> bool:
        return name in self._index

    def __getitem__(self, name: str) -> tuple[Any, Any, Any]:
        i, width = self._index[name]
        f = self._flat
        if width == 0:  # a joint
            return f[i], f[i + 1], f[i + 2]
        return f[i:i + width], f[i + width:i + 2 * width], f[i + 2 * width:i + 3 * width]


class InstantKinematics(Kinematics):
    """The result of one compiled instant (solver._codegen, docs/compiled.md): the flat tuple of
    the compiled function kept as it is, and everything else — conditioning, forces, arrays,
    derivatives — made from it on first read. Building one is a few attribute stores, and
    :meth:`floats` reads the tuple directly, so a caller pays only for what it touches.

    ``unit``: the compiled unit (``index``, ``size``, ``conditioning``, ``scene``); ``given``:
    (φ, ω, ε) as the caller gave them. :meth:`for_unit` also takes ``mask`` and the derivatives
    (by default the single-input analogs, computed on first use)."""

    _samples: tuple[int, ...] = ()
    _valid: np.ndarray | None = None
    _conditioning_arrays: dict[str, Any] | None = None
    _mask = False

    def __init__(self, unit: Any, flat: tuple[Any, ...], given: tuple[Any, Any, Any]) -> None:
        # (Kinematics.__init__ is not called: every attribute it sets is a store here, a class
        # default above, or made on first read below)
        self._unit = unit
        self._flat = flat
        self._phi, self._omega, self._epsilon = given
        scene = unit.scene
        self.points, self.joints, self.inputs = scene.output_points, scene.output_joints, scene.inputs

    @classmethod
    def for_unit(cls, unit: Any, flat: tuple[Any, ...], given: tuple[Any, Any, Any], *, mask: bool = False,
                 derivatives: Derivatives | None = None) -> InstantKinematics:
        k = cls(unit, flat, given)
        if mask:  # (a compiled instant is always assembled: every guard held)
            k._mask, k._valid = True, np.array(True)
        if derivatives is not None:
            k.__dict__["_derivatives"] = derivatives
        return k

    def floats(self, name: str) -> tuple[Any, Any, Any]:
        try:
            return self._unit.readers[name](self._flat)  # type: ignore[no-any-return]
        except KeyError:  # a unit of another order (no readers), or a name not requested
            return Kinematics.floats(self, name)

    def point(self, name: str) -> OutputMotion | InstantMotion:
        try:
            return _new_tuple(InstantMotion, self._unit.point_readers[name](self._flat))  # type: ignore[no-any-return]
        except KeyError:  # several inputs (arrays), or a name not requested (the error)
            return Kinematics.point(self, name)

    def joint(self, name: str) -> OutputMotion | InstantMotion:
        try:
            return _new_tuple(InstantMotion, self._unit.joint_readers[name](self._flat))  # type: ignore[no-any-return]
        except KeyError:
            return Kinematics.joint(self, name)

    point.__doc__, joint.__doc__ = Kinematics.point.__doc__, Kinematics.joint.__doc__

    floats.__doc__ = Kinematics.floats.__doc__

    @cached_property
    def _floats(self) -> FlatFloats:  # type: ignore[override]
        return FlatFloats(self._flat, self._unit.index)

    @cached_property
    def _motions(self) -> dict[str, Motion]:  # type: ignore[override]
        return {}

    @cached_property
    def _conditioning(self) -> dict[str, Any]:  # type: ignore[override]
        names = self._unit.conditioning or ()
        n = self._unit.size
        return dict(zip(names, self._flat[n:n + len(names)]))

    @cached_property
    def _forces(self) -> Any:  # type: ignore[override]
        model = self._unit.scene.forces
        if model is None:
            return None
        return ForceResult(model, self._flat[self._unit.size + len(self._unit.conditioning or ()):], None)

    @cached_property
    def _derivatives(self) -> Derivatives:  # type: ignore[override]
        scene, phi, mask = self._unit.scene, self._phi, self._mask
        return Derivatives(lambda: scene._analogs(phi, mask))
