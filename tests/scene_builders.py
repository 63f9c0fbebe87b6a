"""Scenes built from dicts for the stability and property tests (no files)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

import solver
from solver._loader import parse_scene

__all__ = ["four_bar", "slider_crank", "slotted", "build", "slider_triad_variant", "slider_triad_variant_cases"]


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


#: The slider triad variants' 50-digit reference (tests/reference/slider_triad_variants_mp.py).
SLIDER_TRIAD_VARIANTS = Path(__file__).resolve().parent / "data" / "reference_slider_triad_variants.json"


def slider_triad_variant_cases() -> list[dict]:
    return json.loads(SLIDER_TRIAD_VARIANTS.read_text())["cases"]  # type: ignore[no-any-return]


def slider_triad_variant(case: dict, *, angle: float | None = None, at: float | None = None) -> Any:
    """The reference's scene (module docstring of tests/reference/slider_triad_variants_mp.py)
    from its stored doubles."""
    kind = case["kind"]
    fixed: dict[str, Any] = {"O": [float(x) for x in case["O"]], "C": [float(x) for x in case["C"]]}
    drawn = {k: complex(float(case["drawn"][k][0]), float(case["drawn"][k][1])) for k in "DEF"}
    tri: dict[str, Any] = {
        "type": "slider_triad", "name": "tri", "ends": ["B", "C"], "points": ["D", "E", "F"],
        "lengths": [float(x) for x in case["lengths"]], "shape": {k: [z.real, z.imag] for k, z in drawn.items()},
        "angle": float(np.angle(drawn["E"] - drawn["D"])) if angle is None else angle,
        "at": float(case["phi_d"]) if at is None else at, "joint": "ternary", "slide": "s"}
    guide = {"angle": float(case["angle"]), "offset": float(case["offset"])}
    if kind == "swing_fixed":
        fixed["A"] = [float(x) for x in case["A"]]
        tri.update(block_at="A", guide=guide)
    elif kind == "swing_moving":
        tri.update(block_at="H", guide=guide)
    else:
        tri["guide"] = {"on": ["O", "B"], **guide}
    return build({
        "scene": "slider_triad_variant_ref", "units": {"length": "m", "angle": "rad"}, "fixed": fixed,
        "groups": [{"type": "crank", "name": "crank", "center": "O", "point": "B", "length": float(case["r"])},
                   {"type": "attached", "name": "h", "point": "H", "base": "O", "along": ["O", "B"],
                    "distance": float(case["rho_h"]), "angle": float(case["beta_h"])},
                   tri],
        "outputs": {"points": ["D", "E", "F"], "joints": ["ternary", "s"]},
    })
