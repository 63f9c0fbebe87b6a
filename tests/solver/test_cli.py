"""linkage-solve as a user runs it."""

from __future__ import annotations

import io
import subprocess
import sys

import numpy as np
import pytest

import solver
from solver.cli import csv_header, main, summary


def _run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "solver.cli", *args], capture_output=True, text=True, timeout=120)


def test_summary_of_the_harvester_finger_lists_every_output() -> None:
    r = _run("harvester_finger")
    assert r.returncode == 0, r.stderr
    for name in ("point B", "point C", "point E", "joint finger", "max speed |v|", "max |a|"):
        assert name in r.stdout


def test_summary_says_the_finger_makes_a_full_turn_and_the_drum_pin_moves_at_constant_speed() -> None:
    text = summary_of("harvester_finger")
    assert "ω = 1 rad/s, ε = 0 rad/s²" in text.splitlines()[0]
    finger = _block(text, "joint finger")
    assert "makes a full turn per turn of the input (+360.0°" in finger
    b = _block(text, "point B")
    assert "point B — drum pin" in b
    assert "speed |v| constant 0.2 m/s" in b and "|a| constant 0.2 m/s²" in b
    assert "max" not in b  # a constant is not "a maximum at some φ"


def test_summary_gives_angles_in_degrees_and_names_the_scenes_points() -> None:
    text = summary_of("four_bar")
    assert "swings" in _block(text, "joint rocker") and "°" in _block(text, "joint rocker")
    assert "transmission angle of dyad (between AB and CB)" in text


def summary_of(name: str) -> str:
    scene = solver.load_scene(name)
    return summary(scene, scene.solve(np.linspace(0, 2 * np.pi, 360, endpoint=False)), periodic=True)


def _block(text: str, head: str) -> str:
    lines = text.splitlines()
    i = next(i for i, line in enumerate(lines) if line.strip().startswith(head))
    return "\n".join(lines[i : i + 4])


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


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["four_bar", "--phi-count", "0"], "argument --phi-count: must be at least 1, got 0"),
        (["four_bar", "--omega", "abc"], "argument --omega: 'abc' is not a number"),
        (["four_bar", "--omega", "inf"], "argument --omega: 'inf' is not a finite number"),
        (["four_bar", "--phi", "1,x"], "argument --phi: not a comma-separated list of finite numbers"),
        (["four_bar", "--csv", "/nonexistent-dir/x.csv"], "the folder /nonexistent-dir does not exist"),
        (["four_bar", "--csv", "/etc/hostname/x.csv"], "/etc/hostname is a file, not a folder"),
        (["four_bar", "--csv", "/tmp"], "--csv /tmp: is a directory"),
    ],
)
def test_bad_command_lines_are_one_line_and_exit_2(
    args: list[str], message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    with pytest.raises(SystemExit) as stop:
        code = main(args)
        raise SystemExit(code)
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and message in err, err


def test_a_negative_number_in_exponent_form_is_a_value_not_an_option(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["four_bar", "--phi", "0.5", "--epsilon", "-1e3", "--csv", "-"]) == 0
    row = capsys.readouterr().out.strip().splitlines()[1].split(",")
    k = solver.load_scene("four_bar").solve(0.5, epsilon=-1e3)
    assert float(row[5]) == k.point("A").acceleration[0]


def test_a_yaml_syntax_error_is_one_line_with_the_file_and_line(tmp_path) -> None:  # type: ignore[no-untyped-def]
    path = tmp_path / "broken.yaml"
    path.write_text("scene: x\ngroups: [{type: crank\nunits: {length: m}\n", encoding="utf-8")
    r = _run(str(path))
    assert r.returncode == 2
    assert len(r.stderr.strip().splitlines()) == 1
    assert f"{path}:" in r.stderr and "not valid YAML" in r.stderr


def test_a_closed_pipe_ends_quietly() -> None:
    child = subprocess.Popen(
        [sys.executable, "-m", "solver.cli", "four_bar", "--csv", "-", "--phi-count", "200000"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    assert child.stdout is not None and child.stderr is not None
    child.stdout.readline()
    child.stdout.close()  # `| head -1`
    err = child.stderr.read()
    assert child.wait(timeout=120) == 141
    assert err == b""


def test_deg_reads_the_given_angles_and_the_csv_keeps_phi_in_rad(capsys: pytest.CaptureFixture[str]) -> None:
    """(issue 24) --help says the CSV's phi stays in rad with --deg, and it does."""
    with pytest.raises(SystemExit):
        main(["--help"])
    assert "the CSV's phi column stays in rad" in " ".join(capsys.readouterr().out.split())
    assert main(["four_bar", "--phi", "90", "--deg", "--csv", "-"]) == 0
    row = capsys.readouterr().out.splitlines()[1]
    assert float(row.split(",")[0]) == pytest.approx(np.pi / 2, rel=1e-15)
