"""Efforts and pin loads against an independent 50-digit Newton–Euler reference (issue 17).

The reference (tests/reference/forces_mp.py, mpmath and PyYAML only, never the solver) solves the
Newton–Euler equations of every body of a scene as one linear system at 50 digits, at random
instants (φ or q, ω, ε), and stores input/expected pairs with provenance in
tests/data/forces_<scene>.json. Here the solver's force layer, on its vectorised path (all the
instants of a file in one call) and on its one-instant path (plain floats), must agree with it:

* every input effort ``k.effort(joint)``, every pin reaction ``k.reaction(P, on=X)`` on every body
  meeting at P (where three or more meet, a body's total there: the sum of ``k.reaction(P, on=X,
  by=Y)`` over the solver's pins of X at P), and every sliding pair's ``k.slide_reaction(block)``
  (force on the block from its guide, and its couple about the block's point);
* to REL_TOL relative to max(|expected|, scale): the scale of a force is the largest pin or
  slide force of that instant, of a torque or couple that times the scene's largest body
  (``scale_length`` in the file), so a value passing through zero is held to REL_TOL of the
  instant's loads instead of to a relative error of a tiny number.

Each file also names the scene file and the SHA-256 of its mechanics (units, fixed points, groups,
joints, bodies, gravity, loads, and flywheel and damping where the scene has them): a scene whose
mechanics changed after its reference was made fails here with the command that regenerates it
(descriptions and comments may change freely).
"""

from __future__ import annotations

import importlib
import json
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import solver

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data"
REFERENCE_DIR = ROOT / "tests" / "reference"
FILES = sorted(DATA.glob("forces_*.json"))

REL_TOL = 1e-9
"""Issue 17: relative error ≤ 1e-9 against the independent reference (scaled as above)."""


def _reference_module(name: str = "forces_mp") -> Any:
    if str(REFERENCE_DIR) not in sys.path:
        sys.path.insert(0, str(REFERENCE_DIR))
    return importlib.import_module(name)


def _load(path: Path) -> tuple[solver.Scene, dict]:
    ref = json.loads(path.read_text())
    scene_file = ROOT / ref["scene_file"]
    digest = _reference_module().digest(scene_file)
    assert digest == ref["scene_mechanics_sha256"], (
        f"{ref['scene_file']}'s mechanics changed since {path.name} was made: "
        f"python tests/reference/forces_mp.py {ref['scene_file']}"
    )
    scene = solver.load_scene(scene_file)
    return scene, ref


def _inputs(ref: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(q, ω, ε): (N,) for one input, (N, k) for several."""
    out = []
    for key in ("q", "omega", "epsilon"):
        a = np.array([[float(x) for x in row[key]] for row in ref["samples"]])
        out.append(a[:, 0] if a.shape[1] == 1 else a)
    return out[0], out[1], out[2]


def _expected(ref: dict) -> dict[tuple[str, ...], np.ndarray]:
    """{(kind, names...): (N,) or (N, 2)} of every stored quantity, and the per-sample scales."""
    rows = ref["samples"]
    out: dict[tuple[str, ...], np.ndarray] = {}
    for j in ref["inputs"]:
        out[("effort", j)] = np.array([float(r["effort"][j]) for r in rows])
    for point, bodies in rows[0]["reactions"].items():
        for body in bodies:
            if body != "ground":
                out[("reaction", point, body)] = np.array(
                    [[float(x) for x in r["reactions"][point][body]] for r in rows]
                )
    for block in rows[0]["slides"]:
        out[("slide force", block)] = np.array([[float(x) for x in r["slides"][block]["force"]] for r in rows])
        out[("slide couple", block)] = np.array([float(r["slides"][block]["couple"]) for r in rows])
    return out


def _scales(ref: dict, expected: dict[tuple[str, ...], np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Per sample: (force scale N, torque scale N·m)."""
    forces = [np.hypot(v[:, 0], v[:, 1]) for k, v in expected.items() if k[0] in ("reaction", "slide force")]
    force = np.max(forces, axis=0) if forces else np.ones(len(ref["samples"]))
    return force, force * float(ref["scale_length"])


def _got(scene: solver.Scene, k: Any, key: tuple[str, ...]) -> Any:
    if key[0] == "effort":
        return k.effort(key[1])
    if key[0] == "reaction":  # where 3+ bodies meet, one body's total is the sum over its pins there
        point, body = key[1], key[2]
        others = [
            p.other if p.body == body else p.body for p in scene.pins if p.point == point and body in (p.body, p.other)
        ]
        if len(others) == 1:
            return k.reaction(point, on=body)
        return sum(np.asarray(k.reaction(point, on=body, by=o)) for o in others)
    slide = k.slide_reaction(key[1])
    return slide.force if key[0] == "slide force" else slide.couple


def _check(
    scene: solver.Scene, k: Any, expected: dict, scales: tuple[np.ndarray, np.ndarray], rows: slice | int, where: str
) -> None:
    force_scale, torque_scale = scales
    for key, want in expected.items():
        got = np.asarray(_got(scene, k, key), dtype=float)
        w = want[rows]
        assert got.shape == w.shape, f"{where} {key}: shape {got.shape}, expected {w.shape}"
        scale = force_scale[rows] if key[0] in ("reaction", "slide force") else torque_scale[rows]
        if w.ndim > np.ndim(scale):
            scale = np.asarray(scale)[..., None]
        err = np.abs(got - w) / np.maximum(np.abs(w), scale)
        worst = int(np.argmax(err)) if err.ndim else 0
        assert np.all(err <= REL_TOL), (
            f"{where} {key}: relative error {np.max(err):.3g} > {REL_TOL:g} (first offending entry {worst}: "
            f"got {got.flat[worst]!r}, expected {w.flat[worst]!r})"
        )


def _has_forces(scene: solver.Scene) -> None:
    if not hasattr(solver.Kinematics, "effort"):
        pytest.skip("the force layer (issue 17) has not landed: Kinematics has no effort()")


@pytest.mark.parametrize("path", FILES, ids=[p.stem for p in FILES])
def test_vectorised_efforts_and_reactions_match_the_newton_euler_reference(path: Path) -> None:
    scene, ref = _load(path)
    _has_forces(scene)
    q, omega, epsilon = _inputs(ref)
    expected = _expected(ref)
    k = scene.solve(q, omega=omega, epsilon=epsilon)
    _check(scene, k, expected, _scales(ref, expected), slice(None), f"{ref['scene']} (vectorised)")


@pytest.mark.parametrize("path", FILES, ids=[p.stem for p in FILES])
def test_one_instant_efforts_and_reactions_match_the_newton_euler_reference(path: Path) -> None:
    scene, ref = _load(path)
    _has_forces(scene)
    q, omega, epsilon = _inputs(ref)
    expected = _expected(ref)
    scales = _scales(ref, expected)
    for i in range(len(ref["samples"])):
        if q.ndim == 1:
            k = scene.solve(float(q[i]), omega=float(omega[i]), epsilon=float(epsilon[i]))
        else:
            k = scene.solve(q[i], omega=tuple(map(float, omega[i])), epsilon=tuple(map(float, epsilon[i])))
        _check(scene, k, expected, scales, i, f"{ref['scene']} (one instant, sample {i}: q={ref['samples'][i]['q']})")


def test_the_reference_covers_the_scenes_issue_17_names() -> None:
    """The shipped four-bar, slider-crank (engine), slotted link (harvester finger) and five_bar
    with forces, and test scenes beyond them (tests/forces/scenes/): a massive piston with a
    constant force and a table, a ternary link (attached point) with springs and radians, a
    slotted link with a return spring, a massive slot block, three bodies on one pin (six-bar),
    an angle table, a scene in millimetres, a flywheel and dampers in every kind of revolute joint
    with tables of a 720° period and of a revolute joint (issue 22)."""
    scenes = {json.loads(p.read_text())["scene"] for p in FILES}
    assert {"four_bar_loaded", "engine", "harvester_finger", "five_bar"} <= scenes
    assert {"ref_four_bar_loaded", "ref_engine", "ref_harvester_finger", "ref_five_bar_payload"} <= scenes
    assert {"ref_gripper", "ref_four_bar_loaded_mm", "ref_six_bar", "ref_slotted_block"} <= scenes
    assert "ref_four_bar_damped" in scenes


@pytest.mark.parametrize("path", FILES[:2], ids=[p.stem for p in FILES[:2]])
def test_regenerating_a_reference_reproduces_the_stored_numbers(path: Path) -> None:
    data = _reference_module("forces_mp_data")
    stored = json.loads(path.read_text())
    fresh = data.build(ROOT / stored["scene_file"], len(stored["samples"]))
    assert data.compare(stored, fresh) < 1e-28


def test_the_reference_is_the_same_in_millimetres_and_in_metres() -> None:
    """The reference itself, not the solver: same instant, the two unit systems, same forces."""
    forces_mp = _reference_module()
    from mpmath import mp, mpf

    with mp.workdps(forces_mp.DPS):
        metres, millimetres = (
            forces_mp.load(ROOT / "tests" / "forces" / "scenes" / f"ref_four_bar_loaded{s}.yaml") for s in ("", "_mm")
        )
        args = ([mpf(1.1)], [mpf(-2.5)], [mpf(7.0)])
        a, b = forces_mp.solve(metres, *args), forces_mp.solve(millimetres, *args)
        assert abs(a.effort["crank"] - b.effort["crank"]) < mpf("1e-40")
        assert abs(a.reactions["B"]["rocker"][1] - b.reactions["B"]["rocker"][1]) < mpf("1e-40")
