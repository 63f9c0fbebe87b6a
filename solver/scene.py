"""A mechanism loaded from a scene file, and its solve.

``load_scene`` validates the file into :class:`Scene`; the scene builds a :class:`~solver.plan.Plan`
pruned to its outputs; :meth:`Scene.solve` runs the plan on an array of crank angles (numpy) or
on one angle (plain Python scalars, for the per-tick path of the node).
"""

from __future__ import annotations

import math
import os
import sys
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from types import MethodType
from typing import Any

import numpy as np

from ._arguments import Arguments
from ._backend import NUMPY, SCALAR
from ._codegen import Compiled, layout_of
from ._inputs import check_outputs_move, input_joints
from ._loader import SceneData, parse_scene, read_yaml
from .assembly import unassemblable_intervals
from .errors import AssemblyError, SceneError, SolverError
from .forces import ForceBuffers, ForceModel, ForceResult
from .groups import Context
from .kinematics import Derivatives, InstantKinematics, Kinematics, empty_motion, fill_motion, motion_rows
from .multi import solve_multi
from .plan import Plan, build_plan, order_groups
from .singular import change_points, refine_singular

__all__ = ["Scene", "Link", "load_scene", "find_scene", "shipped_scenes", "scene_dirs", "CHUNK"]

#: Samples per block of the vectorised path: small enough that a group's temporaries stay in
#: the CPU cache, large enough that numpy's per-call overhead is amortised.
CHUNK = 1 << 13


@dataclass(frozen=True)
class Link:
    """A body to draw: a polyline through named points."""

    name: str
    points: tuple[str, ...]


def scene_dirs() -> list[Path]:
    """Where shipped scenes are looked up, in order.

    ``$LINKAGE_SCENES`` (os.pathsep-separated), the source checkout's ``config/scenes``, and
    ``share/linkage_ros/config/scenes`` under this Python's prefix and every ``$AMENT_PREFIX_PATH``
    entry (a colcon install).
    """
    dirs = [Path(p) for p in os.environ.get("LINKAGE_SCENES", "").split(os.pathsep) if p]
    dirs.append(Path(__file__).resolve().parent.parent / "config" / "scenes")
    prefixes = [sys.prefix, *os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep)]
    dirs.extend(Path(p) / "share" / "linkage_ros" / "config" / "scenes" for p in prefixes if p)
    return dirs


def shipped_scenes() -> dict[str, Path]:
    """Every shipped scene by name (``four_bar``, ``hard/parallelogram``, ...)."""
    found: dict[str, Path] = {}
    for d in scene_dirs():
        if d.is_dir():
            for p in sorted(d.rglob("*.yaml")):
                found.setdefault(p.relative_to(d).with_suffix("").as_posix(), p)
    return found


def find_scene(name_or_path: str | os.PathLike[str]) -> Path:
    """A scene file by path, or a shipped scene by name (with or without ``.yaml``)."""
    if not isinstance(name_or_path, str | os.PathLike):
        Arguments("find_scene").fail("name_or_path", name_or_path, "must be a scene's name or a path")
    path = Path(name_or_path)
    if path.is_file():
        return path
    key = path.as_posix().removesuffix(".yaml")
    shipped = shipped_scenes()
    if key in shipped:
        return shipped[key]
    if path.is_dir():
        inside = sorted(p.name for p in path.glob("*.yaml"))
        more = f" and {len(inside) - 5} more" if len(inside) > 5 else ""
        hint = f"; scene files in it: {', '.join(inside[:5])}{more}" if inside else ""
        raise SceneError(f"is a directory, not a scene file{hint}", file=str(name_or_path))
    raise SceneError(
        f"no such scene file, and no shipped scene of that name; shipped: {', '.join(sorted(shipped))}",
        file=str(name_or_path),
    )


def load_scene(name_or_path: str | os.PathLike[str], **model: Any) -> Scene:
    """Load and validate a scene file (a path, or the name of a shipped scene). An MJCF or URDF
    file (``.xml``, ``.mjcf``, ``.urdf``) is imported (solver.models, docs/models.md) with the
    keywords ``inputs=`` (model joint names) and ``keyframe=`` (MJCF)."""
    path = find_scene(name_or_path)
    if path.suffix.lower() in (".xml", ".mjcf", ".urdf"):
        return DOORS["model"](path, **model)  # type: ignore[no-any-return]
    if model:
        raise SceneError(f"{', '.join(model)}: options of a model file (MJCF, URDF), not of a scene", file=str(path))
    data = parse_scene(read_yaml(path), file=str(path), default_name=path.stem)
    return Scene(data)


#: Doors into the packages built on the scene — ``simulate`` (solver.dynamics) and ``reduced``
#: — filled when ``solver`` is imported: the scene never imports them (dependencies point one way).
DOORS: dict[str, Callable[..., Any]] = {}


class Scene:
    """A validated mechanism with a set of outputs and the plan that computes them."""

    def __init__(
        self,
        data: SceneData,
        *,
        points: Iterable[str] | None = None,
        joints: Iterable[str] | None = None,
        forces: bool = True,
    ) -> None:
        self._data = data
        self.name: str = data.name
        self.path: str | None = data.file
        self.dim: int = data.dim
        self.provenance: str = data.provenance
        #: one-line descriptions of points and joints from the scene's ``descriptions:`` (may be empty)
        self.descriptions: Mapping[str, str] = data.descriptions
        #: The input joints, in scene order (docs/inputs.md); one for a single-input scene.
        self.inputs: tuple[str, ...] = input_joints(data.groups)
        #: The driven joint whose coordinate is φ; with several inputs, the first of ``inputs``.
        self.input_joint: str = data.input_joint
        self._multi = len(self.inputs) > 1
        self._label = data.file or data.name
        self.ordered = order_groups(data.groups, data.fixed, file=data.file)
        self.output_points = tuple(data.output_points if points is None else points)
        self.output_joints = tuple(data.output_joints if joints is None else joints)
        for p in self.output_points:
            if p not in self.point_names:
                raise SceneError(
                    f"unknown point '{p}'; points: {list(self.point_names)}", file=data.file, entry="outputs"
                )
        for j in self.output_joints:
            if j not in self.joint_names:
                raise SceneError(
                    f"unknown joint '{j}'; joints: {list(self.joint_names)}", file=data.file, entry="outputs"
                )
        if points is None and joints is None:  # the declared outputs: every input must move one
            check_outputs_move(self.ordered, data.fixed, (*self.output_points, *self.output_joints), file=data.file)
        #: bodies, gravity and loads (solver.forces, docs/forces.md); None when the scene names none
        #: (``forces=False``: the kinematics alone, as if the scene named none — ``with_outputs``)
        self.forces: ForceModel | None = (
            None if data.forces is None or not forces else ForceModel(data.forces, self.inputs)
        )
        more = () if self.forces is None else self.forces.targets  # what the force layer reads
        self.plan: Plan = build_plan(self.ordered, data.fixed, (*self.output_points, *self.output_joints, *more))

    # -- what the scene is -------------------------------------------------------------------

    @cached_property
    def joint_names(self) -> tuple[str, ...]:
        return tuple(n for g in self.ordered for n in g.joints())

    @cached_property
    def joint_units(self) -> dict[str, str]:
        """The unit of every joint's coordinate: "rad" or "m"."""
        return {n: u for g in self.ordered for n, u in g.joint_units().items()}

    @cached_property
    def input_units(self) -> tuple[str, ...]:
        """Each input's unit, in the order of ``inputs``: "rad" (a crank's angle) or "m" (an
        actuator's stroke, whose rates are then m/s and m/s²)."""
        units = self.joint_units
        return tuple(units.get(j, "rad") for j in self.inputs)

    @cached_property
    def input_ranges(self) -> tuple[tuple[float, float] | None, ...]:
        """Each input's range where it has one (an actuator's stroke, m), else None (an angle)."""
        by = {g.input_joint(): g.input_range() for g in self.ordered if g.drives}
        return tuple(by.get(j) for j in self.inputs)

    @cached_property
    def point_names(self) -> tuple[str, ...]:
        joints = set(self.joint_names) | {n for g in self.ordered for n in g.hidden()}
        provided = [n for g in self.ordered for n in g.provides() if n not in joints]
        return tuple(dict.fromkeys([*self._data.fixed, *provided]))

    @cached_property
    def fixed_points(self) -> dict[str, np.ndarray]:
        return {n: _xyz(v) for n, v in self._data.fixed.items()}

    @cached_property
    def links(self) -> tuple[Link, ...]:
        return tuple(
            Link(f"{g.name}" if len(g.links()) == 1 else f"{g.name}.{i}", pts)
            for g in self.ordered
            for i, pts in enumerate(g.links())
        )

    @property
    def has_friction(self) -> bool:
        """Whether the scene names Coulomb friction (solver.forces.friction; then one instant is
        solved uncompiled, and its results have ``friction_loss``, ``efficiency`` ...)."""
        return self.forces is not None and self.forces.friction is not None

    _friction = has_friction

    @property
    def has_forces(self) -> bool:
        """True when the scene names bodies, gravity or loads: its solves give efforts and reactions."""
        return self.forces is not None

    @property
    def bodies(self) -> tuple[Any, ...]:
        """Every link as a :class:`~solver.forces.Body` (name, points, mass, centre, inertia); () without forces."""
        return () if self.forces is None else self.forces.spec.bodies

    @property
    def pins(self) -> tuple[Any, ...]:
        """Every revolute pair as a :class:`~solver.forces.Pin` (point, body, other); () without forces."""
        return () if self.forces is None else self.forces.spec.pins

    @property
    def slides(self) -> tuple[Any, ...]:
        """Every prismatic pair as a :class:`~solver.forces.Slide` (body, guide, point); () without forces."""
        return () if self.forces is None else self.forces.spec.slides

    def with_outputs(
        self,
        *,
        points: Iterable[str] | None = None,
        joints: Iterable[str] | None = None,
        forces: bool | None = None,
    ) -> Scene:
        """The same mechanism asked for other outputs (``None`` keeps the current ones).

        ``forces=False`` drops the force layer (efforts and reactions are then not evaluated: the
        kinematics alone of a scene with bodies or loads); ``True`` restores the scene's own."""
        args = Arguments("with_outputs", scene=self.name)
        points, joints = args.names("points", points, none=True), args.names("joints", joints, none=True)
        forces = None if forces is None else args.flag("forces", forces)
        return Scene(
            self._data,
            points=self.output_points if points is None else points,
            joints=self.output_joints if joints is None else joints,
            forces=self.forces is not None if forces is None else forces,
        )

    def everything(self) -> Scene:
        """The same mechanism with every point and joint as an output (for drawing)."""
        return self.with_outputs(points=self.point_names, joints=self.joint_names)

    # -- solving --------------------------------------------------------------------------------
    def solve(
        self,
        phi: Any,
        *,
        omega: Any = 1.0,
        epsilon: Any = 0.0,
        mask: bool = False,
    ) -> Kinematics:
        """Positions, velocities and accelerations of the outputs at crank angle(s) ``phi`` (rad).

        ``omega`` (rad/s) and ``epsilon`` (rad/s²) are scalars or arrays of phi's shape; with
        the defaults (1, 0) the velocities and accelerations are the analogs. A position where a
        group cannot be assembled raises :class:`~solver.errors.AssemblyError`; with
        ``mask=True`` such samples are flagged in ``Kinematics.valid`` instead.
        A scalar ``phi`` takes the per-tick path — the plan compiled into one straight-line
        function (:meth:`compiled`, docs/compiled.md), today's scalar evaluation wherever one of
        its guards trips — and returns (dim,) points and 0-d joints, read lazily; an array takes
        the vectorised path, in blocks of ``CHUNK`` samples so that the temporaries stay in cache.

        With several inputs (``len(scene.inputs) = k > 1``) ``phi`` is (N, k), or (k,) for one
        instant, and ``omega``, ``epsilon`` scalars (the same for every input), (k,) or (N, k);
        velocities are J·ω and accelerations J·ε + ωᵀ·H·ω (solver.multi, docs/inputs.md).
        Every output's ``.jacobian`` and ``.hessian`` give the exact derivatives in the inputs.
        """
        if mask is not False and mask is not True:
            mask = Arguments("solve", scene=self.name).flag("mask", mask)
        if self._multi:  # several inputs: phi (N, k) or (k,) (solver.multi, docs/inputs.md)
            return solve_multi(self, phi, omega, epsilon, mask)
        if self._friction:  # Coulomb friction is not compiled (solver.forces.friction): the scalar path
            if _is_scalar(phi) and _is_scalar(omega) and _is_scalar(epsilon):
                return self._solve_scalar(float(phi), float(omega), float(epsilon), mask, compiled=False)
        elif type(phi) is float and type(omega) is float and type(epsilon) is float:  # the per-tick call
            try:
                unit = self._instant_unit
            except AttributeError:
                unit = self.compiled()
            flat = unit.core(phi, omega, epsilon)  # None where a guard trips: today's path then
            if flat is None:
                return self._solve_scalar(phi, omega, epsilon, mask, compiled=False)
            if mask:
                return InstantKinematics.for_unit(unit, flat, (phi, omega, epsilon), mask=True)
            return InstantKinematics(unit, flat, (phi, omega, epsilon))
        if _is_scalar(phi) and _is_scalar(omega) and _is_scalar(epsilon):
            return self._solve_scalar(float(phi), float(omega), float(epsilon), mask)
        args = Arguments("solve", scene=self.name)
        phi_arr = args.numbers("phi", phi, unit=self.input_units[0])
        if phi_arr.ndim == 0:  # one instant: its rates numbers too
            for label, value in (("omega", omega), ("epsilon", epsilon)):
                if args.numbers(label, value).ndim:
                    args.fail(label, value, "must be a number where phi is one (one instant)")
            return self._solve_scalar(float(phi_arr), float(omega), float(epsilon), mask)
        if phi_arr.ndim != 1:
            raise SolverError(f"{self.name}: phi must be a float or a 1-D array, got shape {phi_arr.shape}")
        w = _per_sample(omega, phi_arr.shape, "omega", self.name)
        e = _per_sample(epsilon, phi_arr.shape, "epsilon", self.name)
        try:
            return self._solve_blocks(phi_arr, w, e, mask)
        except AssemblyError as exc:
            if mask:
                raise
            # report every failing angle of the sweep, not only those of the first block
            bad = ~self._solve_blocks(phi_arr, w, e, True).valid
            raise AssemblyError(
                group=exc.group,
                phi=phi_arr[bad].tolist(),
                intervals=exc.intervals,
                reason=exc.reason,
                scene=exc.scene,
                unit=exc.unit,
            ) from None

    def _solve_blocks(self, phi: np.ndarray, omega: Any, epsilon: Any, mask: bool) -> Kinematics:
        n = phi.shape[0]
        motions = {p: empty_motion(n, self.dim) for p in self.output_points}
        motions.update({j: empty_motion(n, None) for j in self.output_joints})
        planar = self.dim == 2
        # per output, once per solve: the arrays its rows are written to
        fills = [(p, motion_rows(motions[p], planar=planar)) for p in self.output_points]
        fills += [(j, motion_rows(motions[j], planar=False)) for j in self.output_joints]
        conditioning: dict[str, np.ndarray] = {}
        valid = np.ones(n, bool) if mask else None
        w_block, e_block = np.ndim(omega) != 0, np.ndim(epsilon) != 0
        w, e = omega, epsilon
        forces = None if self.forces is None else ForceBuffers(self.forces, n)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            for lo in range(0, max(n, 1), CHUNK):
                rows = slice(lo, min(lo + CHUNK, n))
                ctx = Context(
                    phi=phi[rows],
                    xp=NUMPY,
                    mask=mask,
                    scene=self._label,
                    find_intervals=self._intervals,
                    owner=self,
                )
                self.plan.run(ctx)
                if w_block:
                    w = omega[rows]
                if e_block:
                    e = epsilon[rows]
                values = ctx.values
                for name, targets in fills:
                    fill_motion(targets, rows, values[name], w, e)
                if forces is not None:  # from the jets just computed (solver.forces.model)
                    forces.put(rows, forces.model.evaluate(values, NUMPY, ctx.conditioning, w, e))
                for name, c in ctx.conditioning.items():
                    if name not in conditioning:
                        conditioning[name] = np.empty(n)
                    conditioning[name][rows] = c
                if valid is not None:
                    valid[rows] = ~np.broadcast_to(ctx.invalid, (rows.stop - rows.start,))
        return Kinematics(
            phi=phi,
            omega=np.broadcast_to(omega, phi.shape),
            epsilon=np.broadcast_to(epsilon, phi.shape),
            motions=motions,
            points=self.output_points,
            joints=self.output_joints,
            conditioning=conditioning,
            valid=valid,
            derivatives=Derivatives(lambda: self._analogs(phi, mask)),
            inputs=self.inputs,
            forces=None if forces is None else forces.result(valid),
        )

    def _analogs(self, phi: Any, mask: bool) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """One input: the jacobian and hessian are the analogs d/dφ and d²/dφ² reshaped,
        (N, dim, 1) and (N, dim, 1, 1) — (N, 1) and (N, 1, 1) for a joint."""
        k = self.solve(phi, mask=mask)
        out = {}
        for name in (*self.output_points, *self.output_joints):
            m = k.point(name) if name in self.output_points else k.joint(name)
            v, a = np.asarray(m.velocity, float), np.asarray(m.acceleration, float)  # (floats at one instant)
            out[name] = (v[..., None], a[..., None, None])
        return out

    def _solve_scalar(
        self, phi: float, omega: float, epsilon: float, mask: bool, *, compiled: bool = True
    ) -> Kinematics:
        if compiled:  # the compiled instant; None where a guard trips (then today's path below)
            unit = self.compiled()
            flat = unit.core(phi, omega, epsilon)
            if flat is not None:
                return InstantKinematics.for_unit(unit, flat, (phi, omega, epsilon), mask=mask)
        if not (math.isfinite(phi) and math.isfinite(omega) and math.isfinite(epsilon)):
            for label, v in (("phi", phi), ("omega", omega), ("epsilon", epsilon)):
                if not math.isfinite(v):
                    raise SolverError(f"{self.name}: {label} must be finite, got {v}")
        ctx = Context(
            phi=phi, xp=SCALAR, mask=mask, scene=self._label, find_intervals=self._intervals, owner=self
        )
        self.plan.run(ctx)
        return Kinematics(
            phi=np.array(phi),
            omega=np.array(omega),
            epsilon=np.array(epsilon),
            motions={},
            floats=_scalar_floats(ctx.values, self.output_points, self.output_joints, omega, epsilon, self.dim),
            points=self.output_points,
            joints=self.output_joints,
            conditioning=ctx.conditioning,
            valid=np.array(not ctx.invalid) if mask else None,
            derivatives=Derivatives(lambda: self._analogs(phi, mask)),
            inputs=self.inputs,
            forces=None if self.forces is None else ForceResult(
                self.forces, self.forces.evaluate(ctx.values, SCALAR, ctx.conditioning, omega, epsilon), None
            ),
        )

    def plan_for(self, names: tuple[str, ...]) -> Plan:
        """The part of this scene's plan that computes ``names`` (kept per set of names)."""
        plans = self.__dict__.setdefault("_plans_for", {})
        if names not in plans:
            plans[names] = build_plan(self.plan.groups, self.plan.fixed, names)
        return plans[names]  # type: ignore[no-any-return]

    def _intervals(self, group: str) -> list[tuple[float, float]]:
        return unassemblable_intervals(self, group)

    # -- the plan's runner's part (solver.singular): Plan.run calls these on its context's owner --
    #: a singular group's analogs replaced by their limit along the branch (or NaN, flagged)
    refine_group = staticmethod(refine_singular)

    def change_points_of(self, group: Any) -> tuple[float, ...]:
        """Where the continuous RRR branch ``group`` flips its assembly mode (solver.singular)."""
        return change_points(self, group)

    # -- one instant, compiled (solver._codegen, docs/compiled.md) -------------------------------
    def compiled(self, *, order: int = 2, derivatives: bool = False) -> Compiled:
        """The plan traced into one straight-line Python function for one instant (built on first
        use, then kept): ``.function(phi, omega, epsilon)`` — with k inputs
        ``.function(q1, …, qk, ω1, …, ωk, ε1, …, εk)`` — returns a flat tuple of floats,
        :meth:`instant_layout` first, then ``.conditioning`` (one figure per group), then the force
        layer's values (``self.forces.layout``) when the scene has bodies or loads. ``order``
        (0, 1, 2): positions only, with velocities, with accelerations. With several inputs,
        ``derivatives=True`` gives every output's Jacobian and Hessian as a function of q alone
        (``.layout``: ``P.J0 …``, ``P.H00 …``), what ``.jacobian`` and ``.hessian`` read.
        A scene with ``friction:`` is not compiled (its friction is solved iteratively): SolverError."""
        if self._friction:
            raise SolverError(f"{self.name}: a scene with friction is not compiled (its friction is solved "
                              "iteratively, solver.forces.friction): use scene.solve, which takes the scalar path")
        key = (order, derivatives)
        try:
            return self._compiled_units[key]
        except AttributeError:
            self._compiled_units: dict[tuple[int, bool], Compiled] = {}
        except KeyError:
            pass
        args = Arguments("compiled", scene=self.name)  # (a new unit only: the cached ones were checked)
        args.choice("order", order, (0, 1, 2))
        args.flag("derivatives", derivatives)
        if key == (2, False) and not self._multi:  # instant()'s own: bound in place of the method
            unit = Compiled(self, order, entry=MethodType(Scene.instant, self), bind=self._bind_instant)
            self._instant_unit = unit
        else:
            unit = Compiled(self, order, derivatives=derivatives)
        self._compiled_units[key] = unit
        return unit

    def _bind_instant(self, checked: Callable[..., tuple[Any, ...]]) -> None:
        """``self.instant`` becomes the compiled function behind the same check of its arguments
        the method makes (three floats, order 2; anything else goes to the method): one call
        frame and no look-up per tick. Rebound whenever the unit is rebuilt (a retrace)."""
        checked.__doc__ = Scene.instant.__doc__
        self.__dict__["instant"] = checked

    def compiled_source(self, *, order: int = 2, derivatives: bool = False) -> str:
        """The generated Python of :meth:`compiled`, to read (docs/compiled.md)."""
        return self.compiled(order=order, derivatives=derivatives).source

    def instant_layout(self, *, order: int = 2) -> tuple[str, ...]:
        """Names of the outputs in :meth:`instant`'s tuple, in order: per output point ``P.x, P.y``
        (``P.z``), ``P.vx …``, ``P.ax …``; per output joint ``J.q, J.dq, J.ddq`` (up to ``order``)."""
        return layout_of(self, order)

    def instant(self, phi: Any, omega: Any = 1.0, epsilon: Any = 0.0, *, order: int = 2) -> tuple[Any, ...]:
        """One instant as a flat tuple (:meth:`instant_layout`, then conditioning and forces, see
        :meth:`compiled`): the compiled path, with today's scalar path wherever a guard trips.
        With k inputs ``phi``, ``omega``, ``epsilon`` are k-tuples (a float rate: every input)."""
        if phi.__class__ is float and omega.__class__ is float and epsilon.__class__ is float and order == 2:
            try:  # the per-tick call: one look-up, one call
                return self._instant_unit.function(phi, omega, epsilon)  # type: ignore[no-any-return]
            except AttributeError:  # not built yet (or several inputs: a float φ is their error)
                pass
        f = self.compiled(order=order).function
        args = Arguments("instant", scene=self.name)
        if not self._multi:
            unit = self.input_units[0]
            return f(args.number("phi", phi, unit=unit), args.number("omega", omega, unit=f"{unit}/s"),  # type: ignore[no-any-return]
                     args.number("epsilon", epsilon, unit=f"{unit}/s²"))
        k = len(self.inputs)
        values = []
        for label, v in (("phi", phi), ("omega", omega), ("epsilon", epsilon)):
            arr = args.numbers(label, v)
            if arr.ndim == 0 and label != "phi":
                arr = np.full(k, float(arr))
            if arr.shape != (k,):
                args.fail(label, v, f"must be {k} numbers (inputs {', '.join(self.inputs)})"
                          + ("" if label == "phi" else " or one for every input"))
            values += arr.tolist()
        return f(*values)  # type: ignore[no-any-return]

    # -- dynamics (solver.dynamics, docs/dynamics.md) ---------------------------------------------
    def simulate(self, t_end: float, **options: Any) -> Any:
        """Forward dynamics from t = 0 to ``t_end`` (s): the inputs move under the scene's loads,
        motors, flywheels and dampers (or ``drive=``); returns a ``solver.dynamics.Trajectory``
        with ``t``, ``phi``, ``omega``, ``epsilon`` and ``.solve()``. Keywords: ``phi0``,
        ``omega0``, ``drive``, ``rtol``, ``atol``, ``method``, ``dt``, ``until_phi``, ``events``,
        ``on_singular``, ``max_step`` (solver.dynamics.simulate)."""
        return DOORS["simulate"](self, t_end, **options)

    def reduced(self) -> Any:
        """The equation of motion in the inputs, Q = M(q)·q̈ + h(q, q̇): a
        ``solver.dynamics.ReducedModel`` with ``mass(q)``, ``bias(q, qd)``,
        ``generalized_forces(q, qd)`` (vectorised) and ``instant(q, qd)`` (one state)."""
        return DOORS["reduced"](self)

    _COMPILED_CACHE = ("_compiled_units", "_instant_unit", "instant", "_reduced")

    def __getstate__(self) -> dict[str, Any]:
        """A scene pickles and copies without its compiled functions (generated code, bound to
        this scene): the copy builds its own on first use, with the same values."""
        return {k: v for k, v in self.__dict__.items() if k not in self._COMPILED_CACHE}

    def __repr__(self) -> str:
        return f"Scene({self.name!r}, points={self.output_points}, joints={self.output_joints})"


def _scalar_floats(
    vals: Mapping[str, Any], points: tuple[str, ...], joints: tuple[str, ...], w: float, e: float, dim: int
) -> dict[str, tuple[Any, Any, Any]]:
    """Real motion of every output at one φ as Python floats: no numpy call at all."""
    out: dict[str, tuple[Any, Any, Any]] = {}
    ww = w * w
    for p in points:
        z0, z1, z2 = vals[p]
        if dim == 2:
            v, a = z1 * w, z2 * ww + z1 * e
            out[p] = ((z0.real, z0.imag), (v.real, v.imag), (a.real, a.imag))
        elif type(z0) is tuple:  # a spatial group's scalar path gives float triples
            out[p] = (z0, tuple(x * w for x in z1), tuple(x2 * ww + x1 * e for x1, x2 in zip(z1, z2)))
        else:  # a fixed spatial point: an array, zero derivatives
            out[p] = (tuple(np.asarray(z0, float).tolist()), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    for j in joints:
        q0, q1, q2 = vals[j]
        out[j] = (float(q0), float(q1 * w), float(q2 * ww + q1 * e))
    return out


_SCALARS = (float, int, np.floating, np.integer)


def _is_scalar(x: Any) -> bool:
    return isinstance(x, _SCALARS) or (isinstance(x, np.ndarray) and x.ndim == 0)


def _per_sample(value: Any, shape: tuple[int, ...], label: str, scene: str) -> Any:
    """A finite scalar stays a float; an array must broadcast to φ's shape."""
    if value.__class__ is float and math.isfinite(value):  # the usual rate: no array made
        return value
    given = Arguments("solve", scene=scene).numbers(label, value)
    if given.ndim == 0:
        return float(given)
    try:
        arr = np.broadcast_to(given, shape)
    except ValueError as exc:
        raise SolverError(f"{scene}: {label} of shape {np.shape(value)} does not match phi's {shape}") from exc
    return arr


def _xyz(value: Any) -> np.ndarray:
    if isinstance(value, complex):
        return np.array([value.real, value.imag])
    return np.asarray(value, dtype=float)
