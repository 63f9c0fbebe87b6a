"""The rerun view: read back from the .rrd, and the same view replayed from the MCAP messages."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("mcap", reason="the record extra (mcap) is not installed")
pytest.importorskip("rosbags", reason="the record extra (rosbags) is not installed")
rr = pytest.importorskip("rerun", reason="the view extra (rerun-sdk, needs numpy >= 2) is not installed")

from rerun.chunk import RrdReader  # noqa: E402
from rosbags.typesys import Stores, get_typestore  # noqa: E402

from linkage_ros.cli import view_main  # noqa: E402
from linkage_ros.engine import Engine  # noqa: E402
from linkage_ros.messages import MessageBuilder  # noqa: E402
from linkage_ros.motion import Motion  # noqa: E402
from linkage_ros.record.mcap import Recorder  # noqa: E402
from linkage_ros.record.mcap_read import read_mcap  # noqa: E402
from linkage_ros.record.replay import run_data_from_mcap  # noqa: E402
from linkage_ros.record.rerun import arrow_scale, write_rrd  # noqa: E402
from linkage_ros.record.run import RunOptions, run_standalone  # noqa: E402
from linkage_ros.record.rundata import RunData  # noqa: E402
from linkage_ros.topics import topic_types  # noqa: E402

RERUN = next((str(p) for p in (Path(sys.executable).parent / "rerun",) if p.exists()),
              shutil.which("rerun") or "rerun")
TICKS = 76  # 1.5 s at 50 Hz


@pytest.fixture(scope="module")
def four_bar(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path, RunData]:
    tmp = tmp_path_factory.mktemp("view")
    mcap, rrd = tmp / "four_bar.mcap", tmp / "four_bar.rrd"
    result = run_standalone(RunOptions(scene="four_bar", duration=1.5, rate=50.0, omega=3.0,
                                       epsilon=0.7, phi0=0.2, mcap=mcap, rrd=rrd,
                                       chunk_interval_s=0.25))
    return mcap, rrd, result.data


def entities(path: Path) -> dict[str, tuple[bool, int]]:
    """Entity path → (static, rows) of every chunk of the recording store."""
    out: dict[str, tuple[bool, int]] = {}
    for chunk in RrdReader(path).stream().to_chunks():
        static, rows = out.get(chunk.entity_path, (False, 0))
        out[chunk.entity_path] = (static or chunk.is_static,
                                  rows + (0 if chunk.is_static else chunk.num_rows))
    return out


def assert_equal_runs(a: RunData, b: RunData) -> None:
    for name in ("t", "phi", "omega", "epsilon"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    for name in ("positions", "velocities", "accelerations", "fixed", "paths"):
        x, y = getattr(a, name), getattr(b, name)
        assert set(x) == set(y), name
        for key in x:
            np.testing.assert_array_equal(x[key], y[key], err_msg=f"{name}[{key}]")
    assert set(a.joints) == set(b.joints)
    for key in a.joints:
        np.testing.assert_array_equal(np.array(a.joints[key]), np.array(b.joints[key]))
    assert a.links == b.links and a.dim == b.dim and a.scene == b.scene


def test_rrd_holds_the_mechanism_static_parts_and_the_plots_on_sim_time(
        four_bar: tuple[Path, Path, RunData]) -> None:
    _, rrd, data = four_bar
    reader = RrdReader(rrd)
    assert len(reader.recordings()) == 1 and len(reader.blueprints()) == 1
    got = entities(rrd)
    moving = {"/mechanism/links/crank", "/mechanism/links/dyad", "/mechanism/points",
              "/mechanism/velocity/A", "/mechanism/velocity/B", "/mechanism/acceleration/A",
              "/mechanism/acceleration/B", "/plots/input/phi", "/plots/input/omega",
              "/plots/input/epsilon"}
    moving |= {f"/plots/joints/{kind}/{j}" for kind in ("position", "velocity", "acceleration")
               for j in ("crank", "coupler", "rocker")}
    for path in moving:
        assert got[path][1] == TICKS, path
    for path in ("/mechanism/fixed", "/mechanism/paths/B", "/mechanism/legend"):
        assert got[path] == (True, 0), path
    timelines = {name for chunk in reader.stream().to_chunks() for name in chunk.timeline_names}
    assert timelines == {"sim_time"}
    assert data.links == [("crank", ("O", "A")), ("dyad", ("A", "B", "C"))]


def test_rerun_rrd_verify_accepts_the_recording(four_bar: tuple[Path, Path, RunData]) -> None:
    _, rrd, _ = four_bar
    done = subprocess.run([RERUN, "rrd", "verify", str(rrd)], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr
    assert "without error" in done.stdout + done.stderr


def test_replay_from_mcap_gives_the_arrays_of_the_run(four_bar: tuple[Path, Path, RunData]) -> None:
    mcap, _, data = four_bar
    replayed, contents = run_data_from_mcap(mcap)
    assert contents.complete and replayed.note == ""
    assert_equal_runs(data, replayed)


def test_view_of_a_file_cut_by_a_crash_shows_every_complete_tick(
        four_bar: tuple[Path, Path, RunData], tmp_path: Path,
        capsys: pytest.CaptureFixture[str]) -> None:
    mcap, _, data = four_bar
    raw = mcap.read_bytes()
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(raw[: int(len(raw) * 0.6)])  # inside the data section, mid-record
    replayed, contents = run_data_from_mcap(cut)
    assert not contents.complete and 0 < replayed.n < data.n
    np.testing.assert_array_equal(replayed.t, data.t[: replayed.n])
    for p in data.positions:
        np.testing.assert_array_equal(replayed.positions[p], data.positions[p][: replayed.n])
    assert "cut short" in replayed.note
    assert view_main([str(cut), "-o", str(tmp_path / "cut.rrd")]) == 0
    assert "cut short" in capsys.readouterr().out
    assert entities(tmp_path / "cut.rrd")["/mechanism/points"][1] == replayed.n


def test_replay_without_scene_metadata_names_published_points_by_their_positions(
        tmp_path: Path) -> None:
    ts = get_typestore(Stores.ROS2_JAZZY)
    engine = Engine("four_bar", Motion(phi0=0.2, omega=3.0))
    builder = MessageBuilder(engine, ts.types)
    path = tmp_path / "plain.mcap"
    with Recorder(path, topic_types(engine), typestore=ts) as rec:  # no linkage_ros record
        for k, frame in enumerate(engine.frames(np.arange(10) / 50.0)):
            rec.write(k * 20_000_000, builder.build(frame, k * 20_000_000))
    data, _ = run_data_from_mcap(path)
    assert data.n == 10 and {"A", "B"} <= set(data.positions)
    assert sorted(data.fixed) == ["pivot_0", "pivot_1"]
    ends = [pts for _, pts in data.links]
    assert ("A", "B") in ends and all(len(pts) == 2 for pts in ends)
    write_rrd(data, tmp_path / "plain.rrd")
    assert entities(tmp_path / "plain.rrd")["/mechanism/points"][1] == 10


def test_arrow_scale_is_a_round_number_that_fits_the_drawing() -> None:
    vectors = {"P": np.array([[3.0, 4.0], [0.0, 1.0]])}  # longest 5
    scale = arrow_scale(vectors, extent=2.0)  # 0.25 · 2 / 5 = 0.1
    assert scale == pytest.approx(0.1)
    assert arrow_scale(vectors, extent=3.0) == pytest.approx(0.1)  # 0.15 → 0.1
    assert arrow_scale(vectors, extent=5.0) == pytest.approx(0.2)  # 0.25 → 0.2
    assert arrow_scale({"P": np.zeros((3, 2))}, extent=1.0) == 1.0


def test_mcap_view_cli_refuses_a_recording_without_joint_kinematics(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    ts = get_typestore(Stores.ROS2_JAZZY)
    path = tmp_path / "other.mcap"
    with Recorder(path, [("chatter", "std_msgs/msg/String")], typestore=ts) as rec:
        rec.write(0, [("chatter", ts.types["std_msgs/msg/String"](data="hi"))])
    assert read_mcap(path).complete
    assert view_main([str(path)]) == 2
    assert "no joint_kinematics" in capsys.readouterr().err
