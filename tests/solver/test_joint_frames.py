"""URDF-style joints of a scene (``{revolute: ...}``, ``{prismatic: ...}``): what they measure,
their analogs two ways (5-point finite differences and the differentiated definition on the
points' analogs), the scalar path equal to the vectorised one, and the errors."""

from __future__ import annotations

import copy
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from scene_builders import build

import solver
from solver.tolerances import EPS

#: 5-point stencils with h = 1e-3 (as tests/solver/test_derivatives.py).
STEP = 1e-3
FIRST_TOL = 1e-9
SECOND_TOL = 1e-6
#: the analogs against the same quantities formed from the points' analogs: rounding only.
DEFINITION_TOL = 1e3 * EPS
PHI = np.linspace(0.05, 2 * np.pi - 0.05, 37)

FOUR_BAR: dict[str, Any] = yaml.safe_load(
    """
scene: four_bar_urdf_joints
units: {length: m, angle: deg}
fixed: {O: [0, 0], C: [0.4, 0], G: [0.1, 0.35]}
groups:
  - {type: crank, name: crank, center: O, point: A, length: 0.1}
  - {type: rrr, name: dyad, ends: [A, C], point: B, lengths: [0.4, 0.3], M: +1}
joints:
  rocker: {angle: [C, B]}
  coupler: {angle: [A, B]}
  rocker_urdf: {revolute: {parent: [O, C], child: [C, B]}}
  coupler_on_crank: {revolute: {parent: [O, A], child: [A, B], offset: 170, sign: -1}}
  motor: {revolute: {parent: [C, G], child: [A, O], offset: -35}}
  c_along_coupler: {prismatic: {guide: [A, B], point: C, offset: 0.01, sign: -1}}
  b_on_rail: {prismatic: {guide: {through: G, angle: 30}, point: B}}
  b_on_fixed_guide: {prismatic: {guide: [O, G], point: B, offset: -0.2}}
outputs:
  points: [A, B]
  joints: [rocker, coupler, rocker_urdf, coupler_on_crank, motor, c_along_coupler, b_on_rail, b_on_fixed_guide]
"""
)
URDF_JOINTS = ("rocker_urdf", "coupler_on_crank", "motor", "c_along_coupler", "b_on_rail", "b_on_fixed_guide")


def _scene(tmp_path: Path, data: dict[str, Any] = FOUR_BAR, name: str = "scene.yaml") -> solver.Scene:
    path = tmp_path / name
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    return solver.load_scene(path)


def _c(xy: np.ndarray) -> np.ndarray:
    return xy[..., 0] + 1j * xy[..., 1]


def _wrap(x: np.ndarray) -> np.ndarray:
    return (x + np.pi) % (2 * np.pi) - np.pi


def test_revolute_is_the_signed_angle_from_parent_to_child_plus_offset_wrapped(tmp_path: Path) -> None:
    scene = _scene(tmp_path).everything()
    k = scene.solve(PHI)
    a, b = _c(k.point("A").position), _c(k.point("B").position)
    o, c, g = 0j, 0.4 + 0j, 0.1 + 0.35j
    # arg((B − C)·conj(C − O)) with C − O = 0.4: the same angle as arg(B − C), but the product's
    # rounding moves atan2's result by an ulp at some samples (numpy's vectorised atan2)
    np.testing.assert_allclose(k.joint("rocker_urdf").position, k.joint("rocker").position, rtol=0,
                               atol=4 * np.pi * EPS)
    expected = _wrap(-(np.angle(b - a) - np.angle(a - o)) + math.radians(170))
    np.testing.assert_allclose(k.joint("coupler_on_crank").position, expected, atol=4 * np.pi * EPS)
    expected = _wrap(np.angle(o - a) - np.angle(g - c) - math.radians(35))
    np.testing.assert_allclose(k.joint("motor").position, expected, atol=4 * np.pi * EPS)
    for name in ("rocker_urdf", "coupler_on_crank", "motor"):
        q = k.joint(name).position
        assert np.all((q > -np.pi) & (q <= np.pi)), name
        assert scene.joint_units[name] == "rad"


def test_prismatic_is_the_signed_distance_along_the_guide_plus_offset(tmp_path: Path) -> None:
    scene = _scene(tmp_path).everything()
    k = scene.solve(PHI)
    a, b = _c(k.point("A").position), _c(k.point("B").position)
    g, c = 0.1 + 0.35j, 0.4 + 0j
    u = (b - a) / np.abs(b - a)
    np.testing.assert_allclose(k.joint("c_along_coupler").position, -((c - a) * np.conj(u)).real + 0.01, atol=1e-16)
    rail = complex(math.cos(math.radians(30)), math.sin(math.radians(30)))
    np.testing.assert_allclose(k.joint("b_on_rail").position, ((b - g) * np.conj(rail)).real, atol=1e-16)
    fixed = g / abs(g)
    np.testing.assert_allclose(k.joint("b_on_fixed_guide").position, (b * np.conj(fixed)).real - 0.2, atol=1e-16)
    assert scene.joint_units["b_on_rail"] == "m"


def test_prismatic_along_a_moving_guide_equals_the_distance_joint_of_the_slotted_link() -> None:
    data = yaml.safe_load(Path(solver.shipped_scenes()["harvester_finger"]).read_text(encoding="utf-8"))
    data["joints"]["eyelet_urdf"] = {"prismatic": {"guide": ["A", "C"], "point": "B"}}
    data["outputs"]["joints"] = ["eyelet", "eyelet_urdf"]
    k = build(data).solve(PHI, omega=1.0)
    for part in ("position", "velocity", "acceleration"):
        np.testing.assert_allclose(
            getattr(k.joint("eyelet_urdf"), part), getattr(k.joint("eyelet"), part), rtol=1e-12, atol=1e-15
        )


@pytest.mark.parametrize("name", URDF_JOINTS)
def test_analogs_match_five_point_finite_differences(tmp_path: Path, name: str) -> None:
    scene = _scene(tmp_path).with_outputs(points=(), joints=[name])
    m = scene.solve(PHI).joint(name)
    f = {s: scene.solve(PHI + s * STEP).joint(name).position for s in (-2, -1, 1, 2)}
    d = (lambda x, y: _wrap(x - y)) if scene.joint_units[name] == "rad" else (lambda x, y: x - y)
    d1 = (8 * d(f[1], f[-1]) - d(f[2], f[-2])) / (12 * STEP)
    d2 = (-d(f[2], m.position) + 16 * d(f[1], m.position) + 16 * d(f[-1], m.position) - d(f[-2], m.position)) / (
        12 * STEP**2
    )
    np.testing.assert_allclose(m.velocity, d1, atol=FIRST_TOL * max(1.0, float(np.max(np.abs(m.velocity)))))
    np.testing.assert_allclose(m.acceleration, d2, atol=SECOND_TOL * max(1.0, float(np.max(np.abs(m.acceleration)))))


def _angle_analogs(r: tuple[np.ndarray, ...]) -> tuple[np.ndarray, np.ndarray]:
    """θ' and θ'' of the direction of r from r = ρe^{jθ} differentiated: θ' = (r × r')/|r|²,
    θ'' = (r × r'')/|r|² − 2(r·r')(r × r')/|r|⁴."""
    r0, r1, r2 = r
    cross = lambda x, y: (np.conj(x) * y).imag
    dot = lambda x, y: (np.conj(x) * y).real
    n = np.abs(r0) ** 2
    return cross(r0, r1) / n, cross(r0, r2) / n - 2 * dot(r0, r1) * cross(r0, r1) / n**2


def test_analogs_equal_the_differentiated_definitions_on_the_points_analogs(tmp_path: Path) -> None:
    scene = _scene(tmp_path).everything()
    k = scene.solve(PHI)
    jets = {p: tuple(_c(x) for x in k.point(p)) for p in ("A", "B")}
    zero = np.zeros_like(PHI, dtype=complex)
    for p, value in (("O", 0j), ("C", 0.4 + 0j), ("G", 0.1 + 0.35j)):
        jets[p] = (zero + value, zero, zero)
    sub = lambda p, q: tuple(x - y for x, y in zip(jets[p], jets[q]))

    def check(name: str, d1: np.ndarray, d2: np.ndarray) -> None:
        m = k.joint(name)
        np.testing.assert_allclose(m.velocity, d1, atol=DEFINITION_TOL * max(1.0, float(np.max(np.abs(d1)))))
        np.testing.assert_allclose(m.acceleration, d2, atol=DEFINITION_TOL * max(1.0, float(np.max(np.abs(d2)))))

    c1, c2 = _angle_analogs(sub("B", "A"))
    p1, p2 = _angle_analogs(sub("A", "O"))
    check("coupler_on_crank", -(c1 - p1), -(c2 - p2))
    c1, c2 = _angle_analogs(sub("O", "A"))
    check("motor", c1, c2)
    # prismatic: q = (P − G)·u, u = r/|r| of the guide r = B − A:  q' = (P − G)'·u + (P − G)·u',
    # u' = θ'·ju, u'' = θ''·ju − θ'²·u
    r = sub("B", "A")
    t1, t2 = _angle_analogs(r)
    u = r[0] / np.abs(r[0])
    u1, u2 = 1j * t1 * u, 1j * t2 * u - t1 * t1 * u
    w = sub("C", "A")
    dot = lambda x, y: (np.conj(x) * y).real
    check("c_along_coupler", -(dot(u, w[1]) + dot(u1, w[0])), -(dot(u, w[2]) + 2 * dot(u1, w[1]) + dot(u2, w[0])))


def test_the_per_tick_path_gives_the_vectorised_values(tmp_path: Path) -> None:
    scene = _scene(tmp_path).everything()
    k = scene.solve(PHI, omega=1.7, epsilon=-0.4)
    for i, phi in enumerate(PHI.tolist()):
        one = scene.solve(phi, omega=1.7, epsilon=-0.4)
        for name in URDF_JOINTS:
            got = np.array([float(x) for x in one.joint(name)])
            want = np.array([k.joint(name).position[i], k.joint(name).velocity[i], k.joint(name).acceleration[i]])
            np.testing.assert_allclose(got, want, rtol=1e-13, atol=1e-15, err_msg=name)


def test_offsets_are_in_the_scene_units(tmp_path: Path) -> None:
    data = copy.deepcopy(FOUR_BAR)
    data["units"] = {"length": "mm", "angle": "rad"}
    data["fixed"] = {"O": [0, 0], "C": [400, 0], "G": [100, 350]}
    for g in data["groups"]:
        if g["type"] == "crank":
            g["length"] = 100
        else:
            g["lengths"] = [400, 300]
    data["joints"]["coupler_on_crank"]["revolute"]["offset"] = math.radians(170)
    data["joints"]["c_along_coupler"]["prismatic"]["offset"] = 10
    data["joints"]["b_on_fixed_guide"]["prismatic"]["offset"] = -200
    data["joints"]["motor"]["revolute"]["offset"] = math.radians(-35)
    data["joints"]["b_on_rail"]["prismatic"]["guide"]["angle"] = math.radians(30)
    mm = _scene(tmp_path, data, "mm.yaml").everything().solve(PHI)
    m = _scene(tmp_path).everything().solve(PHI)
    for name in URDF_JOINTS:
        np.testing.assert_allclose(mm.joint(name).position, m.joint(name).position, atol=1e-13, err_msg=name)


def _with_joint(spec: Any) -> dict[str, Any]:
    data = copy.deepcopy(FOUR_BAR)
    data["joints"] = {"rocker": {"angle": ["C", "B"]}, "j": spec}
    data["outputs"]["joints"] = ["rocker"]
    return data


@pytest.mark.parametrize(
    ("spec", "message"),
    [
        (
            {"revolute": {"parent": ["O", "C"], "child": ["C", "B"], "sign": 2}},
            r"joints\.j\.revolute\.sign: must be \+1 or -1, got 2",
        ),
        ({"revolute": {"parent": ["O", "C"]}}, r"joints\.j\.revolute\.child: missing required field"),
        (
            {"revolute": {"parent": ["O"], "child": ["C", "B"]}},
            r"joints\.j\.revolute\.parent: must name exactly 2 points",
        ),
        (
            {"revolute": {"parent": ["O", "C"], "child": ["C", "B"], "axis": 1}},
            r"joints\.j\.revolute: unknown field\(s\): axis; known: parent, child, offset, sign",
        ),
        (
            {"prismatic": {"guide": ["O", "C"], "point": "B", "ofset": 0.1}},
            r"joints\.j\.prismatic: unknown field 'ofset' \(did you mean 'offset'\?\)",
        ),
        (
            {"prismatic": {"guide": ["O", "C"], "point": "B", "offset": "x"}},
            r"joints\.j\.prismatic\.offset: must be a number",
        ),
        (
            {"prismatic": {"guide": {"through": "O"}, "point": "B"}},
            r"joints\.j\.prismatic\.guide\.angle: missing required field",
        ),
        ({"prismatic": {"guide": ["O", "C"]}}, r"joints\.j\.prismatic\.point: missing required field"),
        (
            {"prismatic": {"guide": "O", "point": "B"}},
            r"joints\.j\.prismatic\.guide: must be \[G0, G1\] or \{through: G0, angle: α\}, got 'O'",
        ),
        (
            {"hinge": {"parent": ["O", "C"]}},
            r"joints\.j: must be one of \{angle: …, distance: …, x: …, y: …, revolute: …",
        ),
    ],
)
def test_malformed_urdf_style_joints_name_the_entry_and_fault(tmp_path: Path, spec: Any, message: str) -> None:
    with pytest.raises(solver.SceneError, match=message):
        _scene(tmp_path, _with_joint(spec))


def test_urdf_style_joints_need_a_planar_scene(tmp_path: Path) -> None:
    data = yaml.safe_load(Path(solver.shipped_scenes()["spherical_converter"]).read_text(encoding="utf-8"))
    data.setdefault("joints", {})["j"] = {"revolute": {"parent": ["O", "K"], "child": ["O", "K"]}}
    with pytest.raises(solver.SceneError, match=r"joints\.j\.revolute: a revolute joint needs a planar scene"):
        _scene(tmp_path, data)


def test_a_joint_on_coincident_points_is_an_assembly_error_not_nan(tmp_path: Path) -> None:
    data = _with_joint({"revolute": {"parent": ["O", "O"], "child": ["C", "B"]}})
    data["outputs"]["joints"] = ["j"]
    with pytest.raises(solver.AssemblyError, match="parent line joins two coincident points"):
        _scene(tmp_path, data).solve(0.3)
