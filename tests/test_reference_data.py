"""Every shipped scene against its independent 50-digit reference (tests/data/reference_*.json).

The references come from tests/reference/mp_reference.py (mpmath only, never the solver):
closed-form positions at mp.dps = 50, analogs by mpmath's numerical differentiation.

Tolerances (issue 2, "How it is checked"):
* positions: TOL_POS absolute, in m for points and slide joints, rad for angle joints;
* analogs and real velocities / accelerations: TOL_REL relative to max(|ref|, scale). The scale
  is the mechanism's typical magnitude times the motion's: L = the scene's largest link length
  ("scale_length" in the file) for points and slide joints, 1 rad for angle joints; times |ω| for
  velocities and ω² + |ε| for accelerations (1 and 1 for the analogs, ω = 1, ε = 0). So a value
  that passes through zero is held to TOL_REL · L, not to a relative error of a tiny number.
"""

from __future__ import annotations

import csv
import importlib.util
import io
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import solver

TOL_POS = 1e-12
TOL_REL = 1e-9
TOL_GENERATOR = 1e-40
"""Regenerating stored values must reproduce them to this (they are 50-digit numbers)."""
CLI_TIMEOUT_S = 120

DATA = Path(__file__).resolve().parent / "data"
SCENES = ("harvester_finger", "four_bar", "four_bar_crossed", "slider_crank", "spherical_converter")
MOTIONS = {"analogs": (1.0, 0.0), "real_motion": (2.5, -0.7)}
"""(ω, ε): the analogs themselves, and the real-motion case stored in each file."""
CLI = "import sys; from solver.cli import main; sys.exit(main())"
"""What the linkage-solve console script runs; used so the test does not depend on PATH."""


def _load_reference(scene: str) -> dict:
    return json.loads((DATA / f"reference_{scene}.json").read_text())


def _floats(values: list) -> np.ndarray:
    """Decimal strings (possibly nested lists) to float64, each correctly rounded by float()."""
    return np.array([_floats(v) if isinstance(v, list) else float(v) for v in values], dtype=float)


def _expected(ref: dict, omega: float, epsilon: float) -> dict[tuple[str, str], tuple[np.ndarray, ...]]:
    """{(kind, name): (position, velocity, acceleration, scale)} for ω, ε (seed 000 eq. 11–12)."""
    length = float(ref["scale_length"])
    out = {}
    for kind, table in (("point", ref["points"]), ("joint", ref["joints"])):
        for name, entry in table.items():
            q, dq, ddq = (_floats(entry[key]) for key in ("position", "d_dphi", "d2_dphi2"))
            unit = 1.0 if entry.get("kind") == "angle" else length
            out[kind, name] = (
                q,
                dq * omega,
                ddq * omega**2 + dq * epsilon,
                np.array([unit * abs(omega), unit * (omega**2 + abs(epsilon))]),
            )
    return out


def _assert_close(label: str, got: np.ndarray, want: tuple[np.ndarray, ...]) -> None:
    """got = (position, velocity, acceleration) arrays against the reference tuple."""
    q, v, a, scale = want
    pos, vel, acc = (np.asarray(x, dtype=float) for x in got)
    assert pos.shape == q.shape, f"{label}: shape {pos.shape}, reference {q.shape}"
    err = np.abs(pos - q)
    assert np.all(err <= TOL_POS), f"{label} position: max error {err.max():.3e} > {TOL_POS:g}"
    for what, value, ref, s in (("velocity", vel, v, scale[0]), ("acceleration", acc, a, scale[1])):
        assert value.shape == ref.shape, f"{label} {what}: shape {value.shape}, reference {ref.shape}"
        rel = np.abs(value - ref) / np.maximum(np.abs(ref), s)
        worst = np.unravel_index(np.argmax(rel), rel.shape)
        assert np.all(rel <= TOL_REL), (
            f"{label} {what}: relative error {rel[worst]:.3e} > {TOL_REL:g} at index {worst} "
            f"(got {value[worst]!r}, reference {ref[worst]!r})"
        )


@pytest.mark.parametrize("motion", MOTIONS)
@pytest.mark.parametrize("scene_name", SCENES)
def test_solver_matches_50_digit_reference(scene_name: str, motion: str) -> None:
    ref = _load_reference(scene_name)
    omega, epsilon = MOTIONS[motion]
    scene = solver.load_scene(scene_name)
    phi = _floats(ref["phi"])
    k = scene.solve(phi, omega=omega, epsilon=epsilon)
    for (kind, name), want in _expected(ref, omega, epsilon).items():
        result = k.point(name) if kind == "point" else k.joint(name)
        _assert_close(f"{scene_name} {kind} {name}", (result.position, result.velocity, result.acceleration), want)


@pytest.mark.parametrize("scene_name", SCENES)
def test_shipped_scene_declares_the_contracted_outputs(scene_name: str) -> None:
    ref = _load_reference(scene_name)
    scene = solver.load_scene(scene_name)
    assert scene.dim == ref["dim"]
    assert scene.input_joint == ref["input_joint"]
    assert set(ref["points"]) <= set(scene.output_points)
    assert set(ref["joints"]) <= set(scene.output_joints)


@pytest.mark.parametrize("scene_name", SCENES)
def test_input_joint_position_is_phi_unwrapped(scene_name: str) -> None:
    """φ = 7 and 100 rad come back as themselves, not reduced to (−π, π]; ω and ε likewise."""
    ref = _load_reference(scene_name)
    phi = _floats(ref["phi"])
    omega, epsilon = MOTIONS["real_motion"]
    scene = solver.load_scene(scene_name)
    scene = scene.with_outputs(joints=(*scene.output_joints, ref["input_joint"]))
    joint = scene.solve(phi, omega=omega, epsilon=epsilon).joint(ref["input_joint"])
    np.testing.assert_array_equal(joint.position, phi)
    np.testing.assert_allclose(joint.velocity, omega, rtol=0, atol=TOL_POS)
    np.testing.assert_allclose(joint.acceleration, epsilon, rtol=0, atol=TOL_POS)


def _csv_columns(scene: object) -> list[str]:
    axes = "xyz"[: scene.dim]
    header = ["phi"]
    for p in scene.output_points:
        header += [f"{p}.{a}" for a in axes] + [f"{p}.v{a}" for a in axes] + [f"{p}.a{a}" for a in axes]
    for j in scene.output_joints:
        header += [f"{j}.q", f"{j}.dq", f"{j}.ddq"]
    return header


@pytest.mark.parametrize("motion", MOTIONS)
@pytest.mark.parametrize("scene_name", SCENES)
def test_cli_csv_matches_50_digit_reference(scene_name: str, motion: str) -> None:
    ref = _load_reference(scene_name)
    omega, epsilon = MOTIONS[motion]
    phi = _floats(ref["phi"])
    argv = [
        scene_name,
        "--phi=" + ",".join(repr(float(p)) for p in phi),
        f"--omega={omega!r}",
        f"--epsilon={epsilon!r}",
        "--csv",
        "-",
    ]
    done = subprocess.run(
        [sys.executable, "-c", CLI, *argv], capture_output=True, text=True, timeout=CLI_TIMEOUT_S, check=False
    )
    assert done.returncode == 0, f"linkage-solve {' '.join(argv[:1])} failed:\n{done.stderr}"
    rows = list(csv.reader(io.StringIO(done.stdout)))
    header, body = rows[0], np.array(rows[1:], dtype=float)
    kinematics = _csv_columns(solver.load_scene(scene_name))
    assert header[: len(kinematics)] == kinematics  # then a scene with forces has its force columns
    assert all(c.endswith(".effort") or c.startswith(("pin.", "slide.")) for c in header[len(kinematics):])
    column = {name: body[:, i] for i, name in enumerate(header)}
    np.testing.assert_array_equal(column["phi"], phi)  # full float precision round trip
    axes = "xyz"[: ref["dim"]]
    for (kind, name), want in _expected(ref, omega, epsilon).items():
        if kind == "point":
            got = tuple(np.column_stack([column[f"{name}.{pre}{a}"] for a in axes]) for pre in ("", "v", "a"))
        else:
            got = tuple(column[f"{name}.{suffix}"] for suffix in ("q", "dq", "ddq"))
        _assert_close(f"CLI {scene_name} {kind} {name}", got, want)


def _generator() -> object:
    path = Path(__file__).resolve().parent / "reference" / "mp_reference.py"
    spec = importlib.util.spec_from_file_location("mp_reference", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("mp_reference", module)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("scene_name", SCENES)
def test_stored_reference_is_what_its_generator_computes(scene_name: str) -> None:
    """A sample of each file (grid ends, every irregular angle) regenerated from scratch."""
    mpmath = pytest.importorskip("mpmath", reason="regenerating the reference needs mpmath")
    gen = _generator()
    stored = _load_reference(scene_name)
    picks = [0, 1, 17, 47, *range(48, len(stored["phi"]))]
    fresh = gen.build_reference(scene_name, [float(stored["phi"][i]) for i in picks])
    assert stored["provenance"].startswith("tests/reference/mp_reference.py (mpmath ")
    for kind in ("points", "joints"):
        assert set(fresh[kind]) == set(stored[kind])
        for name, entry in fresh[kind].items():
            for key in ("position", "d_dphi", "d2_dphi2"):
                for row, i in enumerate(picks):
                    a, b = np.atleast_1d(stored[kind][name][key][i]), np.atleast_1d(entry[key][row])
                    diff = max(abs(mpmath.mpf(x) - mpmath.mpf(y)) for x, y in zip(a, b, strict=True))
                    assert diff < TOL_GENERATOR, f"{scene_name} {name} {key} at phi #{i}: {diff}"
