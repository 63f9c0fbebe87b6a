"""bench/node_floor.py's pieces, untimed: the floor sends the node's own bytes (its joint_states
stamped per tick), the delivered count takes only the ticks of the window, and a short run of
both processes over DDS gives a figure per process, executor and round."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
from rosbags.typesys import Stores, get_typestore

from bench.node_floor import NS, T0, Counter, delivered, floor_messages, stamped, summary
from linkage_ros.runtime import Runtime

STORE = get_typestore(Stores.ROS2_JAZZY)
ROOT = Path(__file__).resolve().parents[2]


def test_the_floor_publishes_the_nodes_bytes_on_the_nodes_topics() -> None:
    once_a_second, every_tick = floor_messages("four_bar", 1000.0)
    runtime = Runtime({"scene": "four_bar", "rate_hz": 1000.0})
    assert once_a_second == runtime.tick(T0) and every_tick == runtime.tick(T0 + NS // 1000)
    assert [t for t, _ in once_a_second] == [t for t, _ in runtime.topics]  # paths and diagnostics
    assert [t for t, _ in every_tick] == [t for t, _ in runtime.topics if t != "diagnostics"]


def test_a_stamped_joint_state_carries_the_stamp_and_nothing_else_changes() -> None:
    _, every_tick = floor_messages("four_bar", 1000.0)
    data = dict(every_tick)["joint_states"]
    again = stamped(data, 1_800_000_000 * NS + 123)
    js: Any = STORE.deserialize_cdr(again, "sensor_msgs/msg/JointState")
    assert (js.header.stamp.sec, js.header.stamp.nanosec) == (1_800_000_000, 123)
    assert len(again) == len(data) and again[12:] == data[12:]
    counter = Counter()
    counter(again)  # inactive: not counted
    counter.active = True
    counter(again)
    assert counter.stamps == [1_800_000_000 * NS + 123]


def test_delivered_counts_distinct_ticks_stamped_inside_the_window() -> None:
    start, stop = 10 * NS, 12 * NS  # 2 s at 1 kHz: 2000 ticks
    ticks = [start + k * 1_000_000 for k in range(2000)]
    backlog = [start - k * 1_000_000 for k in range(1, 500)]  # older ticks arriving late
    assert delivered(ticks + backlog + ticks[:10], start, stop, 1000.0) == 1.0
    assert delivered(ticks[::2], start, stop, 1000.0) == pytest.approx(0.5)
    assert delivered(backlog, start, stop, 1000.0) == 0.0


def test_the_summary_gives_median_and_range_per_executor_and_a_verdict() -> None:
    def r(cpu: float, ok: float) -> dict[str, float]:
        return {"cpu": cpu, "delivered": ok, "received": 1.0, "window_s": 1.0}

    lines = summary({"events": [{"node": r(0.22, 0.999), "floor": r(0.20, 1.0)},
                                {"node": r(0.30, 0.995), "floor": r(0.20, 1.0)}]})
    assert lines[0].startswith("events: node CPU 26.0 [22.0–30.0] %, floor CPU 20.0 [20.0–20.0] %")
    assert "node/floor 1.30 [1.10–1.50]" in lines[0] and "node ≥ 99.50 %" in lines[0]
    assert lines[1].startswith("RESULT events FAIL: node/floor CPU median 1.30")


@pytest.mark.dds
def test_a_short_run_measures_node_and_floor_with_both_executors() -> None:
    env = {**os.environ, "LINKAGE_ROS_DOMAIN_ID": os.environ.get("LINKAGE_ROS_DOMAIN_ID", str(1 + os.getpid() % 100))}
    done = subprocess.run([sys.executable, "-m", "bench.node_floor", "--seconds", "1", "--warmup", "2",
                           "--rate", "200", "--rounds", "1"], cwd=ROOT, env=env, capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    for kind in ("events", "single"):
        rounds = [line for line in lines if line.strip().startswith(f"{kind} round 1")]
        assert [line.split()[3] for line in rounds] == ["node", "floor"]
        assert all("delivered" in line and " 0 joint_states" not in line for line in rounds)
        assert any(line.startswith(f"RESULT {kind} ") for line in lines)
