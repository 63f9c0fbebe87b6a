"""A run of a scene with friction (issue 29) in the MCAP and the rerun view: the friction_power
topic tick for tick, the view's loss and efficiency plots read back from the .rrd equal to the
solver's (``k.friction_loss``, ``k.efficiency``), the blueprint's friction column, and
``linkage-view`` of the MCAP giving the same plots."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("mcap", reason="the record extra (mcap) is not installed")
pytest.importorskip("rosbags", reason="the record extra (rosbags) is not installed")
if importlib.util.find_spec("rerun") is None:
    pytest.skip("the view extra (rerun-sdk) is not installed", allow_module_level=True)

from rerun.chunk import RrdReader

import solver
from linkage_ros.record.friction import EFFICIENCY_ENTITY, FRICTION_ORIGIN, friction_efficiency
from linkage_ros.record.replay import run_data_from_mcap
from linkage_ros.record.run import RunOptions, run_standalone

SCENE = "four_bar_loaded_friction"
OMEGA = 3.0
RATE = 50.0
TICKS = 51
NAMES = ["total", "O", "A", "C", "B"]
#: The run's whole-run solve and the test's (vectorised, the same samples).
TOL_REL = 1e-12


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> Any:
    tmp = tmp_path_factory.mktemp("friction_view")
    mcap, rrd = tmp / "friction.mcap", tmp / "friction.rrd"
    result = run_standalone(RunOptions(scene=SCENE, duration=1.0, rate=RATE, omega=OMEGA, phi0=0.2,
                                       mcap=mcap, rrd=rrd))
    return mcap, rrd, result.data


def scalars(path: Path, prefix: str) -> dict[str, np.ndarray]:
    """Entity → (N,) values of every Scalars entity under ``prefix``, in time order."""
    rows: dict[str, list[tuple[float, float]]] = {}
    for chunk in RrdReader(path).stream().to_chunks():
        if chunk.is_static or not chunk.entity_path.startswith(prefix):
            continue
        batch = chunk.to_record_batch()
        times = [t.total_seconds() for t in batch.column("sim_time").to_pylist()]
        values = [v[0] for v in batch.column("Scalars:scalars").to_pylist()]
        rows.setdefault(chunk.entity_path, []).extend(zip(times, values))
    return {entity: np.array([v for _, v in sorted(pairs)]) for entity, pairs in rows.items()}


def test_the_run_carries_the_solvers_friction_at_every_tick(run: Any) -> None:
    _, _, data = run
    assert list(data.friction) == NAMES and data.n == TICKS
    k = solver.load_scene(SCENE).solve(data.phi, omega=data.omega, epsilon=data.epsilon)
    np.testing.assert_allclose(data.friction["total"], k.friction_power, rtol=TOL_REL)
    for name in NAMES[1:]:
        np.testing.assert_allclose(data.friction[name], k.friction_loss(name), rtol=TOL_REL)
    np.testing.assert_allclose(friction_efficiency(data), k.efficiency, rtol=1e-10)  # P₀ = P − loss: a difference


def test_the_rrd_plots_the_losses_and_the_efficiency(run: Any) -> None:
    _, rrd, data = run
    got = scalars(rrd, "/plots/")
    for name in NAMES:
        np.testing.assert_array_equal(got[f"/{FRICTION_ORIGIN}/{name}"], data.friction[name])
    eta = got[f"/{EFFICIENCY_ENTITY}"]
    assert eta.size == TICKS and np.all((eta > 0.5) & (eta < 1.0))
    np.testing.assert_array_equal(eta, friction_efficiency(data))
    assert len(RrdReader(rrd).blueprints()) == 1


def test_the_blueprint_has_a_friction_column(run: Any) -> None:
    from linkage_ros.record.friction import friction_views
    from linkage_ros.record.rerun import plot_column_count, plot_columns

    _, _, data = run
    views = friction_views(data)
    assert [v.name for v in views] == ["friction losses (W)", "efficiency η"]
    assert plot_column_count(data) == len(plot_columns(data)) + 1


def test_linkage_view_of_the_mcap_gives_the_same_plots(run: Any, tmp_path: Path) -> None:
    from linkage_ros.cli import view_main

    mcap, rrd, data = run
    replayed, _ = run_data_from_mcap(mcap)
    assert list(replayed.friction) == NAMES
    for name in NAMES:
        np.testing.assert_array_equal(replayed.friction[name], data.friction[name])
    assert view_main([str(mcap), "-o", str(tmp_path / "view.rrd")]) == 0
    again, first = scalars(tmp_path / "view.rrd", "/plots/"), scalars(rrd, "/plots/")
    for entity in [f"/{FRICTION_ORIGIN}/{n}" for n in NAMES] + [f"/{EFFICIENCY_ENTITY}"]:
        np.testing.assert_array_equal(again[entity], first[entity])
