"""Random drawings of four-bars, slider-cranks, Watt II and Stephenson III six-bars in both
assembly modes: the drawn pose reproduced at its own input value to 1e-12 of the drawing's size,
and the motion followed continuously, against an independent continuation solve (Newton on the
rigid links from the drawn pose; tests/structure/drawn_mechanisms.py)."""

from __future__ import annotations

import math
import random

import numpy as np
import pytest
from drawn_mechanisms import KINDS, drawing, follow
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from solver import SceneError
from solver._loader import parse_scene
from solver.scene import Scene
from solver.structure import find_structure, scene_dict_from_drawing
from solver.tolerances import SINGULAR

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


_COORD = st.floats(min_value=-1.0, max_value=1.0, allow_nan=False, allow_infinity=False)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(ax=_COORD, ay=_COORD, bx=_COORD, by=_COORD, cx=st.floats(0.2, 1.0), cy=_COORD)
def test_any_four_bar_drawn_loads_in_its_mode_or_is_refused_at_its_toggle(ax, ay, bx, by, cx, cy) -> None:  # type: ignore[no-untyped-def]
    """Hypothesis over bounded drawings: a four-bar drawn anywhere either is refused in one line
    (a toggle, points drawn at one place) or reproduces its pose, in the mode it is drawn in."""
    o, a, b, c = 0j, complex(ax, ay), complex(bx, by), complex(cx, cy)
    assume(min(abs(a - o), abs(b - a), abs(c - b), abs(c - o)) > 1e-3)
    data = {"scene": "h", "units": {"length": "m", "angle": "rad"},
            "drawing": {"points": {"O": [0.0, 0.0], "A": [ax, ay], "B": [bx, by], "C": [cx, cy]},
                        "ground": ["O", "C"], "links": {"crank": ["O", "A"], "coupler": ["A", "B"],
                                                        "rocker": ["C", "B"]}, "inputs": ["crank"]},
            "outputs": {"points": ["B"]}}
    p, q = b - a, b - c
    cond = abs((p.conjugate() * q).imag) / (abs(p) * abs(q))
    if cond < SINGULAR:
        with pytest.raises(SceneError, match="drawn at its toggle"):
            find_structure(data)
        return
    st_ = find_structure(data)
    area = ((b - a).conjugate() * (c - a)).imag
    assert [s.mode for s in st_.steps if s.kind == "rrr"] == [1 if area > 0 else -1]
    assume(cond >= 1e-3)  # (nearer a toggle the closed form's B carries EPS/conditioning)
    k = Scene(parse_scene(data, file=None)).solve(st_.inputs_drawn["crank"])
    size = max(abs(a), abs(b), abs(c))
    assert abs(complex(*k.point("B").position) - b) <= 1e-12 * size
