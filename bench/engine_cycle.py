"""The shipped `engine`'s gas force over its four-stroke cycle (config/scenes/engine.yaml).

An indicator diagram of an illustrative spark-ignition engine on the scene's crank (45 mm) and
rod (155 mm), written as a table of the crank angle over 720° (firing top dead centre at 0°):
compression and expansion polytropic, p = p₁·(V₁/V)ⁿ, with a Wiebe burn between −10° and +40°
raising the pressure by λ (p·(1 + (λ − 1)·x_b)); exhaust and intake strokes at a small gauge
pressure. The force on the piston is (p − p_atm)·A along −x. Run ``python -m bench.engine_cycle``
to print the YAML lines of the table.
"""

from __future__ import annotations

import math

import numpy as np

CRANK, ROD = 45.0, 155.0  # mm
BORE = 80.0  # mm
RATIO = 9.5  # compression ratio
P_ATM, P1 = 0.1e6, 0.095e6  # Pa: ambient, at the start of compression
N_POLY = 1.32  # polytropic exponent
LAMBDA = 3.3  # pressure rise of the burn
BURN = (-10.0, 50.0)  # deg: start and duration of the burn
EXHAUST, INTAKE = 0.115e6, 0.09e6  # Pa
STEP = 5.0  # deg between table entries


def piston_x(phi_deg: np.ndarray) -> np.ndarray:
    p = np.radians(phi_deg)
    return CRANK * np.cos(p) + np.sqrt(ROD**2 - (CRANK * np.sin(p)) ** 2)


def pressure(phi_deg: np.ndarray) -> np.ndarray:
    """Absolute pressure (Pa) at crank angle φ ∈ [0°, 720°) from firing top dead centre."""
    area = math.pi * (BORE / 2) ** 2  # mm²
    swept = area * 2 * CRANK
    clearance = swept / (RATIO - 1)
    volume = clearance + area * (CRANK + ROD - piston_x(phi_deg))
    v1 = clearance + swept
    a = np.where(phi_deg >= 360.0, phi_deg - 720.0, phi_deg)  # −360° … 360° around firing TDC
    motored = P1 * (v1 / volume) ** N_POLY
    x = np.clip((a - BURN[0]) / BURN[1], 0.0, None)
    burnt = 1.0 - np.exp(-5.0 * x**3)
    closed = motored * (1.0 + (LAMBDA - 1.0) * burnt)
    p = np.where((a >= -180.0) & (a <= 180.0), closed, np.where(a > 180.0, EXHAUST, INTAKE))
    return p


def table() -> tuple[np.ndarray, np.ndarray]:
    phi = np.arange(0.0, 720.0 + STEP / 2, STEP)  # 0° … 720° (the same value at both ends)
    force = (pressure(phi) - P_ATM) * math.pi * (BORE / 2000) ** 2
    return phi, force


def main() -> None:
    phi, force = table()
    print("at: [" + ", ".join(f"{v:g}" for v in phi) + "]")
    print("force: [" + ", ".join(f"{v:.1f}" for v in force) + "]")


if __name__ == "__main__":
    main()
