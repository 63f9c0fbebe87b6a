"""Every kind of group with friction: Σ (Q − Q₀)·q̇ = Σ friction losses to round-off (the power
balance — it uses no reaction), third law kept, the seal's effort, and the CSV and summary."""

from __future__ import annotations

import copy
import io
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

import solver
from solver._loader import parse_scene
from solver.cli import write_csv
from solver.forces.report import force_lines

ROOT = Path(__file__).resolve().parents[2]
#: the balance against the input power's size: sums of a few terms in another order
ROUNDING = 1e-12


def _with(name: str, friction: dict[str, Any]) -> solver.Scene:
    data = yaml.safe_load((ROOT / "config/scenes" / f"{name}.yaml").read_text(encoding="utf-8"))
    data = copy.deepcopy(data)
    data["friction"] = friction
    return solver.Scene(parse_scene(data, file=None))


CASES = {
    "four_bar_loaded": {"all_pins": {"mu": 0.1, "radius": 0.008}, "pins": {"B": {"mu": 0.2, "radius": 0.005}}},
    "harvester_finger": {"all_pins": {"mu": 0.1, "radius": 0.01}, "slides": {"finger_link.block": {"mu": 0.2}}},
    "tipper": {"pins": {"O": {"mu": 0.15, "radius": 0.03}}, "actuators": {"lift": {"force": 300.0}}},
    "excavator": {"all_pins": {"mu": 0.1, "radius": 0.04},
                  "actuators": {"boom_cylinder": {"force": 500.0}, "bucket_cylinder": {"force": 200.0}}},
}


def _sweep(scene: solver.Scene, n: int = 97) -> tuple[np.ndarray, Any, float]:
    rng = np.random.default_rng(29)
    if len(scene.inputs) == 1:
        lo, hi = scene.input_ranges[0] or (0.0, 2 * np.pi)
        return np.linspace(lo, hi, n)[1:-1], 0.7, 0.3
    cols = [np.linspace(*(r or (0.0, 1.0)), n)[1:-1] for r in scene.input_ranges]
    phi = np.stack([rng.permutation(c) for c in cols], axis=1)
    return phi, np.array([0.05, -0.04, 0.03])[: len(scene.inputs)], 0.0


@pytest.mark.parametrize("name", sorted(CASES))
def test_power_balance(name: str) -> None:
    scene = _with(name, CASES[name])
    phi, w, e = _sweep(scene)
    k = scene.solve(phi, omega=w, epsilon=e, mask=True)
    ok = np.asarray(k.valid, bool) & ~np.asarray(k.locked, bool)
    assert ok.sum() > 0.9 * len(k.valid)
    rates = np.broadcast_to(np.asarray(w, float), (len(k.valid), len(scene.inputs)))
    gained = sum((np.asarray(k.effort(q)) - np.asarray(k.ideal_effort(q))) * rates[:, i]
                 for i, q in enumerate(scene.inputs))
    scale = max(np.max(np.abs(np.asarray(k.effort(q))[ok] * rates[ok, i])) for i, q in enumerate(scene.inputs))
    assert np.max(np.abs((gained - k.friction_power)[ok])) <= ROUNDING * scale
    assert np.all(k.friction_power[ok] > 0.0)


def test_seal_adds_its_force_against_the_stroke_rate() -> None:
    scene = _with("tipper", {"actuators": {"lift": {"force": 300.0}}})
    for w in (0.05, -0.05):
        k = scene.solve(1.0, omega=w, epsilon=0.0)
        assert k.effort("stroke") - k.ideal_effort("stroke") == pytest.approx(300.0 * np.sign(w), rel=1e-15)
        assert k.friction_loss("lift") == pytest.approx(300.0 * abs(w), rel=1e-15)
        np.testing.assert_array_equal(k.reaction("O", on="body"),
                                      _with("tipper", {"actuators": {"lift": {"force": 0.0}}}).solve(
                                          1.0, omega=w, epsilon=0.0).reaction("O", on="body"))


def test_cylinder_eye_is_refused() -> None:
    with pytest.raises(solver.SceneError, match=r"friction\.pins\.A.*actuator cylinder's eye.*friction\.actuators"):
        _with("tipper", {"pins": {"A": {"mu": 0.1, "radius": 0.01}}})


def test_csv_and_summary_carry_the_friction() -> None:
    scene = _with("four_bar_loaded", CASES["four_bar_loaded"])
    phi = np.linspace(0.0, 2 * np.pi, 360, endpoint=False)
    k = scene.solve(phi, omega=10.0, epsilon=0.0)
    out = io.StringIO()
    write_csv(scene, k, out)
    head, first = out.getvalue().splitlines()[:2]
    cols = head.split(",")
    assert cols[-7:] == ["loss.O", "loss.A", "loss.C", "loss.B", "friction.power", "efficiency", "locked"]
    row = dict(zip(cols, map(float, first.split(","))))
    assert row["friction.power"] == pytest.approx(float(k.friction_power[0]), rel=1e-15)
    lines = force_lines(scene, k)
    assert any(line.startswith("  friction: peak loss") for line in lines)
    assert any(line.startswith("  efficiency: lowest") and "over the turn" in line for line in lines)
