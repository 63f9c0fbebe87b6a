"""The shipped scenes split into those with a URDF export (group scenes) and those without
(vector-contour scenes), decided by :func:`linkage_ros.urdf.exportable_model`."""

from __future__ import annotations

import solver
from linkage_ros.urdf import exportable_model

__all__ = ["EXPORTABLE", "NOT_EXPORTABLE"]


def _split() -> tuple[list[str], list[str]]:
    yes: list[str] = []
    no: list[str] = []
    for name in sorted(solver.shipped_scenes()):
        (yes if exportable_model(solver.load_scene(name)) is not None else no).append(name)
    return yes, no


EXPORTABLE, NOT_EXPORTABLE = _split()
