"""bench/relay.py's pieces: the Gauss–Newton anchor, the 50-digit reference it is judged by, the
JointState bytes both joint_states rows send, and the rows of a quick run."""

from __future__ import annotations

import math

import numpy as np
import pytest

import solver
from bench.relay import (
    DEG,
    DOUBLE_ROCKER,
    FOUR_BAR,
    HARVESTER,
    METHODS,
    NODE_PATH,
    OURS_JOINT_STATES,
    GaussNewton,
    JointStateBytes,
    reference,
    run,
)
from linkage_ros.serialize import pad4

#: The reference rounded to double, against the solver (rad or m; analogs relative to max(|v|, 1)).
TOL = 1e-13


@pytest.mark.parametrize("mech", [FOUR_BAR, HARVESTER, DOUBLE_ROCKER], ids=lambda m: m.scene)
def test_the_bench_reference_agrees_with_the_solver(mech: object) -> None:
    scene = solver.load_scene(mech.scene).everything()  # type: ignore[attr-defined]
    for phi in (0.3, 1.2, -1.0, 1.98):
        (q1, q2), (v1, v2) = reference(mech, phi)  # type: ignore[arg-type]
        k = scene.solve(phi)
        a, b = (k.joint(n) for n in mech.joints)  # type: ignore[attr-defined]
        assert abs(math.remainder(float(a.position) - q1, 2 * math.pi)) <= TOL
        assert abs(float(b.position) - q2) <= TOL or abs(math.remainder(float(b.position) - q2, 2 * math.pi)) <= TOL
        assert abs(float(a.velocity) - v1) <= TOL * max(abs(v1), 1.0)
        assert abs(float(b.velocity) - v2) <= TOL * max(abs(v2), 1.0)


@pytest.mark.parametrize("mech", [FOUR_BAR, HARVESTER], ids=lambda m: m.scene)
def test_warm_started_gauss_newton_follows_small_steps_on_the_scenes_assembly(mech: object) -> None:
    gn = GaussNewton(mech, 0.0)  # type: ignore[arg-type]
    for k in range(1, 361):
        phi = k * DEG
        (q1, q2), _, iterations = gn.solve(phi, 1.0)
        (r1, r2), _ = reference(mech, phi)  # type: ignore[arg-type]
        assert abs(math.remainder(q1 - r1, 2 * math.pi)) <= 1e-12 and iterations < 10
        assert abs(math.remainder(q2 - r2, 2 * math.pi)) <= 1e-12


def test_joint_state_bytes_are_what_rosbags_serialises_padded_to_4() -> None:
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_JAZZY)
    t = store.types
    packer = JointStateBytes(["coupler", "rocker", "crank_joint"], frame_id="world")
    stamp = 1_700_000_123 * 1_000_000_000 + 456_789
    q, dq = (0.1, -2.5, math.pi), (1e-300, -0.0, 7.25)
    msg = t["sensor_msgs/msg/JointState"](
        header=t["std_msgs/msg/Header"](stamp=t["builtin_interfaces/msg/Time"](sec=1_700_000_123, nanosec=456_789),
                                        frame_id="world"),
        name=["coupler", "rocker", "crank_joint"], position=np.array(q), velocity=np.array(dq), effort=np.empty(0),
    )
    data = packer.pack(stamp, q, dq)
    assert data == pad4(store.serialize_cdr(msg, "sensor_msgs/msg/JointState"))
    assert packer.decode(data)["crank_joint"] == (math.pi, 7.25)


def test_quick_bench_gives_three_rows_per_case_and_equal_joint_states_bytes() -> None:
    rows = run(quick=True, repeat=1)
    cases = list(dict.fromkeys(r.case for r in rows))
    assert "hard/double_rocker toggle" in cases
    assert [r.method for r in rows] == [m for _ in cases for m in METHODS]
    ours = [r for r in rows if r.method in (NODE_PATH, OURS_JOINT_STATES)]
    assert all(r.lost == 0 and r.position_error < 1e-9 for r in ours)
    for r in rows:
        assert math.isfinite(r.total_us) and r.total_us == r.solve_us + r.build_us
        if r.method == OURS_JOINT_STATES:  # the node's own joint_states bytes, message for message
            assert f"bytes = the node's in {r.messages}/{r.messages}" in r.note
