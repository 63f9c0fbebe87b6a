"""linkage-solve --csv carries a scene's forces: each input's effort, every pin's and slide's load."""

from __future__ import annotations

import io

import numpy as np
import pytest

import solver
from solver.cli import csv_header, main
from solver.cli_inputs import force_columns

PHI_DEG = (0.0, 37.0, 90.0, 200.0)


def _csv(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[list[str], np.ndarray, str]:
    assert main(list(args)) == 0
    out = capsys.readouterr()
    header = out.out.splitlines()[0].split(",")
    return header, np.loadtxt(io.StringIO(out.out), delimiter=",", skiprows=1, ndmin=2), out.err


def _column(header: list[str], table: np.ndarray, name: str) -> np.ndarray:
    return table[:, header.index(name)]


def test_four_bar_loaded_csv_has_the_crank_torque_and_every_pin_force_to_the_bit(
    capsys: pytest.CaptureFixture[str],
) -> None:
    phi = ",".join(str(p) for p in PHI_DEG)
    header, table, _ = _csv(capsys, "four_bar_loaded", "--phi", phi, "--deg", "--omega", "3", "--epsilon", "0.5",
                            "--csv", "-")
    assert header[-9:] == ["crank.effort", "pin.O.crank.fx", "pin.O.crank.fy", "pin.A.coupler.fx", "pin.A.coupler.fy",
                           "pin.C.rocker.fx", "pin.C.rocker.fy", "pin.B.coupler.fx", "pin.B.coupler.fy"]
    scene = solver.load_scene("four_bar_loaded")
    k = scene.solve(np.radians(PHI_DEG), omega=3.0, epsilon=0.5)
    np.testing.assert_array_equal(_column(header, table, "crank.effort"), k.effort("crank"))
    for pin in scene.pins:
        r = k.reaction(pin.point, on=pin.body, by=pin.other)
        np.testing.assert_array_equal(_column(header, table, f"pin.{pin.point}.{pin.body}.fx"), r[:, 0])
        np.testing.assert_array_equal(_column(header, table, f"pin.{pin.point}.{pin.body}.fy"), r[:, 1])


def test_engine_csv_has_the_pistons_guide_force_and_couple(capsys: pytest.CaptureFixture[str]) -> None:
    header, table, _ = _csv(capsys, "engine", "--phi-count", "12", "--omega", "100", "--csv", "-")
    assert header[-3:] == ["slide.B.piston.fx", "slide.B.piston.fy", "slide.B.piston.couple"]
    k = solver.load_scene("engine").solve(np.linspace(0, 2 * np.pi, 12, endpoint=False), omega=100.0)
    pair = k.slide_reaction("piston")
    np.testing.assert_array_equal(table[:, -3:-1], pair.force)
    np.testing.assert_array_equal(table[:, -1], np.broadcast_to(pair.couple, (12,)))
    np.testing.assert_array_equal(_column(header, table, "crankshaft.effort"), k.effort("crankshaft"))


def test_five_bar_grid_csv_has_one_effort_per_input_and_nan_loads_at_its_singular_sample(
    capsys: pytest.CaptureFixture[str],
) -> None:
    header, table, err = _csv(capsys, "five_bar", "--count", "2", "--omega", "q1=2", "--omega", "q2=-1.5", "--csv", "-")
    assert "q1.effort" in header and "q2.effort" in header and "pin.P.left_distal_link.fx" in header
    grid = table[:, :2]
    k = solver.load_scene("five_bar").solve(grid, omega=(2.0, -1.5))
    for q in ("q1", "q2"):
        np.testing.assert_array_equal(_column(header, table, f"{q}.effort"), k.effort(q))
    singular = np.asarray(k.singular, bool)
    assert singular.any() and np.isnan(_column(header, table, "q1.effort")[singular]).all()
    assert "derivatives, efforts and loads there are nan" in err


def test_a_scene_without_forces_keeps_its_kinematic_columns_only() -> None:
    assert force_columns(solver.load_scene("four_bar")) == []
    assert csv_header(solver.load_scene("four_bar"))[-1] == "rocker.ddq"


@pytest.mark.parametrize("name", ["four_bar_loaded", "engine", "harvester_finger", "five_bar"])
def test_force_columns_are_named_once_each(name: str) -> None:
    cols = force_columns(solver.load_scene(name))
    assert cols and len(cols) == len(set(cols))


@pytest.mark.parametrize(("phi", "said"), [("30", "peaks and RMS at the given angle)"),
                                           ("30,60,200", "peaks and RMS read off the 3 given angles)")])
def test_the_force_summary_of_given_angles_says_they_were_given(
    phi: str, said: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["four_bar_loaded", "--phi", phi, "--deg"]) == 0
    assert f"(each sample exact, {said}" in capsys.readouterr().out
