"""Starts run on a Dask cluster give the same designs as one local process (seeded)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import solver
from solver.synthesis import load_template

distributed = pytest.importorskip("distributed")

HERE = Path(__file__).parent / "templates"


def test_local_cluster_same_result() -> None:
    t = load_template(HERE / "six_bar_path.yaml")
    phi = np.array([0.3, 1.5, 2.9, 4.4, 5.5])
    targets = t.scene([0.65, 0.1, 0.2, -60.0, 0.35, 0.3]).solve(phi).point("E").position
    local = solver.synthesize(t, point="E", through=targets, seed=3, starts=3)
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None)
    with cluster, distributed.Client(cluster) as client:
        remote = solver.synthesize(t, point="E", through=targets, seed=3, starts=3, workers=client)
    assert remote.values == local.values
    np.testing.assert_array_equal(remote.phases, local.phases)
    assert [d.values for d in remote.solutions] == [d.values for d in local.solutions]
    assert remote.exact
