"""The slider triad's variants (the swinging block, fixed or moving pivot; a guide on a moving
link) in the URDF tree: loaded by an independent parser (yourdfpy) and set to the tree joint
states, every cut's two frames coincide and every body point is where the solver put it, over
±0.5 rad of input around the drawn pose (the reference cases' scenes,
tests/scene_builders.py)."""

from __future__ import annotations

import io
from typing import Any

import numpy as np
import pytest
from scene_builders import slider_triad_variant, slider_triad_variant_cases
from test_urdf_closure import TOL_CLOSURE, _body_point_errors, _origin

from linkage_ros.urdf import build_model, generate_urdf, kinematics_tree_joint_states

yourdfpy = pytest.importorskip("yourdfpy", reason="yourdfpy is the independent URDF parser of these checks")


def _scene(kind: str) -> tuple[Any, float]:
    case = next(c for c in slider_triad_variant_cases() if c["kind"] == kind)
    return slider_triad_variant(case), float(case["phi_d"])


@pytest.mark.parametrize("kind", ["swing_fixed", "swing_moving", "carried"])
def test_cut_frames_coincide_and_bodies_follow_the_solver(kind: str) -> None:
    scene, phi_d = _scene(kind)
    model = build_model(scene)
    names = {b.name for b in model.bodies.values()}
    assert ("tri_block" in names) == kind.startswith("swing") and ("tri_slider" in names) == (kind == "carried")
    urdf = yourdfpy.URDF.load(io.StringIO(generate_urdf(scene)), load_meshes=False, build_scene_graph=True)
    phi = phi_d + np.linspace(-0.5, 0.5, 21)
    k = scene.everything().solve(phi, omega=1.7, epsilon=0.3, mask=True)
    states = kinematics_tree_joint_states(model, k)
    valid = np.flatnonzero(np.asarray(k.valid, bool))
    assert valid.size > 10
    worst_cut = worst_point = 0.0
    for i in valid:
        urdf.update_cfg(dict(zip(states.names, (float(q) for q in states.position[i]))))
        for cut in model.cuts:
            gap = _origin(urdf, f"{cut.name}_a") - _origin(urdf, f"{cut.name}_b")
            worst_cut = max(worst_cut, float(np.abs(gap).max()))
        worst_point = max(worst_point, _body_point_errors(urdf, model, k, int(i)))
    assert worst_cut <= TOL_CLOSURE
    assert worst_point <= TOL_CLOSURE
