"""Singular positions: flagged, never silently NaN; found over the turn to rounding."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scene_builders import four_bar, slider_crank, slotted

import solver
from solver import classify
from solver.assembly import unassemblable_intervals
from solver.cli import main, stability_lines

#: angles found by bisection on exact quantities, against closed forms.
ANGLE_TOL = 1e-12


def _dyad(scene: solver.Scene, name: str = "dyad"):  # type: ignore[no-untyped-def]
    return next(g for g in scene.plan.groups if g.name == name)


def test_every_result_carries_per_group_conditioning() -> None:
    k = solver.load_scene("four_bar").solve(np.linspace(0, 6, 7))
    assert set(k.conditioning) == {"dyad"}
    c = k.conditioning["dyad"]
    assert c.shape == (7,) and np.all((c > 0.0) & (c <= 1.0))
    assert not k.singular.any()


def test_toggle_at_the_edge_of_a_range_is_flagged_and_its_analogs_are_nan_not_inf() -> None:
    scene = solver.load_scene("hard/double_rocker")
    (lo, hi), = unassemblable_intervals(scene, "dyad")
    k = scene.solve(np.array([lo, hi, 1.0]))
    assert k.singular.tolist() == [True, True, False]
    assert np.isnan(k.point("B").velocity[:2]).all()  # the rocker's rate grows without bound there
    assert np.isfinite(k.point("B").position).all()
    # positions at the edge are the toggle: A, B, C collinear, stretched
    a, b = k.point("A").position[:2], k.point("B").position[:2]
    assert np.abs(np.hypot(*(b - a).T) + np.hypot(*(b - [0.4, 0.0]).T) - np.hypot(*(a - [0.4, 0.0]).T)).max() < 1e-12


def test_scalar_solve_at_an_exact_toggle_does_not_divide_by_zero() -> None:
    scene = solver.load_scene("hard/double_rocker")
    (lo, _), = unassemblable_intervals(scene, "dyad")
    k = scene.solve(lo)
    assert bool(k.singular) and np.isnan(k.point("B").velocity).all()


def test_slider_crank_touching_its_toggle_is_flagged_with_nan_analogs() -> None:
    # rod = crank, no offset: at φ = 90° the rod stands square to the guide (|n| = l); M held,
    # so the slider's rate jumps there: no limit, NaN, flagged
    scene = slider_crank(0.1, 0.1, 0.0)
    k = scene.solve(np.array([math.pi / 2, 1.0]))
    assert k.singular.tolist() == [True, False]
    assert np.isnan(k.joint("slide").velocity[0]) and np.isfinite(k.joint("slide").velocity[1])
    assert k.joint("slide").position[0] == pytest.approx(0.0, abs=1e-15)


def test_slotted_link_with_its_eyelet_almost_on_the_pivot_is_flagged() -> None:
    scene = slotted(0.2, (0.2, 0.0), 0.3)
    k = scene.solve(np.array([1e-12, 0.5]))
    assert k.singular.tolist() == [True, False]
    assert np.isnan(k.point("C").velocity[0]).all()
    with pytest.raises(solver.AssemblyError, match=r"group 'link' has its eyelet on the pivot; requested φ = 0\.0000°"):
        scene.solve(0.0)


def test_rocker_dead_centres_match_the_collinear_crank_and_coupler() -> None:
    scene = solver.load_scene("four_bar")
    # O, A, B collinear: |OB| = AB ± OA; triangle O, C, B with OC = 0.4, CB = 0.3, B below the ground
    stretched = -math.acos((0.16 + 0.25 - 0.09) / (2 * 0.4 * 0.5)) + 2 * math.pi
    folded = -math.acos((0.16 + 0.09 - 0.09) / (2 * 0.4 * 0.3)) + math.pi
    assert classify.dead_centres(scene, "rocker") == pytest.approx((folded, stretched), abs=ANGLE_TOL)


def test_slider_dead_centres_match_the_collinear_crank_and_rod() -> None:
    scene = solver.load_scene("slider_crank")
    outer = math.asin(0.01 / 0.25)
    inner = math.pi + math.asin(0.01 / 0.15)
    assert classify.dead_centres(scene, "slider") == pytest.approx((outer, inner), abs=ANGLE_TOL)


def test_a_joint_that_does_not_move_has_no_dead_centres() -> None:
    assert classify.dead_centres(solver.load_scene("hard/parallelogram"), "coupler") == ()


@pytest.mark.parametrize(
    ("dims", "kind"),
    [
        ((0.1, 0.4, 0.3, 0.4), "Grashof crank-rocker"),
        ((0.4, 0.3, 0.35, 0.1), "Grashof double-crank (drag link)"),
        ((0.3, 0.1, 0.35, 0.4), "Grashof double-rocker"),
        ((0.1, 0.4, 0.1, 0.4), "change-point four-bar"),
        ((0.1, 0.25, 0.2, 0.4), "non-Grashof triple-rocker"),
    ],
)
def test_grashof_class_of_four_bars(dims: tuple[float, float, float, float], kind: str) -> None:
    scene = four_bar(*dims)
    assert str(classify.grashof(scene, _dyad(scene))).startswith(kind)


def test_transmission_angle_range_follows_the_extremes_of_the_diagonal() -> None:
    scene = solver.load_scene("four_bar")
    lo, hi = classify.transmission_range(scene, _dyad(scene))
    # D = |C − A| from 0.3 to 0.5: cos μ = (0.16 + 0.09 − D²)/0.24
    assert (lo, hi) == pytest.approx((math.acos(0.16 / 0.24), math.pi / 2), abs=ANGLE_TOL)


def test_cli_summary_lists_singular_positions_transmission_and_grashof(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["hard/parallelogram", "--phi-count", "3600"]) == 0
    out = capsys.readouterr().out
    assert "dyad: change points (both assemblies meet; conditioning 0) at φ = 0.0000°, 180.0000°" in out
    assert "(2 of the samples singular)" in out
    assert "transmission angle of dyad (between AB and CB): 0.0000° … 180.0000°" in out
    assert "four-bar dyad: change-point four-bar" in out


def test_cli_summary_of_the_four_bar_names_its_dead_centres() -> None:
    scene = solver.load_scene("four_bar")
    text = "\n".join(stability_lines(scene, scene.solve(np.linspace(0, 1, 3))))
    assert "rocker: dead centre (dq/dφ = 0) at φ = 131.8103°, 323.1301°" in text
    assert "four-bar dyad: Grashof crank-rocker (s + l = 0.5 m < p + q = 0.7 m)" in text


def test_csv_run_notes_its_singular_samples_on_stderr(tmp_path, capsys: pytest.CaptureFixture[str]) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "p.csv"
    assert main(["hard/parallelogram", "--csv", str(out)]) == 0
    err = capsys.readouterr().err
    assert "note: singular position at φ = 0.0000°, 180.0000°" in err
    data = np.genfromtxt(out, delimiter=",", skip_header=1)
    assert data.shape == (360, 19) and np.isfinite(data).all()
