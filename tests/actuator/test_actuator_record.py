"""An actuator scene recorded and viewed: the cylinder drawn as barrel and rod, the input plotted
as a stroke (m), the node's path (engine frames) in metres."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("mcap", reason="the record extra (mcap) is not installed")
pytest.importorskip("rerun", reason="the view extra (rerun-sdk) is not installed")

from rerun.chunk import RrdReader

from linkage_ros.record.rerun import cylinder_strips, plot_columns
from linkage_ros.record.run import RunOptions, run_standalone


def test_a_tipper_run_draws_its_cylinder_as_barrel_and_rod(tmp_path: Path) -> None:
    rrd = tmp_path / "tipper.rrd"
    result = run_standalone(RunOptions(scene="tipper", duration=1.0, rate=20.0, omega=0.2, epsilon=0.0, phi0=0.8,
                                       mcap=tmp_path / "tipper.mcap", rrd=rrd))
    data = result.data
    assert data.cylinders == [("lift", "A", "C", 0.74)]
    np.testing.assert_allclose(data.phi, 0.8 + 0.2 * data.t, rtol=0, atol=1e-15)  # the stroke, m
    (_, _, barrel, wide), (_, _, rod, thin) = cylinder_strips(data)
    a, c = data.fixed["A"], data.positions["C"]
    np.testing.assert_allclose(barrel[:, 0], np.broadcast_to(a, barrel[:, 0].shape))
    np.testing.assert_allclose(rod[:, 1], c)
    np.testing.assert_allclose(np.linalg.norm(barrel[:, 1] - barrel[:, 0], axis=1), 0.74)
    np.testing.assert_allclose(np.linalg.norm(rod[:, 1] - rod[:, 0], axis=1), 0.74)
    assert wide > thin
    paths = {chunk.entity_path for chunk in RrdReader(rrd).stream().to_chunks()}
    assert {"/mechanism/links/lift/barrel", "/mechanism/links/lift/rod", "/mechanism/links/lift.1"} <= paths
    assert "/mechanism/links/lift.0" not in paths  # the cylinder's line is its barrel and rod
    titles = [title for title, _ in plot_columns(data)[0]]
    assert titles == ["input s (m)", "input ṡ (m/s)", "input s̈ (m/s²)"]


def test_the_view_replayed_from_the_mcap_draws_the_cylinder_too(tmp_path: Path) -> None:
    from linkage_ros.record.replay import run_data_from_mcap

    mcap = tmp_path / "tipper.mcap"
    result = run_standalone(RunOptions(scene="tipper", duration=0.5, rate=20.0, omega=0.2, epsilon=0.0, phi0=0.8,
                                       mcap=mcap, rrd=None))
    replayed, _ = run_data_from_mcap(mcap)
    assert replayed.cylinders == result.data.cylinders == [("lift", "A", "C", 0.74)]
    np.testing.assert_array_equal(cylinder_strips(replayed)[1][2], cylinder_strips(result.data)[1][2])
