"""The vector form of a mechanism gives linkage-solve's table of its group form (issue 3).

Check (issue 3, "How it is checked"): the same CSV header and every column equal to TOL_REL
relative to that column's largest magnitude, at several ω and ε, through the CLI as a user runs it.
"""

from __future__ import annotations

import io

import numpy as np
import pytest

import solver
from solver.cli import main

TOL_REL = 1e-12
PAIRS = [
    ("four_bar", "four_bar_vectors"),
    ("harvester_finger", "harvester_finger_vectors"),
    ("slider_crank", "vectors/pl3_slider_crank"),
    ("four_bar_crossed", "vectors/pl4_four_bar_crossed"),
]
MOTIONS = [(1.0, 0.0), (2.5, -0.7), (-40.0, 300.0), (0.013, 1e-5)]


def _csv(scene: str, omega: float, epsilon: float, capsys: pytest.CaptureFixture[str]) -> tuple[str, np.ndarray]:
    assert main([scene, "--phi-count", "720", "--omega", repr(omega), "--epsilon", repr(epsilon), "--csv", "-"]) == 0
    text = capsys.readouterr().out
    header, _, body = text.partition("\n")
    return header, np.loadtxt(io.StringIO(body), delimiter=",")


@pytest.mark.parametrize(("groups", "vectors"), PAIRS)
@pytest.mark.parametrize(("omega", "epsilon"), MOTIONS)
def test_vector_form_gives_the_group_forms_table(
    groups: str, vectors: str, omega: float, epsilon: float, capsys: pytest.CaptureFixture[str]
) -> None:
    h1, t1 = _csv(groups, omega, epsilon, capsys)
    h2, t2 = _csv(vectors, omega, epsilon, capsys)
    # a vector scene has no bodies (docs/forces.md): the group form's force columns come after these
    assert h1.split(",")[: h2.count(",") + 1] == h2.split(",")
    h1, t1 = h2, t1[:, : h2.count(",") + 1]
    scale = np.max(np.abs(t1), axis=0)
    scale = np.where(scale > 0.0, scale, 1.0)  # an identically zero column: held to TOL_REL absolute (SI)
    worst = np.max(np.abs(t1 - t2), axis=0) / scale
    bad = {c: w for c, w in zip(h1.split(","), worst) if w > TOL_REL}
    assert not bad, bad


@pytest.mark.parametrize(("groups", "vectors"), PAIRS)
def test_vector_form_names_the_same_points_and_joints(groups: str, vectors: str) -> None:
    a, b = solver.load_scene(groups), solver.load_scene(vectors)
    assert a.point_names == b.point_names
    assert a.joint_names == b.joint_names
    assert a.input_joint == b.input_joint
    assert (a.output_points, a.output_joints) == (b.output_points, b.output_joints)


@pytest.mark.parametrize(("groups", "vectors"), PAIRS)
def test_one_tick_path_agrees_with_the_sweep(groups: str, vectors: str) -> None:
    s = solver.load_scene(vectors)
    phi = np.radians([0.0, 33.0, 187.0, 301.0])
    k = s.solve(phi, omega=1.7, epsilon=0.4)
    for i, p in enumerate(phi):
        one = s.solve(float(p), omega=1.7, epsilon=0.4)
        for name in s.output_points:
            for x, y in zip(one.point(name), k.point(name)):
                np.testing.assert_allclose(x, y[i], rtol=0, atol=1e-15)
        for name in s.output_joints:
            for x, y in zip(one.joint(name), k.joint(name)):
                np.testing.assert_allclose(x, y[i], rtol=0, atol=1e-14)


def _segments(scene: solver.Scene) -> set[frozenset[str]]:
    return {frozenset(pair) for link in scene.links for pair in zip(link.points, link.points[1:])}


@pytest.mark.parametrize(("groups", "vectors"), PAIRS)
def test_vector_form_draws_every_body_of_the_group_form(groups: str, vectors: str) -> None:
    assert _segments(solver.load_scene(groups)) <= _segments(solver.load_scene(vectors))


def test_ordinary_joints_section_reads_the_vector_models_points() -> None:
    """``joints: {rock2: {angle: [C, B]}}`` beside a vector model: the same rocker angle."""
    import yaml

    from solver._loader import parse_scene

    data = yaml.safe_load(open(solver.find_scene("four_bar_vectors"), encoding="utf-8"))
    data["joints"] = {"rock2": {"angle": ["C", "B"]}}
    data["outputs"]["joints"] = ["rocker", "rock2"]
    k = solver.Scene(parse_scene(data, file=None)).solve(np.linspace(0.0, 6.0, 25), omega=1.5, epsilon=0.2)
    for x, y in zip(k.joint("rocker"), k.joint("rock2")):
        np.testing.assert_allclose(y, x, rtol=0, atol=1e-14)
