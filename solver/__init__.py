"""linkage_ros' solver: exact closed-form kinematics of linkage mechanisms from scene files.

Pure numpy + PyYAML. ``scene = load_scene(path)``; ``k = scene.solve(phi, omega=..., epsilon=...)``;
``k.point("C").position / .velocity / .acceleration``; ``k.joint("finger")...``.
"""

from __future__ import annotations

from . import dynamics  # noqa: F401  (opens Scene.simulate and Scene.reduced, docs/dynamics.md)
from . import vectors as _vectors  # noqa: F401  (registers the vector-loop scene section, seed 004)
from .errors import AssemblyError, DynamicsError, SceneError, SolverError
from .kinematics import Kinematics, Motion
from .scene import Link, Scene, find_scene, load_scene, shipped_scenes

__all__ = [
    "AssemblyError",
    "DynamicsError",
    "Kinematics",
    "Link",
    "Motion",
    "Scene",
    "SceneError",
    "SolverError",
    "find_scene",
    "load_scene",
    "shipped_scenes",
]
__version__ = "0.1.0"
