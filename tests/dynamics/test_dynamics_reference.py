"""Forward dynamics against the 50-digit reference in absolute coordinates (tests/reference/dynamics_mp.py).

The stored pairs (φ, ω, Q_drive → ε) of ``tests/data/dynamics_ref_*.json`` were computed with
Lagrange multipliers on the bodies' absolute coordinates at 50 digits: another formulation, no
closed form, no kinetostatics. ``solver.dynamics`` gives ε = (Q_drive − h)/J from the reduced
model; they agree to round-off (measured: within 2e-14 of ε, a few ulps of the drive and h it is the difference of).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from mpmath import mpf
from reference.dynamics_mp import epsilon

import solver
from solver.tolerances import EPS

DATA = Path(__file__).resolve().parents[1] / "data"
#: ε from the reduced model against the 50-digit value, relative to |ε| (a few ulps of each pass)
REL = 64 * EPS
SCENES = ["four_bar_loaded", "engine"]


def _pairs(name: str) -> list[dict[str, float | str]]:
    data = json.loads((DATA / f"dynamics_ref_{name}.json").read_text(encoding="utf-8"))
    assert data["scene"] == name and "Lagrange multipliers" in data["provenance"]
    return data["states"]  # type: ignore[no-any-return]


@pytest.mark.parametrize("name", SCENES)
def test_input_accelerations_equal_the_50_digit_reference(name: str) -> None:
    scene = solver.load_scene(name)
    model = scene.reduced()
    for s in _pairs(name):
        phi, omega, drive = float(s["phi"]), float(s["omega"]), float(s["drive"])
        m, h, _ = model.instant((phi,), (omega,))
        expected = float(s["epsilon"])
        scale = (abs(drive) + abs(h[0])) / m  # ε is a difference of these: rounding is relative to them
        assert abs((drive - h[0]) / m - expected) <= REL * scale


def test_the_stored_reference_is_what_the_reference_computes() -> None:
    scene = solver.load_scene("engine")
    s = _pairs("engine")[0]
    fresh = epsilon("engine", scene, float(s["phi"]), float(s["omega"]), float(s["drive"]))
    assert abs(fresh - mpf(s["epsilon"])) <= mpf("1e-25") * abs(fresh)
