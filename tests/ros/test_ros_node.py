"""mechanism_node as its own process, over DDS with the real rclpy (Jazzy wheels, Fast DDS).

The node is the installed console script; the test process subscribes (raw CDR, decoded by
rclpy) and calls the parameter services, on localhost and this session's ROS_DOMAIN_ID
(conftest.py). Node processes are shared per module and ended by PID.
"""

from __future__ import annotations

import json
import math
import signal
import struct
import subprocess
import sys
from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import Client, NodeProcess, decode

import solver
from linkage_ros.messages import topic_types

pytestmark = pytest.mark.dds

NS = 1_000_000_000
ROOT = Path(__file__).resolve().parents[2]
REFERENCE = json.loads((ROOT / "tests" / "data" / "reference_four_bar.json").read_text())
DOUBLE_ROCKER = ROOT / "config" / "scenes" / "hard" / "double_rocker.yaml"
TOL_POS = 1e-12  # m, against the solver and the 50-digit reference
TOL_REL = 1e-9
WAIT_S = 20.0
FOUR_BAR_TOPICS = dict(topic_types(["A", "B"]))
PER_TICK = [t for t in FOUR_BAR_TOPICS if t != "diagnostics"]


def absolute(namespace: str, topics: dict[str, str]) -> dict[str, str]:
    return {f"{namespace.rstrip('/')}/{t}": typename for t, typename in topics.items()}


def stamp(topic: str, data: bytes) -> int:
    """Header stamp (ns) straight from the CDR bytes (a MarkerArray's first marker's header)."""
    sec, nanosec = struct.unpack_from("<iI", data, 8 if topic.endswith("markers") else 4)
    return sec * NS + nanosec


def ticks(messages: list[tuple[str, bytes]]) -> dict[int, dict[str, bytes]]:
    out: dict[int, dict[str, bytes]] = defaultdict(dict)
    for topic, data in messages:
        out[stamp(topic, data)][topic.rsplit("/", 1)[-1] if "/points/" not in topic
                                else topic[topic.index("points/"):]] = data
    return out


def wait_for_ticks(client: Client, listener: Any, topic: str, count: int) -> None:
    start = len(listener.by_topic[topic])
    assert client.spin_until(lambda: len(listener.by_topic[topic]) >= start + count, WAIT_S), (
        f"fewer than {count} messages on {topic}"
    )


# ---------------------------------------------------------------------------------------- N1
@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("n1") / "n1.mcap"


@pytest.fixture(scope="module")
def four_bar(start_node: Any, client: Client, recording: Path) -> Any:
    """/mechanism_node: four_bar, ``omega:=2`` (an integer), 100 Hz, recording; a listener on
    every topic from the start."""
    listener = client.listen(absolute("/", FOUR_BAR_TOPICS))
    process = start_node("-p", "scene:=four_bar", "-p", "omega:=2", "-p", "rate_hz:=100.0",
                         "-p", f"record_mcap:={recording}")
    if not client.spin_until(lambda: len(listener.by_topic["/joint_states"]) >= 3, WAIT_S):
        process.kill()
        pytest.fail("no joint_states from mechanism_node:\n" + process.output())
    return process, listener


def test_every_topic_is_published_with_its_type(four_bar: Any, client: Client) -> None:
    expected = {(t, (typename,)) for t, typename in absolute("/", FOUR_BAR_TOPICS).items()}

    def published() -> set[tuple[str, tuple[str, ...]]]:
        found = client.published_by("mechanism_node", "/")
        return {(name, tuple(types)) for name, types in found}

    assert client.spin_until(lambda: expected <= published(), WAIT_S), published()


def test_all_messages_of_a_tick_carry_one_stamp_and_frame_id(four_bar: Any, client: Client) -> None:
    _, listener = four_bar
    wait_for_ticks(client, listener, "/joint_states", 30)
    by_stamp = ticks(listener.messages)
    complete = [s for s, tick in by_stamp.items() if set(PER_TICK) <= set(tick)]
    assert len(complete) >= 25
    assert all(len(tick) <= len(FOUR_BAR_TOPICS) for tick in by_stamp.values())
    for s in complete[-5:]:
        for topic, data in by_stamp[s].items():
            message = decode(data, FOUR_BAR_TOPICS[topic])
            headers = [m.header for m in message.markers] if topic == "markers" else [message.header]
            for header in headers:
                assert header.stamp.sec * NS + header.stamp.nanosec == s
                assert header.frame_id == "world"
    # each stamp is one tick: ascending, no topic twice
    stamps = [stamp(t, d) for t, d in listener.messages if t == "/joint_states"]
    assert stamps == sorted(set(stamps))


def test_values_equal_the_solver_at_the_published_angle(four_bar: Any, client: Client) -> None:
    _, listener = four_bar
    wait_for_ticks(client, listener, "/joint_states", 10)
    scene = solver.load_scene("four_bar").everything()
    checked = 0
    for tick in list(ticks(listener.messages).values())[-10:]:
        if not set(PER_TICK) <= set(tick):
            continue
        jk = decode(tick["joint_kinematics"], FOUR_BAR_TOPICS["joint_kinematics"])
        i = jk.joint_names.index("crank")
        phi, omega, eps = (jk.points[0].positions[i], jk.points[0].velocities[i], jk.points[0].accelerations[i])
        k = scene.solve(phi, omega=omega, epsilon=eps)
        for point in ("A", "B"):
            p = decode(tick[f"points/{point}/position"], FOUR_BAR_TOPICS[f"points/{point}/position"]).point
            v = decode(tick[f"points/{point}/velocity"], FOUR_BAR_TOPICS[f"points/{point}/velocity"]).vector
            a = decode(tick[f"points/{point}/acceleration"], FOUR_BAR_TOPICS[f"points/{point}/acceleration"]).vector
            expected = k.point(point)
            np.testing.assert_allclose([p.x, p.y], expected.position, rtol=0, atol=TOL_POS)
            np.testing.assert_allclose([v.x, v.y], expected.velocity, rtol=0, atol=TOL_POS * abs(omega))
            np.testing.assert_allclose([a.x, a.y], expected.acceleration, rtol=0, atol=TOL_POS * (omega**2 + abs(eps)))
            assert p.z == v.z == a.z == 0.0
        js = decode(tick["joint_states"], FOUR_BAR_TOPICS["joint_states"])
        for name in ("coupler", "rocker"):
            assert js.position[js.name.index(name)] == pytest.approx(k.joint(name).position, abs=TOL_POS)
        checked += 1
    assert checked >= 5


def test_an_integer_start_value_for_a_double_is_taken_as_a_double(four_bar: Any, client: Client) -> None:
    from rcl_interfaces.msg import ParameterType

    (omega,) = client.get_parameters("/mechanism_node", "omega")
    assert omega[0] == ParameterType.PARAMETER_DOUBLE
    _, listener = four_bar
    first = decode(listener.by_topic["/joint_states"][0], FOUR_BAR_TOPICS["joint_states"])
    if omega[1] == 2.0:  # not changed yet by another test
        assert first.velocity[first.name.index("crank")] == 2.0


def test_parameters_are_accepted_and_rejected_with_a_reason_while_publishing(four_bar: Any, client: Client) -> None:
    _, listener = four_bar
    (ok,) = client.set_parameters("/mechanism_node", omega=-1.5)
    assert ok.successful, ok.reason
    (as_int,) = client.set_parameters("/mechanism_node", epsilon=0)  # an integer for a double
    assert as_int.successful, as_int.reason
    (bad,) = client.set_parameters("/mechanism_node", rate_hz=-1.0)
    assert not bad.successful and "rate_hz" in bad.reason
    (missing,) = client.set_parameters("/mechanism_node", record_mcap="/no/such/folder/x.mcap")
    assert not missing.successful and "does not exist" in missing.reason
    (unknown,) = client.set_parameters("/mechanism_node", scene="no_such_mechanism")
    assert not unknown.successful and "unknown scene 'no_such_mechanism'" in unknown.reason
    assert [v for _, v in client.get_parameters("/mechanism_node", "omega", "epsilon", "rate_hz")] == [-1.5, 0.0, 100.0]
    wait_for_ticks(client, listener, "/joint_states", 20)  # still publishing
    assert client.spin_until_latest(listener, "/joint_states", FOUR_BAR_TOPICS["joint_states"],
                                    lambda js: js.velocity[js.name.index("crank")] == -1.5, WAIT_S)
    (back,) = client.set_parameters("/mechanism_node", omega=2.0)
    assert back.successful


def test_a_new_rate_takes_effect_at_run_time(four_bar: Any, client: Client) -> None:
    _, listener = four_bar
    (ok,) = client.set_parameters("/mechanism_node", rate_hz=50)  # an integer, taken as 50.0
    assert ok.successful, ok.reason

    def at_50_hz() -> bool:  # the messages of the old rate still in flight are read first
        last = [stamp("/joint_states", d) for d in listener.by_topic["/joint_states"][-4:]]
        return len(last) == 4 and min(np.diff(last)) > 0.75 * NS / 50

    assert client.spin_until(at_50_hz, WAIT_S)
    start = len(listener.by_topic["/joint_states"])
    wait_for_ticks(client, listener, "/joint_states", 15)
    stamps = [stamp("/joint_states", d) for d in listener.by_topic["/joint_states"][start:]]
    assert float(np.median(np.diff(stamps))) == pytest.approx(NS / 50, rel=0.1)
    (ok,) = client.set_parameters("/mechanism_node", rate_hz=100.0)
    assert ok.successful, ok.reason


def test_diagnostics_come_about_once_a_second(four_bar: Any, client: Client) -> None:
    _, listener = four_bar
    wait_for_ticks(client, listener, "/joint_states", 150)
    stamps = [stamp("/joint_states", d) for d in listener.by_topic["/joint_states"]]
    seconds = (stamps[-1] - stamps[0]) / NS
    diagnostics = listener.by_topic["/diagnostics"]
    assert 0 < len(diagnostics) <= seconds + 2
    status = decode(diagnostics[-1], FOUR_BAR_TOPICS["diagnostics"]).status[0]
    assert status.name == "linkage_ros: four_bar" and status.message == "ok"


def test_linkage_echo_prints_what_the_node_publishes(four_bar: Any) -> None:
    echo = subprocess.run(
        [str(Path(sys.prefix) / "bin" / "linkage-echo"), "joint_states", "--count", "2", "--timeout", "10"],
        capture_output=True, text=True, timeout=60,
    )
    assert echo.returncode == 0, echo.stderr
    assert echo.stdout.count("---") == 2 and "name: ['crank', 'coupler', 'rocker'" in echo.stdout, echo.stdout
    missing = subprocess.run(
        [str(Path(sys.prefix) / "bin" / "linkage-echo"), "no_such_topic", "--timeout", "1"],
        capture_output=True, text=True, timeout=60,
    )
    assert missing.returncode == 1 and "no publisher of /no_such_topic" in missing.stderr


def test_sigint_finishes_the_recording_with_whole_ticks_equal_to_the_wire(
    four_bar: Any, client: Client, recording: Path, tmp_path: Path
) -> None:
    from rosbags.highlevel import AnyReader

    from linkage_ros.record.mcap import read_mcap
    from linkage_ros.record.replay import run_data_from_mcap

    process, listener = four_bar
    wait_for_ticks(client, listener, "/joint_states", 20)
    assert process.stop(signal.SIGINT) == 0
    output = process.output()
    assert "Traceback" not in output and "RCLError" not in output, output
    client.spin_for(0.3)
    contents = read_mcap(recording)
    assert contents.complete  # finished: footer written
    recorded: dict[tuple[str, int], bytes] = {(m.topic, m.log_time): m.data for m in contents.messages}
    stamps_by_topic: dict[str, set[int]] = defaultdict(set)
    for topic, s in recorded:
        stamps_by_topic[topic].add(s)
    per_tick = [stamps_by_topic[t] for t in absolute("/", {t: "" for t in PER_TICK})]
    assert all(s == per_tick[0] for s in per_tick) and len(per_tick[0]) >= 20  # whole ticks only
    # every message that went over the wire is in the file, byte for byte
    for topic, data in listener.messages:
        assert recorded[topic, stamp(topic, data)] == data, topic
    # rosbags' AnyReader decodes every message
    counts: dict[str, int] = defaultdict(int)
    with AnyReader([recording]) as reader:
        for connection, _, raw in reader.messages():
            reader.deserialize(raw, connection.msgtype)
            counts[connection.topic] += 1
    assert counts["/joint_states"] == len(per_tick[0])
    # linkage-view reads it, with the names of the metadata record on what the markers draw
    data, _ = run_data_from_mcap(recording)
    assert data.scene == "four_bar" and {"A", "B"} <= set(data.positions)
    assert {name for name, _ in data.links} and set(data.fixed) == {"O", "C"}
    view = subprocess.run(
        [str(Path(sys.prefix) / "bin" / "linkage-view"), str(recording), "-o", str(tmp_path / "n1.rrd")],
        capture_output=True, text=True, timeout=120,
    )
    assert view.returncode == 0, view.stdout + view.stderr
    assert (tmp_path / "n1.rrd").stat().st_size > 0


# ---------------------------------------------------------------------------------------- sim time
def test_sim_time_from_a_clock_publisher_drives_phi_on_the_50_digit_reference(start_node: Any, client: Client) -> None:
    """use_sim_time: stamps are the /clock times; with ω = the reference grid's step and 1 s
    clock steps, tick n is at the grid's φ_n, where B is compared with the 50-digit values."""
    from builtin_interfaces.msg import Time
    from rosgraph_msgs.msg import Clock

    step = float(REFERENCE["phi"][1])
    names = ("joint_states", "points/B/position", "points/B/velocity")
    topics = absolute("/sim", {t: FOUR_BAR_TOPICS[t] for t in names})
    listener = client.listen(topics)
    process = start_node("-r", "__ns:=/sim", "-p", "use_sim_time:=true", "-p", "scene:=four_bar",
                         "-p", f"omega:={step!r}", "-p", "rate_hz:=100.0")
    clock = client.node.create_publisher(Clock, "/clock", 10)
    try:
        t0 = 1_000 * NS
        length = float(REFERENCE["scale_length"])
        for n in range(6):
            now = t0 + n * NS

            def answered(now: int = now, topic: str = "/sim/points/B/velocity") -> bool:
                return any(stamp(topic, d) == now for d in listener.by_topic[topic])

            def tick(now: int = now) -> bool:
                clock.publish(Clock(clock=Time(sec=now // NS, nanosec=now % NS)))
                return client.spin_until(answered, 0.3)

            assert any(tick() for _ in range(60)), f"no tick at clock {now}:\n" + process.output()
            client.spin_for(0.05)
            got = {t.rsplit("/sim/", 1)[1]: next(d for d in listener.by_topic[t] if stamp(t, d) == now) for t in topics}
            js = decode(got["joint_states"], FOUR_BAR_TOPICS["joint_states"])
            phi = js.position[js.name.index("crank")]
            assert phi == pytest.approx(float(REFERENCE["phi"][n]), abs=1e-15)
            b = decode(got["points/B/position"], FOUR_BAR_TOPICS["points/B/position"]).point
            ref_b = [float(x) for x in REFERENCE["points"]["B"]["position"][n]]
            np.testing.assert_allclose([b.x, b.y], ref_b, rtol=0, atol=TOL_POS)
            v = decode(got["points/B/velocity"], FOUR_BAR_TOPICS["points/B/velocity"]).vector
            ref_v = np.array([float(x) for x in REFERENCE["points"]["B"]["d_dphi"][n]]) * step
            scale = max(np.abs(ref_v).max(), length * step)
            np.testing.assert_allclose([v.x, v.y], ref_v, rtol=0, atol=TOL_REL * scale)
    finally:
        client.node.destroy_publisher(clock)
        assert process.stop(signal.SIGTERM) == 0


# ---------------------------------------------------------------------------------------- unassemblable
def test_unassemblable_stops_then_reverses_and_never_publishes_non_finite(start_node: Any, client: Client) -> None:
    topics = absolute("/rock", {t: FOUR_BAR_TOPICS[t] for t in ("joint_states", "diagnostics")})
    listener = client.listen(topics)
    process = start_node("-r", "__ns:=/rock", "-p", f"scene:={DOUBLE_ROCKER}", "-p", "omega:=5.0",
                         "-p", "rate_hz:=100.0")
    try:
        def error_seen(text: str) -> bool:
            return any(
                s.level == b"\x02" and text in s.message
                for d in listener.by_topic["/rock/diagnostics"]
                for s in decode(d, FOUR_BAR_TOPICS["diagnostics"]).status
            )

        assert client.spin_until(lambda: error_seen("stopped"), WAIT_S), process.output()
        assert error_seen("cannot be assembled for φ in (113.9")
        wait_for_ticks(client, listener, "/rock/joint_states", 10)

        def held() -> bool:  # the moving ticks still in flight on a loaded machine are read first
            last = [decode(d, FOUR_BAR_TOPICS["joint_states"]) for d in listener.by_topic["/rock/joint_states"][-5:]]
            return len({m.position[0] for m in last}) == 1 and all(v == 0.0 for m in last for v in m.velocity)

        assert client.spin_until(held, WAIT_S)
        # an accepted set resumes the held input (docs/ros.md): into the gap again, reversed there
        (ok,) = client.set_parameters("/rock/mechanism_node", on_unassemblable="reverse")
        assert ok.successful
        assert client.spin_until(lambda: error_seen("reversed"), WAIT_S), process.output()
        wait_for_ticks(client, listener, "/rock/joint_states", 10)
        assert client.spin_until_latest(listener, "/rock/joint_states", FOUR_BAR_TOPICS["joint_states"],
                                        lambda js: abs(js.velocity[0]) == pytest.approx(5.0), WAIT_S)
        for data in listener.by_topic["/rock/joint_states"]:
            message = decode(data, FOUR_BAR_TOPICS["joint_states"])
            assert all(math.isfinite(x) for x in [*message.position, *message.velocity])
    finally:
        assert process.stop(signal.SIGTERM) == 0


# ---------------------------------------------------------------------------------------- signals
def test_sigterm_at_1khz_exits_0_with_a_finished_recording_of_whole_ticks(
    start_node: Any, client: Client, tmp_path: Path
) -> None:
    from mcap.reader import make_reader

    target = tmp_path / "term.mcap"
    listener = client.listen(absolute("/term", {"joint_states": FOUR_BAR_TOPICS["joint_states"]}))
    process: NodeProcess = start_node("-r", "__ns:=/term", "-p", "scene:=four_bar", "-p", "rate_hz:=1000.0",
                                      "-p", f"record_mcap:={target}")
    try:
        assert client.spin_until(lambda: len(listener.by_topic["/term/joint_states"]) >= 200, WAIT_S), process.output()
    finally:
        code = process.stop(signal.SIGTERM)
    output = process.output()
    assert code == 0 and "Traceback" not in output and "RCLError" not in output, output
    with open(target, "rb") as fh:
        reader = make_reader(fh)
        summary = reader.get_summary()
        assert summary is not None and summary.statistics is not None
        counts = {summary.channels[c].topic: n for c, n in summary.statistics.channel_message_counts.items()}
        stamps: dict[str, set[int]] = defaultdict(set)
        for _, channel, message in reader.iter_messages():
            stamps[channel.topic].add(message.log_time)
    per_tick = [stamps[f"/term/{t}"] for t in PER_TICK]
    assert all(s == per_tick[0] for s in per_tick), {t: counts.get(f"/term/{t}") for t in PER_TICK}
    assert len(per_tick[0]) >= 200


def test_the_single_threaded_executor_still_runs_the_node(start_node: Any, client: Client) -> None:
    import os

    listener = client.listen(absolute("/single", {"joint_states": FOUR_BAR_TOPICS["joint_states"]}))
    process = start_node("-r", "__ns:=/single", "-p", "scene:=four_bar",
                         env={**os.environ, "LINKAGE_ROS_EXECUTOR": "single"})
    try:
        assert client.spin_until(lambda: len(listener.by_topic["/single/joint_states"]) >= 5, WAIT_S), process.output()
        (ok,) = client.set_parameters("/single/mechanism_node", omega=3.0)
        assert ok.successful
    finally:
        assert process.stop(signal.SIGINT) == 0


# ---------------------------------------------------------------------------------------- start errors
@pytest.mark.parametrize(
    ("args", "reason"),
    [
        (("-p", "rate_hz:=0.0"), "cannot start: rate_hz must be > 0"),
        (("-p", "scene:=no_such_mechanism"), "cannot start: unknown scene 'no_such_mechanism'"),
        (("-p", "record_mcap:=/no/such/folder/run.mcap"), "does not exist"),
        (("-p", "omega:=fast"), "cannot start: omega must be a finite number"),
        (("-p",), "cannot start: failed to initialize rcl"),
    ],
)
def test_unusable_start_values_give_one_line_and_exit_1(start_node: Any, args: tuple[str, ...], reason: str) -> None:
    expect_one_line_and_exit_1(start_node("-r", "__ns:=/bad", *args), reason)


def test_an_unknown_executor_is_refused_with_one_line(start_node: Any) -> None:
    import os

    process = start_node("-r", "__ns:=/bad", env={**os.environ, "LINKAGE_ROS_EXECUTOR": "fast"})
    expect_one_line_and_exit_1(process, "cannot start: LINKAGE_ROS_EXECUTOR must be one of events, single")


def expect_one_line_and_exit_1(process: NodeProcess, reason: str) -> None:
    code = process.wait()
    output = process.output()
    assert code == 1, output
    lines = [line for line in output.splitlines() if "cannot start:" in line]
    assert len(lines) == 1 and reason in lines[0], output
    assert "Traceback" not in output
