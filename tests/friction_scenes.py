"""The shipped scenes with illustrative friction and their frictionless originals (issue 29).

``four_bar_loaded_friction``, ``engine_friction`` and ``excavator_friction`` are
``four_bar_loaded``, ``engine`` and ``excavator`` with a ``friction:`` key (and their own name
and provenance): the originals, their reference tests, dynamics, benches and docs numbers stay
frictionless. :func:`without_friction` loads a scene without its ``friction:`` key, so a test
compares a friction scene with its frictionless self explicitly.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import solver
from solver._loader import parse_scene, read_yaml

__all__ = ["FRICTION_SCENES", "scene_text", "without_friction"]

#: A shipped scene with friction → the shipped scene it adds friction to.
FRICTION_SCENES = {
    "engine_friction": "engine",
    "excavator_friction": "excavator",
    "four_bar_loaded_friction": "four_bar_loaded",
}


def scene_text(name: str) -> dict[str, Any]:
    """A shipped scene's file as read (a dict)."""
    data = read_yaml(Path(solver.find_scene(name)))
    assert isinstance(data, dict)
    return data


def without_friction(name: str) -> solver.Scene:
    """The shipped scene ``name`` loaded without its ``friction:`` key (everything else as read)."""
    path = Path(solver.find_scene(name))
    data = {k: v for k, v in scene_text(name).items() if k != "friction"}
    return solver.Scene(parse_scene(data, file=str(path)))
