"""linkage-solve as a user runs it."""

from __future__ import annotations

import io
import subprocess
import sys

import numpy as np
import pytest

import solver
from solver.cli import csv_header, main


def _run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "solver.cli", *args], capture_output=True, text=True, timeout=120)


def test_summary_of_the_harvester_finger_lists_every_output() -> None:
    r = _run("harvester_finger")
    assert r.returncode == 0, r.stderr
    for name in ("point B", "point C", "point E", "joint finger", "max |v|", "max |a|"):
        assert name in r.stdout


def test_csv_has_the_contract_header_and_full_precision(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["four_bar", "--phi", "0,90,180", "--deg", "--omega", "2", "--epsilon", "0.5", "--csv", "-"]) == 0
    text = capsys.readouterr().out
    lines = text.strip().splitlines()
    assert lines[0] == (
        "phi,A.x,A.y,A.vx,A.vy,A.ax,A.ay,B.x,B.y,B.vx,B.vy,B.ax,B.ay,"
        "coupler.q,coupler.dq,coupler.ddq,rocker.q,rocker.dq,rocker.ddq"
    )
    table = np.loadtxt(io.StringIO(text), delimiter=",", skiprows=1)
    k = solver.load_scene("four_bar").solve(np.radians([0, 90, 180]), omega=2, epsilon=0.5)
    np.testing.assert_array_equal(table[:, 7:9], k.point("B").position)
    np.testing.assert_array_equal(table[:, -1], k.joint("rocker").acceleration)


def test_spatial_scene_has_z_columns() -> None:
    header = csv_header(solver.load_scene("spherical_converter"))
    assert header[:4] == ["phi", "K.x", "K.y", "K.z"]
    assert header[-3:] == ["cage.q", "cage.dq", "cage.ddq"]


def test_default_sweep_is_360_angles_of_one_turn(tmp_path) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "t.csv"
    assert main(["slider_crank", "--csv", str(out)]) == 0
    table = np.loadtxt(out, delimiter=",", skiprows=1)
    assert table.shape[0] == 360
    assert table[1, 0] == pytest.approx(2 * np.pi / 360)


def test_errors_are_one_line_without_traceback_and_exit_non_zero() -> None:
    r = _run("no_such_scene")
    assert r.returncode != 0
    assert "Traceback" not in r.stderr
    assert r.stderr.startswith("linkage-solve: error: no_such_scene: no such scene file")
