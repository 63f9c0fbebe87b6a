"""An actuator mixed with a crank (k = 2): the crank turns the base of the cylinder, which pushes a
link about a fixed pivot. Jacobian and Hessian against central differences of the positions, the
compiled instant against the scalar path to the bit, and the force against virtual power."""

from __future__ import annotations

from typing import Any

import numpy as np
from scene_builders import build

from solver.forces.virtual import virtual_efforts

MIXED: dict[str, Any] = {
    "scene": "crank_and_ram",
    "units": {"length": "m", "angle": "rad"},
    "fixed": {"Q": [-1.2, -0.4], "O": [0.0, 0.0]},
    "groups": [
        {"type": "crank", "name": "crank", "center": "Q", "point": "A", "length": 0.15, "joint": "q"},
        {"type": "actuator", "name": "ram", "base": "A", "point": "C", "pivot": "O", "length": 0.8, "M": -1,
         "joint": "s", "stroke": [0.5, 1.2]},
        {"type": "attached", "name": "tip", "point": "T", "base": "O", "along": ["O", "C"], "distance": 1.5,
         "angle": 0.3},
    ],
    "outputs": {"points": ["C", "T"], "joints": ["s", "q"]},
    "bodies": {"arm": {"points": ["O", "C"], "mass": 40.0, "center": [0.7, 0.05], "inertia": 6.0}},
    "gravity": [0.0, -9.81],
}
SAMPLES = np.array([[0.3, 0.8], [1.9, 0.95], [4.0, 1.05]])


def test_jacobian_and_hessian_agree_with_central_differences() -> None:
    scene = build(MIXED)
    assert scene.inputs == ("q", "s") and scene.input_units == ("rad", "m")
    k = scene.solve(SAMPLES)
    h = 1e-5
    for i, row in enumerate(SAMPLES):
        for a in range(2):
            e_a = np.eye(2)[a] * h
            pts = scene.solve(np.array([row - e_a, row, row + e_a])).point("T").position
            np.testing.assert_allclose(k.point("T").jacobian[i, :, a], (pts[2] - pts[0]) / (2 * h), atol=1e-8)
            np.testing.assert_allclose(k.point("T").hessian[i, :, a, a], (pts[2] - 2 * pts[1] + pts[0]) / h**2,
                                       atol=1e-4)
        d = np.array([h, h])
        m = np.array([h, -h])
        corners = scene.solve(np.array([row + d, row - m, row + m, row - d])).point("T").position
        mixed = (corners[0] - corners[1] - corners[2] + corners[3]) / (4 * h * h)
        np.testing.assert_allclose(k.point("T").hessian[i, :, 0, 1], mixed, atol=1e-4)


def test_the_compiled_instant_is_the_scalar_path_to_the_bit() -> None:
    scene = build(MIXED).everything()
    unit = scene.compiled()
    for row in SAMPLES:
        args = (*row.tolist(), 0.7, -0.05, 0.2, 0.3)
        unit.function(*args)  # (traces the branch)
        assert unit.core(*args) is not None
        assert unit.core(*args) == unit.fallback(*args)


def test_the_ram_force_and_the_crank_torque_are_the_virtual_power_efforts() -> None:
    scene = build(MIXED)
    w, e = (0.7, -0.05), (0.2, 0.3)
    k = scene.solve(SAMPLES, omega=w, epsilon=e)
    want = virtual_efforts(scene, SAMPLES, omega=w, epsilon=e)
    for j in scene.inputs:
        np.testing.assert_allclose(k.effort(j), want[j], rtol=1e-11, atol=1e-9)
