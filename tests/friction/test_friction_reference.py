"""Friction against the 50-digit reference (tests/data/friction_ref_slider_crank.json, written by
tests/reference/friction_mp.py; provenance in the file): one instant and vectorised."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import solver

ROOT = Path(__file__).resolve().parents[2]
DATA = json.loads((ROOT / "tests/data/friction_ref_slider_crank.json").read_text(encoding="utf-8"))
SCENE = solver.load_scene(ROOT / DATA["scene_file"])
ROWS = DATA["samples"]
#: the issue's bound: effort and pin forces to 1e-12 relative (to the sample's largest force)
REF_TOL = 1e-12
#: sums of the same terms in another order, and Q − Q₀ against the losses
ROUNDING = 1e-13


def _close(got: object, want: object, scale: float) -> None:
    g, w = np.asarray(got, float), np.asarray(want, float)
    assert np.max(np.abs(g - w)) <= REF_TOL * scale, (g, w)


def _check(k: solver.Kinematics, row: dict, i: int | None) -> None:
    def at(x: object) -> object:
        return x if i is None else np.asarray(x)[i]

    forces = [np.hypot(*map(float, r["value"])) for r in row["reactions"].values()]
    scale = max(forces)
    _close(at(k.effort("crank")), float(row["effort"]), abs(float(row["effort"])) + 0.1 * scale)
    _close(at(k.ideal_effort("crank")), float(row["effort0"]), abs(float(row["effort0"])) + 0.1 * scale)
    for point, r in row["reactions"].items():
        _close(at(k.reaction(point, on=r["on"])), [float(v) for v in r["value"]], scale)
    s = k.slide_reaction("piston")
    _close(at(s.force), [float(v) for v in row["slide"]["force"]], scale)
    _close(at(s.couple), float(row["slide"]["couple"]), 0.1 * scale)
    _close(at(k.friction_power), float(row["loss"]), abs(float(row["loss"])) + 1.0)


@pytest.mark.parametrize("row", ROWS, ids=[f"phi={r['phi'][:6]}" for r in ROWS])
def test_one_instant_matches_the_reference(row: dict) -> None:
    k = SCENE.solve(float(row["phi"]), omega=float(row["omega"]), epsilon=float(row["epsilon"]))
    _check(k, row, None)


def test_vectorised_matches_the_reference() -> None:
    phi = np.array([float(r["phi"]) for r in ROWS])
    w = np.array([float(r["omega"]) for r in ROWS])
    e = np.array([float(r["epsilon"]) for r in ROWS])
    k = SCENE.solve(phi, omega=w, epsilon=e)
    for i, row in enumerate(ROWS):
        _check(k, row, i)


def test_power_balance_and_losses_add_up() -> None:
    """(Q − Q₀)·ω = Σ friction losses, to round-off, over a sweep; efficiency in (0, 1] while driving."""
    phi = np.linspace(0.0, 2 * np.pi, 181)
    k = SCENE.solve(phi, omega=15.0, epsilon=0.0)
    q, q0 = k.effort("crank"), k.ideal_effort("crank")
    parts = sum(k.friction_loss(n) for n in ("O", "A", "B", "piston"))
    np.testing.assert_allclose(parts, k.friction_power, rtol=ROUNDING, atol=0.0)
    scale = np.max(np.abs(q)) * 15.0
    assert np.max(np.abs((q - q0) * 15.0 - k.friction_power)) <= ROUNDING * scale
    assert np.all(k.friction_power >= 0.0)
    driving = q0 * 15.0 > 0.0  # the ideal mechanism takes power: η = Q₀/Q in (0, 1]
    assert np.all((k.efficiency[driving] > 0.0) & (k.efficiency[driving] <= 1.0))
    back = q0 * 15.0 < 0.0  # the loads drive: η = Q/Q₀ ≤ 1 (negative where friction outweighs them)
    assert np.all(k.efficiency[back] <= 1.0)
    assert not np.any(k.locked)
