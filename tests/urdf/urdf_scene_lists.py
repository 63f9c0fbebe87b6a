"""The shipped scenes, split into those with a URDF export and those without (decided by
:func:`linkage_ros.urdf.exportable_model`; issue 8 asks that the second list be empty), and the
vector-loop scenes among them."""

from __future__ import annotations

import solver
from linkage_ros.urdf import exportable_model

__all__ = ["EXPORTABLE", "NOT_EXPORTABLE", "SHIPPED", "SINGLE_INPUT", "VECTOR_SCENES"]

SHIPPED = sorted(solver.shipped_scenes())


def _split() -> tuple[list[str], list[str]]:
    yes: list[str] = []
    no: list[str] = []
    for name in SHIPPED:
        (yes if exportable_model(solver.load_scene(name)) is not None else no).append(name)
    return yes, no


EXPORTABLE, NOT_EXPORTABLE = _split()
#: Scenes written as vector contours (seed 004), not groups.
VECTOR_SCENES = [n for n in SHIPPED if any(g.kind == "vector_input" for g in solver.load_scene(n).ordered)]
#: The exportable scenes driven by one input φ (the sweeps and engine runs of test_urdf_closure and
#: test_urdf_states); the several-input ones (the five-bar) are checked in tests/multi/test_multi_urdf.py.
SINGLE_INPUT = [n for n in EXPORTABLE if len(solver.load_scene(n).inputs) == 1]
