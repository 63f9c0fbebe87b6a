"""The per-tick entry points: ``scene.instant`` is the compiled function behind the method's own
check of its arguments, and ``scene.solve(float)`` returns a result read lazily from the flat
tuple — both give exactly what the general paths give."""

from __future__ import annotations

import math
import random

import numpy as np
import pytest
from compiled_compare import bits, outcome

import solver
from solver.kinematics import InstantKinematics, InstantMotion


def _angles(n: int, seed: int) -> list[tuple[float, float, float]]:
    rng = random.Random(seed)
    return [(rng.uniform(-7.0, 7.0), rng.uniform(-30.0, 30.0), rng.uniform(-50.0, 50.0)) for _ in range(n)]


def test_instant_is_the_compiled_function_to_the_bit() -> None:
    scene = solver.load_scene("four_bar").everything()
    unit = scene.compiled()
    assert scene.instant is scene.__dict__["instant"]  # bound in place of the method
    for args in _angles(100, seed=1):
        assert outcome(scene.instant, *args) == outcome(unit.function, *args) == outcome(unit.fallback, *args)
    assert scene.instant(0.7) == scene.instant(0.7, 1.0, 0.0)


@pytest.mark.parametrize("phi, omega, epsilon", [(1, 2, 0), (np.float64(0.7), 2.0, 0.5),
                                                 (0.7, np.float32(2.0), np.int64(1)), (np.array(0.7), 2, 0.5)])
def test_other_numbers_go_through_the_method_and_give_floats(phi: object, omega: object, epsilon: object) -> None:
    scene = solver.load_scene("four_bar").everything()
    want = scene.instant(float(phi), float(omega), float(epsilon))  # type: ignore[arg-type]
    got = scene.instant(phi, omega, epsilon)
    assert [bits(x) for x in got] == [bits(x) for x in want]
    assert all(type(x) is float for x in got)


def test_other_orders_go_through_the_method() -> None:
    scene = solver.load_scene("four_bar").everything()
    scene.instant(0.3)
    for order in (0, 1, 2):
        assert scene.instant(0.7, 2.0, 0.5, order=order) == scene.compiled(order=order).function(0.7, 2.0, 0.5)
    assert len(scene.instant(0.7, order=0)) < len(scene.instant(0.7, order=1)) < len(scene.instant(0.7))


def test_errors_through_the_bound_instant_are_the_methods() -> None:
    scene = solver.load_scene("four_bar")
    scene.instant(0.3)
    with pytest.raises(solver.SolverError, match="phi must be finite"):
        scene.instant(math.inf)
    with pytest.raises(solver.SolverError, match="epsilon must be finite"):
        scene.instant(0.3, 1.0, math.nan)


@pytest.mark.parametrize("name", ["engine", "four_bar_loaded", "harvester_finger"])
def test_instant_follows_the_function_through_rebuilds(name: str) -> None:
    """A miss on an untraced branch (here: rates exactly 0, the groups' fast paths) rebuilds the
    function: ``scene.instant`` is rebound to it."""
    scene = solver.load_scene(name).everything()
    unit = scene.compiled()
    paths, seen = unit.paths, [scene.instant]  # (the functions kept: a freed one's id is reused)
    samples = _angles(60, seed=4)
    samples += [(p, 0.0, e) for p, _, e in samples[:20]] + [(p, w, 0.0) for p, w, _ in samples[20:40]]
    for args in samples + [(p, 0.0, 0.0) for p, _, _ in samples[40:]]:
        assert outcome(scene.instant, *args) == outcome(unit.fallback, *args)
        if scene.instant is not seen[-1]:
            seen.append(scene.instant)
    assert unit.paths > paths
    assert len(seen) == 1 + unit.paths - paths  # rebound at every rebuild
    for args in _angles(30, seed=5):
        assert outcome(scene.instant, *args) == outcome(unit.function, *args)


def test_several_inputs_keep_the_method() -> None:
    scene = solver.load_scene("five_bar")
    scene.instant((1.0, 2.0), 1.0, 0.0)
    assert "instant" not in scene.__dict__
    with pytest.raises(solver.SolverError, match=r"five_bar: instant: phi must be 2 numbers \(inputs q1, q2\), "
                                                 r"got 1.0$"):
        scene.instant(1.0)


def test_a_solve_at_one_instant_reads_its_flat_tuple_lazily() -> None:
    scene = solver.load_scene("four_bar_loaded")
    k = scene.solve(0.7, omega=2.0, epsilon=0.5)
    slow = scene._solve_scalar(0.7, 2.0, 0.5, False, compiled=False)
    assert type(k) is InstantKinematics
    assert not {"_conditioning", "_forces", "_motions", "_derivatives"} & set(k.__dict__)  # nothing made yet
    for name in (*scene.output_points, *scene.output_joints):
        assert k.floats(name) == slow.floats(name)
    assert k.conditioning == slow.conditioning
    assert [bits(k.effort(j)) for j in scene.inputs] == [bits(slow.effort(j)) for j in scene.inputs]
    p = scene.output_points[0]
    assert k.point(p) == slow.point(p) and type(k.point(p)) is type(slow.point(p)) is InstantMotion
    assert all(type(x) is tuple and all(type(c) is float for c in x) for x in k.point(p))
    assert all(type(x) is float for x in k.joint(scene.output_joints[0]))
    for a, b in zip(k.derivatives(p), slow.derivatives(p)):
        np.testing.assert_array_equal(a, b)
    assert k.derivatives(p)[0].shape == (2, 1) and k.derivatives(p)[1].shape == (2, 1, 1)
    with pytest.raises(solver.SolverError, match="point 'nowhere' was not requested"):
        k.point("nowhere")
    assert k.phi == 0.7 and k.omega == 2.0 and k.epsilon == 0.5 and k.valid
    with pytest.raises(solver.SolverError, match="'nowhere' was not requested"):
        k.floats("nowhere")
    masked = scene.solve(0.7, omega=2.0, epsilon=0.5, mask=True)
    assert masked.valid.shape == () and bool(masked.valid)


@pytest.mark.parametrize("name", ["four_bar", "harvester_finger", "slider_crank", "vectors/pl2_scotch_yoke"])
def test_the_one_call_spellings_give_the_same_bits_at_awkward_angles(name: str) -> None:
    """``cmath.rect(1.0, a)`` for ``complex(cos a, sin a)`` (signed zeros, subnormals, huge
    angles), the conditional for ``max(x, 0.0)`` and a float's ``abs``: what the scalar path gives."""
    scene = solver.load_scene(name).everything()
    unit = scene.compiled()
    assert "rect" in unit.source and "max(" not in unit.source
    angles = [0.0, -0.0, 5e-324, -5e-324, 1e-300, -1e-300, math.pi, -math.pi, math.pi / 2, 1e22, -1e22, 1e300]
    for a in angles:
        for w, e in ((1.0, 0.0), (-2.5, 7.0), (-0.0, -0.0)):
            assert outcome(unit.function, a, w, e) == outcome(unit.fallback, a, w, e), (a, w, e)


@pytest.mark.parametrize("name", ["four_bar", "four_bar_loaded", "five_bar"])
def test_a_used_scene_pickles_and_copies_without_its_compiled_code(name: str) -> None:
    import copy
    import pickle

    scene = solver.load_scene(name).everything()
    q = (0.4, 1.9) if name == "five_bar" else 0.4
    first = scene.solve(q, omega=1.5, epsilon=0.25)
    for other in (pickle.loads(pickle.dumps(scene)), copy.copy(scene), copy.deepcopy(scene)):
        assert "instant" not in other.__dict__ and "_compiled_units" not in other.__dict__
        again = other.solve(q, omega=1.5, epsilon=0.25)
        for point in scene.output_points:
            assert bits(again.floats(point)) == bits(first.floats(point))
        if name != "five_bar":
            assert other.instant is not scene.instant
            assert other.instant(0.4, 1.5, 0.25) == scene.instant(0.4, 1.5, 0.25)
