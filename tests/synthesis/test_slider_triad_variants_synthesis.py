"""Synthesis varies the slider triad's variants' free values as the fixed guide's (docs/synthesis.md
§ Triads): the swinging block's line in the ternary link (its angle and offset), its pivot A, the
binary links' lengths; a guide on a moving link's angle and offset. A population of designs is
solved design by design, each row equal to its own loaded scene's sweep to the bit."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from scene_builders import slider_triad_variant_cases

from solver.synthesis.population import run
from solver.synthesis.template import load_template


def _template(kind: str) -> tuple[dict, dict]:
    """The reference's first case of ``kind`` and the triad's free values around its own (|BE|,
    the guide's angle and offset)."""
    case = next(c for c in slider_triad_variant_cases() if c["kind"] == kind)
    lengths = [float(x) for x in case["lengths"]]
    angle, offset = float(case["angle"]), float(case["offset"])
    tri = {"lengths": [{"free": [0.98 * lengths[0], 1.02 * lengths[0]]}, lengths[1]],
           "guide": {"angle": {"free": [angle - 0.02, angle + 0.02]},
                     "offset": {"free": [offset - 0.01, offset + 0.01]}}}
    return case, tri


def _data(case: dict, tri: dict) -> dict:
    """The case's scene (tests/scene_builders.py's slider_triad_variant, without H) with the free
    values; the swinging block's pivot A free in x too."""
    fixed: dict[str, Any] = {"O": [float(x) for x in case["O"]], "C": [float(x) for x in case["C"]]}
    drawn = {k: [float(v) for v in case["drawn"][k]] for k in "DEF"}
    d, e = complex(*drawn["D"]), complex(*drawn["E"])
    group: dict[str, Any] = {"type": "slider_triad", "name": "tri", "ends": ["B", "C"], "points": ["D", "E", "F"],
                             "lengths": tri["lengths"], "shape": drawn, "angle": math.atan2((e - d).imag, (e - d).real),
                             "at": float(case["phi_d"]), "joint": "ternary", "slide": "s"}
    if case["kind"] == "carried":
        group["guide"] = {"on": ["O", "B"], **tri["guide"]}
    else:
        fixed["A"] = [{"free": [float(case["A"][0]) - 0.005, float(case["A"][0]) + 0.005]}, float(case["A"][1])]
        group.update(block_at="A", guide=tri["guide"])
    return {"scene": f"variant_{case['kind']}", "units": {"length": "m", "angle": "rad"}, "fixed": fixed,
            "groups": [{"type": "crank", "name": "crank", "center": "O", "point": "B", "length": float(case["r"])},
                       group],
            "outputs": {"points": ["D", "F"], "joints": ["ternary", "s"]}}


@pytest.mark.parametrize("kind", ["swing_fixed", "carried"])
def test_a_population_of_variant_designs_solves_as_each_design_s_own_scene(kind: str) -> None:
    case, tri = _template(kind)
    tpl = load_template(_data(case, tri))
    rng = np.random.default_rng(3)
    x = tpl.lo + (tpl.hi - tpl.lo) * rng.random((6, len(tpl.lo)))
    phi = float(case["phi_d"]) + np.linspace(-0.3, 0.3, 40)
    ctx = run(tpl, x, np.broadcast_to(phi, (6, phi.size)), ("D", "F", "ternary", "s"))
    invalid = np.broadcast_to(ctx.invalid, (6, phi.size))
    assert invalid.any(axis=1).sum() < 6
    for i in range(6):
        k = tpl.scene(x[i]).with_outputs(points=["D", "F"], joints=["ternary", "s"], forces=False).solve(phi, mask=True)
        np.testing.assert_array_equal(invalid[i], ~k.valid)
        good = k.valid
        for m, part in enumerate(("position", "velocity", "acceleration")):
            for joint in ("ternary", "s"):
                np.testing.assert_array_equal(ctx.values[joint][m][i][good], getattr(k.joint(joint), part)[good])
            for point in ("D", "F"):
                xy = getattr(k.point(point), part)[good]
                np.testing.assert_array_equal(ctx.values[point][m][i][good], xy[:, 0] + 1j * xy[:, 1])
