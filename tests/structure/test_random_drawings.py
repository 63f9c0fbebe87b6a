"""Random drawings of four-bars, slider-cranks, Watt II and Stephenson III six-bars in both
assembly modes: the drawn pose reproduced at its own input value to 1e-12 of the drawing's size,
and the motion followed continuously, against an independent continuation solve (Newton on the
rigid links from the drawn pose; tests/structure/drawn_mechanisms.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from drawn_mechanisms import KINDS, drawing, follow

from solver._loader import parse_scene
from solver.scene import Scene
from solver.structure import find_structure

#: The assembly modes drawn: one dyad (four-bar, slider-crank) or two (the six-bars).
MODES = {"four_bar": [(1,), (-1,)], "slider_crank": [(1,), (-1,)],
         "watt_ii": [(1, 1), (1, -1), (-1, 1), (-1, -1)], "stephenson_iii": [(1, 1), (1, -1), (-1, 1), (-1, -1)]}
CASES = [(kind, seed, modes) for kind in KINDS for modes in MODES[kind] for seed in range(3)]
#: Step of the continuation (rad) and how far it goes each way from the drawn input value.
STEP = math.radians(2.0)
SPAN = math.pi


@pytest.mark.parametrize(("kind", "seed", "modes"), CASES, ids=[f"{k}-{s}-{m}" for k, s, m in CASES])
def test_a_random_drawing_reproduces_its_pose_and_follows_it(kind: str, seed: int, modes: tuple[int, ...]) -> None:
    data = drawing(kind, seed, modes)
    st = find_structure(data, source=data["scene"])
    # the modes read off the drawing are the ones it was drawn in
    assert tuple(s.mode for s in st.steps if s.mode is not None) == modes
    scene = Scene(parse_scene(data, file=data["scene"])).everything()
    pts = {k: complex(*v) for k, v in data["drawing"]["points"].items()}
    size = max(abs(z) for z in pts.values())
    phi0 = st.inputs_drawn["crank"]
    k0 = scene.solve(phi0)  # the per-tick path
    kv = scene.solve(np.array([phi0]))  # the vectorised path
    for p, z in pts.items():
        assert abs(complex(*k0.point(p).position) - z) <= 1e-12 * size, p
        assert abs(complex(*kv.point(p).position[0]) - z) <= 1e-12 * size, p
    for direction in (1.0, -1.0):
        phis = phi0 + direction * STEP * np.arange(1, int(SPAN / STEP) + 1)
        unknown, path = follow(data["drawing"], phis)
        k = scene.solve(phis, mask=True)
        cond = np.min(np.stack([np.broadcast_to(c, phis.shape) for c in k.conditioning.values()]), axis=0)
        followed = 0
        for i, sol in enumerate(path):
            if sol is None or not k.valid[i] or cond[i] < 0.05:
                break  # near a toggle or past the assembly's end: the reference stops here
            for j, p in enumerate(unknown):
                got = complex(*k.point(p).position[i])
                assert abs(got - complex(sol[2 * j], sol[2 * j + 1])) <= 1e-10 * size, (p, phis[i])
            followed += 1
        assert followed >= 5, f"followed only {followed} steps"


@pytest.mark.parametrize("kind", KINDS)
def test_the_plan_does_not_depend_on_the_order_the_drawing_lists_things_in(kind: str) -> None:
    import random

    from solver.structure import scene_dict_from_drawing

    data = drawing(kind, 7, MODES[kind][-1])
    expected = scene_dict_from_drawing(data)["groups"]
    rng = random.Random(kind)
    for _ in range(5):
        shuffled = dict(data)
        dr = dict(data["drawing"])
        for key in ("points", "links", "slides"):
            if key in dr:
                items = list(dr[key].items())
                rng.shuffle(items)
                dr[key] = dict(items)
        shuffled["drawing"] = dr
        assert scene_dict_from_drawing(shuffled)["groups"] == expected
