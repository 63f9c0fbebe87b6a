"""linkage-run, its MCAP and rerun recordings and linkage-view for a scene with several inputs
(the five-bar, issue 14): per-input motion laws on the command line, every recorded point equal
to the solver at that stamp's (q1, q2), one plotted series per input, one-line errors."""

from __future__ import annotations

import contextlib
import io
import math
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("mcap", reason="the record extra (mcap) is not installed")
pytest.importorskip("rosbags", reason="the record extra (rosbags) is not installed")
pytest.importorskip("rerun", reason="the view extra (rerun-sdk, needs numpy >= 2) is not installed")

from rerun.chunk import RrdReader
from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_typestore

import solver
from linkage_ros.cli import run_main, view_main
from linkage_ros.motion import Motions
from linkage_ros.record.replay import run_data_from_mcap

RATE = 50.0
DURATION = 1.0
PHI0, OMEGA, EPSILON = (1.5, 1.2), (2.0, -1.5), (0.7, 0.0)
LAWS = ["--phi0", "q1=1.5", "--phi0", "q2=1.2", "--omega", "q1=2", "--omega", "q2=-1.5",
        "--epsilon", "q1=0.7"]
POSITION_TOL = 1e-12  # m: the recorded P is the solver's own number, bit for bit in practice
RELATIVE_TOL = 1e-12  # velocities and accelerations, relative to their largest value


@pytest.fixture(scope="module")
def five_bar_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path, str]:
    tmp = tmp_path_factory.mktemp("five_bar_run")
    mcap, rrd = tmp / "five_bar.mcap", tmp / "five_bar.rrd"
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = run_main(["five_bar", *LAWS, "--duration", str(DURATION), "--rate", str(RATE),
                         "--mcap", str(mcap), "--rrd", str(rrd)])
    assert code == 0, out.getvalue()
    return mcap, rrd, out.getvalue()


def _messages(mcap: Path) -> dict[str, list[tuple[int, object]]]:
    out: dict[str, list[tuple[int, object]]] = {}
    with AnyReader([mcap], default_typestore=get_typestore(Stores.ROS2_JAZZY)) as reader:
        for conn, stamp, raw in reader.messages():
            out.setdefault(conn.topic, []).append((stamp, reader.deserialize(raw, conn.msgtype)))
    return out


def _entities(path: Path) -> dict[str, tuple[bool, int]]:
    out: dict[str, tuple[bool, int]] = {}
    for chunk in RrdReader(path).stream().to_chunks():
        static, rows = out.get(chunk.entity_path, (False, 0))
        out[chunk.entity_path] = (static or chunk.is_static, rows + (0 if chunk.is_static else chunk.num_rows))
    return out


def test_the_header_states_each_inputs_law(five_bar_run: tuple[Path, Path, str]) -> None:
    first = five_bar_run[2].splitlines()[0]
    assert "2 inputs: 'q1' from φ0 = 85.9437°, ω = 2 rad/s, ε = 0.7 rad/s²; 'q2' from φ0 = 68.7549°, " \
           "ω = -1.5 rad/s, ε = 0 rad/s²" in first
    assert "(51 ticks)" in first and "point P" in five_bar_run[2]


def test_every_recorded_point_is_the_solver_at_the_inputs_of_its_stamp(
        five_bar_run: tuple[Path, Path, str]) -> None:
    messages = _messages(five_bar_run[0])
    stamps = np.array([s for s, _ in messages["/points/P/position"]])
    assert stamps.size == int(DURATION * RATE) + 1
    t = stamps / 1e9
    q, w, e = Motions.of(2, phi0=PHI0, omega=OMEGA, epsilon=EPSILON).states(t)
    expected = solver.load_scene("five_bar").solve(q, omega=w, epsilon=e).point("P")
    recorded = {kind: np.array([[getattr(getattr(m, field), c) for c in "xy"]
                                for _, m in messages[f"/points/P/{kind}"]])
                for kind, field in (("position", "point"), ("velocity", "vector"), ("acceleration", "vector"))}
    np.testing.assert_allclose(recorded["position"], expected.position, rtol=0, atol=POSITION_TOL)
    for kind in ("velocity", "acceleration"):
        want = getattr(expected, kind)
        np.testing.assert_allclose(recorded[kind], want, rtol=0, atol=RELATIVE_TOL * np.abs(want).max())
    # joint_states carries both input joints at their law's angle
    names = list(messages["/joint_states"][0][1].name)  # type: ignore[attr-defined]
    assert {"q1", "q2"} <= set(names)
    got = np.array([[m.position[names.index(j)] for j in ("q1", "q2")]  # type: ignore[attr-defined]
                    for _, m in messages["/joint_states"]])
    np.testing.assert_allclose(got, q, rtol=0, atol=1e-15)


def test_diagnostics_carry_each_inputs_phi_omega_epsilon(five_bar_run: tuple[Path, Path, str]) -> None:
    messages = _messages(five_bar_run[0])
    stamp, last = messages["/diagnostics"][-1]
    values = {kv.key: kv.value for st in last.status for kv in st.values}  # type: ignore[attr-defined]
    q, w, e = Motions.of(2, phi0=PHI0, omega=OMEGA, epsilon=EPSILON).state(stamp / 1e9)
    for key, row in (("phi", q), ("omega", w), ("epsilon", e)):
        assert [float(values[f"{key}/{name}"]) for name in ("q1", "q2")] == list(row)
        assert key not in values


def test_the_rerun_view_has_one_series_per_input(five_bar_run: tuple[Path, Path, str]) -> None:
    _, rrd, _ = five_bar_run
    got = _entities(rrd)
    ticks = int(DURATION * RATE) + 1
    for kind in ("phi", "omega", "epsilon"):
        for q in ("q1", "q2"):
            assert got[f"/plots/input/{kind}/{q}"][1] == ticks, kind + q
        assert f"/plots/input/{kind}" not in got
    assert got["/mechanism/points"][1] == ticks and "/mechanism/paths/P" in got
    # the planar drawing is mirrored y up by a static transform on each drawn child (docs/recording.md)
    assert all(got[f"/mechanism/{child}"][0] for child in ("links", "points", "fixed", "paths"))
    assert len(RrdReader(rrd).blueprints()) == 1


def test_linkage_view_of_the_mcap_gives_the_same_run(
        five_bar_run: tuple[Path, Path, str], tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    mcap, rrd, _ = five_bar_run
    data, contents = run_data_from_mcap(mcap)
    assert contents.complete and data.inputs == ("q1", "q2") and data.phi.shape == (data.n, 2)
    q, w, e = Motions.of(2, phi0=PHI0, omega=OMEGA, epsilon=EPSILON).states(data.t)
    np.testing.assert_array_equal(data.phi, q)
    np.testing.assert_array_equal(data.omega, w)
    np.testing.assert_array_equal(data.epsilon, e)
    out = tmp_path / "view.rrd"
    assert view_main([str(mcap), "-o", str(out)]) == 0
    assert "finished" in capsys.readouterr().out
    assert set(_entities(out)) == set(_entities(rrd))


def test_a_node_recording_of_the_five_bar_replays_from_the_input_joints(tmp_path: Path) -> None:
    """The node sends diagnostics now and then, not every tick: φ, ω, ε come from the input joints."""
    pytest.importorskip("rclpy", reason="linkage_ros.node needs rclpy")
    from linkage_ros.node import mcap_recorder
    from linkage_ros.runtime import Runtime

    store = get_typestore(Stores.ROS2_JAZZY)
    path = tmp_path / "node.mcap"
    runtime = Runtime({"scene": "five_bar", "input_omegas": [2.0, -1.5], "input_phi0s": [1.5, 1.2],
                       "rate_hz": 100.0, "record_mcap": str(path)},
                      store.types, serialize=store.serialize_cdr, recorder_factory=mcap_recorder("/"))
    t0 = 1_700_000_000 * 1_000_000_000
    for i in range(30):
        runtime.tick(t0 + i * 10_000_000)
    runtime.close()
    data, _ = run_data_from_mcap(path)
    assert data.n == 30 and data.inputs == ("q1", "q2")
    np.testing.assert_array_equal(data.phi, np.stack([data.joints["q1"][0], data.joints["q2"][0]], axis=1))
    np.testing.assert_allclose(data.omega, np.tile([2.0, -1.5], (30, 1)), rtol=0, atol=1e-15)
    assert view_main([str(path), "-o", str(tmp_path / "node.rrd")]) == 0
    assert _entities(tmp_path / "node.rrd")["/plots/input/omega/q2"][1] == 30


def test_a_plain_value_applies_to_every_input_and_cycles_follow_the_fastest(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(tmp_path)
    assert run_main(["five_bar", "--phi0", "1.2", "--omega", "2", "--omega", "q2=-4", "--rate", "20",
                     "--no-rrd", "--mcap", "run.mcap"]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first.startswith(f"scene five_bar: {2 * math.pi / 4:g} s of simulated time")  # one turn of q2
    assert "'q1' from φ0 = 68.7549°, ω = 2 rad/s" in first and "'q2' from φ0 = 68.7549°, ω = -4 rad/s" in first
    data, _ = run_data_from_mcap(tmp_path / "run.mcap")
    np.testing.assert_array_equal(data.omega[0], [2.0, -4.0])
    assert data.inputs == ("q1", "q2")


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--omega", "q3=2"], "--omega 'q3=2': give INPUT=VALUE with INPUT one of q1, q2"),
        (["--epsilon", "=1"], "--epsilon '=1': give INPUT=VALUE with INPUT one of q1, q2"),
        (["--phi0", "q1=abc"], "--phi0 'q1=abc': 'abc' is not a number"),
        (["--omega", "q2=1e7"], "--omega 'q2=1e7': |1e7| is beyond 1e+06"),
        (["--omega", "q1=nan"], "'nan' is not a finite number"),
        (["--omega", "abc"], "argument --omega: 'abc' is not a number"),
        (["--omega", "0"], "with ω = 0 and ε = 0 for every input (q1, q2) no input turns, so the default "
                           "one turn never ends: give --duration"),
    ],
)
def test_bad_per_input_options_are_one_line_and_exit_2(
        args: list[str], message: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
        capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(tmp_path)
    try:
        code = run_main(["five_bar", *args])
    except SystemExit as stop:  # argparse's own exit
        code = int(stop.code or 0)
    assert code == 2
    captured = capsys.readouterr()
    assert captured.out == "" and len(captured.err.strip().splitlines()) == 1, captured.err
    assert message in captured.err
    assert list(tmp_path.iterdir()) == []


def test_a_single_input_scene_takes_its_input_by_name_too(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(tmp_path)
    assert run_main(["four_bar", "--omega", "crank=3", "--duration", "0.05", "--no-mcap", "--no-rrd"]) == 0
    assert "input 'crank' from φ0 = 0°; ω = 3 rad/s" in capsys.readouterr().out.splitlines()[0]
    assert run_main(["four_bar", "--omega", "q1=3", "--no-mcap", "--no-rrd"]) == 2
    assert "--omega 'q1=3': give INPUT=VALUE with INPUT one of crank" in capsys.readouterr().err
