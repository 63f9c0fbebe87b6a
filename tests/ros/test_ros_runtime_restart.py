"""A (re)start of the node's run without ROS (issue 30): the first tick after a change of
``phi0`` (or ``scene``, ``mode``, ``dynamics_tolerance``, ``input_phi0s``) is the new run's
t = 0, exactly at ``phi0`` (at rest in dynamic mode with ``omega`` 0), however long the change
took; and a restart on the same scene reuses its compiled instant (no new trace)."""

from __future__ import annotations

import struct
from pathlib import Path

from test_ros_dynamic import pendulum_scene

from linkage_ros.engine import every_output
from linkage_ros.runtime import Runtime
from linkage_ros.serialize import read_joint_state

NS = 1_000_000_000
START_NS = 7 * NS
PERIOD_NS = NS // 1000


def joint(messages: list[tuple[str, bytes]], name: str) -> tuple[float, float]:
    """(position, velocity) of joint ``name`` in the tick's joint_states bytes."""
    data = dict(messages)["joint_states"]
    fields = read_joint_state(data)
    assert fields is not None
    names, positions, velocities, _ = fields
    i = list(names).index(name)
    return positions[i], velocities[i]


def stamp_of(data: bytes) -> int:
    sec, nanosec = struct.unpack_from("<iI", data, 4)
    return sec * NS + nanosec


def test_the_first_tick_after_a_phi0_change_is_at_phi0_whenever_it_comes() -> None:
    rt = Runtime({"scene": "four_bar", "omega": 2.0, "rate_hz": 1000.0})
    for i in range(50):
        rt.tick(START_NS + i * PERIOD_NS)
    now = START_NS + 50 * PERIOD_NS
    assert rt.update({"phi0": 0.7}, now) is None
    late = now + 83 * PERIOD_NS  # the first tick comes 83 ms after the set
    assert joint(rt.tick(late), "crank") == (0.7, 2.0)
    assert rt.run_time(late) == 0.0
    position, _ = joint(rt.tick(late + PERIOD_NS), "crank")
    assert abs(position - (0.7 + 2.0e-3)) < 1e-15


def test_a_dynamic_restart_starts_at_phi0_at_rest(tmp_path: Path) -> None:
    scene = pendulum_scene(tmp_path)
    rt = Runtime({"scene": str(scene), "mode": "dynamic", "phi0": 0.3, "omega": 0.0, "rate_hz": 1000.0})
    assert joint(rt.tick(START_NS), "crank") == (0.3, 0.0)
    for i in range(1, 300):
        rt.tick(START_NS + i * PERIOD_NS)
    moving = joint(rt.tick(START_NS + 300 * PERIOD_NS), "crank")
    assert moving[1] != 0.0  # it fell
    assert rt.update({"phi0": 0.3}, START_NS + 300 * PERIOD_NS) is None
    assert rt.update({"phi0": 0.4}, START_NS + 301 * PERIOD_NS) is None
    assert joint(rt.tick(START_NS + 400 * PERIOD_NS), "crank") == (0.4, 0.0)


def test_a_restart_on_the_same_scene_keeps_its_compiled_instant() -> None:
    rt = Runtime({"scene": "four_bar", "rate_hz": 1000.0})
    scene = rt.engine.scene
    full = every_output(scene)
    assert rt.update({"phi0": 0.5}, START_NS) is None
    assert rt.engine.scene is scene and every_output(rt.engine.scene) is full
    assert rt.update({"scene": "four_bar"}, START_NS) is None  # the same value: nothing reloaded
    assert rt.engine.scene is scene
    assert rt.update({"scene": "four_bar_loaded"}, START_NS) is None
    assert rt.engine.scene is not scene
