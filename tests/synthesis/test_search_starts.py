"""The multi-start search's parts: the batched Levenberg–Marquardt polish, the start box at the
targets' scale, and 7-point instances that end exact whatever the seed (issue 32)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import solver
from solver.synthesis import load_template
from solver.synthesis.api import SHORT_SAMPLES, make_goal
from solver.synthesis.batch import polish_batch
from solver.synthesis.result import meets_constraints
from solver.synthesis.search import start_box
from solver.tolerances import EXACT_MISS

FOUR_BAR = Path(__file__).parents[2] / "config" / "templates" / "four_bar_path.yaml"
CRANK_ROCKER = np.array([0.0, 0.0, 0.4, 0.05, 0.1, 0.35, 0.3, 0.2, 30.0])
#: a four-bar of the template's ranges (crank 0.141, coupler 0.685, rocker 0.412; P off the coupler)
SEVEN = np.array([-0.6412, 0.5312, 0.1506, 0.1009, 0.1413, 0.6853, 0.4117, 0.2946, -61.0])


def _goal(t, targets):  # type: ignore[no-untyped-def]
    return make_goal(t, point="P", through=targets, at=None, joint=None, pairs=None, poses=None,
                     input_range=None, min_transmission=math.radians(30.0), max_ratio=None, samples=180)


def _points(t, x, phi):  # type: ignore[no-untyped-def]
    return t.scene(x).with_outputs(points=["P"], joints=[]).solve(phi).point("P").position


def test_batch_polish_ends_at_round_off_from_near_starts() -> None:
    """Eight starts near the generating design, perturbed 1 % of each range, at once: each ends
    at a zero of the seven targets' residuals to round-off (the family of zeros is 2-dimensional,
    so the ends differ from the design, and each is checked by its own scene)."""
    t = load_template(FOUR_BAR)
    phi = np.linspace(0.3, 5.9, 7)
    targets = _points(t, CRANK_ROCKER, phi)
    goal = _goal(t, targets)
    rng = np.random.default_rng(3)
    x0 = CRANK_ROCKER + 0.01 * (t.hi - t.lo) * rng.uniform(-1, 1, (8, t.lo.size))
    ph0 = phi + rng.uniform(-0.02, 0.02, (8, 7))
    ends = polish_batch(t, goal, x0, ph0, iterations=60)
    assert np.all(np.sqrt(2.0 * ends.cost) * goal.scale <= EXACT_MISS)
    for x, ph in zip(ends.x, ends.phases):
        assert np.abs(_points(t, x, ph) - targets).max() <= EXACT_MISS
        assert np.all(x >= t.lo) and np.all(x <= t.hi)


def test_start_box_at_the_targets_scale() -> None:
    """A 0.1 m path in [-1, 1] m bounds: the starts' pivots lie within 1.5 sizes of the targets'
    middle and their lengths under 3 sizes (inside the bounds)."""
    t = load_template(FOUR_BAR)
    targets = np.array([[0.30, 0.20], [0.36, 0.24], [0.40, 0.18], [0.35, 0.12], [0.31, 0.15]])
    goal = _goal(t, targets)
    box = start_box(t, goal, np.random.default_rng(0), 200)
    assert isinstance(box, np.ndarray) and box.shape == (200, t.lo.size)
    size = goal.scale
    mid = 0.5 * (targets.min(axis=0) + targets.max(axis=0))
    for i, f in enumerate(t.free):
        assert np.all(box[:, i] >= f.lo) and np.all(box[:, i] <= f.hi)
        if f.path[0] == "fixed":
            assert np.all(np.abs(box[:, i] - mid[f.path[2]]) <= 1.5 * size + 1e-12)
        elif f.kind == "length":
            assert np.all(box[:, i] <= max(3.0 * size, f.lo + 0.1 * (f.hi - f.lo)) + 1e-12)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_seven_points_end_exact_whatever_the_seed(seed: int) -> None:
    """Seven coupler points of a random crank-rocker: exact and feasible with seeds 0, 1, 2 (the
    issue's trial: 7.0 mm, exact, 12 mm by seed), checked by solving the returned scene."""
    t = load_template(FOUR_BAR)
    targets = _points(t, SEVEN, np.array([0.4, 1.1, 2.0, 2.9, 3.9, 4.8, 5.6]))
    res = solver.synthesize(t, point="P", through=targets, seed=seed)
    got = _points(t, res.best.x, res.phases)
    assert np.abs(got - targets).max() <= EXACT_MISS and res.exact
    assert meets_constraints(res.scene, res.goal) is None
    assert res.goal.sweep.size == SHORT_SAMPLES  # short starts without timing: the coarser sweep


@pytest.mark.parametrize(("count", "slack", "short"), [(5, 4, True), (7, 2, True), (9, 0, True), (10, -1, False)])
def test_short_starts_where_the_zeros_form_a_family(count: int, slack: int, short: bool) -> None:
    """Unknowns (9 dimensions + a phase per target) minus equations (2 per target): the
    dimension of the family of zeros; a task with one (slack ≥ 0) and no force terms runs short
    starts (35 generations, 64 of them by default: issue 32), an over-determined one long ones."""
    from dataclasses import replace

    from solver.synthesis.search import short_starts
    from solver.synthesis.search import slack as slack_of

    t = load_template(FOUR_BAR)
    goal = _goal(t, _points(t, CRANK_ROCKER, np.linspace(0.3, 5.9, count)))
    assert slack_of(t, goal) == slack
    assert short_starts(t, goal) is short
    assert short_starts(t, replace(goal, effort_weight=1.0)) is False  # force terms: long starts


@pytest.mark.parametrize(("count", "at", "weighted", "stage"),
                         [(5, False, False, True), (6, False, False, True), (7, False, False, False),
                          (6, True, False, False), (6, False, True, False)])
def test_seeded_stages_where_the_family_has_dimension_three(count: int, at: bool, weighted: bool, stage: bool) -> None:
    """A path task without timing whose family of zeros has dimension ≥ 3 (9 + K − 2K for K
    targets: 5 and 6 targets) begins with seeded stages; 7 targets (dimension 2), timing or force
    terms keep the DE starts."""
    from dataclasses import replace

    from solver.synthesis.search import seeded

    t = load_template(FOUR_BAR)
    phi = np.linspace(0.3, 5.9, count)
    goal = _goal(t, _points(t, CRANK_ROCKER, phi))
    if at:
        goal = replace(goal, at=phi)
    if weighted:
        goal = replace(goal, effort_weight=1.0)
    assert seeded(t, goal) is stage


#: bench.synthesis' six-target case 0 (rounded): four of the six targets within 0.42 rad of the
#: input, the case on which a DE start ended exact about 1 time in 10 (docs/synthesis.md).
SIX = np.array([0.1737, -0.3617, -0.1639, 0.7739, 0.1043, 0.8319, 1.4572, 0.4147, 142.1245])


@pytest.mark.parametrize("seed", [0, 1])
def test_six_points_end_exact_in_the_first_seeded_stage(seed: int) -> None:
    """The hard six-target case: exact and feasible in its first start (a seeded stage), checked by
    solving the returned scene; the stage is deterministic per seed (run again, the same values).
    Seed 1 took a second stage while the feasible ends were polished first (issue 32)."""
    from solver.synthesis.search import Options, run_start

    t = load_template(FOUR_BAR)
    targets = _points(t, SIX, np.array([0.412, 1.961, 5.201, 5.445, 5.537, 5.622]))
    res = solver.synthesize(t, point="P", through=targets, seed=seed)
    assert res.starts == 1
    got = _points(t, res.best.x, res.phases)
    assert np.abs(got - targets).max() <= EXACT_MISS and res.exact
    assert meets_constraints(res.scene, res.goal) is None
    again = run_start(t, res.goal, seed, 0, Options(), None)
    assert any(np.array_equal(p.x, res.best.x) for p in again.polished)


def test_seeded_order_takes_feasible_and_infeasible_ends_in_turn() -> None:
    """The stage's one-by-one polishes: feasible and infeasible ends in turn, each kind by cost,
    the feasible first; the ends not near a zero left out."""
    from solver.synthesis.search import _seeded_order

    cost = np.array([5.0, 1.0, 4.0, 2.0, 3.0, 0.5, 9.0])
    near = np.array([0, 1, 2, 3, 4, 5])
    ok = np.array([True, False, True, False, False, True])
    assert _seeded_order(cost, near, ok) == [5, 1, 2, 3, 0, 4]
    assert _seeded_order(cost, near, np.zeros(6, bool)) == [5, 1, 3, 4, 2, 0]


def test_polish_while_falling_stops_at_a_zero_or_a_stall(monkeypatch: pytest.MonkeyPatch) -> None:
    """The stage's chunked polish: from a point of the family it ends exact in its first chunk;
    from a far start it stops when a chunk no longer lowers the residual (never worse than its
    start), within the chunks' budget."""
    from solver.synthesis import search
    from solver.synthesis.polish import polish

    t = load_template(FOUR_BAR)
    phi = np.array([0.412, 1.961, 5.201, 5.445, 5.537, 5.622])
    goal = _goal(t, _points(t, SIX, phi))
    chunks: list[float] = []

    def counted(*args, **kwargs):  # type: ignore[no-untyped-def]
        out = polish(*args, **kwargs)
        chunks.append(out.cost)
        return out

    monkeypatch.setattr(search, "polish", counted)
    p = search._polish_while_falling(t, goal, SIX, phi)
    assert math.sqrt(2.0 * p.cost) * goal.scale <= EXACT_MISS and len(chunks) == 1
    chunks.clear()
    start = polish(t, goal, CRANK_ROCKER, phi, max_nfev=1)
    q = search._polish_while_falling(t, goal, CRANK_ROCKER, phi)
    assert q.cost == min(chunks) <= start.cost and 1 <= len(chunks) <= search.SEEDED_CHUNKS
    stalled = [a for a, b in zip(chunks, chunks[1:]) if b >= a / search.SEEDED_GAIN**2]
    assert len(chunks) == search.SEEDED_CHUNKS or math.sqrt(2.0 * q.cost) * goal.scale <= EXACT_MISS or stalled


def test_no_seeded_stages_with_a_triad() -> None:
    """A triad's sweep is solved design by design: a path task on a triad template keeps the DE
    starts (a screen of 10,000 designs would take minutes)."""
    from solver.synthesis.search import seeded, slack

    t = load_template(Path(__file__).parent / "templates" / "triad_press_path.yaml")
    goal = make_goal(t, point="F", through=[[0.3, 0.6], [0.35, 0.65]], at=None, joint=None, pairs=None, poses=None,
                     input_range=None, min_transmission=math.radians(30.0), max_ratio=None, samples=180)
    assert slack(t, goal) == 3 and not seeded(t, goal)
