"""Mechanisms from robot model files (issue 31): MJCF through MuJoCo's compiler, URDF through yourdfpy.

``solver.load_scene("gripper.xml", inputs=[...], keyframe=...)`` (or :func:`load_model`) reads the
file into plain data (solver.models.spatial), lays it into its plane (solver.models.planar) and
writes the equivalent group scene (solver.models.build), which loads like any scene file. The
scene's joints are the model's, under its names and in its convention (qpos from the model's
reference, signed by the axis), so the published joint states drive the same model in MuJoCo or
RViz. ``scene.model`` keeps what the scene file cannot say: the plane's frame, the file's kind.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import SceneError
from .planar import Plane, lay_out

__all__ = ["MODEL_SUFFIXES", "ModelInfo", "load_model", "model_scene_data"]

#: File suffixes read as robot models instead of scene YAML.
MODEL_SUFFIXES = (".xml", ".mjcf", ".urdf")


@dataclass(frozen=True)
class ModelInfo:
    """What an imported scene's model file says beyond the scene: the plane's frame in the
    model's world, the file, its kind and pose, and the scene data written for it."""

    file: str
    kind: str
    pose: str
    plane: Plane
    inputs: tuple[str, ...]
    data: dict[str, Any]


def _read(path: Path, keyframe: str | int | None) -> Any:
    if path.suffix.lower() == ".urdf":
        if keyframe is not None:
            raise SceneError("a URDF has no keyframes: it is read at zero joint positions", file=str(path),
                             entry="keyframe")
        from .urdf import read_urdf

        return read_urdf(path)
    from .mjcf import read_mjcf

    return read_mjcf(path, keyframe=keyframe)


def model_scene_data(path: str | os.PathLike[str], *, inputs: Sequence[str] | None = None,
                     keyframe: str | int | None = None) -> tuple[dict[str, Any], ModelInfo]:
    """The scene data (SI units) for a model file, and what the model says beyond it."""
    from .build import scene_data

    p = Path(path)
    model = _read(p, keyframe)
    lay = lay_out(model)
    data = scene_data(lay, inputs)
    used = tuple(g["joint"] for g in data["groups"] if g["type"] == "crank" and "follows" not in g)
    return data, ModelInfo(str(p), model.kind, model.pose, lay.plane, used, data)


def load_model(path: str | os.PathLike[str], *, inputs: Sequence[str] | None = None,
               keyframe: str | int | None = None) -> Any:
    """A :class:`solver.Scene` from an MJCF or URDF file (module docstring)."""
    from .._loader import parse_scene
    from ..scene import Scene

    data, info = model_scene_data(path, inputs=inputs, keyframe=keyframe)
    scene = Scene(parse_scene(data, file=str(path), default_name=Path(path).stem))
    scene.model = info  # type: ignore[attr-defined]
    return scene
