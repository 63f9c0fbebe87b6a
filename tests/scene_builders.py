"""Scenes built from dicts for the stability and property tests (no files)."""

from __future__ import annotations

from typing import Any

import solver
from solver._loader import parse_scene

__all__ = ["four_bar", "slider_crank", "slotted", "build"]


def build(data: dict[str, Any]) -> solver.Scene:
    return solver.Scene(parse_scene(data, file=None))


def four_bar(
    crank: float, coupler: float, rocker: float, ground: float, *, mode: int = 1, through: str | None = None
) -> solver.Scene:
    """Crank OA about O = (0, 0), RRR dyad A–B–C with C = (ground, 0)."""
    dyad: dict[str, Any] = {
        "type": "rrr", "name": "dyad", "ends": ["A", "C"], "point": "B", "lengths": [coupler, rocker], "M": mode,
    }
    if through is not None:
        dyad["through_change_points"] = through
    return build({
        "scene": "four_bar_test",
        "units": {"length": "m", "angle": "rad"},
        "fixed": {"O": [0.0, 0.0], "C": [ground, 0.0]},
        "groups": [{"type": "crank", "name": "crank", "center": "O", "point": "A", "length": crank}, dyad],
        "joints": {"coupler": {"angle": ["A", "B"]}, "rocker": {"angle": ["C", "B"]}},
        "outputs": {"points": ["A", "B"], "joints": ["coupler", "rocker"]},
    })


def slider_crank(crank: float, rod: float, offset: float, *, mode: int = 1, angle: float = 0.0) -> solver.Scene:
    return build({
        "scene": "slider_crank_test",
        "units": {"length": "m", "angle": "rad"},
        "fixed": {"O": [0.0, 0.0]},
        "groups": [
            {"type": "crank", "name": "crank", "center": "O", "point": "A", "length": crank},
            {"type": "rrp", "name": "rod", "end": "A", "point": "B", "length": rod,
             "guide": {"through": "O", "angle": angle, "offset": offset}, "M": mode, "joint": "slide"},
        ],
        "outputs": {"points": ["A", "B"], "joints": ["slide"]},
    })


def slotted(crank: float, pivot: tuple[float, float], tip: float) -> solver.Scene:
    return build({
        "scene": "slotted_test",
        "units": {"length": "m", "angle": "rad"},
        "fixed": {"O": [0.0, 0.0], "P": list(pivot)},
        "groups": [
            {"type": "crank", "name": "drum", "center": "O", "point": "B", "length": crank},
            {"type": "slotted", "name": "link", "pivot": "P", "through": "B", "points": {"C": tip}},
        ],
        "joints": {"finger": {"angle": ["P", "C"]}},
        "outputs": {"points": ["B", "C"], "joints": ["finger"]},
    })
