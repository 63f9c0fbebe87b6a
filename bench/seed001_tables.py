"""Seed 001 (Kosiyuk & Kravchuk 2019), Tables 1–2: maxima of the cage's angular velocity and
angular acceleration at 50, 150, 250 and 500 rpm of the shaft, α = 40°.

Columns: ours (the solver on the shipped scene ``spherical_converter``), the paper's Mathcad and
SolidWorks Motion values, and their relative differences from ours. Ours is found from the
solver alone: a sweep of one turn at constant shaft speed (it contains φ = 0, where
max ω_cage = ω / tan α lies), then the best sample's neighbourhood is swept again, finer, until
the bracket is narrower than ``PHI_TOL``. The closed forms (max ω_cage = ω / tan α,
max |ε_cage| = ω² · max |ψ''|) are checked against this in tests/test_seed001_tables.py.

Run: ``.venv/bin/python bench/seed001_tables.py`` (prints markdown).
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass

import numpy as np

import solver

__all__ = [
    "PAPER",
    "RPM",
    "Maximum",
    "cage_maximum",
    "main",
    "markdown",
    "shaft_speed",
    "table_rows",
]

RPM = (50, 150, 250, 500)
PAPER: dict[str, dict[str, tuple[float, ...]]] = {
    # 001_2e976e0dccb962d4.txt, Таблиця 1 and Таблиця 2 (rad/s and rad/s²), in RPM order.
    "omega": {
        "Mathcad": (6.24608, 18.72632, 31.20656, 62.41312),
        "SolidWorks": (6.248287, 18.70996, 31.18908, 62.3607),
    },
    "epsilon": {
        "Mathcad": (31.57624, 283.8247, 788.2013, 3152.805),
        "SolidWorks": (31.5905, 283.7909, 788.314, 3106.394),
    },
}
SCENE = "spherical_converter"
JOINT = "cage"
SWEEP_SAMPLES = 3600
ZOOM_SAMPLES = 201
PHI_TOL = 1e-12
"""Bracket width (rad) at which the refinement stops; the maximum's value then moves by ~PHI_TOL²."""


@dataclass(frozen=True)
class Maximum:
    value: float
    """max |ω_cage| (rad/s) or max |ε_cage| (rad/s²)."""
    phi: float
    """Shaft angle (rad) in [0, 2π) where it occurs (|ψ''| peaks at four symmetric angles; one of them)."""


def shaft_speed(rpm: float) -> float:
    """Shaft angular velocity (rad/s) from rpm."""
    return 2.0 * math.pi * rpm / 60.0


def _cage(scene: solver.Scene, phi: np.ndarray, omega: float, quantity: str) -> np.ndarray:
    joint = scene.solve(phi, omega=omega, epsilon=0.0).joint(JOINT)
    return np.abs(joint.velocity if quantity == "omega" else joint.acceleration)


def cage_maximum(rpm: float, quantity: str, *, scene: solver.Scene | None = None) -> Maximum:
    """The solver's maximum of |ω_cage| (quantity "omega") or |ε_cage| ("epsilon") over a turn."""
    if quantity not in PAPER:
        raise ValueError(f"quantity must be one of {sorted(PAPER)}, not {quantity!r}")
    scene = scene or solver.load_scene(SCENE)
    omega = shaft_speed(rpm)
    phi = np.linspace(0.0, 2.0 * math.pi, SWEEP_SAMPLES, endpoint=False)
    values = _cage(scene, phi, omega, quantity)
    best = int(np.argmax(values))
    best_value, best_phi = float(values[best]), float(phi[best])
    half_width = 2.0 * math.pi / SWEEP_SAMPLES
    while half_width > PHI_TOL:
        phi = np.linspace(best_phi - half_width, best_phi + half_width, ZOOM_SAMPLES)
        values = _cage(scene, phi, omega, quantity)
        i = int(np.argmax(values))
        if values[i] > best_value:
            best_value, best_phi = float(values[i]), float(phi[i])
        half_width *= 4.0 / (ZOOM_SAMPLES - 1)
    return Maximum(best_value, best_phi % (2.0 * math.pi))


def table_rows(quantity: str, *, scene: solver.Scene | None = None) -> list[dict[str, float]]:
    """One row per rpm: ours, φ at the maximum, each paper column and its relative difference."""
    scene = scene or solver.load_scene(SCENE)
    rows = []
    for i, rpm in enumerate(RPM):
        ours = cage_maximum(rpm, quantity, scene=scene)
        row = {"rpm": rpm, "ours": ours.value, "phi": ours.phi}
        for source, values in PAPER[quantity].items():
            row[source] = values[i]
            row[f"{source} rel"] = (values[i] - ours.value) / ours.value
        rows.append(row)
    return rows


def markdown(*, scene: solver.Scene | None = None) -> str:
    scene = scene or solver.load_scene(SCENE)
    titles = {
        "omega": ("Table 1. Maximum angular velocity of the cage, rad/s", "ω / tan α, at φ = 0"),
        "epsilon": (
            "Table 2. Maximum angular acceleration of the cage, rad/s²",
            "ω² · max |ψ''|, at sin²φ = 3(t+1) − √(9(t+1)² − t(t+2)), t = tan²α",
        ),
    }
    lines = []
    for quantity, (title, closed_form) in titles.items():
        lines += [
            f"**{title}** (α = 40°; ours = solver, exact closed form {closed_form})",
            "",
            "| shaft, rpm | ours | φ at max, deg | Mathcad | Δ Mathcad | SolidWorks | Δ SolidWorks |",
            "|---:|---:|---:|---:|---:|---:|---:|",
        ]
        for r in table_rows(quantity, scene=scene):
            lines.append(
                f"| {r['rpm']} | {r['ours']:.10g} | {math.degrees(r['phi']):.4f} | {r['Mathcad']:.7g} | "
                f"{100 * r['Mathcad rel']:+.3f} % | {r['SolidWorks']:.7g} | {100 * r['SolidWorks rel']:+.3f} % |"
            )
        lines.append("")
    lines.append("Δ = (paper − ours) / ours. Paper values: seeds/001, Таблиця 1–2.")
    return "\n".join(lines)


def main() -> int:
    print(markdown())
    return 0


if __name__ == "__main__":
    sys.exit(main())
