"""Bad actuator scenes and strokes: one SceneError line each, an AssemblyError naming the strokes in m."""

from __future__ import annotations

import copy
from typing import Any

import numpy as np
import pytest

import solver
from solver._loader import parse_scene

TIPPER: dict[str, Any] = {
    "scene": "tipper_test",
    "units": {"length": "m", "angle": "deg"},
    "fixed": {"O": [0.0, 0.0], "A": [-1.4, -0.55]},
    "groups": [
        {"type": "actuator", "name": "lift", "base": "A", "point": "C", "pivot": "O", "length": 0.8, "M": -1,
         "joint": "stroke", "stroke": [0.74, 1.30]},
        {"type": "attached", "name": "front", "point": "F", "base": "O", "along": ["O", "C"], "distance": 2.4},
    ],
    "joints": {"floor": {"angle": ["O", "F"]}},
    "outputs": {"points": ["C", "F"], "joints": ["stroke", "floor"]},
}


def build(change: Any = None, **fields: Any) -> solver.Scene:
    data = copy.deepcopy(TIPPER)
    data["groups"][0].update(fields)
    if change is not None:
        change(data)
    return solver.Scene(parse_scene(data, file="tipper_test.yaml"))


@pytest.mark.parametrize(
    ("stroke", "match"),
    [
        ([1.3, 0.74], r"groups\[0\]\.stroke: the closed length must be less than the open length, got \[1\.3, 0\.74\]"),
        ([0.9, 0.9], r"the closed length must be less than the open length"),
        ([0.0, 1.3], r"groups\[0\]\.stroke: the closed and open lengths must be positive, got \[0, 1\.3\]"),
        ([-0.5, 1.3], r"the closed and open lengths must be positive"),
        ([0.74], r"groups\[0\]\.stroke: must be \[closed, open\] lengths of the actuator"),
        (["a", 1.0], r"groups\[0\]\.stroke: must be a number"),
    ],
)
def test_a_bad_stroke_range_is_one_scene_error_line(stroke: Any, match: str) -> None:
    with pytest.raises(solver.SceneError, match=match) as exc:
        build(stroke=stroke)
    assert "\n" not in str(exc.value) and str(exc.value).startswith("tipper_test.yaml")


def test_a_pivot_that_is_not_on_a_link_is_one_scene_error_line() -> None:
    with pytest.raises(solver.SceneError, match=r"actuator 'lift': pivot 'Z' is not on a link \(no fixed point nor a "
                                                 r"point any group places\); give a fixed point or a point of a link"):
        build(pivot="Z")
    with pytest.raises(solver.SceneError, match=r"actuator 'lift': pivot 'floor' is not on a link \(a joint\)"):
        build(pivot="floor")
    with pytest.raises(solver.SceneError, match=r"groups\[0\]\.pivot: 'A' cannot be both the base, point or pivot"):
        build(pivot="A")


def test_an_actuator_also_driven_by_a_crank_is_over_determined() -> None:
    def crank_too(data: dict[str, Any]) -> None:
        data["groups"].append({"type": "crank", "name": "motor", "center": "O", "point": "C", "length": 0.8})

    with pytest.raises(solver.SceneError, match=r"'C' is defined twice: by actuator 'lift' and by crank 'motor': "
                                                 r"too many inputs \(over-determined\)"):
        build(crank_too)


def test_a_stroke_outside_its_range_is_an_assembly_error_in_metres() -> None:
    scene = build()
    with pytest.raises(solver.AssemblyError, match=r"group 'lift' is outside its stroke \[0\.74, 1\.3\] m \(closed "
                                                   r"and open lengths\); requested s = 1\.35 m$"):
        scene.solve(1.35)
    with pytest.raises(solver.AssemblyError, match=r"requested s = 0\.5 m, 1\.4 m$"):
        scene.solve(np.array([0.5, 0.9, 1.4]))
    k = scene.solve(np.array([0.5, 0.9, 1.4]), mask=True)
    assert k.valid.tolist() == [False, True, False]
    excavator = solver.load_scene("excavator")
    outside = r"group 'arm_cylinder' is outside its stroke \[1\.3, 1\.9\] m"
    samples = r" .* at 1 sample\(s\) of \(boom_stroke, arm_stroke, bucket_stroke\) = \(1\.2 m, 2 m, 1\.2 m\)"
    with pytest.raises(solver.errors.SampleAssemblyError, match=outside + samples):
        excavator.solve((1.2, 2.0, 1.2))


def test_a_stroke_that_cannot_reach_is_a_closed_form_gap_in_metres() -> None:
    """|s − l| ≤ D ≤ s + l: with D = |AO| = 1.50416 and l = 0.8, strokes below 0.70416 m cannot close."""
    scene = build(stroke=[0.5, 1.3])
    gaps = solver.assembly.gaps(scene)
    ((lo, hi),) = gaps["lift"]
    assert (lo, hi) == (0.5, pytest.approx(abs(complex(-1.4, -0.55)) - 0.8, abs=1e-15))
    gap = r"group 'lift' cannot be assembled for s in \(0\.5 m, 0\.704161 m\); requested s = 0\.6 m$"
    with pytest.raises(solver.AssemblyError, match=gap):
        scene.solve(0.6)


def test_a_continuous_branch_needs_a_crank_angle() -> None:
    def dyad(data: dict[str, Any]) -> None:
        data["fixed"]["P"] = [-3.0, 1.0]
        data["groups"].append({"type": "rrr", "name": "dy", "ends": ["F", "P"], "point": "B", "lengths": [1.0, 1.0],
                               "M": 1, "through_change_points": "continuous"})

    with pytest.raises(solver.SceneError, match=r"rrr 'dy': through_change_points: continuous follows change points "
                                                 r"in a crank angle; a scene driven by actuator 'lift' uses 'keep'"):
        build(dyad)


def test_a_mass_on_the_cylinder_is_refused() -> None:
    def heavy(data: dict[str, Any]) -> None:
        data["bodies"] = {"cyl": {"points": ["A", "C"], "mass": 30.0}}

    with pytest.raises(solver.SceneError, match=r"bodies\.cyl\.mass: .* is an actuator's cylinder, a massless "
                                                 r"two-force member"):
        build(heavy)


def test_the_cylinder_aligned_with_the_pushed_link_is_a_singular_position() -> None:
    """At s = D − l the cylinder pushes through the pivot: conditioning 0, flagged, analogs NaN
    (no limit at a range edge), and the summary names it in metres."""
    scene = build(stroke=[0.5, 1.3])
    edge = abs(complex(-1.4, -0.55)) - 0.8
    k = scene.solve(np.array([edge, edge + 1e-3]), mask=True)
    assert k.singular.tolist() == [True, False] and k.valid.all()
    assert np.isnan(k.point("C").velocity[0]).all() and np.isfinite(k.point("C").velocity[1]).all()
    assert solver.classify.toggles(scene, scene.plan.groups[0]) == {"range edges": (pytest.approx(edge, abs=1e-15),)}
    lines = solver.cli.stability_lines(scene, k)
    assert "    lift: toggles at the edges of the unassemblable range (conditioning 0) at s = 0.7042 m" in lines
