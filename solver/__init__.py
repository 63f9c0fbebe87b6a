"""linkage_ros' solver: exact closed-form kinematics of linkage mechanisms from scene files.

numpy + PyYAML, and scipy for dynamics and synthesis (imported on first use). ``scene =
load_scene(path)``; ``k = scene.solve(phi, omega=..., epsilon=...)``; ``k.point("C").position /
.velocity / .acceleration``; ``k.joint("finger")...``; ``scene.simulate(t_end, ...)``;
``solver.synthesize(template, ...)``.
"""

from __future__ import annotations

from typing import Any

from . import vectors as _vectors  # noqa: F401  (registers the vector-loop scene section, seed 004)
from .errors import ArgumentError, AssemblyError, DynamicsError, SceneError, SolverError, SynthesisError
from .kinematics import Kinematics, Motion
from .scene import DOORS, Link, Scene, find_scene, load_scene, shipped_scenes

__all__ = [
    "ArgumentError",
    "AssemblyError",
    "DynamicsError",
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


def _simulate(scene: Scene, t_end: float, **options: Any) -> Any:
    import inspect

    from ._arguments import Arguments
    from .dynamics import simulate
    from .errors import DynamicsArgumentError

    known = inspect.signature(simulate).parameters
    for name in options:
        if name not in known or name in ("scene", "t_end"):
            Arguments("simulate", scene=scene.name, error=DynamicsArgumentError).fail(
                name, options[name], "is not an option of simulate; options: " + ", ".join(
                    p for p in known if p not in ("scene", "t_end")))
    return simulate(scene, t_end, **options)


def _reduced(scene: Scene) -> Any:
    from .dynamics import reduced_model

    return reduced_model(scene)


def _model(path: Any, **options: Any) -> Scene:
    from .models import load_model

    return load_model(path, **options)  # type: ignore[no-any-return]


# Scene.simulate and Scene.reduced (docs/dynamics.md): solver.dynamics, imported on first use;
# load_scene of an MJCF or URDF file: solver.models (docs/models.md)
DOORS.update(simulate=_simulate, reduced=_reduced, model=_model)
