"""The summary's extremes are the closed form's, or said to be read off the samples; singular
positions and dead centres are named apart; rounding noise is "zero"."""

from __future__ import annotations

import math

import numpy as np
import pytest

import solver
from solver import classify
from solver.cli import main, summary
from solver.summary import Output, Sweep, summary_lines


def _block(text: str, title: str) -> str:
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(f"  {title}"))
    end = next((i for i in range(start + 1, len(lines)) if not lines[i].startswith("    ")), len(lines))
    return "\n".join(lines[start:end])


def _summary(name: str, count: int) -> str:
    scene = solver.load_scene(name)
    return summary(scene, scene.solve(np.linspace(0, 2 * np.pi, count, endpoint=False)), periodic=True)


def test_a_crank_pins_range_is_exact_between_coarse_samples() -> None:
    # 7 samples miss φ = 180°: read off them, x would end at 0.1·cos(154.3°) = -0.0901
    text = _summary("four_bar", 7)
    assert "position: x -0.1 … 0.1 m, y -0.1 … 0.1 m" in _block(text, "point A")
    assert "read off" not in text and "≈" not in text


def test_a_rockers_swing_ends_at_its_dead_centres_to_rounding() -> None:
    scene = solver.load_scene("four_bar")
    ends = scene.solve(np.array(classify.dead_centres(scene, "rocker"))).joint("rocker").position
    lo, hi = np.degrees(np.sort(ends))
    text = _summary("four_bar", 13)  # every 27.7°
    assert f"swings {lo:.2f}° … {hi:.2f}° (a range of {hi - lo:.2f}°)" in _block(text, "joint rocker")


def test_the_largest_speed_is_the_closed_forms_maximum() -> None:
    scene = solver.load_scene("four_bar").with_outputs(points=("B",), joints=())
    phi = np.linspace(0, 2 * np.pi, 2_000_001)
    speed = np.linalg.norm(scene.solve(phi).point("B").velocity, axis=1)
    i = int(np.argmax(speed))
    # the fine grid's best (within (π/1e6)²·|f''| ≈ 1e-12 of the maximum) against the summary's
    text = _summary("four_bar", 36)
    line = next(x for x in _block(text, "point B").splitlines() if "velocity" in x)
    assert f"max speed |v| = {speed[i]:.6g} m/s at φ = {math.degrees(phi[i]):.2f}°" in line


def test_extremes_that_cannot_be_refined_are_said_to_be_read_off_the_samples() -> None:
    t = np.linspace(0.0, 1.0, 11)
    q = np.sin(3 * t)
    sweep = Sweep(phi=t, t=t, joints=[Output("J", q, np.cos(t), -np.sin(t), unit="m")])
    assert summary_lines(sweep)[0] == "  extremes read off the ticks (every 0.1 s)"
    given = Sweep(phi=np.array([0.3, 0.1, 0.2]), joints=[Output("J", q[:3], q[:3], q[:3], unit="m")])
    assert summary_lines(given)[0] == "  extremes read off the samples"


def test_beside_a_gap_extremes_reach_its_exact_edges_and_rates_are_unbounded(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert main(["hard/double_rocker", "--mask"]) == 0
    out = capsys.readouterr().out
    assert "≈" not in out and "read off" not in out
    # the crank pin's leftmost x is at the gap's edge, cos φ = −0.40625: 0.1 · (−0.40625)
    assert "position: x -0.040625 … 0.1 m, y -0.1 … 0.1 m" in _block(out, "point A")
    b = _block(out, "point B")
    assert "velocity: speed |v| grows without bound toward the gap's edge at φ = 246.03°" in b
    # B's extremes against a dense sweep of the assemblable arc, edges included
    scene = solver.load_scene("hard/double_rocker")
    ((lo, hi),) = solver.assembly.gaps(scene)["dyad"]
    phi = np.concatenate([np.linspace(hi - 2 * np.pi, lo, 400_001)])
    pos = scene.solve(phi, mask=True).point("B").position
    x, y = pos[:, 0], pos[:, 1]
    assert f"x {x.min():.6g} … {x.max():.6g} m, y {y.min():.6g} … {y.max():.6g} m" in b


def test_rounding_noise_about_zero_is_zero_and_a_still_angle_is_constant() -> None:
    text = _summary("hard/parallelogram", 360)
    coupler = _block(text, "joint coupler")
    assert "position: constant 0.0000°" in coupler
    assert "velocity: zero to rounding (at most " in coupler
    assert "acceleration: zero to rounding" in _block(text, "joint rocker")
    gripper = _summary("gripper_finger", 360)
    assert "acceleration: zero to rounding" in _block(gripper, "joint finger_joint")


def test_singular_positions_and_dead_centres_are_listed_under_their_own_names() -> None:
    text = _summary("four_bar", 36)
    lines = text.splitlines()
    head = lines.index("  singular positions over the turn, a group's conditioning 0 (0 of the samples singular):")
    assert lines[head + 1] == "    none"
    dead = "  dead centres over the turn (an output joint at rest, its extreme position; not singular):"
    assert lines[head + 2] == dead
    assert lines[head + 3].startswith("    coupler: dead centre (dq/dφ = 0) at φ = 60.0000°")
    assert lines[head + 4] == "    rocker: dead centre (dq/dφ = 0) at φ = 131.8103°, 323.1301°"
    para = _summary("hard/parallelogram", 36)
    assert "dead centres" not in para
    change = "    dyad: change points (both assemblies meet; conditioning 0) at φ = 0.0000°, 180.0000°"
    assert change in para.splitlines()


def test_more_sections_are_appended_in_order() -> None:
    scene = solver.load_scene("slider_crank")
    k = scene.solve(np.linspace(0, 2 * np.pi, 36, endpoint=False))
    text = summary(scene, k, periodic=True, sections=[lambda s: [f"  forces: {len(s.phi)} samples"]])
    assert text.splitlines()[-1] == "  forces: 36 samples"


SINGLE = [n for n in sorted(solver.shipped_scenes()) if len(solver.load_scene(n).inputs) == 1
          and n != "hard/double_rocker"]


@pytest.mark.parametrize("name", SINGLE)
def test_refined_extremes_bound_the_samples_and_match_a_dense_sweep(name: str) -> None:
    from solver._extremes import extreme
    from solver.cli import _evaluator

    scene = solver.load_scene(name)
    span = scene.input_ranges[0]  # one turn, or an actuator's stroke (its ends included)
    lo, hi, periodic = (0.0, 2 * np.pi, True) if span is None else (span[0], span[1], False)
    coarse = np.linspace(lo, hi, 24, endpoint=not periodic)
    dense = np.linspace(lo, hi, 200_001)
    for p in scene.output_points:
        evaluate = _evaluator(scene, p, point=True, omega=1.0, epsilon=0.0)
        pos = evaluate(coarse)[0]
        truth = evaluate(dense)[0]
        for axis in range(pos.shape[1]):
            for largest in (True, False):
                e = extreme(pos[:, axis], largest=largest, phi=coarse, evaluate=evaluate,
                            quantity=lambda q, v, a, i=axis: q[:, i], periodic=periodic)
                sign = 1.0 if largest else -1.0
                assert e.exact
                assert sign * e.value >= sign * pos[e.sample, axis]  # never worse than the samples
                best = sign * np.max(sign * truth[:, axis])
                # the dense grid is within (π/1e5)²·|x''|/2 ≈ 1e-10·size of the true extreme
                assert abs(e.value - best) <= 1e-9 * max(1.0, abs(best)), (p, axis, largest)
