"""Strokes spoken of in their own units, and the command lines' frictions (issue 30): a stroke's
dynamic run in m, m/s and N; machine dynamics that does not apply to a stroke says so; a motor on a
stroke gives a force; degrees refused in degrees; reversed ranges refused; one instant of several
inputs; every default in --help."""

from __future__ import annotations

import argparse
import contextlib
import io
import re
from pathlib import Path

import numpy as np
import pytest

import solver
from solver import cli, cli_inputs, synth_cli

pytest.importorskip("mcap", reason="the record extra (mcap) is not installed")
pytest.importorskip("rosbags", reason="the record extra (rosbags) is not installed")

from linkage_ros import cli as run_cli
from linkage_ros.motion import Motion, Motions

TEMPLATE = Path(__file__).parents[2] / "config" / "templates" / "four_bar_path.yaml"


def _run(*argv: str) -> tuple[int, str]:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = run_cli.run_main([*argv, "--no-mcap", "--no-rrd"])
    return code, out.getvalue()


def _tipper_with(tmp_path: Path, motor: str) -> Path:
    text = Path(solver.find_scene("tipper")).read_text(encoding="utf-8")
    path = tmp_path / "tipper_motor.yaml"
    path.write_text(text.replace("scene: tipper", "scene: tipper_motor") + f"motor: {{stroke: {motor}}}\n",
                    encoding="utf-8")
    return path


def test_a_strokes_dynamic_run_speaks_m_m_per_s_and_n() -> None:
    code, text = _run("tipper", "--dynamics", "--duration", "1", "--drive", "80000")
    lines = text.splitlines()
    assert code == 0
    assert lines[0].endswith("the motion from the equation of motion: 'stroke' from s0 = 0.74 m, ṡ0 = 0 m/s; angles "
                             "in degrees, everything else SI")
    assert "°" not in lines[0].split("'stroke'")[1].split(";")[0]
    forces = next(line for line in lines if line.startswith("forces (SI), at "))
    assert "ω" not in forces and "rad/s" not in forces and "at each sample's ṡ and s̈" in forces
    assert any(line.startswith("  input power Σ Q·ṡ: peak |P| = ") for line in lines)
    assert "dynamics: drive constant effort 80000 N; DOP853" in text


def test_several_strokes_name_each_constant_effort_in_n() -> None:
    code, text = _run("excavator", "--dynamics", "--duration", "0.05", "--drive", "1000,2000,3000")
    assert code == 0
    assert ("dynamics: drive constant effort boom_stroke 1000 N, arm_stroke 2000 N, bucket_stroke 3000 N;"
            in text)
    assert "'boom_stroke' from s0 = 1.05 m, ṡ0 = 0 m/s; 'arm_stroke' from s0 = 1.3 m" in text
    assert re.search(r"forces \(SI\), at ṡ boom_stroke = 0, arm_stroke = 0, bucket_stroke = 0 m/s, s̈ .* m/s², with",
                     text)


def test_a_motor_on_a_stroke_gives_a_force_and_its_run_up_does_not_apply(tmp_path: Path) -> None:
    path = _tipper_with(tmp_path, "{stall_force: 90000, no_load_speed: 0.5}")
    code, text = _run(str(path), "--dynamics", "--duration", "0.2")
    assert code == 0
    assert "dynamics: drive the scene's motor (stroke: stall force 90000 N, no-load speed 0.5 m/s);" in text
    assert ("  run-up: does not apply ('stroke' is an actuator's stroke [0.74, 1.3] m: no load cycle, so no steady "
            "speed to run up to)") in text
    assert "cannot be assembled" not in text
    table = solver.load_scene(_tipper_with(tmp_path, "{speed: [0, 0.5], force: [90000, 0]}"))
    assert table.simulate(0.05, drive="motor", on_singular="stop").drive == "motor"


@pytest.mark.parametrize(("motor", "message"), [
    ("{stall_torque: 90000, no_load_speed: 0.5}",
     r"motor\.stroke\.stall_torque: 'stroke' is an actuator's stroke: its motor gives a force \(N\); write "
     r"stall_force"),
    ("{speed: [0, 0.5], torque: [90000, 0]}", r"motor\.stroke\.torque: .* write force"),
    ("{speed: [0, 0.5, 1.0], force: [90000, 0]}", r"motor\.stroke\.force: has 2 forces for 3 speeds"),
])
def test_a_motor_on_a_stroke_refuses_torques_with_the_key_to_write(tmp_path: Path, motor: str, message: str) -> None:
    with pytest.raises(solver.SceneError, match=message):
        solver.load_scene(_tipper_with(tmp_path, motor))


def test_a_flywheel_on_a_stroke_says_an_actuators_input(tmp_path: Path) -> None:
    text = Path(solver.find_scene("tipper")).read_text(encoding="utf-8") + "flywheel: {stroke: 1.0}\n"
    path = tmp_path / "tipper_flywheel.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(solver.SceneError, match=r"a flywheel turns with a crank; 'stroke' is an actuator's input$"):
        solver.load_scene(path)


def test_a_motions_repr_is_in_its_inputs_unit() -> None:
    assert repr(Motion(phi0=0.74, omega=0.1, unit="m")).startswith("Motion(1 segment(s); last from t=0 s: s=0.74 m, "
                                                                   "ṡ=0.1 m/s, s̈=0 m/s², ")
    assert "φ=0.3 rad, ω=1 rad/s, ε=0 rad/s²" in repr(Motion(phi0=0.3))
    laws = Motions.of(2, phi0=(0.3, 1.0), units=("rad", "m"))
    assert "s=1 m" in repr(laws) and "φ=0.3 rad" in repr(laws)


def test_min_transmission_is_refused_in_degrees(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    targets = tmp_path / "targets.csv"
    targets.write_text("0.1,0.2\n0.2,0.25\n", encoding="utf-8")
    with pytest.raises(SystemExit) as info:
        synth_cli.main([str(TEMPLATE), "--point", "P", "--through", str(targets), "--min-transmission", "95"])
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert "argument --min-transmission: must be in [0, 90) degrees, got 95" in err and "rad" not in err


@pytest.mark.parametrize(("argv", "message"), [
    (["tipper", "--range", "1.2:1.0"], "--range '1.2:1.0': LO must be less than HI (the sweep runs from LO to HI"),
    (["tipper", "--range", "1.0:1.0"], "--range '1.0:1.0': LO must be less than HI"),
    (["five_bar", "--range", "q1=2:1"], "--range 'q1=2:1': LO must be less than HI (the grid runs from LO to HI"),
    (["excavator", "--phi", "1.3,1.6"], "--phi: give 3 values, one per input (boom_stroke, arm_stroke, "
                                        "bucket_stroke)"),
    (["excavator", "--phi", "1.3,1.6,1.2;1.3,1.6,1.2"], "--phi '1.3,1.6,1.2;1.3,1.6,1.2': one instant"),
    (["excavator", "--phi", "1.3,1.6,1.2", "--samples", "1.3,1.6,1.2"], "--phi and --samples: give one instant"),
])
def test_reversed_ranges_and_bad_instants_are_refused(capsys: pytest.CaptureFixture[str], argv: list[str],
                                                      message: str) -> None:
    assert cli.main(argv) == 2
    assert message in capsys.readouterr().err


def test_one_instant_of_several_inputs_is_accepted(capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main(["excavator", "--phi", "1.3,1.6,1.2", "--csv", "-"]) == 0
    rows = np.loadtxt(io.StringIO(capsys.readouterr().out), delimiter=",", skiprows=1, ndmin=2)
    assert rows.shape[0] == 1 and rows[0, :3].tolist() == [1.3, 1.6, 1.2]
    k = solver.load_scene("excavator").solve((1.3, 1.6, 1.2))
    assert rows[0, 3:5].tolist() == list(k.point(solver.load_scene("excavator").output_points[0]).position)
    assert cli.main(["five_bar", "--deg", "--phi", "60,120", "--csv", "-"]) == 0  # --deg scales angles
    row = np.loadtxt(io.StringIO(capsys.readouterr().out), delimiter=",", skiprows=1, ndmin=2)[0]
    np.testing.assert_allclose(row[:2], np.radians([60.0, 120.0]), rtol=0, atol=1e-15)


def _parsers() -> list[argparse.ArgumentParser]:
    return [run_cli._run_parser(), cli._parser(), cli_inputs._parser(), synth_cli._parser()]


#: options whose default is "not given" and means something a user must be told
SAY_WHEN_NONE = {"--duration", "--time-limit", "--max-ratio", "--drive", "--points", "--mcap", "--rrd", "--dask"}


@pytest.mark.parametrize("parser", _parsers(), ids=lambda p: p.prog)
def test_every_default_is_in_help(parser: argparse.ArgumentParser) -> None:
    missing = []
    for action in parser._actions:
        if not action.option_strings or action.help in (None, argparse.SUPPRESS) and action.default is None:
            continue
        text = str(action.help or "")
        default = action.default
        if default is None:
            if set(action.option_strings) & SAY_WHEN_NONE and "default" not in text:
                missing.append(action.option_strings[0])
            continue
        if default in (False, [], argparse.SUPPRESS) or action.dest == "help":
            continue
        shown = {str(default), f"{default:g}" if isinstance(default, float) else str(default),
                 re.sub(r"e-0*(\d)", r"e-\1", f"{default:g}") if isinstance(default, float) else str(default)}
        if not any(s in text for s in shown):
            missing.append(action.option_strings[0])
    assert not missing, f"{parser.prog}: no default in the help of {missing}"
