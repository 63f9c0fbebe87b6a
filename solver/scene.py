"""A mechanism loaded from a scene file, and its solve.

``load_scene`` validates the file into :class:`Scene`; the scene builds a :class:`~solver.plan.Plan`
pruned to its outputs; :meth:`Scene.solve` runs the plan on an array of crank angles (numpy) or
on one angle (plain Python scalars, for the per-tick path of the node).
"""

from __future__ import annotations

import math
import os
import sys
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np

from ._backend import NUMPY, SCALAR
from ._loader import SceneData, parse_scene, read_yaml
from .errors import SceneError, SolverError
from .groups import Context
from .kinematics import Kinematics
from .plan import Plan, build_plan, order_groups

__all__ = ["Scene", "Link", "load_scene", "find_scene", "shipped_scenes", "scene_dirs"]


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
    path = Path(name_or_path)
    if path.is_file():
        return path
    key = path.as_posix().removesuffix(".yaml")
    shipped = shipped_scenes()
    if key in shipped:
        return shipped[key]
    raise SceneError(
        f"no such scene file, and no shipped scene of that name; shipped: {', '.join(sorted(shipped))}",
        file=str(name_or_path),
    )


def load_scene(name_or_path: str | os.PathLike[str]) -> Scene:
    """Load and validate a scene file (a path, or the name of a shipped scene)."""
    path = find_scene(name_or_path)
    data = parse_scene(read_yaml(path), file=str(path), default_name=path.stem)
    return Scene(data)


class Scene:
    """A validated mechanism with a set of outputs and the plan that computes them."""

    def __init__(self, data: SceneData, *, points: Iterable[str] | None = None, joints: Iterable[str] | None = None) -> None:
        self._data = data
        self.ordered = order_groups(data.groups, data.fixed, file=data.file)
        self.output_points = tuple(data.output_points if points is None else points)
        self.output_joints = tuple(data.output_joints if joints is None else joints)
        for p in self.output_points:
            if p not in self.point_names:
                raise SceneError(f"unknown point '{p}'; points: {list(self.point_names)}", file=data.file, entry="outputs")
        for j in self.output_joints:
            if j not in self.joint_names:
                raise SceneError(f"unknown joint '{j}'; joints: {list(self.joint_names)}", file=data.file, entry="outputs")
        self.plan: Plan = build_plan(self.ordered, data.fixed, (*self.output_points, *self.output_joints))

    # -- what the scene is -------------------------------------------------------------------
    name = property(lambda self: self._data.name)
    path = property(lambda self: self._data.file)
    dim = property(lambda self: self._data.dim)
    provenance = property(lambda self: self._data.provenance)
    input_joint = property(lambda self: self._data.input_joint)

    @cached_property
    def joint_names(self) -> tuple[str, ...]:
        return tuple(n for g in self.ordered for n in g.joints())

    @cached_property
    def point_names(self) -> tuple[str, ...]:
        joints = set(self.joint_names)
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

    def with_outputs(self, *, points: Iterable[str] | None = None, joints: Iterable[str] | None = None) -> Scene:
        """The same mechanism asked for other outputs (``None`` keeps the current ones)."""
        return Scene(
            self._data,
            points=self.output_points if points is None else points,
            joints=self.output_joints if joints is None else joints,
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
        """
        scalar = np.ndim(phi) == 0
        phi_arr = np.asarray(phi, dtype=float)
        if phi_arr.ndim > 1:
            raise SolverError(f"phi must be a float or a 1-D array, got shape {phi_arr.shape}")
        omega_arr = np.broadcast_to(np.asarray(omega, dtype=float), phi_arr.shape)
        epsilon_arr = np.broadcast_to(np.asarray(epsilon, dtype=float), phi_arr.shape)
        for label, arr in (("phi", phi_arr), ("omega", omega_arr), ("epsilon", epsilon_arr)):
            if not np.all(np.isfinite(arr)):
                raise SolverError(f"{self.name}: {label} must be finite, got {arr[~np.isfinite(arr)][:3]}")
        ctx = Context(
            phi=float(phi_arr) if scalar else phi_arr,
            xp=SCALAR if scalar else NUMPY,
            mask=mask,
            scene=self.path or self.name,
            find_intervals=self._intervals,
        )
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            self.plan.run(ctx)
        return Kinematics(
            phi=phi_arr,
            omega=omega_arr,
            epsilon=epsilon_arr,
            values=ctx.values,
            points=self.output_points,
            joints=self.output_joints,
            conditioning=ctx.conditioning,
            valid=None if not mask else ~np.asarray(ctx.invalid, bool),
            scalar=scalar,
        )

    def assemblable(self, phi: float) -> bool:
        """Whether every group of the plan can be assembled at the single angle ``phi``."""
        ctx = Context(phi=float(phi), xp=SCALAR, mask=True)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            self.plan.run(ctx)
        return not ctx.invalid

    def _intervals(self, group: str) -> list[tuple[float, float]]:
        from .assembly import unassemblable_intervals

        return unassemblable_intervals(self, group)

    def __repr__(self) -> str:
        return f"Scene({self.name!r}, points={self.output_points}, joints={self.output_joints})"


def _xyz(value: Any) -> np.ndarray:
    if isinstance(value, complex):
        return np.array([value.real, value.imag])
    return np.asarray(value, dtype=float)


