"""The rerun view stays readable for force scenes and mixed joints: every plot one unit, numbered
y axes, the legend in full, load arrows visible for most of a turn and never huge."""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkage_ros.forces import MAX_FRACTION as FORCES_MAX_FRACTION
from linkage_ros.forces import LoadArrows, load_arrows
from linkage_ros.record._drawing import plot_range as _range
from linkage_ros.record.forces import arrow_vectors, load_rule
from linkage_ros.record.rerun import WINDOW_PX, legend_share, legend_text, plot_columns
from linkage_ros.record.run import RunOptions, run_standalone

MIN_FRACTION, MAX_FRACTION = 0.03, 0.6
"""Of the drawing's extent: an arrow shorter than the first is hard to see at the default window
(the engine: ~8 mm, ~12 px); none may be longer than the second."""


@pytest.fixture(scope="module")
def engine():  # type: ignore[no-untyped-def]
    return run_standalone(RunOptions(scene="engine", duration=1.0, rate=100.0)).data


def test_angles_and_lengths_are_never_on_one_axis(engine) -> None:  # type: ignore[no-untyped-def]
    assert engine.joint_units["piston_x"] == "m" and engine.joint_units["crankshaft"] == "rad"
    for column in plot_columns(engine)[1:]:
        for title, paths in column:
            if not paths:  # the crank's angle alone: its φ, plotted apart (the plot is left out)
                continue
            units = {engine.joint_units[p.rsplit("/", 1)[1]] for p in paths}
            assert len(units) == 1, title
            assert f"({next(iter(units))}" in title


def test_the_engines_load_arrows_are_visible_for_most_of_a_turn_and_never_huge(engine) -> None:  # type: ignore[no-untyped-def]
    rule, extent = load_rule(engine), engine.extent()
    longest = np.max([np.linalg.norm(arrow_vectors(rule, v, 2), axis=1) for v in engine.loads.values()], axis=0)
    assert np.mean(longest >= MIN_FRACTION * extent) >= 0.75
    assert float(np.max(longest)) <= MAX_FRACTION * extent
    # the peak (the gas force near firing top dead centre, ~15.6 kN: 2 decades above the knee) is
    # drawn, not 7.8 m proportionally nor 3 knee lengths on one knee length per tenfold, but half
    # the drawing long: a tenfold adds less than a knee length (linkage_ros.forces.load_arrows)
    peak = max(float(np.max(np.linalg.norm(v[:, :2], axis=1))) for v in engine.loads.values())
    assert peak > 100.0 * rule.knee and rule.scale * peak > MAX_FRACTION * extent
    assert rule.decade is not None and rule.decade < rule.scale * rule.knee
    assert float(np.max(longest)) == pytest.approx(FORCES_MAX_FRACTION * extent, rel=1e-12)


def test_the_arrow_length_is_proportional_to_the_knee_then_one_knee_length_per_tenfold() -> None:
    rule = LoadArrows(2e-4, 300.0)
    forces = np.array([0.0, 10.0, 300.0, 3000.0, 30000.0, math.nan])
    assert rule.length(forces[:3]) == pytest.approx([0.0, 2e-3, 0.06])
    assert rule.length(forces[3:5]) == pytest.approx([0.12, 0.18])
    assert [rule.factor(float(f)) for f in forces[:5]] == pytest.approx(list(rule.factor(forces[:5])), rel=1e-15)
    assert math.isnan(rule.factor(math.nan)) and np.isnan(rule.factor(forces)[-1])
    assert LoadArrows(0.005).length(1e6) == pytest.approx(5e3)  # no knee: proportional
    short = rule._replace(decade=0.03)  # a tenfold adds 0.03 m, not a knee length (0.06 m)
    assert short.length(forces[2:5]) == pytest.approx([0.06, 0.09, 0.12])
    assert short.factor(3000.0) == pytest.approx(float(short.factor(np.array([3000.0]))[0]), rel=1e-15)
    assert short.describe() == "× 0.0002 m/N up to 300 N, then +0.03 m per ×10"


def test_a_peak_far_above_the_knee_is_drawn_at_most_the_largest_fraction_and_a_near_one_as_before() -> None:
    extent = 1.0
    loads = np.full((100, 2), [100.0, 0.0])
    loads[0] = [2.0e5, 0.0]  # 3.2 decades above the knee (125 N at 2e-3 m/N)
    rule = load_arrows({"P": loads}, extent)
    assert rule.knee == pytest.approx(125.0) and rule.length(2.0e5) == pytest.approx(FORCES_MAX_FRACTION * extent)
    loads[0] = [1.0e3, 0.0]  # less than a tenfold above the knee: one knee length per tenfold
    near = load_arrows({"P": loads}, extent)
    assert near.decade is None and near.length(1.0e3) < FORCES_MAX_FRACTION * extent


@pytest.mark.parametrize(("lo", "hi", "marks"), [(-70.0, 88.0, (-100.0, 100.0)), (0.11, 0.2, (0.1, 0.2)),
                                                  (0.11, 0.21, (0.1, 0.3)), (0.0, 6.283, (0.0, 7.0)),
                                                  (-0.69, 0.69, (-1.0, 1.0))])
def test_each_y_range_shows_two_numbered_powers_of_ten(lo: float, hi: float, marks: tuple[float, float]) -> None:
    bottom, top = _range(np.array([lo, hi]))
    assert bottom < marks[0] <= lo and hi <= marks[1] < top


def test_rounding_noise_around_a_constant_is_plotted_flat() -> None:
    bottom, top = _range(np.array([0.0, 7e-15, -5e-15]))
    assert bottom < -0.9 and top > 0.9


def test_the_legend_panel_is_tall_enough_for_five_bars_list_of_loads() -> None:
    data = run_standalone(RunOptions(scene="five_bar", duration=0.1, rate=100.0)).data
    text = legend_text(data)
    assert "P on left_distal_link from right_distal_link" in text
    # every plotted series is identifiable from the legend alone: each joint and its colour
    from linkage_ros.record._drawing import SERIES_COLOUR_NAMES, SERIES_PALETTE

    assert len(SERIES_COLOUR_NAMES) == len(SERIES_PALETTE)
    key = ", ".join(f"{j} {SERIES_COLOUR_NAMES[i]}" for i, j in enumerate(data.joints))
    assert f"one colour per joint, the inputs and efforts in their joint's: {key}." in text
    assert "q1 red" in text and "q2 blue" in text
    _, legend = legend_share(text, len(plot_columns(data)))
    assert legend >= 40.0 + 16.0 * 5  # five lines at the default window's width
    assert legend <= 0.45 * WINDOW_PX[1]


def test_a_recording_replays_with_its_joints_units(tmp_path) -> None:  # type: ignore[no-untyped-def]
    from linkage_ros.record.replay import run_data_from_mcap

    mcap = tmp_path / "engine.mcap"
    run_standalone(RunOptions(scene="engine", duration=0.2, rate=50.0, mcap=mcap))
    data, _ = run_data_from_mcap(mcap)
    assert data.joint_units == {"crankshaft": "rad", "piston_x": "m"}
    titles = [title for column in plot_columns(data) for title, _ in column]
    # the slide in its own unit; the crank, the only angle, is the input: plotted apart as φ, ω, ε
    assert "joint positions (m)" in titles and "input φ (rad)" in titles and "joint angles (rad)" not in titles


def test_a_revolving_joint_is_plotted_as_one_continuous_line_and_a_slide_as_it_is(engine) -> None:  # type: ignore[no-untyped-def]
    data = run_standalone(RunOptions(scene="harvester_finger", duration=1.0, rate=100.0)).data
    raw = data.joints["finger"][0]
    plotted = data.plotted_joint("finger")[0]
    assert np.nanmax(np.abs(np.diff(raw))) > math.pi  # the finger turns: its angle wraps at 2π
    assert np.nanmax(np.abs(np.diff(plotted))) < 0.5  # plotted, it does not jump
    np.testing.assert_allclose(np.mod(plotted - raw + math.pi, 2 * math.pi) - math.pi, 0.0, atol=1e-12)
    assert data.plotted_joint("finger")[1] is data.joints["finger"][1]
    assert engine.plotted_joint("piston_x")[0] is engine.joints["piston_x"][0]


def test_the_engines_pin_and_slide_labels_at_b_stand_apart_and_off_the_pin(engine) -> None:  # type: ignore[no-untyped-def]
    """R_B and R_B_slide (two loads at one pin) are drawn beyond their arrows' tips: apart from
    each other and from the pin's own name at every tick (the viewer's own arrow labels sit at
    the arrows' middles, on each other, issue 30)."""
    from linkage_ros.record._drawing import LINK_RADIUS, position_of
    from linkage_ros.record.forces import LABEL_GAP, LABEL_REACH, label_positions

    radius = LINK_RADIUS * engine.extent()
    rule = load_rule(engine)
    pin = position_of(engine, "B")
    turns = (("B", 0.25 * math.pi), ("B_slide", 0.75 * math.pi))
    anchors = [label_positions(pin, arrow_vectors(rule, engine.loads[key], engine.dim), radius, turn,
                               chars=len(key) + 2) for key, turn in turns]
    apart = np.hypot(*(anchors[0] - anchors[1])[:, :2].T)
    assert apart.min() >= LABEL_GAP * radius  # a label's height (~10 px) is 5-10 link radii at the default window
    for a in anchors:
        assert np.hypot(*(a - pin)[:, :2].T).min() >= LABEL_REACH * radius * (1 - 1e-12)


def test_a_vanished_load_labels_away_from_its_pin_in_the_given_direction() -> None:
    from linkage_ros.record.forces import LABEL_REACH, label_positions

    at = label_positions(np.array([[1.0, 2.0]]), np.zeros((1, 2)), 0.01, 0.5 * math.pi)
    np.testing.assert_allclose(at, [[1.0, 2.0 + LABEL_REACH * 0.01]], rtol=0, atol=1e-15)


def test_a_dynamic_runs_legend_is_sized_for_the_mechanism_column_beside_its_energy_column() -> None:
    from linkage_ros.record.rerun import plot_column_count

    data = run_standalone(RunOptions(scene="four_bar_pendulum", duration=0.1, rate=100.0)).data
    assert plot_column_count(data) == len(plot_columns(data))
    data.energy = {"kinetic": np.zeros(data.n), "balance": np.zeros(data.n)}  # as a dynamic run's
    assert plot_column_count(data) == len(plot_columns(data)) + 1
    text = "word " * 200  # a long legend: the narrower column of a dynamic run needs a taller panel
    assert legend_share(text, plot_column_count(data))[1] > legend_share(text, len(plot_columns(data)))[1]
