"""Starts run on a Dask cluster, or on local processes, give the same designs as one process (seeded)."""

from __future__ import annotations

import multiprocessing
from pathlib import Path

import numpy as np
import pytest

import solver
from solver.synthesis import load_template

HERE = Path(__file__).parent / "templates"


def test_local_cluster_same_result() -> None:
    distributed = pytest.importorskip("distributed")
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


def test_local_processes_same_result() -> None:
    """``workers=2``: two starts at once on two local processes, read in start order: the same
    designs as one process (the starts are seeded by their index)."""
    t = load_template(HERE / "six_bar_path.yaml")
    phi = np.array([0.3, 1.5, 2.9, 4.4, 5.5])
    targets = t.scene([0.65, 0.1, 0.2, -60.0, 0.35, 0.3]).solve(phi).point("E").position
    local = solver.synthesize(t, point="E", through=targets, seed=3, starts=3)
    pool = solver.synthesize(t, point="E", through=targets, seed=3, starts=3, workers=2)
    assert pool.values == local.values and pool.starts == local.starts
    np.testing.assert_array_equal(pool.phases, local.phases)
    assert [d.values for d in pool.solutions] == [d.values for d in local.solutions]
    assert multiprocessing.active_children() == []  # the pool's processes ended with the search
