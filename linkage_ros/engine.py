"""From a time to a solved frame: the motion law, the solver and the unassemblable policy.

``Engine(scene, motion).frame(t)`` solves one crank angle into a
:class:`~linkage_ros.frame.Frame`; ``frames(times)`` solves whole runs vectorised. Every point and
joint of the scene is solved (drawing the links needs all of them); ``published_points`` names
the points whose kinematics are published as topics and whose paths over one cycle are drawn.

Where the mechanism cannot be assembled, the engine never returns NaN. With
``on_unassemblable="stop"`` the input stops at the last valid tick (a hold segment of the motion:
φ frozen, ω = ε = 0) and every frame reports status ``"unassemblable"`` with the φ interval until
the motion is changed. With ``"reverse"`` the drive reverses where φ crosses the boundary of the
interval (or, when the interval is not known, at the last valid tick); the frame of the reversal
reports ``"unassemblable"``, the frames after it are ordinary.
"""

from __future__ import annotations

import math
import weakref
from collections.abc import Callable, Iterator, Mapping, Sequence
from types import MappingProxyType
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

import solver
from solver.errors import AssemblyError, SceneError, format_intervals
from solver.tolerances import NEAR_SINGULAR

from .forces import (
    LoadPair,
    force_layout,
    forces_row,
    frame_forces,
    frame_friction,
    friction_names,
    friction_row,
    run_forces,
    run_friction,
    sampled_loads,
)
from .frame import (
    NO_VALUES,
    STATUS_BEHIND,
    STATUS_NEAR_SINGULAR,
    STATUS_OK,
    STATUS_UNASSEMBLABLE,
    Angles,
    Frame,
    JointState,
    PointState,
    finite_sum,
    with_status,
)
from .motion import SEGMENT_HOLD, Motion, Motions

__all__ = [
    "ON_UNASSEMBLABLE",
    "Engine",
    "every_output",
    "interval_containing",
]

#: Accepted values of ``on_unassemblable``.
ON_UNASSEMBLABLE = ("stop", "reverse")

TWO_PI = 2.0 * math.pi
#: Samples of the input angle over one cycle for the drawn paths (1° apart, closed).
PATH_SAMPLES = 361
#: Ticks solved together by :meth:`Engine.frames`.
CHUNK = 4096


#: Each loaded scene's every-output copy, kept while the scene lives: a restart of the node on the
#: same scene (``phi0``, ``mode``, ...) reuses its compiled instant instead of tracing it again.
_EVERYTHING: weakref.WeakKeyDictionary[Any, Any] = weakref.WeakKeyDictionary()


def every_output(scene: Any) -> Any:
    """``scene.everything()`` (every point and joint an output), one per loaded scene."""
    try:
        return _EVERYTHING[scene]
    except (KeyError, TypeError):
        pass
    full = scene.everything()
    try:
        _EVERYTHING[scene] = full
    except TypeError:  # pragma: no cover - a scene that cannot be weakly referenced
        pass
    return full


class Engine:
    """Maps run time to solved frames of one scene under one :class:`~linkage_ros.motion.Motion`
    (:class:`~linkage_ros.motion.Motions` for a scene with several inputs).

    ``scene`` is a :class:`solver.Scene` or anything :func:`solver.load_scene` accepts (a path or
    a shipped name). ``points`` selects the published points (default: the scene's outputs).
    ``near_singular_below`` is the conditioning under which a frame is ``"near_singular"``.
    Raises :class:`solver.AssemblyError` when the motion's start angle cannot be assembled and
    :class:`solver.SceneError` for unknown point names.
    """

    def __init__(
        self,
        scene: Any,
        motion: Motion | Motions,
        *,
        points: Sequence[str] | None = None,
        on_unassemblable: str = "stop",
        near_singular_below: float = NEAR_SINGULAR,
        path_samples: int = PATH_SAMPLES,
    ) -> None:
        if not hasattr(scene, "with_outputs"):
            scene = solver.load_scene(scene)
        if on_unassemblable not in ON_UNASSEMBLABLE:
            raise ValueError(
                f"on_unassemblable must be one of {', '.join(ON_UNASSEMBLABLE)}; "
                f"got {on_unassemblable!r}"
            )
        self.scene = scene
        self.motion = motion
        self.on_unassemblable = on_unassemblable
        self.near_singular_below = float(near_singular_below)
        chosen = tuple(scene.output_points) if points is None else tuple(points)
        unknown = [p for p in chosen if p not in scene.point_names]
        if unknown:
            raise SceneError(
                f"unknown point(s) {', '.join(unknown)}; the scene defines "
                f"{', '.join(scene.point_names)}",
                file=str(getattr(scene, "path", "") or scene.name),
                entry="points",
            )
        self.published_points: tuple[str, ...] = chosen
        self.point_names: tuple[str, ...] = tuple(scene.point_names)
        self.joint_names: tuple[str, ...] = tuple(scene.joint_names)
        self._full = every_output(scene)
        #: The input joints; with several (docs/inputs.md) ``motion`` is a
        #: :class:`~linkage_ros.motion.Motions` and a frame's phi, omega, epsilon are k-tuples.
        self.inputs: tuple[str, ...] = tuple(getattr(scene, "inputs", (scene.input_joint,)))
        if (len(self.inputs) > 1) != isinstance(motion, Motions) or (
            isinstance(motion, Motions) and len(motion) != len(self.inputs)
        ):
            raise ValueError(
                f"scene '{scene.name}' has {len(self.inputs)} input(s) ({', '.join(self.inputs)}): give "
                + ("a Motion" if len(self.inputs) == 1 else f"Motions of {len(self.inputs)} laws, one per input")
            )
        phi0: Angles
        omega0: Angles
        eps0: Angles
        if isinstance(motion, Motions):
            t0, phi0, omega0, eps0 = motion.start()
        else:
            start = motion.segments[0]
            t0, phi0, omega0, eps0 = start.t0, start.phi0, start.omega0, start.epsilon
        #: Whether frames carry efforts and loads (the scene has bodies, gravity or loads), the
        #: loads they carry, and each input's effort unit (N·m or N).
        self.forces: bool
        self.load_pairs: tuple[LoadPair, ...]
        self.effort_units: dict[str, str]
        self.forces, self.load_pairs, self.effort_units = force_layout(scene, self.inputs)
        #: The entries of ``frame.friction`` (``total``, then each element; empty without friction).
        self.friction_names: tuple[str, ...] = friction_names(scene)
        self._event_message = ""
        first = self._tick(t0, phi0, omega0, eps0)
        if not isinstance(first, Frame):
            raise first
        self._last_valid_t = t0
        self.paths: dict[str, NDArray[np.float64]] = self._paths(phi0, path_samples)
        #: The loads' (Fx, Fy) over the cycle the paths are drawn for, at the starting motion
        #: (what the markers' arrow scale is chosen from); empty without forces.
        self.load_samples: dict[str, NDArray[np.float64]] = self._load_samples(phi0, path_samples)

    # ------------------------------------------------------------------ one tick
    def frame(self, t: float) -> Frame:
        """The frame at run time ``t`` (s). Adds a hold or reverse segment where needed."""
        t = float(t)
        phi, omega, eps = self.motion.state(t)
        result = self._tick(t, phi, omega, eps)
        if isinstance(result, Frame):
            if result.status != STATUS_UNASSEMBLABLE and t >= self._last_valid_t:
                self._last_valid_t = t
            return result
        return self._unassemblable(t, phi, omega, result)

    def frame_at(self, phi: float | tuple[float, ...], omega: float | tuple[float, ...],
                 epsilon: float | tuple[float, ...], *, t: float = 0.0) -> Frame | AssemblyError:
        """The frame at an input state given from outside (topic mode, :mod:`linkage_ros.relay`),
        not from the motion law: no hold or reverse; where the mechanism cannot be assembled (or
        the solve is not finite) the :class:`solver.AssemblyError` is returned, not raised.
        With several inputs ``phi``, ``omega``, ``epsilon`` are k-tuples."""
        if isinstance(phi, tuple):
            return self._tick(float(t), phi, omega, epsilon, holding=False)
        return self._tick(float(t), float(phi), float(omega), float(epsilon), holding=False)  # type: ignore[arg-type]

    def mark_valid(self, t: float) -> None:
        """Note an ordinary frame at ``t`` solved outside :meth:`frame` (the node's fast path,
        :mod:`linkage_ros.instant`): where a later stop holds the input."""
        if t >= self._last_valid_t:
            self._last_valid_t = t

    def _tick(
        self, t: float, phi: Angles, omega: Angles, eps: Angles, *, holding: bool | None = None
    ) -> Frame | AssemblyError:
        """One solve at a scalar φ: the frame, or the reason it has none (``holding``: whether
        the frame is a hold of the motion; None: ask the motion)."""
        try:
            k = self._full.solve(phi, omega=omega, epsilon=eps)
        except AssemblyError as error:
            return error
        if holding is None:
            holding = self.motion.segment_at(t).tag == SEGMENT_HOLD
        frame = self._make_frame(t, phi, omega, eps, k, None, holding=holding)
        total = finite_sum(frame)
        if not math.isfinite(total):
            return _non_finite(phi, k.conditioning, self.inputs)
        return frame

    def _unassemblable(self, t: float, phi: Angles, omega: Angles, error: AssemblyError) -> Frame:
        # The φ interval and the end of it the input crossed: one input only (with several,
        # SampleAssemblyError.intervals is empty and Motions.crossing always None).
        interval: tuple[float, float] | None = None
        boundary: float | None = None
        if isinstance(phi, float) and isinstance(omega, float):
            interval = interval_containing(error.intervals, phi)
            boundary = None if interval is None else _boundary(interval, phi, omega)
        where = (
            f"φ in {format_intervals([interval])}" if interval is not None else f"φ = {_angles(phi, '.6g')} rad"
        )
        reason = f"group '{error.group}' {error.reason} for {where}"
        t_last = min(self._last_valid_t, t)
        if self.on_unassemblable == "reverse":
            candidates: list[float] = []
            if boundary is not None:
                t_cross = self.motion.crossing(boundary, t_last, t)
                if t_cross is not None:
                    candidates.append(t_cross)
            candidates.append(t_last)
            restore = _restorer(self.motion)
            for t_rev in candidates:
                restore()
                self.motion.reverse(t_rev)
                p, w, e = self.motion.state(t)
                result = self._tick(t, p, w, e)
                if isinstance(result, Frame):
                    self._event_message = f"{reason}; reversed at t = {t_rev:.6f} s"
                    self._last_valid_t = t
                    return with_status(result, STATUS_UNASSEMBLABLE, self._event_message)
            restore()
        # stop (or a reversal that found no valid state): hold at the last valid tick.
        self.motion.hold(t_last)
        p, w, e = self.motion.state(t)
        self._event_message = f"{reason}; stopped at φ = {_angles(p, '.6f')} rad"
        result = self._tick(t, p, w, e)
        if not isinstance(result, Frame):  # pragma: no cover - the held angle solved before
            raise result
        return result

    # ------------------------------------------------------------------ whole runs
    def frames(self, times: ArrayLike) -> Iterator[Frame]:
        """Frames at ``times`` (ascending, s), solved ``CHUNK`` ticks at a time.

        A generator: consume it in order and do not interleave :meth:`frame` calls.
        """
        all_times = np.asarray(times, dtype=np.float64).reshape(-1)
        for start in range(0, all_times.size, CHUNK):
            chunk = all_times[start : start + CHUNK]
            phi, omega, eps = self.motion.states(chunk)
            solved = self._solve_chunk(phi, omega, eps)
            if solved is None:
                for t in chunk:
                    yield self.frame(float(t))
                continue
            k, forces = solved
            tags = [self.motion.segment_at(t).tag for t in chunk.tolist()]
            for i, t in enumerate(chunk.tolist()):
                holding = tags[i] == SEGMENT_HOLD
                if not holding:
                    self._last_valid_t = t
                yield self._make_frame(
                    t, _row(phi, i), _row(omega, i), _row(eps, i), k, i, holding=holding, forces=forces
                )

    # ------------------------------------------------------------------ helpers
    def _solve_chunk(self, phi: NDArray[np.float64], omega: Any, eps: Any) -> tuple[Any, Any] | None:
        """Kinematics of every point and joint at many angles, and the efforts and loads
        (None without forces), or None if any is not valid."""
        try:
            k = self._full.solve(phi, omega=omega, epsilon=eps)
        except AssemblyError:
            return None
        for name in self.point_names:
            if not all(np.isfinite(x).all() for x in k.point(name)):
                return None
        for name in self.joint_names:
            if not all(np.isfinite(x).all() for x in k.joint(name)):
                return None
        if not self.forces:
            return k, None
        efforts, loads = run_forces(k, self.inputs, self.load_pairs)
        friction = run_friction(k, self.friction_names)
        if not all(np.isfinite(v).all() for v in (*efforts.values(), *loads.values(), *friction.values())):
            return None
        return k, (efforts, loads, friction)

    def _make_frame(
        self,
        t: float,
        phi: Angles,
        omega: Angles,
        eps: Angles,
        k: Any,
        i: int | None,
        *,
        holding: bool,
        forces: tuple[Mapping[str, NDArray[np.float64]], ...] | None = None,
    ) -> Frame:
        """The frame of sample ``i`` of ``k`` (``None``: a scalar solve); ``forces``: the
        efforts, loads and friction of a vectorised ``k`` (:func:`~linkage_ros.forces.run_forces`,
        :func:`~linkage_ros.forces.run_friction`)."""
        if i is None:
            # the solver's 3-tuples become the named tuples as they are (no per-field __new__)
            floats, new = k.floats, tuple.__new__
            points = {name: new(PointState, floats(name)) for name in self.point_names}
            joints = {name: new(JointState, floats(name)) for name in self.joint_names}
        else:
            points = {}
            for name in self.point_names:
                ps = k.point(name)
                points[name] = PointState(ps.position[i], ps.velocity[i], ps.acceleration[i])
            joints = {}
            for name in self.joint_names:
                js = k.joint(name)
                joints[name] = JointState(
                    float(js.position[i]), float(js.velocity[i]), float(js.acceleration[i])
                )
        efforts, loads = (NO_VALUES, NO_VALUES) if not self.forces else (
            frame_forces(k, self.inputs, self.load_pairs) if forces is None else forces_row(forces, i))
        friction = NO_VALUES if not self.friction_names else (
            frame_friction(k, self.friction_names) if forces is None else friction_row(forces[2], i))
        conditioning = 1.0
        worst = ""
        for group, values in k.conditioning.items():
            value = float(values if i is None else values[i])
            if value < conditioning:
                conditioning, worst = value, group
        if holding:  # a dynamic law (linkage_ros.dynamic) says why it holds itself
            status, message = STATUS_UNASSEMBLABLE, getattr(self.motion, "stop_message", "") or self._event_message
        elif getattr(self.motion, "behind", ""):  # a dynamic law that does not keep up with real time
            status, message = STATUS_BEHIND, self.motion.behind  # type: ignore[union-attr]
        elif conditioning < self.near_singular_below:
            status = STATUS_NEAR_SINGULAR
            message = f"group '{worst}' near singular: conditioning {conditioning:.3g}"
        else:
            status, message = STATUS_OK, ""
        return Frame(
            t=t,
            phi=phi,
            omega=omega,
            epsilon=eps,
            points=MappingProxyType(points),
            joints=MappingProxyType(joints),
            status=status,
            conditioning=conditioning,
            message=message,
            efforts=efforts,
            loads=loads,
            friction=friction,
        )

    def _paths(self, phi0: Any, samples: int) -> dict[str, NDArray[np.float64]]:
        """Each published point over one turn of the input from ``phi0``; only the assemblable
        run of angles that contains ``phi0`` (the one the mechanism can reach).

        With several inputs: along the motion laws themselves, over the time of one turn of the
        fastest input at its initial speed (a single point when no input moves)."""
        plan = self.scene.with_outputs(points=self.published_points, joints=())
        grid, _, _ = self._cycle(phi0, samples)
        k = plan.solve(grid, omega=1.0, epsilon=0.0, mask=True)
        valid = np.asarray(k.valid, dtype=bool).copy()
        positions = {p: np.asarray(k.point(p).position, dtype=np.float64) for p in self.published_points}
        for p in self.published_points:
            valid &= np.isfinite(positions[p]).all(axis=1)
        order = _reachable_run(valid)
        return {p: np.ascontiguousarray(positions[p][order]) for p in self.published_points}


    def _cycle(self, phi0: Any, samples: int) -> tuple[Any, Any, Any]:
        """(φ, ω, ε) over one turn of the input from ``phi0`` at its starting ω, ε (an actuator's
        whole stroke); with several inputs along the motion laws, over one turn of the fastest
        input at its initial speed."""
        if isinstance(self.motion, Motions):
            t0, _, omega0, _ = self.motion.start()
            fastest = max(abs(w) for w in omega0)
            span = TWO_PI / fastest if fastest > 0.0 else 0.0
            return self.motion.states(t0 + np.linspace(0.0, span, samples))
        start = self.motion.segments[0]
        stroke = getattr(self.scene, "input_ranges", (None,))[0]
        if stroke is not None:  # an actuator: its whole stroke, closed to open
            return np.linspace(stroke[0], stroke[1], samples), start.omega0, start.epsilon
        return phi0 + np.linspace(0.0, TWO_PI, samples), start.omega0, start.epsilon

    def _load_samples(self, phi0: Any, samples: int) -> dict[str, NDArray[np.float64]]:
        """(Fx, Fy) of every load over the cycle of :meth:`_cycle` (valid samples only)."""
        if not self.forces:
            return {}
        grid, omega, eps = self._cycle(phi0, samples)
        k = self._full.solve(grid, omega=omega, epsilon=eps, mask=True)
        return sampled_loads(k, self.inputs, self.load_pairs)


def _reachable_run(valid: NDArray[np.bool_]) -> NDArray[np.intp]:
    """Indices of the run of valid samples that contains sample 0, wrapping around the turn."""
    n = valid.size
    if valid.all():
        return np.arange(n)
    if not valid[0]:
        return np.arange(0)
    end = int(np.argmin(valid))  # first invalid sample
    # Samples n-1 and 0 are the same angle (the grid is closed): continue backwards from n-2.
    begin = n - 1
    while begin - 1 >= 0 and valid[begin - 1] and begin - 1 >= end:
        begin -= 1
    if begin <= n - 2 and valid[n - 2]:
        return np.concatenate([np.arange(begin, n - 1), np.arange(0, end)])
    return np.arange(0, end)


def interval_containing(
    intervals: Sequence[tuple[float, float]], phi: float
) -> tuple[float, float] | None:
    """The interval (rad, within one turn) that contains φ modulo 2π, shifted next to φ."""
    for lo, hi in intervals:
        shift = math.floor((phi - lo) / TWO_PI) * TWO_PI
        if lo + shift <= phi <= hi + shift:
            return (lo + shift, hi + shift)
    return None


def _restorer(motion: Motion | Motions) -> Callable[[], None]:
    """A function that puts ``motion`` back as it is now, after tentative reversals."""
    if isinstance(motion, Motions):
        laws = motion.snapshot()
        return lambda: motion.restore(laws)
    segments = motion.snapshot()
    return lambda: motion.restore(segments)


def _boundary(interval: tuple[float, float], phi: float, omega: float) -> float:
    """The end of ``interval`` that the input crossed to get to ``phi`` moving at ``omega``."""
    lo, hi = interval
    if omega > 0.0:
        return lo
    if omega < 0.0:
        return hi
    return lo if phi - lo < hi - phi else hi


def _non_finite(phi: Any, conditioning: Mapping[str, Any], inputs: Sequence[str]) -> AssemblyError:
    """A solve with a non-finite number: the group at its singular position (where velocities,
    and loads, are not finite, e.g. the five-bar's distal links stretched), named by the worst
    conditioning; "(all)" when no group is singular."""
    worst = min(conditioning, key=lambda g: float(conditioning[g]), default=None)
    if worst is not None and float(conditioning[worst]) < NEAR_SINGULAR:
        group, reason = worst, f"is at a singular position (conditioning {float(conditioning[worst]):.2g})"
    else:
        group, reason = "(all)", "gives non-finite values"
    if isinstance(phi, tuple):  # several inputs
        from solver.multi import SampleAssemblyError

        return SampleAssemblyError(group=group, samples=[phi], inputs=list(inputs), reason=reason)
    return AssemblyError(group=group, phi=[phi], reason=reason)


def _row(values: NDArray[np.float64], i: int) -> Any:
    """Sample ``i`` of a run's input values: a float, or a k-tuple with several inputs."""
    row = values[i]
    return float(row) if row.ndim == 0 else tuple(row.tolist())


def _angles(phi: Any, spec: str) -> str:
    """φ in a message: one number, or (q1, …, qk) with several inputs."""
    if isinstance(phi, tuple):
        return "(" + ", ".join(format(p, spec) for p in phi) + ")"
    return format(phi, spec)
