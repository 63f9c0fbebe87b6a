"""linkage-run: the node's topics on simulated time, values equal to the solver's."""

from __future__ import annotations

import importlib.util
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("mcap", reason="the record extra (mcap) is not installed")
pytest.importorskip("rosbags", reason="the record extra (rosbags) is not installed")
pytest.importorskip("mcap_ros2", reason="the record extra (mcap-ros2-support) is not installed")

from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_typestore

import solver
from linkage_ros.cli import run_main
from linkage_ros.engine import Engine
from linkage_ros.motion import Motion
from linkage_ros.record.mcap_read import read_mcap
from linkage_ros.record.run import (
    RunOptions,
    duration_for_cycles,
    run_standalone,
    summary_lines,
)
from linkage_ros.record.rundata import RunData
from linkage_ros.topics import topic_types

TS = get_typestore(Stores.ROS2_JAZZY)
EPS = np.finfo(float).eps
TOL = 1e3 * EPS  # same solver, same inputs: equal up to rounding of the vectorised solve
SEED_SCENES = ["four_bar", "four_bar_crossed", "slider_crank", "harvester_finger",
               "spherical_converter"]
NS = 1_000_000_000
OMEGA, EPSILON, PHI0, RATE = 3.0, 0.7, 0.2, 100.0

HAVE_RERUN = importlib.util.find_spec("rerun") is not None


@pytest.fixture(scope="module")
def recorded(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, RunData]:
    path = tmp_path_factory.mktemp("run") / "finger.mcap"
    result = run_standalone(RunOptions(
        scene="harvester_finger", duration=0.5, rate=RATE, omega=OMEGA, epsilon=EPSILON,
        phi0=PHI0, mcap=path))
    assert {"markers", "points/C/position", "joint_kinematics"} <= set(result.templated)
    return path, result.data


def solved(scene_name: str, t: np.ndarray) -> object:
    scene = solver.load_scene(scene_name)
    scene = scene.with_outputs(points=scene.point_names, joints=scene.joint_names)
    phi = PHI0 + OMEGA * t + 0.5 * EPSILON * t * t
    return scene.solve(phi, omega=OMEGA + EPSILON * t, epsilon=np.full_like(t, EPSILON))


def test_ticks_are_k_over_rate_from_phi0_and_every_topic_of_a_tick_has_its_stamp(
        recorded: tuple[Path, RunData]) -> None:
    path, data = recorded
    assert data.n == 51 and data.t[0] == 0.0 and data.phi[0] == PHI0
    np.testing.assert_array_equal(data.t, np.arange(51) / RATE)
    contents = read_mcap(path)
    engine = Engine("harvester_finger", Motion(phi0=PHI0, omega=OMEGA, epsilon=EPSILON))
    expected = {f"/{name}": typename for name, typename in topic_types(engine)}
    assert contents.topics() == expected
    stamps = np.rint(np.arange(51) / RATE * NS).astype(np.int64)
    by_stamp: dict[int, list[str]] = {}
    for m in contents.messages:
        assert m.log_time == m.publish_time
        by_stamp.setdefault(m.log_time, []).append(m.topic)
    assert sorted(by_stamp) == stamps.tolist()
    assert all(v == list(expected) for v in by_stamp.values()), "node's topic order per tick"


def test_rosbags_reader_gives_point_kinematics_equal_to_the_solver(
        recorded: tuple[Path, RunData]) -> None:
    path, _ = recorded
    got: dict[str, list[list[float]]] = {}
    times = []
    with AnyReader([path], default_typestore=TS) as reader:
        for con, stamp, raw in reader.messages():
            msg = reader.deserialize(raw, con.msgtype)
            if con.topic.startswith("/points/C/"):
                vec = msg.point if con.topic.endswith("position") else msg.vector
                got.setdefault(con.topic.rsplit("/", 1)[1], []).append([vec.x, vec.y, vec.z])
                if con.topic.endswith("position"):
                    times.append(stamp / NS)
    k = solved("harvester_finger", np.array(times)).point("C")
    for kind, ref in (("position", k.position), ("velocity", k.velocity),
                      ("acceleration", k.acceleration)):
        arr = np.array(got[kind])
        np.testing.assert_allclose(arr[:, :2], ref, rtol=0, atol=TOL * np.abs(ref).max())
        assert np.all(arr[:, 2] == 0.0), "planar scenes publish z = 0"


def test_mcap_ros2_decoder_gives_joint_kinematics_equal_to_the_solver(
        recorded: tuple[Path, RunData]) -> None:
    path, _ = recorded
    rows, times = [], []
    with open(path, "rb") as fh:
        reader = make_reader(fh, decoder_factories=[DecoderFactory()])
        for _, _channel, message, msg in reader.iter_decoded_messages(topics=["/joint_kinematics"]):
            point = msg.points[0]
            names = list(msg.joint_names)
            rows.append((list(point.positions), list(point.velocities), list(point.accelerations)))
            times.append(message.log_time / NS)
    k = solved("harvester_finger", np.array(times))
    for j, name in enumerate(names):
        ref = k.joint(name)
        for i, series in enumerate((ref.position, ref.velocity, ref.acceleration)):
            got = np.array([r[i][j] for r in rows])
            np.testing.assert_allclose(got, series, rtol=0, atol=TOL * max(1.0, np.abs(series).max()))


@pytest.mark.parametrize("scene", SEED_SCENES)
def test_template_serialisation_writes_the_bytes_the_builder_writes(
        scene: str, tmp_path: Path) -> None:
    opts = dict(scene=scene, duration=1.2, rate=50.0, omega=OMEGA, epsilon=EPSILON, phi0=PHI0)
    fast = run_standalone(RunOptions(**opts, mcap=tmp_path / "fast.mcap"))
    slow = run_standalone(RunOptions(**opts, mcap=tmp_path / "slow.mcap", fast=False))
    assert "markers" in fast.templated and not slow.templated
    a, b = read_mcap(tmp_path / "fast.mcap"), read_mcap(tmp_path / "slow.mcap")
    assert len(a.messages) == len(b.messages) == 61 * len(a.topics())
    assert a.messages == b.messages


def test_cycles_give_the_time_of_n_turns_of_the_input() -> None:
    assert duration_for_cycles(1, 2 * math.pi, 0.0) == pytest.approx(1.0, rel=4 * EPS)
    assert duration_for_cycles(2, -math.pi, 0.0) == pytest.approx(4.0, rel=4 * EPS)
    for omega, eps in ((1.0, 0.5), (1.0, -0.5), (0.0, 2.0), (-3.0, 1.0)):
        t = duration_for_cycles(3, omega, eps)
        assert abs(omega * t + 0.5 * eps * t * t) == pytest.approx(6 * math.pi, rel=1e-12)
    with pytest.raises(ValueError, match="never turns"):
        duration_for_cycles(1, 0.0, 0.0)


def test_summary_gives_range_and_maxima_with_where_they_occur() -> None:
    t = np.linspace(0.0, 1.0, 5)
    pos = np.stack([t, -t], axis=1)
    vel = np.array([[0.0, 0.0], [3.0, 4.0], [1.0, 0.0], [0.0, 0.0], [0.0, 0.0]])
    acc = np.zeros((5, 2))
    acc[3] = (0.0, -2.0)
    data = RunData("demo", 2, t, 2 * t, np.ones(5), np.zeros(5), {"P": pos}, {"P": vel},
                   {"P": acc}, {"J": (t, -3 * t, t)}, [], {})
    note, *lines = summary_lines(data, ["P"], ["J"], {"J": "m"}, descriptions={"P": "the tip"})
    assert note == "  extremes read off the ticks (every 0.25 s)"  # not refined: said so once
    assert lines[0] == "  point P — the tip"
    assert lines[1] == "    position: x 0 … 1 m, y -1 … 0 m"
    assert lines[2] == "    velocity: max speed |v| = 5 m/s at t = 0.25 s (φ = 28.65°)"
    assert lines[3].startswith("    acceleration: max |a| = 2 m/s² at t = 0.75 s")
    assert lines[5] == "    position: 0 … 1 m"
    assert lines[6].startswith("    velocity: max |velocity| = 3 m/s at t = 1 s")


def test_summary_of_a_run_says_full_turn_and_constant_speed() -> None:
    t = np.linspace(0.0, 1.0, 101)
    phi = 2 * np.pi * t
    z = np.exp(1j * phi)
    pos, vel, acc = (np.stack([w.real, w.imag], axis=1) for w in (z, 2 * np.pi * 1j * z, -(2 * np.pi) ** 2 * z))
    q = np.angle(z)  # wraps at ±180°
    data = RunData("demo", 2, t, phi, np.full(101, 2 * np.pi), np.zeros(101), {"B": pos}, {"B": vel},
                   {"B": acc}, {"q": (q, np.full(101, 2 * np.pi), np.zeros(101))}, [], {})
    text = "\n".join(summary_lines(data, ["B"], ["q"]))
    assert "speed |v| constant 6.28319 m/s" in text
    assert "|a| constant 39.4784 m/s²" in text
    assert "makes a full turn over the run (+360.0°" in text
    assert "velocity: |velocity| constant 6.28319 rad/s" in text
    assert "acceleration: zero" in text


def test_cli_writes_default_files_under_runs_and_prints_a_summary(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(tmp_path)
    assert run_main(["slider_crank", "--cycles", "0.25", "--rate", "40"]) == 0
    out = capsys.readouterr().out
    mcaps, rrds = list(Path("runs").glob("slider_crank-*.mcap")), list(Path("runs").glob("*.rrd"))
    assert len(mcaps) == 1 and len(rrds) == (1 if HAVE_RERUN else 0)
    assert read_mcap(mcaps[0]).complete
    assert "max speed |v|" in out and "max |a|" in out and "ticks in" in out and "wall-clock" in out


def test_without_rerun_the_run_still_records_mcap_and_says_why_there_is_no_rrd(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    """Jazzy's system numpy is 1.26 and rerun-sdk 0.41 needs numpy 2: the main job must not fail."""
    import linkage_ros.cli as cli

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(cli, "_have_rerun", lambda: False)
    assert run_main(["slider_crank", "--cycles", "0.1", "--rate", "40"]) == 0
    assert list(Path("runs").glob("*.mcap")) and not list(Path("runs").glob("*.rrd"))
    assert "rerun-sdk is not installed" in capsys.readouterr().err
    assert run_main(["slider_crank", "--cycles", "0.1", "--rrd", "x.rrd"]) == 2


def test_cli_rejects_an_unknown_scene_with_exit_status_2(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert run_main(["no_such_scene", "--no-mcap", "--no-rrd"]) == 2
    assert "error:" in capsys.readouterr().err


@pytest.mark.skipif(not HAVE_RERUN, reason="the view extra (rerun-sdk, needs numpy >= 2) is not installed")
def test_sigint_stops_the_run_and_finishes_both_files(tmp_path: Path) -> None:
    mcap, rrd = tmp_path / "long.mcap", tmp_path / "long.rrd"
    code = ("from linkage_ros.cli import run_main; raise SystemExit(run_main(["
            f"'harvester_finger', '--duration', '3600', '--mcap', {str(mcap)!r}, "
            f"'--rrd', {str(rrd)!r}, '--chunk-interval', '0.2']))")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    child = subprocess.Popen([sys.executable, "-c", code], env=env, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and (not mcap.exists() or mcap.stat().st_size < 200_000):
        time.sleep(0.05)
    child.send_signal(signal.SIGINT)
    out, err = child.communicate(timeout=120)
    assert child.returncode == 130, err
    assert "files finished" in err
    contents = read_mcap(mcap)
    assert contents.complete and contents.messages
    with open(mcap, "rb") as fh:
        summary = make_reader(fh).get_summary()
    assert summary is not None and summary.statistics.message_count == len(contents.messages)
    assert rrd.stat().st_size > 0 and "ticks in" in out
