"""An MJCF file read through MuJoCo's own compiler into a :class:`~solver.models.spatial.SpatialModel`.

No MJCF is parsed here: ``mujoco.MjModel.from_xml_path`` resolves defaults, classes, includes,
``compiler angle``, ``ref``, ``childclass``; ``mj_kinematics`` at the pose (qpos0, or a
keyframe's qpos) gives every body's frame and every joint's world anchor and axis. Read from the
compiled model:

* bodies welded to their parent (no joint) join the parent's rigid body; its points are its sites
  (named after them) and its model bodies' origins; the world body and all
  welded to it are the ground; masses, centres and inertias are summed over each rigid body
  (parallel-axis theorem) from ``body_mass``, ``xipos`` and ``ximat``·diag(``body_inertia``);
* hinge and slide joints (a ball or free joint is refused: spatial), their ``qpos0`` reference;
* ``<connect>`` equalities (``eq_data[0:3]`` the anchor in body1's frame, ``eq_data[3:6]`` the
  one MuJoCo computed in body2's so that the constraint holds at qpos0): a closure pin;
* ``<joint>`` equalities: joint1 − qpos0₁ = Σ cᵢ·(joint2 − qpos0₂)ⁱ; linear ones (c₂ … c₄ = 0)
  are couplings, the others refused;
* the joints the actuators drive (a joint transmission, or a fixed tendon's joints).

``mujoco`` is an optional dependency, imported here only: a missing one is one SceneError line.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from ..errors import SceneError
from .spatial import GROUND_BODY, Body, Closure, Coupling, Joint, SpatialModel

__all__ = ["read_mjcf"]


def _mujoco(file: str) -> Any:
    try:
        import mujoco
    except ImportError:
        raise SceneError(
            "reading MJCF needs the mujoco package (MuJoCo's own compiler reads the file): pip install mujoco",
            file=file,
        ) from None
    return mujoco


def read_mjcf(path: str | Path, *, keyframe: str | int | None = None) -> SpatialModel:
    """The model at qpos0 (or at ``keyframe``, by name or index) as plain data."""
    file = str(path)
    mj = _mujoco(file)
    try:
        m = mj.MjModel.from_xml_path(file)
    except (ValueError, OSError) as exc:
        first = " ".join(str(exc).split("\n")[:2]).strip()
        raise SceneError(f"MuJoCo cannot compile it: {first}", file=file) from None
    d = mj.MjData(m)
    pose = "qpos0"
    qpos = np.array(m.qpos0, float)
    if keyframe is not None:
        k = keyframe if isinstance(keyframe, int) else mj.mj_name2id(m, mj.mjtObj.mjOBJ_KEY, str(keyframe))
        if not 0 <= k < m.nkey:
            names = [mj.mj_id2name(m, mj.mjtObj.mjOBJ_KEY, i) for i in range(m.nkey)]
            raise SceneError(f"no keyframe {keyframe!r}; keyframes: {names or 'none'}", file=file, entry="keyframe")
        qpos = np.array(m.key_qpos[k], float)
        pose = f"keyframe {keyframe!r}"
    d.qpos[:] = qpos
    mj.mj_kinematics(m, d)

    def name(kind: Any, i: int, fallback: str) -> str:
        return mj.mj_id2name(m, kind, i) or fallback

    body_names = [name(mj.mjtObj.mjOBJ_BODY, b, f"body{b}") for b in range(m.nbody)]
    joint_names = [name(mj.mjtObj.mjOBJ_JOINT, j, f"joint{j}") for j in range(m.njnt)]
    # rigid bodies: a body without joints is welded to its parent
    rigid = [0] * m.nbody
    for b in range(1, m.nbody):
        rigid[b] = b if m.body_jntnum[b] > 0 else rigid[m.body_parentid[b]]
    for b in range(1, m.nbody):
        if m.body_jntnum[b] > 1:
            kinds = ", ".join(joint_names[j] for j in range(m.body_jntadr[b], m.body_jntadr[b] + m.body_jntnum[b]))
            raise SceneError(
                f"body '{body_names[b]}' has {m.body_jntnum[b]} joints ({kinds}): a planar linkage's body turns "
                "or slides on one joint to its parent (split it into bodies, one joint each)",
                file=file,
                entry=f"body {body_names[b]}",
            )
    label = {r: (GROUND_BODY if r == 0 else body_names[r]) for r in set(rigid)}
    bodies: dict[str, Body] = {}
    for r in sorted(set(rigid)):
        members = [b for b in range(m.nbody) if rigid[b] == r]
        points = {name(mj.mjtObj.mjOBJ_SITE, s, f"site{s}"): np.array(d.site_xpos[s], float)
                  for s in range(m.nsite) if int(m.site_bodyid[s]) in members}
        points.update({body_names[b]: np.array(d.xpos[b], float) for b in members if b != 0})
        mass = float(sum(m.body_mass[b] for b in members))
        com = np.zeros(3)
        inertia = np.zeros((3, 3))
        if mass > 0.0:
            com = sum((m.body_mass[b] * np.array(d.xipos[b]) for b in members), np.zeros(3)) / mass
            for b in members:
                rot = np.array(d.ximat[b]).reshape(3, 3)
                own = rot @ np.diag(m.body_inertia[b]) @ rot.T
                r_ = np.array(d.xipos[b]) - com
                inertia += own + m.body_mass[b] * (float(r_ @ r_) * np.eye(3) - np.outer(r_, r_))
        origins = frozenset(body_names[b] for b in members if b != 0) - {
            name(mj.mjtObj.mjOBJ_SITE, s, "") for s in range(m.nsite)}
        bodies[label[r]] = Body(label[r], points, mass, com, inertia, origins)

    joints: list[Joint] = []
    for j in range(m.njnt):
        kind = int(m.jnt_type[j])
        b = int(m.jnt_bodyid[j])
        if kind in (int(mj.mjtJoint.mjJNT_BALL), int(mj.mjtJoint.mjJNT_FREE)):
            what = "ball" if kind == int(mj.mjtJoint.mjJNT_BALL) else "free"
            raise SceneError(
                f"joint '{joint_names[j]}' of body '{body_names[b]}' is a {what} joint: a spatial mechanism, "
                "not a planar one (hinges with parallel axes and slides across them only)",
                file=file,
                entry=f"joint {joint_names[j]}",
            )
        adr = int(m.jnt_qposadr[j])
        rng = (float(m.jnt_range[j][0]), float(m.jnt_range[j][1])) if m.jnt_limited[j] else None
        axis = np.array(d.xaxis[j], float)
        joints.append(Joint(
            name=joint_names[j],
            kind="hinge" if kind == int(mj.mjtJoint.mjJNT_HINGE) else "slide",
            parent=label[rigid[m.body_parentid[b]]],
            child=label[rigid[b]],
            anchor=np.array(d.xanchor[j], float),
            axis=axis / np.linalg.norm(axis),
            value=float(qpos[adr]),
            reference=float(m.qpos0[adr]),
            range=rng,
        ))

    closures: list[Closure] = []
    couplings: list[Coupling] = []
    for e in range(m.neq):
        if not m.eq_active0[e]:
            continue
        etype = int(m.eq_type[e])
        ename = name(mj.mjtObj.mjOBJ_EQUALITY, e, f"equality[{e}]")
        data = np.array(m.eq_data[e], float)
        if etype == int(mj.mjtEq.mjEQ_CONNECT):
            o1, o2 = int(m.eq_obj1id[e]), int(m.eq_obj2id[e])
            if int(m.eq_objtype[e]) == int(mj.mjtObj.mjOBJ_SITE):
                b1, b2 = int(m.site_bodyid[o1]), int(m.site_bodyid[o2])
                p1, p2 = np.array(d.site_xpos[o1]), np.array(d.site_xpos[o2])
            else:
                b1, b2 = o1, o2
                p1 = np.array(d.xpos[b1]) + np.array(d.xmat[b1]).reshape(3, 3) @ data[0:3]
                p2 = np.array(d.xpos[b2]) + np.array(d.xmat[b2]).reshape(3, 3) @ data[3:6]
            closures.append(Closure(
                ename if mj.mj_id2name(m, mj.mjtObj.mjOBJ_EQUALITY, e) else f"{body_names[b1]}_{body_names[b2]}",
                label[rigid[b1]], label[rigid[b2]], p1, float(np.linalg.norm(p1 - p2)),
            ))
        elif etype == int(mj.mjtEq.mjEQ_JOINT):
            j1, j2 = int(m.eq_obj1id[e]), int(m.eq_obj2id[e])
            poly = data[0:5]
            if j2 < 0:
                raise SceneError(
                    f"{ename} holds joint '{joint_names[j1]}' at a constant: lock it in the model (weld the bodies) "
                    "instead of an equality",
                    file=file,
                    entry=f"equality {ename}",
                )
            if np.any(poly[2:] != 0.0):
                raise SceneError(
                    f"{ename}: joint '{joint_names[j1]}' = polynomial of '{joint_names[j2]}' with polycoef "
                    f"{' '.join(f'{c:g}' for c in poly)}: only a linear one (polycoef c0 c1 0 0 0) is a coupled "
                    "input with exact analogs",
                    file=file,
                    entry=f"equality {ename}",
                )
            if poly[1] == 0.0:
                raise SceneError(
                    f"{ename}: polycoef c1 = 0 holds joint '{joint_names[j1]}' at a constant, not coupled to "
                    f"'{joint_names[j2]}'",
                    file=file,
                    entry=f"equality {ename}",
                )
            r1 = float(m.qpos0[m.jnt_qposadr[j1]])
            r2 = float(m.qpos0[m.jnt_qposadr[j2]])
            couplings.append(Coupling(
                joint_names[j1], joint_names[j2], float(poly[1]), r1 + float(poly[0]) - float(poly[1]) * r2,
                f"equality {ename}",
            ))
        elif etype == int(mj.mjtEq.mjEQ_WELD):
            raise SceneError(
                f"{ename} is a weld: weld the bodies in the model itself (a body without a joint)",
                file=file,
                entry=f"equality {ename}",
            )

    actuated: list[str] = []
    for a in range(m.nu):
        trn, obj = int(m.actuator_trntype[a]), int(m.actuator_trnid[a][0])
        if trn in (int(mj.mjtTrn.mjTRN_JOINT), int(mj.mjtTrn.mjTRN_JOINTINPARENT)):
            actuated.append(joint_names[obj])
        elif trn == int(mj.mjtTrn.mjTRN_TENDON):
            adr, num = int(m.tendon_adr[obj]), int(m.tendon_num[obj])
            for w in range(adr, adr + num):
                if int(m.wrap_type[w]) == int(mj.mjtWrap.mjWRAP_JOINT):
                    actuated.append(joint_names[int(m.wrap_objid[w])])

    model_name = Path(file).stem
    version = getattr(mj, "__version__", "?")
    return SpatialModel(
        name=model_name,
        file=file,
        kind="MJCF",
        bodies=bodies,
        joints=tuple(joints),
        closures=tuple(closures),
        couplings=tuple(couplings),
        actuated=tuple(dict.fromkeys(actuated)),
        gravity=np.array(m.opt.gravity, float),
        pose=pose,
        provenance=f"imported from {Path(file).name} (MJCF, compiled by MuJoCo {version}) at {pose}",
    )
