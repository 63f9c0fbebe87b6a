"""``linkage-run SCENE --dynamics`` (issue 22): the motion from the equation of motion, recorded
as a kinematic run is (the node's topics in the MCAP, the rerun view) plus the energy plots, and
a summary of the run-up, ω, δ, the drive's peaks and the energy balance; bad options are one line."""

from __future__ import annotations

import importlib.util
import re
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("mcap", reason="the record extra (mcap) is not installed")
pytest.importorskip("rosbags", reason="the record extra (rosbags) is not installed")

from rosbags.highlevel import AnyReader

import solver
from linkage_ros.cli import run_main

HAVE_RERUN = importlib.util.find_spec("rerun") is not None
RATE, DURATION = 50.0, 1.0
TICKS = 51
STALL, NO_LOAD = 4.0, 30.0


def motor_scene(folder: Path) -> Path:
    """four_bar_loaded with a DC motor and a flywheel on its crank."""
    text = Path(solver.find_scene("four_bar_loaded")).read_text()
    path = folder / "four_bar_motor.yaml"
    path.write_text(text.replace("scene: four_bar_loaded", "scene: four_bar_motor")
                    + f"motor: {{crank: {{stall_torque: {STALL}, no_load_speed: {NO_LOAD}}}}}\n"
                    + "flywheel: {crank: 0.01}\n")
    return path


@pytest.fixture(scope="module")
def motor_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path | None, str]:
    import contextlib
    import io

    tmp = tmp_path_factory.mktemp("dynamics")
    mcap, rrd = tmp / "run.mcap", tmp / "run.rrd"
    argv = [str(motor_scene(tmp)), "--dynamics", "--duration", str(DURATION), "--rate", str(RATE),
            "--mcap", str(mcap)] + (["--rrd", str(rrd)] if HAVE_RERUN else ["--no-rrd"])
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert run_main(argv) == 0
    return mcap, rrd if HAVE_RERUN else None, out.getvalue()


def test_the_summary_says_drive_run_up_speeds_delta_peaks_and_energy_balance(motor_run: Any) -> None:
    _, _, text = motor_run
    lines = text.splitlines()
    assert lines[0].startswith("scene four_bar_motor: 1 s of simulated time at 50 Hz (up to 51 ticks), the motion "
                               "from the equation of motion: 'crank' from φ0 = 0°, ω0 = 0 rad/s")
    assert ("dynamics: drive the scene's motor (crank: stall torque 4 N·m, no-load speed 30 rad/s); DOP853, "
            "rtol 1e-09, atol 1e-09") in text
    assert re.search(r"\n  run-up from rest at φ0: [0-9.]+ s to the steady band ω ≥ [0-9.]+ rad/s \(steady: periodic "
                     r"solution over one 360° cycle", text)
    assert re.search(r"\n  crank: ω mean [0-9.]+, min 0, max [0-9.]+ rad/s over the run \(time mean\)", text)
    assert re.search(r"\n  δ = \(ω_max − ω_min\)/ω_mean = [0-9.]+ over the last full 360° cycle", text)
    assert "\n  crank: peak motor effort 4 N·m at t = 0 s, peak motor power " in text
    balance = re.search(r"energy balance: \|T \+ V − W_drive − W_other − its start\| ≤ (\S+) J", text)
    assert balance is not None and float(balance.group(1)) < 1e-6


def test_the_recording_holds_the_motors_torque_on_joint_states(motor_run: Any) -> None:
    mcap, _, _ = motor_run
    with AnyReader([mcap]) as reader:
        states = [reader.deserialize(raw, c.msgtype) for c, _, raw in reader.messages()
                  if c.topic == "/joint_states"]
    assert len(states) == TICKS
    for js in states:
        i = list(js.name).index("crank")
        assert js.effort[i] == pytest.approx(STALL * (1.0 - js.velocity[i] / NO_LOAD), rel=1e-9, abs=1e-12)


@pytest.mark.skipif(not HAVE_RERUN, reason="the view extra (rerun-sdk) is not installed")
def test_the_rerun_view_plots_the_energies_and_the_balance_error(motor_run: Any) -> None:
    from rerun.chunk import RrdReader

    _, rrd, _ = motor_run
    rows: dict[str, int] = {}
    for chunk in RrdReader(rrd).stream().to_chunks():
        if not chunk.is_static:
            rows[chunk.entity_path] = rows.get(chunk.entity_path, 0) + chunk.num_rows
    for entity in ("kinetic", "gravity", "work_drive", "work_other"):
        assert rows[f"/plots/energy/{entity}"] == TICKS
    assert "/plots/energy/springs" not in rows  # no springs: no series
    assert rows["/plots/energy_balance"] == TICKS


def test_a_toggle_ends_the_run_with_its_message(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert run_main(["five_bar", "--dynamics", "--phi0", "0.3", "--duration", "1", "--no-mcap", "--no-rrd"]) == 0
    text = capsys.readouterr().out
    assert "dynamics: drive free (the loads alone)" in text
    assert re.search(r"\n  stopped: five_bar, t = 0\.129\d* s, q1 = .* reaches a singular position of group "
                     r"'distal'", text)


def test_several_inputs_under_constant_efforts_are_recorded_up_to_their_toggle(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    mcap = tmp_path / "five_bar.mcap"
    assert run_main(["five_bar", "--dynamics", "--drive", "0.1,-0.1", "--phi0", "q1=2.2", "--phi0", "q2=0.9",
                     "--omega0", "q1=1", "--duration", "1", "--mcap", str(mcap), "--no-rrd"]) == 0
    text = capsys.readouterr().out
    assert "'q1' from φ0 = 126.051°, ω0 = 1 rad/s; 'q2' from φ0 = 51.5662°, ω0 = 0 rad/s" in text
    assert "dynamics: drive constant effort q1 0.1 N·m, q2 -0.1 N·m;" in text
    assert "\n  stopped: five_bar, t = 0.15" in text
    assert "\n  q1: peak drive effort 0.1 N·m at t = 0 s" in text and "\n  q2: peak drive effort -0.1 N·m" in text
    with AnyReader([mcap]) as reader:
        states = [reader.deserialize(raw, c.msgtype) for c, _, raw in reader.messages() if c.topic == "/joint_states"]
    assert len(states) == 16  # the ticks 0 … 0.15 s before the toggle at 0.1533 s
    for js in states:
        effort = dict(zip(js.name, js.effort))
        assert effort["q1"] == pytest.approx(0.1, rel=1e-9) and effort["q2"] == pytest.approx(-0.1, rel=1e-9)


@pytest.mark.parametrize(("argv", "message"), [
    (["four_bar_loaded", "--dynamics", "--omega", "3"],
     "--omega: the kinematic law; with --dynamics the motion follows from the equation of motion"),
    (["four_bar_loaded", "--dynamics", "--cycles", "2"], "--cycles does not go with --dynamics"),
    (["four_bar_loaded", "--drive", "motor"], "--drive: only with --dynamics"),
    (["four_bar_loaded", "--dynamics", "--drive", "1,2"], "--drive '1,2': give one finite effort, or 1"),
    (["four_bar_loaded", "--dynamics", "--drive", "motor"], "drive='motor' but the scene has no 'motor:'"),
    (["four_bar", "--dynamics"], "four_bar: names no bodies, gravity or loads: nothing gives it inertia"),
])
def test_bad_options_are_one_line_and_exit_2(argv: list[str], message: str,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    assert run_main([*argv, "--no-mcap", "--no-rrd"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("linkage-run: error: ") and message in err
