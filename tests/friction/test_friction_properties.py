"""Invariants of friction on bounded finite ranges (hypothesis): the power balance, the third law,
friction never helps a driven mechanism, and the ideal mechanism is the limit μ → 0."""

from __future__ import annotations

import copy
import math
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

import solver
from solver._loader import parse_scene

ROOT = Path(__file__).resolve().parents[2]
BASE: dict[str, Any] = yaml.safe_load((ROOT / "tests/forces/scenes/friction_slider_crank.yaml").read_text("utf-8"))
#: sums of a few exact terms in another order, against the input power's size
ROUNDING = 1e-12


def _scene(mu_pin: float, radius: float, mu_slide: float) -> solver.Scene:
    data = copy.deepcopy(BASE)
    data["friction"] = {"all_pins": {"mu": mu_pin, "radius": radius}, "slides": {"piston": {"mu": mu_slide}}}
    return solver.Scene(parse_scene(data, file=None))


@settings(max_examples=8, deadline=None)
@given(
    phi=st.floats(0.0, 2 * math.pi),
    omega=st.floats(0.5, 60.0) | st.floats(-60.0, -0.5),
    epsilon=st.floats(-500.0, 500.0),
    mu_pin=st.floats(1e-4, 0.3),
    radius=st.floats(0.001, 0.03),
    mu_slide=st.floats(1e-4, 0.4),
)
def test_power_balance_third_law_and_dissipation(phi: float, omega: float, epsilon: float, mu_pin: float,
                                                 radius: float, mu_slide: float) -> None:
    scene = _scene(mu_pin, radius, mu_slide)
    k = scene.solve(phi, omega=omega, epsilon=epsilon)
    if k.locked:  # no solution: flagged, every value NaN, and said in one line
        assert math.isnan(k.effort("crank"))
        return
    q, q0 = k.effort("crank"), k.ideal_effort("crank")
    assert k.friction_power >= 0.0
    scale = (abs(q) + abs(q0)) * abs(omega) + 1e-300
    assert abs((q - q0) * omega - k.friction_power) <= ROUNDING * scale
    assert (q - q0) * omega >= -ROUNDING * scale  # friction only takes power
    np.testing.assert_array_equal(k.reaction("A", on="crank"), -k.reaction("A", on="rod"))
    if q0 * omega > 0.0:
        assert 0.0 < k.efficiency <= 1.0


@settings(max_examples=4, deadline=None)
@given(phi=st.floats(0.0, 2 * math.pi), omega=st.floats(0.5, 60.0))
def test_small_friction_tends_to_the_ideal_mechanism(phi: float, omega: float) -> None:
    """Q − Q₀ = O(μ): halving every μ halves the difference to first order."""
    k1 = _scene(1e-6, 0.01, 1e-6).solve(phi, omega=omega, epsilon=0.0)
    k2 = _scene(5e-7, 0.01, 5e-7).solve(phi, omega=omega, epsilon=0.0)
    d1 = k1.effort("crank") - k1.ideal_effort("crank")
    d2 = k2.effort("crank") - k2.ideal_effort("crank")
    assert abs(d1 - 2 * d2) <= 1e-4 * abs(d1) + 1e-12 * abs(k1.ideal_effort("crank"))
