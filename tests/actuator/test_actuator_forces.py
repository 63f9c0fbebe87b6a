"""The cylinder's force (the effort of a stroke input) against virtual power, and against the same
mechanism driven by a crank about the pushed link's pivot: f = Q·dθ/ds (power ṡ·f = θ̇·Q)."""

from __future__ import annotations

import copy
import itertools
from typing import Any

import numpy as np
import pytest

import solver
from solver._loader import parse_scene
from solver._yaml import load_yaml
from solver.forces.virtual import virtual_efforts


def test_tipper_cylinder_force_is_the_virtual_power_effort() -> None:
    scene = solver.load_scene("tipper")
    s = np.linspace(*scene.input_ranges[0], 25)
    w, e = 0.06 * np.cos(3 * s), 0.5 * np.sin(2 * s)
    k = scene.solve(s, omega=w, epsilon=e)
    want = virtual_efforts(scene, s, omega=w, epsilon=e)["stroke"]
    np.testing.assert_allclose(k.effort("stroke"), want, rtol=1e-12, atol=1e-9)
    assert np.all(k.effort("stroke") > 0.0)  # the cylinder pushes to hold the load up


def test_excavator_cylinder_forces_are_the_virtual_power_efforts() -> None:
    scene = solver.load_scene("excavator")
    q = np.array(list(itertools.product(*[np.linspace(*r, 4) for r in scene.input_ranges])))
    w, e = (0.05, -0.08, 0.1), (0.3, 0.2, -0.5)
    k = scene.solve(q, omega=w, epsilon=e)
    want = virtual_efforts(scene, q, omega=w, epsilon=e)
    for j in scene.inputs:
        np.testing.assert_allclose(k.effort(j), want[j], rtol=1e-11, atol=1e-8 * np.abs(want[j]).max())


def test_the_pins_of_a_cylinder_carry_its_force_along_its_axis() -> None:
    scene = solver.load_scene("tipper").with_outputs(points=["A", "C"])
    k = scene.solve(np.linspace(0.8, 1.2, 5), omega=0.1, epsilon=-0.2)
    f = k.effort("stroke")
    axis = k.point("C").position - k.point("A").position
    axis /= np.linalg.norm(axis, axis=1)[:, None]
    at_a = k.reaction("A", on="lift.cylinder")
    at_c = k.reaction("C", on="lift.cylinder")
    np.testing.assert_allclose(at_a, f[:, None] * axis, rtol=1e-13, atol=1e-9)
    np.testing.assert_allclose(at_c, -at_a, rtol=0, atol=0)


def _crank_tipper() -> solver.Scene:
    """tipper.yaml with its cylinder replaced by a motor turning the body about O."""
    data: dict[str, Any] = copy.deepcopy(load_yaml(solver.find_scene("tipper")))
    data["groups"][0] = {"type": "crank", "name": "motor", "center": "O", "point": "C", "length": 0.8,
                         "joint": "theta"}
    data["outputs"]["joints"] = ["theta"]
    data.pop("descriptions")
    return solver.Scene(parse_scene(data, file="tipper_crank"))


@pytest.mark.parametrize(("sdot", "sddot"), [(0.0, 0.0), (0.08, -0.3)])
def test_the_cylinder_force_is_the_crank_torque_times_dtheta_ds(sdot: float, sddot: float) -> None:
    cylinder = solver.load_scene("tipper")
    angle = cylinder.with_outputs(points=[], joints=["stroke"])
    crank = _crank_tipper()
    s = np.linspace(0.75, 1.29, 13)
    # θ(s) of the body about O, with its analogs: the angle of O → C
    theta_scene = solver.Scene(parse_scene({**load_yaml(solver.find_scene("tipper")),
                                            "joints": {"theta": {"angle": ["O", "C"]}},
                                            "outputs": {"joints": ["theta"]}, "descriptions": {}},
                                           file="theta"))
    th = theta_scene.solve(s).joint("theta")
    theta, d1, d2 = th.position, th.velocity, th.acceleration
    f = cylinder.solve(s, omega=sdot, epsilon=sddot).effort("stroke")
    q = crank.solve(theta, omega=d1 * sdot, epsilon=d2 * sdot * sdot + d1 * sddot).effort("theta")
    np.testing.assert_allclose(f, q * d1, rtol=1e-12)
    assert angle.solve(s).joint("stroke").position.tolist() == s.tolist()
