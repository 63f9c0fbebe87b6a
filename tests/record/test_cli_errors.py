"""linkage-run, linkage-view, linkage-mcap and linkage-urdf: a bad command line or output path is
one line on stderr and a non-zero exit, a closed pipe ends quietly, and only the default runs/
folder is created on the user's behalf (issue #13)."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

from linkage_ros.cli import mcap_main, run_main, view_main
from linkage_ros.urdf import main as urdf_main

HAVE_RERUN = importlib.util.find_spec("rerun") is not None


def _one_line(capsys: pytest.CaptureFixture[str]) -> tuple[str, str]:
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1, captured.err
    return captured.out, lines[0]


def _exit(main, args: list[str]) -> int:  # type: ignore[no-untyped-def]
    try:
        return int(main(args))
    except SystemExit as stop:  # argparse's own exit
        return int(stop.code or 0)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--rate", "abc"], "argument --rate: 'abc' is not a number > 0"),
        (["--rate", "-5"], "argument --rate: must be > 0, got -5"),
        (["--duration", "0"], "argument --duration: must be > 0, got 0"),
        (["--cycles", "0"], "argument --cycles: must be > 0, got 0"),
        (["--omega", "0"], "the input never turns, so the default one turn never ends: give --duration"),
        (["--omega", "0", "--cycles", "2"], "so --cycles 2 never ends"),
        (["--mcap", "missing-folder/run.mcap"], "the folder missing-folder does not exist"),
        (["--mcap", "/etc/hostname/run.mcap"], "/etc/hostname is a file, not a folder"),
        (["--rrd", ".", "--no-mcap"], "--rrd .: is a directory"),
        (["--points", "A,Z"], "--points: 'Z' is not a point of four_bar"),
        (["--duration", "1e9"], "ticks: at most 10,000,000 in one run"),
    ],
)
def test_linkage_run_refuses_bad_input_in_one_line_before_anything_runs(
    args: list[str], message: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    assert _exit(run_main, ["four_bar", *args]) == 2
    out, err = _one_line(capsys)
    assert message in err
    assert out == ""  # no run header before the error
    assert list(tmp_path.iterdir()) == []  # no folder created, no file written


def test_linkage_run_takes_a_negative_number_in_exponent_form_as_a_value(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    assert run_main(["four_bar", "--epsilon", "-1e3", "--duration", "0.05", "--no-mcap", "--no-rrd"]) == 0
    out = capsys.readouterr().out
    assert "ε = -1000 rad/s²" in out.splitlines()[0]


def test_linkage_run_states_omega_epsilon_and_wall_time_and_says_the_finger_turns(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    assert run_main(["harvester_finger", "--no-rrd", "--rate", "200"]) == 0
    out = capsys.readouterr().out
    assert "ω = 6.28319 rad/s, ε = 0 rad/s²" in out.splitlines()[0]
    assert "joint finger — angle of the finger" in out
    assert "makes a full turn over the run (+360.0°" in out
    assert "point B — drum pin" in out and "speed |v| constant 1.25664 m/s" in out
    assert "s of wall-clock time (1 s simulated)" in out
    assert [p.name for p in tmp_path.iterdir()] == ["runs"]  # the one folder made for the user


@pytest.mark.parametrize(
    ("output", "message"),
    [
        ("/etc/hostname/x.rrd", "/etc/hostname is a file, not a folder"),
        (".", "is a directory"),
        ("sub", "is a directory"),
        ("missing/x.rrd", "the folder missing does not exist"),
    ],
)
def test_linkage_view_refuses_an_output_it_cannot_write_in_one_line(
    output: str, message: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "sub").mkdir()
    (tmp_path / "run.mcap").write_bytes(b"not really")
    assert _exit(view_main, ["run.mcap", "-o", output]) == 2
    _, err = _one_line(capsys)
    assert message in err


def test_linkage_view_of_a_missing_or_garbage_file_is_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert _exit(view_main, [str(tmp_path / "none.mcap")]) == 2
    assert "no such file" in _one_line(capsys)[1]
    junk = tmp_path / "junk.mcap"
    junk.write_bytes(bytes(range(256)))
    if HAVE_RERUN:
        assert _exit(view_main, [str(junk)]) == 2
        assert "not a readable linkage_ros recording" in _one_line(capsys)[1]


@pytest.mark.skipif(not HAVE_RERUN, reason="the view extra (rerun-sdk) is not installed")
def test_linkage_view_without_o_keeps_the_rrd_that_linkage_run_wrote(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    mcap, rrd = tmp_path / "r.mcap", tmp_path / "r.rrd"
    assert run_main(["four_bar", "--cycles", "0.05", "--mcap", str(mcap), "--rrd", str(rrd)]) == 0
    before = rrd.read_bytes()
    assert view_main([str(mcap)]) == 0
    assert rrd.read_bytes() == before
    assert (tmp_path / "r.view.rrd").stat().st_size > 0
    assert "rerun: " + str(tmp_path / "r.view.rrd") in capsys.readouterr().out


def test_linkage_mcap_errors_are_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert _exit(mcap_main, ["info", str(tmp_path / "none.mcap")]) == 2
    assert "no such file" in _one_line(capsys)[1]
    junk = tmp_path / "junk.mcap"
    junk.write_bytes(b"x" * 100)
    assert _exit(mcap_main, ["info", str(junk)]) == 2
    assert str(junk) in _one_line(capsys)[1]
    assert _exit(mcap_main, ["recover", str(junk), str(tmp_path / "no" / "fixed.mcap")]) == 2
    assert "does not exist" in _one_line(capsys)[1]
    assert _exit(mcap_main, ["nonsense"]) == 2
    assert "see linkage-mcap --help" in _one_line(capsys)[1]


def test_linkage_mcap_info_into_a_closed_pipe_ends_quietly(tmp_path: Path) -> None:
    mcap = tmp_path / "r.mcap"
    assert run_main(["four_bar", "--cycles", "0.2", "--mcap", str(mcap), "--no-rrd"]) == 0
    code = "import sys; from linkage_ros.cli import mcap_main; sys.exit(mcap_main(sys.argv[1:]))"
    child = subprocess.Popen(
        [sys.executable, "-c", code, "info", str(mcap)], stdout=subprocess.PIPE, stderr=subprocess.PIPE
    )
    assert child.stdout is not None and child.stderr is not None
    child.stdout.close()  # `| head -0`: the reader is gone before the first line
    err = child.stderr.read()
    assert child.wait(timeout=60) in (0, 141)
    assert b"Traceback" not in err and b"Broken pipe" not in err


def test_linkage_run_into_a_closed_pipe_ends_quietly() -> None:
    code = "import sys; from linkage_ros.cli import run_main; sys.exit(run_main(sys.argv[1:]))"
    child = subprocess.Popen(
        [sys.executable, "-c", code, "four_bar", "--cycles", "0.2", "--no-mcap", "--no-rrd"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE,
    )
    assert child.stdout is not None and child.stderr is not None
    child.stdout.close()  # `linkage-run four_bar | head -0`
    err = child.stderr.read()
    assert child.wait(timeout=60) in (0, 141)
    assert b"Traceback" not in err and b"Broken pipe" not in err


def test_linkage_urdf_errors_are_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert _exit(urdf_main, ["four_bar", "-o", str(tmp_path)]) == 2
    assert "is a directory" in _one_line(capsys)[1]
    assert _exit(urdf_main, ["four_bar", "-o", str(tmp_path / "no" / "x.urdf")]) == 2
    assert "does not exist" in _one_line(capsys)[1]
    assert _exit(urdf_main, ["no_such_scene"]) == 2
    assert "no such scene file" in _one_line(capsys)[1]


def test_dev_says_in_its_own_words_when_python_cannot_be_run(tmp_path: Path) -> None:
    dev = Path(__file__).resolve().parents[2] / "dev"
    env = {"PATH": "/usr/bin:/bin", "PYTHON": str(tmp_path / "python3.12"), "HOME": str(tmp_path)}
    done = subprocess.run(["bash", str(dev), "run"], capture_output=True, text=True, env=env, timeout=60)
    assert done.returncode == 127
    assert f"./dev: PYTHON={tmp_path / 'python3.12'} cannot be run" in done.stderr
    assert "set PYTHON to a Python 3.11 or 3.12 interpreter" in done.stderr
