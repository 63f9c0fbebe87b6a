"""The shipped scenes with illustrative friction: each is its original plus ``friction:`` (no
drift), its frictionless self is the original to the bit, and its summary and CSV show the
friction losses and the efficiency, instantaneous and over the turn (docs/forces.md#friction)."""

from __future__ import annotations

import io

import numpy as np
import pytest
from friction_scenes import FRICTION_SCENES, scene_text, without_friction

import solver
from solver import cli, cli_inputs
from solver.forces.friction import cycle_efficiency
from solver.forces.report import force_lines

#: The motion each scene's checks are solved at: its bench's / steady running speed.
OMEGA = {"four_bar_loaded_friction": 3.0, "engine_friction": 219.6, "excavator_friction": 0.1}
#: The power balance Σ (Q − Q₀)·q̇ = Σ losses, against the input power's size (sums in another order).
ROUNDING = 1e-12


def _sweep(scene: solver.Scene) -> np.ndarray:
    if len(scene.inputs) == 1:
        return np.linspace(0.0, 2 * np.pi, 361)
    rng = np.random.default_rng(29)
    cols = [np.linspace(lo, hi, 41) for lo, hi in scene.input_ranges]  # type: ignore[misc]
    return np.stack([rng.permutation(c) for c in cols], axis=1)


@pytest.mark.parametrize("name", sorted(FRICTION_SCENES))
def test_the_scene_is_its_original_with_friction(name: str) -> None:
    original = FRICTION_SCENES[name]
    mine, theirs = scene_text(name), scene_text(original)
    assert mine["scene"] == name and mine["friction"]
    assert "Illustrative friction" in mine["provenance"] and theirs["provenance"] in mine["provenance"]
    drop = ("scene", "provenance", "friction")
    assert {k: v for k, v in mine.items() if k not in drop} == {k: v for k, v in theirs.items() if k not in drop}


@pytest.mark.parametrize("name", sorted(FRICTION_SCENES))
def test_without_its_friction_the_scene_gives_the_originals_efforts_to_the_bit(name: str) -> None:
    scene, original = solver.load_scene(name), solver.load_scene(FRICTION_SCENES[name])
    phi = _sweep(scene)
    w = OMEGA[name]
    k0 = without_friction(name).solve(phi, omega=w, epsilon=0.0)
    ko = original.solve(phi, omega=w, epsilon=0.0)
    kf = scene.solve(phi, omega=w, epsilon=0.0)
    for q in scene.inputs:
        np.testing.assert_array_equal(k0.effort(q), ko.effort(q))
        np.testing.assert_array_equal(kf.ideal_effort(q), ko.effort(q))  # Q₀ is the original's effort
        assert not np.array_equal(kf.effort(q), ko.effort(q))
    for pin in scene.pins:
        np.testing.assert_array_equal(k0.reaction(pin.point, on=pin.body), ko.reaction(pin.point, on=pin.body))
    assert not np.asarray(kf.locked).any()
    rates = np.broadcast_to(np.asarray(w, float), (len(kf.valid), len(scene.inputs)))
    gained = sum((np.asarray(kf.effort(q)) - np.asarray(ko.effort(q))) * rates[:, i]
                 for i, q in enumerate(scene.inputs))
    scale = max(np.max(np.abs(np.asarray(kf.effort(q)) * rates[:, i])) for i, q in enumerate(scene.inputs))
    assert np.max(np.abs(gained - kf.friction_power)) <= ROUNDING * scale
    assert np.all(np.asarray(kf.friction_power) > 0.0)


@pytest.mark.parametrize("name", ["four_bar_loaded_friction", "engine_friction"])
def test_the_summary_shows_the_losses_and_the_efficiency_over_the_turn(name: str) -> None:
    scene = solver.load_scene(name)
    k = scene.solve(np.linspace(0.0, 2 * np.pi, 360, endpoint=False), omega=OMEGA[name], epsilon=0.0)
    lines = force_lines(scene, k)
    losses = [line for line in lines if line.startswith("  friction: peak loss")]
    assert len(losses) == 1
    for element in [p.point for p in scene.pins] + ["piston"] * (name == "engine_friction"):
        assert f"{element} " in losses[0].split("mean", 1)[1]
    (eta,) = [line for line in lines if line.startswith("  efficiency: lowest")]
    over = cycle_efficiency(k)
    assert 0.5 < over < 1.0
    assert f"over the turn {over:.4g}" in eta


def test_the_excavators_summary_shows_each_seal_and_the_lowest_efficiency() -> None:
    scene = solver.load_scene("excavator_friction")
    k = scene.solve(_sweep(scene), omega=OMEGA["excavator_friction"], epsilon=0.0)
    lines = force_lines(scene, k)
    (losses,) = [line for line in lines if line.startswith("  friction: peak loss")]
    for seal in ("boom_cylinder 40 W", "arm_cylinder 30 W", "bucket_cylinder 20 W"):  # F·|ṡ| at ṡ = 0.1 m/s
        assert seal in losses
    eta = np.asarray(k.efficiency)
    assert np.all((eta > 0.5) & (eta < 1.0))  # every stroke extends: the inputs drive everywhere
    assert any(line.startswith(f"  efficiency: lowest {eta.min():.4g}") for line in lines)


@pytest.mark.parametrize("name", sorted(FRICTION_SCENES))
def test_the_csv_carries_each_loss_the_power_and_the_efficiency(name: str) -> None:
    scene = solver.load_scene(name)
    k = scene.solve(_sweep(scene)[:5], omega=OMEGA[name], epsilon=0.0)
    writer = cli if len(scene.inputs) == 1 else cli_inputs
    cols = writer.csv_header(scene)
    assert cols[-3:] == ["friction.power", "efficiency", "locked"]
    assert {c for c in cols if c.startswith("loss.")} >= {f"loss.{p.point}" for p in scene.pins
                                                           if ".cylinder" not in p.body}
    out = io.StringIO()
    writer.write_csv(scene, k, out)
    rows = [dict(zip(cols, map(float, row.split(",")))) for row in out.getvalue().splitlines()[1:]]
    assert [r["efficiency"] for r in rows] == [float(v) for v in k.efficiency]
    assert all(r["locked"] == 0.0 for r in rows)


@pytest.mark.parametrize("name", sorted(FRICTION_SCENES))
def test_a_friction_scene_is_not_compiled_its_original_is(name: str) -> None:
    with pytest.raises(solver.SolverError, match=rf"{name}: a scene with friction is not compiled"):
        solver.load_scene(name).compiled()
    solver.load_scene(FRICTION_SCENES[name]).compiled()


def test_one_instant_of_several_inputs_with_friction_is_the_vectorised_sample() -> None:
    """A scene with several inputs and friction at one instant takes the scalar path (it is not
    compiled): the same efforts and losses as the vectorised solve, to round-off."""
    scene = solver.load_scene("excavator_friction")
    q, w = (1.3, 1.5, 1.2), (0.1, 0.05, -0.02)
    one = scene.solve(q, omega=w, epsilon=0.0)
    many = scene.solve(np.array([q, q]), omega=np.array([w, w]), epsilon=0.0)
    for j in scene.inputs:
        assert one.effort(j) == pytest.approx(float(many.effort(j)[0]), rel=1e-13)
        assert one.effort(j) != pytest.approx(one.ideal_effort(j), rel=1e-3)
    assert one.friction_power == pytest.approx(float(many.friction_power[0]), rel=1e-13)


def test_a_relative_velocity_zero_to_rounding_takes_the_accelerations_direction() -> None:
    """four_bar_loaded's coupler and rocker turn alike at φ = 0 (the crank on the line of the fixed
    pivots): pin B's relative velocity there is a rounded zero (3e-17), whose sign must not pick
    the friction's direction (tolerances.RELATIVE_REST): φ = 0 and 2π give the same effort, the
    limit from the side the relative acceleration points to (φ → 0⁺ at ω > 0)."""
    scene = solver.load_scene("four_bar_loaded_friction")
    at = [float(scene.solve(p, omega=3.0, epsilon=0.0).effort("crank")) for p in (0.0, 2 * np.pi)]
    swept = np.asarray(scene.solve(np.array([0.0, 2 * np.pi]), omega=3.0, epsilon=0.0).effort("crank"))
    assert at[0] == pytest.approx(at[1], rel=1e-14) and swept[0] == pytest.approx(swept[1], rel=1e-14)
    right = float(scene.solve(1e-7, omega=3.0, epsilon=0.0).effort("crank"))
    left = float(scene.solve(-1e-7, omega=3.0, epsilon=0.0).effort("crank"))
    assert abs(at[0] - right) < 1e-5 * abs(at[0]) < abs(at[0] - left)  # the friction at B flips across φ = 0
