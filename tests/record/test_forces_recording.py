"""Forces recorded (issue 17): linkage-run writes the efforts and the pin and slide loads into the
MCAP (the node's topics, through the one builder) and the rerun view (arrows at the pins, the
effort over time); linkage-view shows the same from the MCAP; a scene without forces is as before."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("mcap", reason="the record extra (mcap) is not installed")
pytest.importorskip("rosbags", reason="the record extra (rosbags) is not installed")

from rosbags.highlevel import AnyReader

import solver
from linkage_ros.record.replay import run_data_from_mcap
from linkage_ros.record.run import RunOptions, RunResult, run_standalone

HAVE_RERUN = importlib.util.find_spec("rerun") is not None
OMEGA, EPSILON, PHI0 = 3.0, 0.5, 0.2
TICKS = 51  # 1 s at 50 Hz
TOL_REL = 1e-12


def run(scene: str, tmp: Path, *, rrd: bool = True) -> tuple[Path, Path | None, RunResult]:
    mcap = tmp / f"{scene}.mcap"
    rrd_path = tmp / f"{scene}.rrd" if rrd and HAVE_RERUN else None
    result = run_standalone(RunOptions(scene=scene, duration=1.0, rate=50.0, omega=OMEGA, epsilon=EPSILON,
                                       phi0=PHI0, mcap=mcap, rrd=rrd_path))
    return mcap, rrd_path, result


@pytest.fixture(scope="module")
def loaded(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path | None, RunResult]:
    return run("four_bar_loaded", tmp_path_factory.mktemp("loaded"))


@pytest.fixture(scope="module")
def engine(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path | None, RunResult]:
    return run("engine", tmp_path_factory.mktemp("engine"), rrd=False)


def read(mcap: Path) -> dict[str, list[Any]]:
    out: dict[str, list[Any]] = {}
    with AnyReader([mcap]) as reader:
        for connection, _, raw in reader.messages():
            out.setdefault(connection.topic, []).append(reader.deserialize(raw, connection.msgtype))
    return out


def solved(scene: str, result: RunResult) -> Any:
    d = result.data
    return solver.load_scene(scene).solve(d.phi, omega=d.omega, epsilon=d.epsilon)


def test_mcap_holds_the_solvers_efforts_and_pin_loads_at_every_tick(loaded: Any) -> None:
    mcap, _, result = loaded
    messages = read(mcap)
    k = solved("four_bar_loaded", result)
    assert result.ticks == TICKS
    states = messages["/joint_states"]
    effort = np.array([dict(zip(m.name, m.effort))["crank"] for m in states])
    np.testing.assert_allclose(effort, k.effort("crank"), rtol=TOL_REL)
    assert all(dict(zip(m.name, m.effort))["crank_joint"] == dict(zip(m.name, m.effort))["crank"] for m in states)
    pins = {"O": ("crank", "ground"), "A": ("coupler", "crank"), "C": ("rocker", "ground"), "B": ("coupler", "rocker")}
    for point, (on, by) in pins.items():
        wrenches = messages[f"/pin_loads/{point}"]
        assert len(wrenches) == TICKS
        force = np.array([(w.wrench.force.x, w.wrench.force.y) for w in wrenches])
        expected = k.reaction(point, on=on, by=by)
        np.testing.assert_allclose(force, expected, rtol=0, atol=TOL_REL * np.abs(expected).max())
    # the rerun arrays are the same numbers
    np.testing.assert_array_equal(result.data.efforts["crank"], effort)
    assert result.data.effort_units == {"crank": "N·m"}


def test_a_slider_gives_its_guide_force_and_couple_on_slide_loads(engine: Any) -> None:
    mcap, _, result = engine
    messages = read(mcap)
    k = solved("engine", result)
    slide = k.slide("piston")
    wrenches = messages["/slide_loads/B"]
    got = np.array([(w.wrench.force.x, w.wrench.force.y, w.wrench.torque.z) for w in wrenches])
    scale = np.abs(slide.force).max()
    np.testing.assert_allclose(got[:, :2], slide.force, rtol=0, atol=TOL_REL * scale)
    np.testing.assert_allclose(got[:, 2], slide.couple, rtol=0, atol=TOL_REL * scale)
    assert {"/pin_loads/O", "/pin_loads/A", "/pin_loads/B"} <= set(messages)
    # the block's pin and its slide stay apart in the run's arrays
    assert {"B", "B_slide"} <= set(result.data.loads) and result.data.load_pins["B_slide"] == ("B", "piston", "ground")
    effort = np.array([dict(zip(m.name, m.effort))["crankshaft"] for m in messages["/joint_states"]])
    np.testing.assert_allclose(effort, k.effort("crankshaft"), rtol=TOL_REL)


def test_replay_from_the_mcap_gives_the_same_forces(loaded: Any) -> None:
    mcap, _, result = loaded
    replayed, _ = run_data_from_mcap(mcap)
    assert set(replayed.loads) == set(result.data.loads)
    for key, values in result.data.loads.items():
        np.testing.assert_array_equal(replayed.loads[key], values)
    np.testing.assert_array_equal(replayed.efforts["crank"], result.data.efforts["crank"])
    assert replayed.load_pins == result.data.load_pins
    assert replayed.effort_units == result.data.effort_units


def test_a_scene_without_forces_records_no_load_topic_and_an_empty_effort(tmp_path: Path) -> None:
    mcap, _, result = run("four_bar", tmp_path, rrd=False)
    messages = read(mcap)
    assert not [t for t in messages if "loads" in t]
    assert all(len(m.effort) == 0 for m in messages["/joint_states"])
    assert result.data.loads == {} and result.data.efforts == {}


@pytest.mark.skipif(not HAVE_RERUN, reason="the view extra (rerun-sdk) is not installed")
def test_rrd_holds_load_arrows_at_the_pins_and_the_effort_series(loaded: Any, tmp_path: Path) -> None:
    from rerun.chunk import RrdReader

    from linkage_ros.cli import view_main

    mcap, rrd, result = loaded
    assert rrd is not None and result.arrow_scales["load"] > 0.0

    def rows(path: Path) -> dict[str, int]:
        out: dict[str, int] = {}
        for chunk in RrdReader(path).stream().to_chunks():
            if not chunk.is_static:
                out[chunk.entity_path] = out.get(chunk.entity_path, 0) + chunk.num_rows
        return out

    got = rows(rrd)
    for key in ("O", "A", "B", "C"):
        assert got[f"/mechanism/loads/{key}"] == TICKS
    assert got["/plots/effort/crank"] == TICKS
    # linkage-view: the same entities from the MCAP
    assert view_main([str(mcap), "-o", str(tmp_path / "view.rrd")]) == 0
    replayed = rows(tmp_path / "view.rrd")
    assert {p: replayed.get(p) for p in got if "loads" in p or "effort" in p} == {
        p: n for p, n in got.items() if "loads" in p or "effort" in p}


@pytest.mark.screenshot
@pytest.mark.skipif(not HAVE_RERUN, reason="the view extra (rerun-sdk) is not installed")
def test_headless_viewer_draws_the_load_arrows_and_the_effort_plot(tmp_path: Path) -> None:
    """The real viewer, rendered headless: magenta load arrows in the mechanism view, and the
    effort series (the crank's colour) in the plots' first column."""
    shots = pytest.importorskip("record.test_screenshot")
    if not shots.LAVAPIPE.exists() or shots.RERUN is None:
        pytest.skip("no software Vulkan driver or rerun viewer (see tests/record/test_screenshot.py)")
    from linkage_ros.record.forces import LOAD_COLOR

    rrd = tmp_path / "loaded.rrd"
    run_standalone(RunOptions(scene="four_bar_loaded", duration=2.0, rate=50.0, omega=OMEGA, rrd=rrd))
    found = 0
    for attempt in range(shots.ATTEMPTS):
        shot = shots.screenshot(rrd, tmp_path / f"shot{attempt}.png")
        h, w, _ = shot.shape
        mechanism = shot[int(0.08 * h): int(0.78 * h), : int(0.45 * w)]
        found = int(shots.near(mechanism, LOAD_COLOR).sum())
        if found > shots.MIN_PIVOT_PIXELS and not shots.problems(shot):
            break
    assert found > shots.MIN_PIVOT_PIXELS, f"{found} load-arrow pixels in the mechanism view"


def test_linkage_run_summary_adds_the_force_lines_read_off_the_ticks(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from linkage_ros.cli import run_main

    assert run_main(["four_bar_loaded", "--omega", "3", "--duration", "1", "--rate", "50",
                     "--mcap", str(tmp_path / "s.mcap"), "--no-rrd"]) == 0
    out = capsys.readouterr().out
    heading = next(line for line in out.splitlines() if line.startswith("forces"))
    assert "each sample exact" in heading and "read off 51 ticks, every 0.02 s" in heading
    assert "  effort crank: peak |Q| = " in out and " N·m" in out
    assert "  input power Σ Q·ω: peak |P| = " in out
    for pin in ("O (crank–ground)", "A (coupler–crank)", "C (rocker–ground)", "B (coupler–rocker)"):
        assert f"  pin {pin}: peak load " in out
    assert "pin loads as R × " not in out  # the arrow scales are printed with a rerun view only


def test_a_recording_without_our_metadata_still_gives_the_loads_by_topic_name(tmp_path: Path) -> None:
    """E.g. ``ros2 bag record`` of a live node: the loads keyed by their topics' names (a
    slide's with ``_slide``), no bodies known, the effort of the input joint kept."""
    from rosbags.typesys import Stores, get_typestore

    from linkage_ros.engine import Engine
    from linkage_ros.messages import MessageBuilder
    from linkage_ros.motion import Motion
    from linkage_ros.record.mcap import Recorder
    from linkage_ros.topics import topic_types

    ts = get_typestore(Stores.ROS2_JAZZY)
    engine = Engine("engine", Motion(phi0=0.2, omega=OMEGA))
    builder = MessageBuilder(engine, ts.types)
    path = tmp_path / "plain.mcap"
    frames = list(engine.frames(np.arange(10) / 50.0))
    with Recorder(path, topic_types(engine), typestore=ts) as rec:  # no linkage_ros record
        for i, frame in enumerate(frames):
            rec.write(i * 20_000_000, builder.build(frame, i * 20_000_000))
    data, _ = run_data_from_mcap(path)
    assert set(data.loads) == {"O", "A", "B", "B_slide"}
    assert data.load_pins["B_slide"] == ("B", "", "")
    np.testing.assert_array_equal(data.loads["B_slide"], [f.loads["B_slide"] for f in frames])
    np.testing.assert_array_equal(data.efforts["crankshaft"], [f.efforts["crankshaft"] for f in frames])
