"""The force layer's API: what a scene lists, what a solve gives, and where it refuses or flags."""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from scene_builders import build

import solver
from solver.forces import Pin, Slide
from solver.forces.report import force_lines, force_section
from solver.summary import Sweep, summary_lines

FORCE_SCENES = ["four_bar_loaded", "engine", "harvester_finger", "five_bar"]


def _bare(scene: solver.Scene) -> solver.Scene:
    return scene.with_outputs(forces=False)


def _samples(scene: solver.Scene, n: int = 50) -> np.ndarray:
    if len(scene.inputs) == 1:
        return np.linspace(0.0, 2 * math.pi, n)
    return np.column_stack([np.linspace(1.2, 1.9, n), np.linspace(1.0, 2.0, n)])


def test_a_scene_lists_its_bodies_pins_and_slides_with_their_scene_names() -> None:
    four = solver.load_scene("four_bar_loaded")
    assert four.has_forces
    assert [b.name for b in four.bodies] == ["crank", "coupler", "rocker"]
    assert four.pins == (
        Pin("O", "crank", "ground"),
        Pin("A", "coupler", "crank"),
        Pin("C", "rocker", "ground"),
        Pin("B", "coupler", "rocker"),
    )
    assert four.slides == ()
    engine = solver.load_scene("engine")
    assert engine.slides == (Slide("piston", "ground", "B"),)
    assert Pin("B", "rod", "piston") in engine.pins
    finger = solver.load_scene("harvester_finger")
    assert finger.slides == (Slide("finger_link.block", "finger", "B"),)  # the eyelet slides along the finger
    assert Pin("B", "finger_link.block", "drum") in finger.pins


def test_a_scene_without_force_keys_has_none_and_says_so() -> None:
    scene = solver.load_scene("four_bar")
    assert not scene.has_forces and scene.pins == () and scene.bodies == () and scene.slides == ()
    k = scene.solve(np.linspace(0, 1, 3))
    with pytest.raises(solver.SolverError, match="this scene names no bodies, gravity or loads"):
        k.effort("crank")


def test_with_outputs_can_drop_the_force_layer_and_bring_it_back() -> None:
    scene = solver.load_scene("four_bar_loaded")
    bare = scene.with_outputs(forces=False)
    assert scene.has_forces and not bare.has_forces and bare.pins == ()
    assert bare.everything().has_forces is False  # later output sets keep the choice
    assert bare.with_outputs(forces=True).pins == scene.pins
    assert scene.everything().has_forces
    with pytest.raises(solver.SolverError, match="this scene names no bodies, gravity or loads"):
        bare.solve(0.3).effort("crank")
    k = bare.with_outputs(forces=True).solve(0.3, omega=3.0)
    assert k.effort("crank") == scene.solve(0.3, omega=3.0).effort("crank")


@pytest.mark.parametrize("name", FORCE_SCENES)
def test_forces_leave_the_kinematics_unchanged_to_the_bit(name: str) -> None:
    scene = solver.load_scene(name)
    bare = _bare(scene)
    q = _samples(scene)
    a, b = scene.solve(q, omega=3.0, epsilon=0.5), bare.solve(q, omega=3.0, epsilon=0.5)
    for p in scene.output_points:
        for attr in ("position", "velocity", "acceleration"):
            np.testing.assert_array_equal(getattr(a.point(p), attr), getattr(b.point(p), attr))
    for j in scene.output_joints:
        np.testing.assert_array_equal(a.joint(j).acceleration, b.joint(j).acceleration)


@pytest.mark.parametrize("name", FORCE_SCENES)
def test_efforts_and_reactions_have_the_shapes_of_joints_and_points(name: str) -> None:
    scene = solver.load_scene(name)
    q = _samples(scene, 7)
    k = scene.solve(q, omega=2.0, epsilon=0.3)
    for j in scene.inputs:
        assert k.effort(j).shape == (7,)
    for pin in scene.pins:
        assert k.reaction(pin.point, on=pin.body, by=pin.other).shape == (7, 2)
    for s in scene.slides:
        pair = k.slide_reaction(s.body)
        assert pair.force.shape == (7, 2) and np.shape(pair.couple) == (7,) and pair.guide == s.guide
    one = scene.solve(float(q[2]) if q.ndim == 1 else tuple(q[2]), omega=2.0, epsilon=0.3)
    for j in scene.inputs:
        assert isinstance(one.effort(j), float)
    for pin in scene.pins:
        assert one.reaction(pin.point, on=pin.body, by=pin.other).shape == (2,)


def test_a_slider_blocks_pair_reaction_is_normal_to_its_guide() -> None:
    scene = solver.load_scene("engine")
    k = scene.solve(np.linspace(0, 2 * math.pi, 90), omega=300.0)
    pair = k.slide_reaction("piston")
    assert np.abs(pair.force[:, 0]).max() <= 1e-12 * np.abs(pair.force).max()  # the guide is along x
    np.testing.assert_array_equal(pair.couple, 0.0)  # a piston without inertia, its centre at the pin
    np.testing.assert_array_equal(k.slide("piston").force, pair.force)


def test_wrong_questions_are_one_clear_solver_error() -> None:
    k = solver.load_scene("four_bar_loaded").solve(np.linspace(0, 1, 3))
    with pytest.raises(solver.SolverError, match=r"'rocker' is not an input joint; efforts are given for \['crank'\]"):
        k.effort("rocker")
    with pytest.raises(solver.SolverError, match=r"no pin at 'B' on body 'crank'; pins at B: coupler–rocker"):
        k.reaction("B", on="crank")
    with pytest.raises(solver.SolverError, match=r"'coupler' is not a slider block; blocks: \[\]"):
        k.slide_reaction("coupler")


def test_where_three_bodies_meet_by_names_the_other_side() -> None:
    scene = build(
        {
            "scene": "two_dyads_on_one_pin",
            "units": {"length": "m", "angle": "rad"},
            "fixed": {"O": [0.0, 0.0], "C": [0.4, 0.0], "D": [-0.3, 0.1]},
            "groups": [
                {"type": "crank", "name": "crank", "center": "O", "point": "A", "length": 0.1},
                {"type": "rrr", "name": "right", "ends": ["A", "C"], "point": "B", "lengths": [0.4, 0.3], "M": 1},
                {"type": "rrr", "name": "left", "ends": ["A", "D"], "point": "E", "lengths": [0.35, 0.3], "M": -1},
            ],
            "outputs": {"points": ["B", "E"]},
            "gravity": [0.0, -9.81],
            "bodies": {"r1": {"points": ["A", "B"], "mass": 1.0}, "l1": {"points": ["A", "E"], "mass": 0.5}},
        }
    )
    k = scene.solve(np.linspace(0, 1, 4))
    with pytest.raises(solver.SolverError, match=r"'crank' has 2 pins at 'A' \(with r1, l1\): say which with by="):
        k.reaction("A", on="crank")
    total = k.reaction("A", on="crank", by="r1") + k.reaction("A", on="crank", by="l1")
    np.testing.assert_array_equal(k.reaction("A", on="r1"), -k.reaction("A", on="crank", by="r1"))
    assert np.isfinite(total).all()


def _parallelogram() -> solver.Scene:
    return build(
        {
            "scene": "parallelogram_loaded",
            "units": {"length": "m", "angle": "rad"},
            "fixed": {"O": [0.0, 0.0], "C": [0.4, 0.0]},
            "groups": [
                {"type": "crank", "name": "crank", "center": "O", "point": "A", "length": 0.1},
                {"type": "rrr", "name": "dyad", "ends": ["A", "C"], "point": "B", "lengths": [0.4, 0.1], "M": 1},
            ],
            "outputs": {"points": ["B"]},
            "gravity": [0.0, -9.81],
            "bodies": {"coupler": {"points": ["A", "B"], "mass": 1.0, "center": [0.2, 0.0], "inertia": 0.01}},
        }
    )


def test_at_a_singular_position_the_unbounded_values_are_nan_and_flagged_never_a_crash() -> None:
    scene = _parallelogram()
    k = scene.solve(np.array([0.0, 0.5, math.pi]), mask=True)  # links collinear at φ = 0 and π
    assert list(k.singular) == [True, False, True]
    assert np.isnan(k.effort("crank")[[0, 2]]).all() and np.isfinite(k.effort("crank")[1])
    assert np.isnan(k.reaction("B", on="coupler")[0]).all()
    one = scene.solve(0.0)  # the per-tick path: NaN, no ZeroDivisionError
    assert math.isnan(one.effort("crank")) and bool(one.singular)


def test_unassemblable_samples_in_mask_mode_give_nan_forces() -> None:
    scene = build(
        {
            "scene": "double_rocker_loaded",
            "units": {"length": "m", "angle": "rad"},
            "fixed": {"O": [0.0, 0.0], "C": [0.4, 0.0]},
            "groups": [
                {"type": "crank", "name": "crank", "center": "O", "point": "A", "length": 0.3},
                {"type": "rrr", "name": "dyad", "ends": ["A", "C"], "point": "B", "lengths": [0.2, 0.25], "M": 1},
            ],
            "outputs": {"points": ["B"]},
            "gravity": [0.0, -9.81],
            "bodies": {"coupler": {"points": ["A", "B"], "mass": 1.0}},
        }
    )
    k = scene.solve(np.array([0.3, math.pi]), omega=1.0, mask=True)  # at π the crank is too far from C
    assert list(k.valid) == [True, False]
    assert np.isfinite(k.effort("crank")[0]) and not np.isfinite(k.effort("crank")[1])
    with pytest.raises(solver.AssemblyError):
        scene.solve(math.pi)


def test_a_table_of_an_angle_is_read_in_the_turn_it_starts() -> None:
    def scene(at: list[float]) -> solver.Scene:
        return build(
            {
                "scene": "angle_table",
                "units": {"length": "m", "angle": "deg"},
                "fixed": {"O": [0.0, 0.0], "C": [0.4, 0.0]},
                "groups": [
                    {"type": "crank", "name": "crank", "center": "O", "point": "A", "length": 0.1},
                    {"type": "rrr", "name": "dyad", "ends": ["A", "C"], "point": "B", "lengths": [0.4, 0.3], "M": 1},
                ],
                "outputs": {"points": ["B"]},
                "loads": [
                    {
                        "body": "dyad.2",
                        "point": "B",
                        "direction": [0.0, 1.0],
                        "table": {"of": "crank", "at": at, "force": [0.0, 100.0, 0.0]},
                    }
                ],
            }
        )

    phi = np.radians([200.0, 270.0, 330.0, 560.0])
    a = scene([-180.0, -90.0, 180.0]).solve(phi)  # the same law over (−180°, 180°] and [180°, 540°)
    b = scene([180.0, 270.0, 540.0]).solve(phi)
    np.testing.assert_allclose(a.effort("crank"), b.effort("crank"), rtol=1e-12, atol=1e-12)


def test_the_summary_gives_peaks_and_rms_read_off_the_samples_with_the_step() -> None:
    scene = solver.load_scene("four_bar_loaded")
    phi = np.linspace(0.0, 2 * math.pi, 360, endpoint=False)
    k = scene.solve(phi, omega=3.0)
    lines = force_lines(scene, k)
    assert lines[0] == ("forces (SI), at ω = 3 rad/s, ε = 0 rad/s², with the bodies' inertia "
                        "(each sample exact, peaks and RMS read off 360 samples, step 1°)")
    effort = k.effort("crank")
    j = int(np.argmax(np.abs(effort)))
    at = f"{math.degrees(phi[j]):.2f}°"
    assert lines[1].startswith(f"  effort crank: peak |Q| = {abs(effort[j]):.6g} N·m at φ = {at}")
    assert f"RMS {math.sqrt(np.mean(effort**2)):.6g} N·m" in lines[1]
    assert lines[2].startswith("  input power Σ Q·ω: peak |P| = ")
    assert [line.split(":")[0] for line in lines[3:]] == [f"  pin {p.point} ({p.body}–{p.other})" for p in scene.pins]
    text = summary_lines(Sweep(phi=phi, inputs=scene.inputs), sections=[force_section(scene, k)])
    assert lines[0] in text
    assert force_lines(solver.load_scene("four_bar"), solver.load_scene("four_bar").solve(phi)) == []


def test_the_force_block_says_at_which_motion_and_leaves_out_the_power_at_the_default_speed() -> None:
    """linkage-solve without --omega solves at 1 rad/s: the block says so, says how to ask for
    statics or an operating speed, and does not repeat the effort as a power in W (issue 24)."""
    scene = solver.load_scene("four_bar_loaded")
    phi = np.linspace(0.0, 2 * math.pi, 36, endpoint=False)
    lines = force_lines(scene, scene.solve(phi), default_speed=True)
    assert lines[0].startswith("forces (SI), at ω = 1 rad/s, ε = 0 rad/s², with the bodies' inertia (")
    assert "--omega 0 for statics" in lines[1]
    assert not any("input power" in line for line in lines)
    ramp = scene.solve(phi, omega=np.linspace(1.0, 2.0, 36), epsilon=0.5)
    assert force_lines(scene, ramp)[0].startswith("forces (SI), at each sample's ω and ε, with the bodies' inertia")
    data = yaml.safe_load((Path(solver.__file__).parents[1] / "config/scenes/four_bar_loaded.yaml").read_text())
    data["bodies"] = {name: {"points": body["points"]} for name, body in data["bodies"].items()}  # no mass
    massless = build(data)
    assert force_lines(massless, massless.solve(phi), default_speed=True)[:2] == [
        "forces (SI), the same at every speed: no body has mass or inertia (each sample exact, peaks and RMS "
        "read off 36 samples, step 10°)",
        massless_effort_line(massless, phi)]


def massless_effort_line(scene: solver.Scene, phi: np.ndarray) -> str:
    return next(x for x in force_lines(scene, scene.solve(phi, omega=7.0)) if x.startswith("  effort "))


def test_a_slide_line_says_how_often_the_block_changes_side_and_leaves_out_a_couple_that_is_zero() -> None:
    scene = solver.load_scene("engine")
    phi = np.linspace(0.0, 2 * math.pi, 360, endpoint=False)
    k = scene.solve(phi, omega=100.0)
    line = next(x for x in force_lines(scene, k) if x.startswith("  slide "))
    assert "couple" not in line  # the piston's load acts at its pin: the couple is 0 at every sample
    # the count, read here off the guide's normal force (y: the cylinder is along x), the turn closed
    normal = np.sign(np.asarray(k.slide_reaction("piston").force)[:, 1])
    normal = normal[normal != 0.0]
    changes = int(np.count_nonzero(normal != np.roll(normal, 1)))
    assert changes >= 2 and changes % 2 == 0  # a closed turn: as many changes there as back
    assert re.search(r"peak normal force [\d.]+ N at φ = [\d.]+°, RMS [\d.]+ N; changes the side of the guide "
                     rf"it presses on {changes} times a turn$", line), line
    part = scene.solve(np.radians([10.0, 20.0, 30.0]), omega=100.0)
    line = next(x for x in force_lines(scene, part) if x.startswith("  slide "))
    assert line.endswith("; presses on one side of the guide throughout")


def test_the_input_power_at_rest_is_said_to_be_zero_and_a_tiny_one_is_not() -> None:
    scene = solver.load_scene("four_bar_loaded")
    phi = np.linspace(0.0, 2 * math.pi, 36, endpoint=False)
    assert "  input power Σ Q·ω: zero" in force_lines(scene, scene.solve(phi, omega=0.0))
    lines = force_lines(scene, scene.solve(phi, omega=1e-300))  # |P| ~ 1e-300 W: tiny, not rounding
    assert any(line.startswith("  input power Σ Q·ω: peak |P| = ") for line in lines)


def test_a_runs_summary_says_when_each_peak_happens_as_well_as_where() -> None:
    scene = solver.load_scene("five_bar")
    q = np.column_stack([np.linspace(1.2, 1.9, 5), np.linspace(1.0, 2.0, 5)])
    times = np.linspace(0.0, 0.04, 5)
    lines = force_lines(scene, scene.solve(q), sampling="read off 5 ticks, every 0.01 s", times=times)
    j = int(np.argmax(np.abs(scene.solve(q).effort("q1"))))
    assert lines[1].startswith("  effort q1: peak |Q| = ")
    angles = f"q1 = {math.degrees(q[j, 0]):.2f}°, q2 = {math.degrees(q[j, 1]):.2f}°"
    assert f" at t = {times[j]:.6g} s ({angles})" in lines[1]


def test_the_summary_counts_singular_samples_and_leaves_them_out() -> None:
    scene = _parallelogram()
    k = scene.solve(np.linspace(0.0, 2 * math.pi, 8, endpoint=False), mask=True)
    lines = force_lines(scene, k)
    assert lines[1] == "  2 singular sample(s) left out (unbounded loads: k.singular)"


def _pin_names(scene: Any) -> list[str]:
    return [p.point for p in scene.pins]


def test_an_attached_point_joins_the_link_that_carries_it() -> None:
    scene = solver.load_scene("gripper_finger")
    assert not scene.has_forces
    data = {
        "scene": "tip_loaded",
        "units": {"length": "m", "angle": "deg"},
        "fixed": {"O": [0.0, 0.0], "C": [0.045, 0.0]},
        "groups": [
            {"type": "crank", "name": "proximal", "center": "O", "point": "A", "length": 0.015},
            {"type": "rrr", "name": "linkage", "ends": ["A", "C"], "point": "B", "lengths": [0.05, 0.04], "M": -1},
            {
                "type": "attached",
                "name": "tip",
                "point": "T",
                "base": "A",
                "along": ["A", "B"],
                "distance": 0.07,
                "angle": 15,
            },
        ],
        "outputs": {"points": ["T"]},
        "bodies": {"distal": {"points": ["A", "B", "T"], "mass": 0.05}},
        "loads": [{"body": "distal", "point": "T", "force": [-4.0, -1.5]}],
    }
    loaded = build(data)
    assert _pin_names(loaded) == ["O", "A", "C", "B"]
    assert [b.points for b in loaded.bodies if b.name == "distal"] == [("A", "B", "T")]
    k = loaded.solve(np.linspace(0, 1, 5), omega=0.0)
    jac = build({**data, "bodies": {}, "loads": []}).with_outputs(points=["T"]).solve(np.linspace(0, 1, 5))
    assert jac.point("T").velocity.shape == (5, 2)
    assert np.isfinite(k.effort("proximal")).all()
