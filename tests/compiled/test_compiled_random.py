"""Random scenes of every group kind: the compiled instant is the scalar path to the bit.

Each scene chains a crank, a crank-fed RRR dyad, a point attached to its coupler, a second
(unfed) dyad, an RRP slider, a slotted link and joints of every kind (angle, distance, x, y,
URDF revolute with offset and sign, URDF prismatic on a moving and on a fixed guide); a
continuous-branch four-bar; the spherical crank-slider; two-input five-bars with rates that are
exactly zero (the groups' fast path for them is a guard too). Samples include the round angles,
where exact zeros appear.
"""

from __future__ import annotations

import math
from typing import Any

from compiled_compare import agree
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scene_builders import build, four_bar

import solver

SETTINGS = settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
ANGLES = st.floats(-7.0, 7.0, allow_nan=False)
RATES = st.floats(-20.0, 20.0, allow_nan=False)
ROUND = [0.0, math.pi / 2, math.pi, 1.5 * math.pi, -math.pi / 4]


def _chain(p: dict[str, Any]) -> solver.Scene:
    return build({
        "scene": "chain",
        "units": {"length": "m", "angle": "rad"},
        "fixed": {"O": [0.0, 0.0], "C": [p["ground"], 0.0], "G": [p["gx"], p["gy"]]},
        "groups": [
            {"type": "crank", "name": "crank", "center": "O", "point": "A", "length": p["crank"]},
            {"type": "rrr", "name": "dyad", "ends": ["A", "C"], "point": "B", "lengths": [p["coupler"], p["rocker"]],
             "M": p["m1"]},
            {"type": "attached", "name": "tip", "point": "D", "base": "A", "along": ["A", "B"],
             "distance": p["tip"], "angle": p["tip_angle"]},
            {"type": "rrr", "name": "second", "ends": ["D", "G"], "point": "E", "lengths": [p["l3"], p["l4"]],
             "M": p["m2"]},
            {"type": "rrp", "name": "rod", "end": "B", "point": "S", "length": p["rod"],
             "guide": {"through": "O", "angle": p["guide"], "offset": p["offset"]}, "M": p["m3"], "joint": "slide"},
            {"type": "slotted", "name": "slot", "pivot": "G", "through": "A", "points": {"T": p["slot"]}},
        ],
        "joints": {
            "coupler": {"angle": ["A", "B"]},
            "reach": {"distance": ["D", "E"]},
            "ex": {"x": "E"},
            "sy": {"y": "S"},
            "elbow": {"revolute": {"parent": ["O", "A"], "child": ["A", "B"], "offset": p["q0"], "sign": p["sign"]}},
            "along": {"prismatic": {"guide": ["C", "B"], "point": "D", "offset": p["d0"]}},
            "level": {"prismatic": {"guide": {"through": "G", "angle": p["guide"]}, "point": "T", "sign": -1}},
        },
        "outputs": {"points": ["B", "D", "E", "S", "T"],
                    "joints": ["crank", "coupler", "reach", "ex", "sy", "elbow", "along", "level", "slide"]},
    })


CHAIN = st.fixed_dictionaries({
    "crank": st.floats(0.05, 0.15), "ground": st.floats(0.35, 0.5), "coupler": st.floats(0.3, 0.5),
    "rocker": st.floats(0.3, 0.5), "m1": st.sampled_from([1, -1]), "tip": st.floats(0.05, 0.3),
    "tip_angle": st.floats(-3.0, 3.0), "gx": st.floats(0.6, 0.9), "gy": st.floats(0.2, 0.5),
    "l3": st.floats(0.3, 0.6), "l4": st.floats(0.3, 0.6), "m2": st.sampled_from([1, -1]),
    "rod": st.floats(0.6, 1.0), "guide": st.floats(-0.5, 0.5), "offset": st.floats(-0.1, 0.1),
    "m3": st.sampled_from([1, -1]), "slot": st.floats(-0.4, 0.6).filter(lambda x: abs(x) > 1e-3),
    "q0": st.floats(-3.0, 3.0), "sign": st.sampled_from([1, -1]), "d0": st.floats(-0.2, 0.2),
})


@SETTINGS
@given(CHAIN, st.lists(st.tuples(ANGLES, RATES, RATES), min_size=6, max_size=6))
def test_a_chain_of_every_group_and_joint_kind(p: dict[str, Any], samples: list[tuple[float, float, float]]) -> None:
    scene = _chain(p)
    for args in [*samples, *((r, 1.0, 0.0) for r in ROUND)]:
        assert agree(scene, *args), args


@SETTINGS
@given(st.floats(0.05, 0.2), st.floats(0.05, 0.3), st.sampled_from([1, -1]),
       st.lists(ANGLES, min_size=8, max_size=8))
def test_a_continuous_branch_through_its_change_points(
    crank: float, slack: float, mode: int, phis: list[float]
) -> None:
    # a parallelogram (change points at 0 and π) and a near-parallelogram, branch followed in φ
    for ground in (0.4, 0.4 + slack * 0.01):
        scene = four_bar(crank, 0.4, crank, ground, mode=mode, through="continuous").everything()
        for phi in [*phis, 0.0, math.pi, 2 * math.pi, 1e-9, math.pi - 1e-9]:
            assert agree(scene, phi, 1.5, -0.5), phi


@SETTINGS
@given(st.floats(0.05, 1.5), st.floats(0.01, 1.0), st.lists(st.tuples(ANGLES, RATES, RATES), min_size=6, max_size=6))
def test_the_spherical_crank_slider(alpha: float, radius: float, samples: list[tuple[float, float, float]]) -> None:
    scene = build({
        "scene": "sphere", "units": {"length": "m", "angle": "rad"}, "fixed": {"O": [0.0, 0.0, 0.0]},
        "groups": [{"type": "spherical_crank_slider", "name": "conv", "center": "O", "point": "K",
                    "shaft": "shaft", "cage": "cage", "alpha": alpha, "radius": radius}],
        "outputs": {"points": ["K", "O"], "joints": ["shaft", "cage"]},
    })
    for args in [*samples, *((r, 1.0, 0.0) for r in ROUND)]:
        assert agree(scene, *args), args


@SETTINGS
@given(
    st.floats(0.1, 0.2), st.floats(0.2, 0.3), st.sampled_from([1, -1]),
    st.lists(st.tuples(st.floats(0.3, 2.8), st.floats(0.3, 2.8)), min_size=5, max_size=5),
    st.lists(st.sampled_from([0.0, 1.0, -2.5, 3.0]), min_size=4, max_size=4),
)
def test_two_inputs_with_rates_that_are_exactly_zero(
    crank: float, distal: float, mode: int, qs: list[tuple[float, float]], rates: list[float]
) -> None:
    scene = build({
        "scene": "five", "units": {"length": "m", "angle": "rad"},
        "fixed": {"O1": [0.0, 0.0], "O2": [0.2, 0.0]},
        "groups": [
            {"type": "crank", "name": "left", "center": "O1", "point": "A1", "length": crank, "joint": "q1"},
            {"type": "crank", "name": "right", "center": "O2", "point": "A2", "length": crank, "joint": "q2"},
            {"type": "rrr", "name": "distal", "ends": ["A1", "A2"], "point": "P", "lengths": [distal, distal],
             "M": mode},
        ],
        "joints": {"left_distal": {"angle": ["A1", "P"]}},
        "outputs": {"points": ["P", "A1"], "joints": ["q1", "q2", "left_distal"]},
    })
    for q in qs:
        assert agree(scene, *q, *rates), (q, rates)
