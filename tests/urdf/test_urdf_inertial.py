"""The URDF for effort-driven work: ``<inertial>`` from the scene's ``bodies:``, real limits, and
links named after the scene's bodies — read back by an independent parser (yourdfpy)."""

from __future__ import annotations

import io
import math
import xml.etree.ElementTree as ET
from dataclasses import replace
from typing import Any

import numpy as np
import pytest

import solver
from linkage_ros.urdf import build_model, generate_urdf, kinematics_tree_joint_states
from linkage_ros.urdf.inertial import POINT_MASS_RADIUS_PER_SIZE
from linkage_ros.urdf.writer import DEFAULT_EFFORT, DEFAULT_VELOCITY, drive_limits

yourdfpy = pytest.importorskip("yourdfpy", reason="yourdfpy is the independent URDF parser of these checks")

#: Scenes with masses (``bodies:``), group form.
MASSIVE = ("excavator", "tipper", "engine", "harvester_finger", "four_bar_pendulum", "four_bar_loaded", "five_bar")
#: The centre of mass placed by the URDF against the one the scene defines (m): rounding only.
TOL_CENTER = 1e-9


def _load(scene: Any) -> Any:
    return yourdfpy.URDF.load(io.StringIO(generate_urdf(scene)), load_meshes=False, build_scene_graph=True)


def _world_center(body: Any, k: Any, i: int) -> np.ndarray:
    """G in the world from the scene's definition (docs/forces.md): G = O + c·(X − O)/|X − O|; a
    block's G = B + c·e, e its guide (an RRP's fixed direction, a slotted link's pivot → eyelet)."""
    def z(p: str) -> complex:
        x = k.point(p).position[i]
        return complex(x[0], x[1])

    origin = z(body.frame[0])
    if body.link.block:
        e = body.link.guide if body.link.guide is not None else z(body.link.along[1]) - z(body.link.along[0])
    else:
        e = z(body.frame[1]) - origin
    g = origin + body.center * e / abs(e)
    return np.array([g.real, g.imag, 0.0])


@pytest.mark.parametrize("name", MASSIVE)
def test_every_body_with_mass_is_a_link_named_after_it_with_its_mass_centre_and_inertia(name: str) -> None:
    scene = solver.load_scene(name)
    model = build_model(scene)
    urdf = _load(scene)
    massive = [b for b in scene.bodies if not b.inert]
    assert massive
    for body in massive:
        link = urdf.link_map[body.name]  # the link takes the scene's name
        inertial = link.inertial
        assert inertial is not None, body.name
        assert inertial.mass == pytest.approx(body.mass, rel=1e-15)
        ixx, iyy, izz = np.diag(inertial.inertia)
        assert np.count_nonzero(inertial.inertia - np.diag(np.diag(inertial.inertia))) == 0
        assert min(ixx, iyy, izz) > 0.0 and ixx + iyy >= izz and ixx + izz >= iyy and iyy + izz >= ixx
        if body.inertia > 0.0:
            assert (izz, ixx, iyy) == pytest.approx((body.inertia, body.inertia / 2, body.inertia / 2), rel=1e-15)
    # the centre, carried by the tree's joints, lands where the scene puts it, over the motion
    n = 24
    columns = []
    for span in scene.input_ranges:  # a stroke's inner part, a crank's turn (the five-bar: about its middle)
        if span is not None:
            lo, hi = span
            columns.append(np.linspace(lo + 0.1 * (hi - lo), hi - 0.1 * (hi - lo), n))
        elif len(scene.inputs) == 1:
            columns.append(np.linspace(0.0, 2 * math.pi, n, endpoint=False))
        else:
            columns.append(np.linspace(2.0, 2.4, n) if not columns else np.linspace(0.9, 1.3, n))
    phi = columns[0] if len(columns) == 1 else np.column_stack(columns)
    k = scene.everything().solve(phi, mask=True)
    states = kinematics_tree_joint_states(model, k)
    valid = np.flatnonzero(np.asarray(k.valid, bool))
    assert valid.size > n // 4
    worst = 0.0
    for i in valid:
        urdf.update_cfg(dict(zip(states.names, (float(q) for q in states.position[i]))))
        for body in massive:
            inertial = urdf.link_map[body.name].inertial
            pose = np.asarray(urdf.get_transform(body.name, "world")) @ inertial.origin
            worst = max(worst, float(np.abs(pose[:3, 3] - _world_center(body, k, int(i))).max()))
    assert worst <= TOL_CENTER


def test_the_excavator_links_are_the_boom_the_arm_and_the_bucket_and_the_cylinder_joints_keep_their_names() -> None:
    scene = solver.load_scene("excavator")
    root = ET.fromstring(generate_urdf(scene))
    links = [e.get("name") for e in root.findall("link")]
    for name in ("boom", "arm", "side_link", "bucket_rod", "bucket"):
        assert name in links
    assert "boom_cylinder" not in links and "bucket_link_DG" not in links and "bucket_link_EG" not in links
    joints = {e.get("name"): e for e in root.findall("joint")}
    for cyl, stroke in (("boom_cylinder", (1.05, 1.6)), ("arm_cylinder", (1.3, 1.9)), ("bucket_cylinder", (1.0, 1.45))):
        rod = joints[f"{cyl}_rod_joint"]  # the relay's names, unchanged
        assert rod.get("type") == "prismatic"
        assert rod.find("child").get("link") == f"{cyl}_rod"  # type: ignore[union-attr]
        limit = rod.find("limit")
        assert limit is not None
        assert (float(limit.get("lower")), float(limit.get("upper"))) == stroke  # type: ignore[arg-type]
    assert joints["boom_joint"].find("child").get("link") == "boom"  # type: ignore[union-attr]
    assert joints["bucket_joint"].find("parent").get("link") == "arm"  # type: ignore[union-attr]


LIMITED = (*MASSIVE, "four_bar", "slider_crank", "spherical_converter", "harvester_finger_vectors")


@pytest.mark.parametrize("name", LIMITED)
def test_no_limit_is_zero_and_every_prismatic_and_driven_joint_has_one(name: str) -> None:
    scene = solver.load_scene(name)
    urdf = _load(scene)
    driven = 0
    for joint in urdf.robot.joints:
        if joint.type == "prismatic":
            assert joint.limit is not None and joint.limit.lower < joint.limit.upper
        if joint.limit is not None:
            driven += joint.type != "prismatic"
            assert joint.limit.effort > 0.0 and joint.limit.velocity > 0.0, joint.name
    assert driven + sum(j.type == "prismatic" for j in urdf.robot.joints) >= 1


def test_a_motor_sets_effort_and_velocity_of_the_joint_it_drives() -> None:
    scene = solver.load_scene("harvester_finger")  # drum motor: 40 N·m stall, 8 rad/s no-load
    urdf = _load(scene)
    drum = urdf.joint_map["drum_joint"]
    assert (drum.limit.effort, drum.limit.velocity) == (40.0, 8.0)
    assert urdf.joint_map["finger_joint"].limit is None  # a passive pin
    eyelet = urdf.joint_map["finger_link_eyelet_joint"].limit
    assert (eyelet.effort, eyelet.velocity) == (DEFAULT_EFFORT, DEFAULT_VELOCITY)
    assert drive_limits(solver.load_scene("four_bar"), "crank") == (DEFAULT_EFFORT, DEFAULT_VELOCITY)


def test_a_motor_table_gives_its_largest_torque_and_the_speed_where_it_falls_to_zero(tmp_path: Any) -> None:
    text = open(solver.load_scene("harvester_finger").path, encoding="utf-8").read()
    line = "  drum: {stall_torque: 40.0, no_load_speed: 8.0}"
    assert line in text
    table = "  drum: {speed: [0.0, 4.0, 10.0], torque: [30.0, 20.0, -10.0]}"
    (tmp_path / "h.yaml").write_text(text.replace(line, table), encoding="utf-8")
    scene = solver.load_scene(str(tmp_path / "h.yaml"))
    assert drive_limits(scene, "drum") == pytest.approx((30.0, 8.0), rel=1e-15)  # 20 → −10 between 4 and 10


def test_a_point_mass_gets_a_small_sphere_and_a_flywheel_counts_in_the_crank() -> None:
    urdf = _load(solver.load_scene("engine"))
    piston = urdf.link_map["piston"].inertial  # 0.35 kg, no inertia in the scene
    radius = POINT_MASS_RADIUS_PER_SIZE * 0.155  # the scene's size: the rod's 155 mm
    assert piston.mass == 0.35
    np.testing.assert_allclose(piston.inertia, np.eye(3) * 0.4 * 0.35 * radius**2, rtol=1e-12, atol=0)
    crank = urdf.link_map["crank"].inertial  # 2.0e-3 kg·m² of the crank + the 0.5913 kg·m² flywheel
    assert crank.inertia[2, 2] == pytest.approx(2.0e-3 + 0.5913, rel=1e-12)
    assert urdf.joint_map["crank_joint"].child == "crank" and "crankshaft" not in urdf.link_map


def test_a_scene_without_bodies_keeps_the_group_names_and_writes_no_inertial() -> None:
    root = ET.fromstring(generate_urdf(solver.load_scene("four_bar")))
    assert root.find("link/inertial") is None
    assert {"crank", "dyad_AB", "dyad_CB"} <= {e.get("name") for e in root.findall("link")}


def test_a_body_with_mass_that_no_link_carries_is_refused_with_its_name() -> None:
    from types import SimpleNamespace

    from linkage_ros.urdf.inertial import name_and_weigh

    scene = solver.load_scene("four_bar_loaded")
    model = build_model(solver.load_scene("four_bar"))  # the same tree, without the scene's names
    real = scene.forces.spec  # type: ignore[union-attr]
    stray = replace(real.bodies[1], name="ghost", frame=("O", "B"))  # O and B lie on no one link
    fake = SimpleNamespace(forces=SimpleNamespace(spec=SimpleNamespace(names={}, bodies=(stray,))))
    with pytest.raises(solver.SceneError, match=r"body 'ghost' \(points A, B\) is carried by no single link"):
        name_and_weigh(fake, model, lambda message: solver.SceneError(message))
    twice = SimpleNamespace(forces=SimpleNamespace(spec=SimpleNamespace(
        names={"dyad.1": "coupler"}, bodies=(real.bodies[1], replace(real.bodies[1], name="coupler_twin")))))
    with pytest.raises(solver.SceneError, match="bodies 'coupler_twin' and 'coupler' would both be link 'dyad_AB'"):
        name_and_weigh(twice, model, lambda message: solver.SceneError(message))
