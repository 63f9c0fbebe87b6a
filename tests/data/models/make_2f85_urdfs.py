"""Writes the two URDF forms of robotiq_2f85.xml beside it (issue 31; PROVENANCE.md):

* ``robotiq_2f85_onshape.urdf`` — loops closed the onshape-to-robot way: per finger two frame
  links ``closing_<finger>_1`` (on the follower) and ``closing_<finger>_2`` (on the coupler) at
  the connect point;
* ``robotiq_2f85_urdfplus.urdf`` — loops closed the URDF+ way: per finger a frame link
  ``<finger>_loop`` on the follower at the connect point and a ``<constraint type="loop">`` with
  the coupler as predecessor, that frame as successor, and the loop frame's origin in the
  coupler's frame.

Both carry the left driver as ``<mimic>`` of the right one and a transmission on the right
driver. Link frames are MuJoCo's body frames at qpos0, moved to the joint's anchor (a URDF
joint's frame is its child link's); inertials are the compiled bodies'. Run from the repository:
``python tests/data/models/make_2f85_urdfs.py`` (needs mujoco).
"""

from __future__ import annotations

import math
from pathlib import Path

import mujoco
import numpy as np

HERE = Path(__file__).resolve().parent
FINGERS = ("right", "left")


def rpy(r: np.ndarray) -> tuple[float, float, float]:
    """URDF's roll, pitch, yaw of a rotation matrix (R = Rz(yaw)·Ry(pitch)·Rx(roll))."""
    pitch = math.asin(max(-1.0, min(1.0, -r[2, 0])))
    if abs(r[2, 0]) < 1.0 - 1e-12:
        return math.atan2(r[2, 1], r[2, 2]), pitch, math.atan2(r[1, 0], r[0, 0])
    return math.atan2(-r[1, 2], r[1, 1]), pitch, 0.0


def fmt(values: object) -> str:
    return " ".join(repr(float(v)) for v in values)  # type: ignore[attr-defined]


Frames = dict[str, tuple[np.ndarray, np.ndarray]]


def frames() -> tuple[Frames, dict[str, str], mujoco.MjModel, mujoco.MjData]:
    m = mujoco.MjModel.from_xml_path(str(HERE / "robotiq_2f85.xml"))
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)
    out: dict[str, tuple[np.ndarray, np.ndarray]] = {"base": (np.eye(3), np.zeros(3))}
    joint_of: dict[str, str] = {}
    for b in range(2, m.nbody):  # (0 world, 1 base_mount; base is the root link at the world origin)
        name = m.body(b).name
        rot = d.xmat[b].reshape(3, 3).copy()
        if name == "base":
            continue
        if m.body_jntnum[b]:
            j = int(m.body_jntadr[b])
            joint_of[name] = m.joint(j).name
            out[name] = (rot, d.xanchor[j].copy())
        else:
            out[name] = (rot, d.xpos[b].copy())
    return out, joint_of, m, d


def write(kind: str) -> str:
    f, joint_of, m, d = frames()
    lines = ['<?xml version="1.0"?>', f"<!-- written by make_2f85_urdfs.py from robotiq_2f85.xml ({kind}) -->",
             f'<robot name="robotiq_2f85_{kind}">']

    def inertial(body: str) -> str:
        b = m.body(body).id
        rot, p = f[body]
        com = rot.T @ (d.xipos[b] - p)
        i_world = d.ximat[b].reshape(3, 3) @ np.diag(m.body_inertia[b]) @ d.ximat[b].reshape(3, 3).T
        i = rot.T @ i_world @ rot
        return (f'    <inertial><origin xyz="{fmt(com)}" rpy="0 0 0"/><mass value="{float(m.body_mass[b])!r}"/>'
                f'<inertia ixx="{float(i[0, 0])!r}" ixy="{float(i[0, 1])!r}" ixz="{float(i[0, 2])!r}" '
                f'iyy="{float(i[1, 1])!r}" iyz="{float(i[1, 2])!r}" izz="{float(i[2, 2])!r}"/></inertial>')

    def link(name: str, body: str | None) -> None:
        lines.append(f'  <link name="{name}">')
        if body is not None:
            lines.append(inertial(body))
        lines.append("  </link>")

    def joint(name: str, kind_: str, parent: str, child: str, rot_c: np.ndarray, p_c: np.ndarray,
              extra: str = "") -> None:
        rot_p, p_p = f[parent]
        xyz, r = rot_p.T @ (p_c - p_p), rot_p.T @ rot_c
        lines.append(f'  <joint name="{name}" type="{kind_}"><parent link="{parent}"/><child link="{child}"/>'
                     f'<origin xyz="{fmt(xyz)}" rpy="{fmt(rpy(r))}"/>{extra}</joint>')

    link("base", "base")
    parent = {"driver": "base", "coupler": "driver", "spring_link": "base", "follower": "spring_link",
              "pad": "follower"}
    for finger in FINGERS:
        for part in ("driver", "coupler", "spring_link", "follower", "pad"):
            name = f"{finger}_{part}"
            link(name, name)
            par = "base" if parent[part] == "base" else f"{finger}_{parent[part]}"
            rot, p = f[name]
            if name in joint_of:
                j = m.joint(joint_of[name]).id
                axis = rot.T @ d.xaxis[j]
                lo, hi = m.jnt_range[j]
                extra = (f'<axis xyz="{fmt(axis)}"/>'
                         f'<limit lower="{float(lo)!r}" upper="{float(hi)!r}" effort="5" velocity="2"/>')
                if name == "left_driver":
                    extra += '<mimic joint="right_driver_joint" multiplier="1" offset="0"/>'
                joint(joint_of[name], "revolute", par, name, rot, p, extra)
            else:
                joint(f"{name}_fixed", "fixed", par, name, rot, p)
        e = m.equality(f"{finger}_loop").id
        b1 = int(m.eq_obj1id[e])
        point = d.xpos[b1] + d.xmat[b1].reshape(3, 3) @ m.eq_data[e][0:3]
        follower, coupler = f[f"{finger}_follower"], f[f"{finger}_coupler"]
        if kind == "onshape":
            for side, on in (("1", f"{finger}_follower"), ("2", f"{finger}_coupler")):
                frame = f"closing_{finger}_{side}"
                link(frame, None)
                f[frame] = (f[on][0], point)
                joint(f"{frame}_frame", "fixed", on, frame, f[on][0], point)
        else:
            frame = f"{finger}_loop"
            link(frame, None)
            f[frame] = (follower[0], point)
            joint(f"{frame}_frame", "fixed", f"{finger}_follower", frame, follower[0], point)
            rot_c, p_c = coupler
            xyz, r = rot_c.T @ (point - p_c), rot_c.T @ follower[0]
            lines.append(f'  <constraint name="{finger}_loop" type="loop"><predecessor link="{finger}_coupler"/>'
                         f'<successor link="{frame}"/><origin xyz="{fmt(xyz)}" rpy="{fmt(rpy(r))}"/></constraint>')
    lines.append('  <transmission name="fingers"><type>transmission_interface/SimpleTransmission</type>'
                 '<joint name="right_driver_joint"><hardwareInterface>hardware_interface/EffortJointInterface'
                 '</hardwareInterface></joint><actuator name="fingers_actuator"><mechanicalReduction>1'
                 '</mechanicalReduction></actuator></transmission>')
    lines.append("</robot>")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    for kind in ("onshape", "urdfplus"):
        (HERE / f"robotiq_2f85_{kind}.urdf").write_text(write(kind))
