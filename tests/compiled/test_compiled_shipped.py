"""The compiled instant equals today's scalar path to the bit on every shipped scene, and hands
every instant near an assembly limit, a dead centre or a singular position back to it."""

from __future__ import annotations

import math
import random

import numpy as np
import pytest
from compiled_compare import agree, bits, compiled_hit, outcome
from friction_scenes import FRICTION_SCENES

import solver
from solver.assembly import gaps
from solver.scene import shipped_scenes

#: A scene with friction is not compiled (solver.forces.friction; its refusal and its original's
#: compiled instant: tests/friction/test_friction_scenes.py): its original is here.
SCENES = sorted(n for n in shipped_scenes() if n not in FRICTION_SCENES)
#: Scenes with no traced path yet (every instant takes the scalar path, which the first test still
#: checks). A triad is traced: its tick is one opaque call (solver.groups._triad_tick).
UNTRACED: tuple[str, ...] = ()


def _samples(scene: solver.Scene, n: int, seed: int) -> list[tuple[float, ...]]:
    """Inputs over a turn (angles) or a little beyond the stroke (an actuator's, m)."""
    rng = random.Random(seed)
    k = len(scene.inputs)
    spans = [((-7.0, 7.0) if k == 1 else (0.3, 2.8)) if r is None else (r[0] - 0.02, r[1] + 0.02)
             for r in scene.input_ranges]
    if k == 1:
        return [(rng.uniform(*spans[0]), rng.uniform(-30.0, 30.0), rng.uniform(-50.0, 50.0)) for _ in range(n)]
    return [
        tuple(rng.uniform(*span) for span in spans) + tuple(rng.uniform(-5.0, 5.0) for _ in range(2 * k))
        for _ in range(n)
    ]


@pytest.mark.parametrize("name", SCENES)
@pytest.mark.parametrize("everything", [False, True], ids=["outputs", "everything"])
def test_compiled_values_are_the_scalar_paths_to_the_bit(name: str, everything: bool) -> None:
    scene = solver.load_scene(name)
    scene = scene.everything() if everything else scene
    samples = _samples(scene, 150, seed=len(name))
    assert all(agree(scene, *s) for s in samples)
    if name in UNTRACED:
        return
    # and the compiled code itself serves the regular samples (not the fallback every time)
    served = sum(compiled_hit(scene, *s) for s in samples)
    assert scene.compiled().paths >= 1
    assert served >= 0.5 * len(samples) or name.startswith("hard/double_rocker")


@pytest.mark.parametrize("name", [n for n in SCENES if len(solver.load_scene(n).inputs) == 1])
def test_near_the_limits_the_instant_is_exactly_todays(name: str) -> None:
    """At the ends of unassemblable intervals (± a few ulps and 1e-12 … 1e-6 rad), change points,
    dead centres and round angles (an actuator's stroke ends): the same values, flags or error as
    the scalar path."""
    scene = solver.load_scene(name).everything()
    phis = [0.0, math.pi / 2, math.pi, -math.pi, 2 * math.pi, 1e-300, -0.0]
    for span in scene.input_ranges:
        for edge in span or ():
            phis += [edge, float(np.nextafter(edge, edge + 1)), float(np.nextafter(edge, edge - 1))]
    for intervals in gaps(scene).values():
        for lo, hi in intervals:
            for edge in (lo, hi):
                for d in (0.0, 1e-15, 1e-12, 1e-9, 1e-6, 1e-3):
                    phis += [edge + d, edge - d]
                phis += [float(np.nextafter(edge, edge + 1)), float(np.nextafter(edge, edge - 1))]
    k = scene.solve(np.linspace(0.0, 2 * math.pi, 721), mask=True)
    worst = np.argsort(k.min_conditioning)[:6]  # the sweep's most singular samples, and around them
    for i in worst:
        f = float(k.phi[i])
        phis += [f + d for d in (-1e-4, -1e-7, 0.0, 1e-7, 1e-4)]
    for p in phis:
        assert agree(scene, p, 1.0, 0.0), p
        assert agree(scene, p, -2.5, 7.0), p


@pytest.mark.parametrize("name", SCENES)
def test_solve_at_one_instant_reads_the_same_through_the_compiled_path(name: str) -> None:
    scene = solver.load_scene(name).everything()
    k_in = len(scene.inputs)
    for args in _samples(scene, 20, seed=7):
        if k_in == 1:
            phi, w, e = args
            fast = scene.solve(phi, omega=w, epsilon=e, mask=True)
            slow = scene._solve_scalar(phi, w, e, True, compiled=False)
        else:
            q, w, e = args[:k_in], args[k_in:2 * k_in], args[2 * k_in:]
            fast = scene.solve(q, omega=w, epsilon=e, mask=True)
            slow = solver.multi.solve_instant(scene, q, w, e, True)
        assert bool(fast.valid) == bool(slow.valid)
        if not bool(slow.valid):
            continue
        for name_ in (*scene.output_points, *scene.output_joints):
            assert fast.floats(name_) == slow.floats(name_)
            m, n = (fast.point(name_), slow.point(name_)) if name_ in scene.output_points else (
                fast.joint(name_), slow.joint(name_))
            for a, b in zip(m, n):
                np.testing.assert_array_equal(a, b)
        assert fast.conditioning == slow.conditioning
        assert bool(fast.singular) == bool(slow.singular)


def test_an_unassemblable_instant_raises_todays_error() -> None:
    scene = solver.load_scene("hard/double_rocker")
    (lo, hi), *_ = gaps(scene)["dyad"] if "dyad" in gaps(scene) else next(iter(gaps(scene).values()))
    phi = 0.5 * (lo + hi)
    with pytest.raises(solver.AssemblyError, match="cannot be assembled") as fast:
        scene.instant(phi)
    with pytest.raises(solver.AssemblyError) as slow:
        scene._solve_scalar(phi, 1.0, 0.0, False, compiled=False)
    assert str(fast.value) == str(slow.value)
    assert not scene.solve(phi, mask=True).valid


def test_a_non_finite_input_is_todays_error() -> None:
    scene = solver.load_scene("four_bar")
    for bad in (math.nan, math.inf):
        with pytest.raises(solver.SolverError, match="must be finite"):
            scene.instant(bad)
        with pytest.raises(solver.SolverError, match="omega must be finite"):
            scene.instant(0.3, bad, 0.0)


def test_jacobians_and_hessians_of_several_inputs_come_from_compiled_code_to_the_bit() -> None:
    scene = solver.load_scene("five_bar").everything()
    unit = scene.compiled(derivatives=True)
    rng = random.Random(5)
    served = 0
    for _ in range(60):
        q = (rng.uniform(0.5, 2.6), rng.uniform(0.5, 2.6))
        assert agree_derivatives(scene, q)
        served += unit.core(*q) is not None
        k = scene.solve(q, omega=(1.5, -0.5), epsilon=(0.0, 2.0), mask=True)
        if bool(k.valid):
            for name in (*scene.output_points, *scene.output_joints):
                jac, hess = solver.multi.instant_jets(scene, q, name)
                want = solver.multi.derivative_arrays(jac, hess, name in scene.output_points)
                got = k.point(name) if name in scene.output_points else k.joint(name)
                np.testing.assert_array_equal(got.jacobian, want[0])
                np.testing.assert_array_equal(got.hessian, want[1])
    assert served >= 30


def agree_derivatives(scene: solver.Scene, q: tuple[float, float]) -> bool:
    unit = scene.compiled(derivatives=True)
    return outcome(unit.function, *q) == outcome(unit.fallback, *q)


@pytest.mark.parametrize("name", [n for n in SCENES if solver.load_scene(n).forces is not None])
def test_efforts_and_reactions_are_outputs_of_the_same_compiled_function(name: str) -> None:
    scene = solver.load_scene(name)
    unit = scene.compiled()
    served = 0
    for args in _samples(scene, 40, seed=11):
        flat = unit.core(*args)
        if flat is None:
            continue
        served += 1
        start = unit.size + len(unit.conditioning or ())
        assert len(flat) - start == len(scene.forces.layout)
        slow = unit.fallback(*args)
        assert [bits(x) for x in flat[start:]] == [bits(x) for x in slow[start:]]
        k_in = len(scene.inputs)
        if k_in == 1:
            fast = scene.solve(args[0], omega=args[1], epsilon=args[2])
        else:
            fast = scene.solve(args[:k_in], omega=args[k_in:2 * k_in], epsilon=args[2 * k_in:])
        for joint in scene.inputs:
            assert bits(fast.effort(joint)) == bits(slow[start + scene.forces.index[("effort", joint)]])
    assert served >= 20


@pytest.mark.parametrize("name", ["hard/parallelogram", "hard/antiparallelogram", "five_bar", "gripper_finger"])
def test_functions_rebuilt_after_misses_stay_exact(name: str) -> None:
    """Misses on untraced branches are traced and the function rebuilt, again and again: every
    rebuilt function still gives the scalar path's values (and serves more instants itself)."""
    scene = solver.load_scene(name).everything()
    unit = scene.compiled()
    samples = _samples(scene, 120, seed=3)
    if len(scene.inputs) > 1:  # rates exactly zero, one input at a time: other fast paths
        samples += [(*s[:2], 0.0, s[3], s[4], 0.0) for s in samples[:40]]
        samples += [(*s[:2], s[2], 0.0, 0.0, s[5]) for s in samples[:40]]
    for s in samples:
        scene.instant(s[0], s[1], s[2]) if len(scene.inputs) == 1 else scene.instant(s[:2], s[2:4], s[4:])
    assert unit.traces > 1
    assert all(agree(scene, *s) for s in samples)
    assert sum(compiled_hit(scene, *s) for s in samples) >= 0.8 * len(samples)


def test_one_instant_of_several_inputs_wants_one_value_per_input() -> None:
    scene = solver.load_scene("five_bar")
    assert scene.instant((1.0, 2.0), 1.0, 0.0) == scene.instant((1.0, 2.0), (1.0, 1.0), (0.0, 0.0))
    with pytest.raises(solver.SolverError, match=r"five_bar: instant: phi must be 2 numbers \(inputs q1, q2\), "
                                                 r"got 1.0$"):
        scene.instant(1.0)
    with pytest.raises(solver.SolverError, match="omega must be 2 numbers"):
        scene.instant((1.0, 2.0), (1.0, 2.0, 3.0))
