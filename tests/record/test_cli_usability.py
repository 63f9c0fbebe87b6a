"""What a user tripped on in the recording tools (issue 19): linkage-view's times, linkage-mcap's
messages, --spawn where no viewer can open, and plot legends that name every series."""

from __future__ import annotations

import importlib.util
import os
import stat
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("mcap", reason="the record extra (mcap) is not installed")
pytest.importorskip("rosbags", reason="the record extra (rosbags) is not installed")

from rosbags.typesys import Stores, get_typestore

from linkage_ros.cli import mcap_main, view_main
from linkage_ros.record.mcap import Recorder
from linkage_ros.record.replay import METADATA_NAME, scene_metadata
from linkage_ros.record.rerun import LEGEND_ROWS, plot_columns
from linkage_ros.record.rundata import RunData
from linkage_ros.record.viewer import ViewerError, display_problem, open_viewer, viewer_environment
from linkage_ros.runtime import Runtime

STORE = get_typestore(Stores.ROS2_JAZZY)
NS = 1_000_000_000
T0 = 1_700_000_000 * NS  # 2023-11-14 22:13:20 UTC: a live node's stamps are wall-clock times
HAVE_RERUN = importlib.util.find_spec("rerun") is not None
NO_DISPLAY = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY", "WAYLAND_SOCKET")}


@pytest.fixture(scope="module")
def live_recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """What mechanism_node records: 30 ticks at 100 Hz under wall-clock stamps."""
    path = tmp_path_factory.mktemp("live") / "live.mcap"

    def factory(target: str, topics: Any, *, engine: Any, frame_id: str) -> Recorder:
        return Recorder(target, topics, typestore=STORE,
                        metadata={METADATA_NAME: scene_metadata(engine, frame_id=frame_id)})

    runtime = Runtime({"scene": "four_bar", "record_mcap": str(path)}, STORE.types, recorder_factory=factory)
    for k in range(30):
        runtime.tick(T0 + k * NS // 100)
    runtime.close()
    return path


# ---------------------------------------------------------------------------------------- times
@pytest.mark.skipif(not HAVE_RERUN, reason="the view extra (rerun-sdk) is not installed")
def test_linkage_view_prints_run_time_and_the_start_as_a_date(
    live_recording: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert view_main([str(live_recording), "-o", str(tmp_path / "live.rrd")]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first == (f"{live_recording}: finished; 271 messages, 30 ticks over 0.29 s of run time, "
                     "from 2023-11-14 22:13:20.000 UTC")


def test_linkage_mcap_info_is_one_line_with_run_time_then_the_topics(
    live_recording: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert mcap_main(["info", str(live_recording)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith(f"{live_recording}: finished; 271 messages on 10 topics, 0.29 s from "
                               "2023-11-14 22:13:20.000 UTC; ros2 profile, written by linkage_ros ")
    assert len(lines) == 11 and lines[1].split() == ["/joint_states", "sensor_msgs/msg/JointState", "30"]


def test_linkage_mcap_names_each_file_once_in_one_line(
    live_recording: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    cut, fixed = tmp_path / "cut.mcap", tmp_path / "fixed.mcap"
    data = live_recording.read_bytes()
    cut.write_bytes(data[: len(data) * 2 // 3])
    assert mcap_main(["info", str(cut)]) == 0
    head = capsys.readouterr().out.splitlines()[0]
    assert head.startswith(f"{cut}: NOT finished (readable up to byte ")
    assert f"make a finished copy with: linkage-mcap recover {cut} FIXED.mcap)" in head
    assert mcap_main(["recover", str(cut), str(fixed)]) == 0
    out = capsys.readouterr().out.strip()
    assert out.startswith(f"{fixed}: ") and f" recovered from {cut} (cut short: the last " in out
    assert "\n" not in out and out.count(str(cut)) == 1
    empty, missing = tmp_path / "empty.mcap", tmp_path / "missing.mcap"
    empty.write_bytes(b"")
    for args, line in (
        (["info", str(empty)], f"linkage-mcap: error: {empty}: empty file"),
        (["info", str(missing)], f"linkage-mcap: error: {missing}: no such file"),
        (["info", str(tmp_path)], f"linkage-mcap: error: {tmp_path}: is a directory, not an MCAP file"),
        (["recover", str(cut), str(cut)],
         f"linkage-mcap: error: FIXED {cut}: write the recovered copy to another file than BROKEN"),
        (["recover", str(cut), str(tmp_path / "no" / "x.mcap")],
         f"linkage-mcap: error: FIXED {tmp_path / 'no' / 'x.mcap'}: the folder {tmp_path / 'no'} does not exist "
         "(create it first)"),
    ):
        assert mcap_main(args) == 2
        assert capsys.readouterr().err.strip() == line


# ---------------------------------------------------------------------------------------- --spawn
def test_no_display_is_told_apart_from_a_display() -> None:
    assert display_problem({}, "linux") == "no display (none of DISPLAY, WAYLAND_DISPLAY is set)"
    assert display_problem({"WAYLAND_DISPLAY": "wayland-0"}, "linux") is None
    assert display_problem({"DISPLAY": ":0"}, "linux") is None
    assert display_problem({}, "darwin") is None and display_problem({}, "win32") is None


def test_a_viewer_that_fails_at_once_gives_its_reason_in_one_line(tmp_path: Path,
                                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    fake = tmp_path / "rerun"
    fake.write_text("#!/bin/sh\necho 'INFO lots of log lines' >&2\n"
                    "echo 'Error: winit EventLoopError: os error at mod.rs:788: "
                    "Failed to open connection to X server' >&2\n"
                    "exit 1\n")
    fake.chmod(fake.stat().st_mode | stat.S_IXUSR)
    monkeypatch.setenv("DISPLAY", ":987")
    start = time.monotonic()
    with pytest.raises(ViewerError, match=r"^the rerun viewer exited at once \(status 1\): "
                                          r"Failed to open connection to X server$"):
        open_viewer(tmp_path / "x.rrd", executable=str(fake))
    assert time.monotonic() - start < 5.0
    handed_over = tmp_path / "handed_over"  # a viewer already running takes the file: status 0
    handed_over.write_text("#!/bin/sh\necho 'Another viewer is already running, streaming data to it.' >&2\n")
    handed_over.chmod(handed_over.stat().st_mode | stat.S_IXUSR)
    assert open_viewer(tmp_path / "x.rrd", executable=str(handed_over)) > 0
    monkeypatch.delenv("DISPLAY")
    for name in ("WAYLAND_DISPLAY", "WAYLAND_SOCKET"):
        monkeypatch.delenv(name, raising=False)
    with pytest.raises(ViewerError, match="no display"):
        open_viewer(tmp_path / "x.rrd", executable=str(fake))


@pytest.mark.skipif(os.name != "posix", reason="XDG_RUNTIME_DIR is a POSIX desktop variable")
def test_the_viewer_gets_a_runtime_folder_so_it_prints_no_xdg_error(tmp_path: Path,
                                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    """Without XDG_RUNTIME_DIR the viewer printed "error: XDG_RUNTIME_DIR is invalid or not set"
    twice (issue 24): it is started with a private folder instead; a valid one is kept."""
    for unset in ({}, {"XDG_RUNTIME_DIR": ""}, {"XDG_RUNTIME_DIR": str(tmp_path / "missing")}):
        folder = Path(viewer_environment(unset)["XDG_RUNTIME_DIR"])
        assert folder.is_absolute() and folder.is_dir() and folder.stat().st_uid == os.getuid()
        assert folder.stat().st_mode & 0o077 == 0
    assert viewer_environment({"XDG_RUNTIME_DIR": str(tmp_path), "X": "1"}) == {
        "XDG_RUNTIME_DIR": str(tmp_path), "X": "1"}
    seen = tmp_path / "seen"  # what a started viewer finds in its environment
    fake = tmp_path / "rerun"
    fake.write_text(f"#!/bin/sh\nprintf '%s' \"$XDG_RUNTIME_DIR\" > {seen}\n")
    fake.chmod(fake.stat().st_mode | stat.S_IXUSR)
    monkeypatch.setenv("DISPLAY", ":987")
    monkeypatch.delenv("XDG_RUNTIME_DIR", raising=False)
    open_viewer(tmp_path / "x.rrd", executable=str(fake))
    assert Path(seen.read_text()).is_dir()


@pytest.mark.skipif(not HAVE_RERUN, reason="the view extra (rerun-sdk) is not installed")
def test_linkage_run_spawn_without_a_display_says_in_one_line_how_to_view(tmp_path: Path) -> None:
    rrd = tmp_path / "run.rrd"
    start = time.monotonic()
    done = subprocess.run(
        [str(Path(sys.executable).parent / "linkage-run"), "four_bar", "--cycles", "0.2", "--no-mcap",
         "--rrd", str(rrd), "--spawn"], env=NO_DISPLAY, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert time.monotonic() - start < 15.0
    assert done.stderr.strip() == (
        "linkage-run: note: no viewer started: no display (none of DISPLAY, WAYLAND_DISPLAY is set); "
        f"view it with `rerun {rrd}` where there is a display")
    assert rrd.stat().st_size > 0


# ---------------------------------------------------------------------------------------- legends
def _run_data(joints: list[str], inputs: tuple[str, ...] = ()) -> RunData:
    n = 5
    shape = (n, len(inputs)) if inputs else (n,)
    return RunData(scene="s", dim=2, t=np.arange(n) / 10.0, phi=np.zeros(shape), omega=np.zeros(shape),
                   epsilon=np.zeros(shape), positions={}, velocities={}, accelerations={},
                   joints={j: (np.zeros(n), np.zeros(n), np.zeros(n)) for j in joints}, links=[],
                   fixed={}, input_joint=joints[0], inputs=inputs)


@pytest.mark.parametrize(
    ("joints", "inputs", "columns"),
    [
        (["q1", "q2", "left_distal", "right_distal"], ("q1", "q2"), 2),  # the five-bar
        (["crank", "coupler", "rocker"], (), 2),
        ([f"j{i}" for i in range(9)], (), 3),  # more joints (8 besides the input) than a legend shows
    ],
)
def test_every_series_is_in_one_plot_whose_legend_shows_it(joints: list[str], inputs: tuple[str, ...],
                                                           columns: int) -> None:
    layout = plot_columns(_run_data(joints, inputs))
    assert len(layout) == columns and all(len(column) == 3 for column in layout)
    paths = [p for column in layout for _, plot in column for p in plot]
    expected = {f"plots/joints/{kind}/{j}" for kind in ("position", "velocity", "acceleration") for j in joints}
    # an input's position, rate and acceleration are its φ, ω, ε, plotted in the inputs' column
    # only (issue 24: its growing angle beside the others' swings flattened them)
    expected -= {f"plots/joints/{kind}/{q}" for kind in ("position", "velocity", "acceleration")
                 for q in (inputs or (joints[0],))}
    expected |= ({f"plots/input/{kind}/{q}" for kind in ("phi", "omega", "epsilon") for q in inputs} if inputs
                 else {"plots/input/phi", "plots/input/omega", "plots/input/epsilon"})
    assert sorted(paths) == sorted(expected)  # each exactly once
    angles = next(plot for column in layout[1:] for title, plot in column if title.startswith("joint angles"))
    assert not {f"plots/joints/position/{q}" for q in (inputs or (joints[0],))} & set(angles)
    assert all(len(plot) <= LEGEND_ROWS for column in layout for _, plot in column)
