"""linkage_ros' solver: exact closed-form kinematics of linkage mechanisms from scene files.

Pure numpy + PyYAML. ``scene = load_scene(path)``; ``k = scene.solve(phi, omega=..., epsilon=...)``;
``k.point("C").position / .velocity / .acceleration``; ``k.joint("finger")...``.
"""

from __future__ import annotations

from typing import Any

from . import vectors as _vectors  # noqa: F401  (registers the vector-loop scene section, seed 004)
from .errors import AssemblyError, SceneError, SolverError, SynthesisError
from .kinematics import Kinematics, Motion
from .scene import Link, Scene, find_scene, load_scene, shipped_scenes

__all__ = [
    "AssemblyError",
    "Kinematics",
    "Link",
    "Motion",
    "Scene",
    "SceneError",
    "SolverError",
    "SynthesisError",
    "find_scene",
    "load_scene",
    "shipped_scenes",
    "synthesize",
]
__version__ = "0.1.0"


def synthesize(template: Any, **task: Any) -> Any:
    """Path, function or motion generation from a template scene: ``solver.synthesis.synthesize``
    (docs/synthesis.md); imported on first use, so that ``import solver`` does not load scipy."""
    from .synthesis import synthesize as run

    return run(template, **task)
