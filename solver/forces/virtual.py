"""Route 1: input efforts by virtual power, from the analogs alone (the cross-check of route 2).

With the Jacobian columns ∂G/∂q_k (first analogs of the centres of mass), ∂θ/∂q_k (of the
bodies' angles) and ∂P/∂q_k (of the load points), ideal pins doing no work:

    Q_k = Σ_bodies [ m·(a_G − g)·∂G/∂q_k + I·α·∂θ/∂q_k ]
          − Σ_forces F·∂P/∂q_k − Σ_torques T·∂θ_body/∂q_k − Σ_springs (f·∂P₁/∂q_k − f·∂P₂/∂q_k)
          + Σ_dampers c·q̇_j·∂q_j/∂q_k

(f the spring's force on its first end P₁). One input: the columns are the velocity analogs of
the same pass that gives the accelerations a = a_q·ω² + v_q·ε; several inputs: one pass seeded
with (q, ω, ε) gives the real accelerations, one per input seeded with (q, e_k, 0) the columns
(solver.multi). No reaction appears and no group's equilibrium is written: the formulas shared
with route 2 are only the bodies' kinematics (solver.forces.frames). Vectorised (numpy) only.
"""

from __future__ import annotations

from typing import Any, TypeAlias

import numpy as np

from .._backend import NUMPY, dot
from ..errors import SolverError
from ..groups import Context
from ..jet import Jet
from .frames import accel, body_motion, spring_force, table_force
from .spec import Damper, PointForce, Spring, TableForce, Torque

#: a :class:`solver.scene.Scene`; not imported, since the scene sits above this module (it
#: calls this one): dependencies point one way, annotations included.
Scene: TypeAlias = Any

__all__ = ["virtual_efforts"]


def _run(scene: Scene, phi: np.ndarray, seeds: dict[str, Jet] | None) -> dict[str, Jet]:
    ctx = Context(phi=phi, xp=NUMPY, mask=True, owner=scene, seeds=seeds)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        return scene.plan.run(ctx).values


def virtual_efforts(scene: Scene, phi: Any, *, omega: Any = 1.0, epsilon: Any = 0.0) -> dict[str, np.ndarray]:
    """Each input's effort over the samples ``phi`` ((N,) or, with k inputs, (N, k)) by virtual power."""
    model = scene.forces
    if model is None:
        raise SolverError(f"{scene.name} names no bodies, gravity or loads")
    k = len(scene.inputs)
    q = np.asarray(phi, float)
    if k == 1:
        q = np.atleast_1d(q)
        real = _run(scene, q, None)
        cols = [real]
        ww: Any = np.asarray(omega, float) ** 2
        scale: Any = np.asarray(omega, float)  # a joint's rate = its analog·ω
        eps: Any = np.asarray(epsilon, float)
    else:
        q = np.atleast_2d(q)
        n = q.shape[0]
        w = np.broadcast_to(np.asarray(omega, float), (n, k))
        e = np.broadcast_to(np.asarray(epsilon, float), (n, k))
        qs = [np.ascontiguousarray(q[:, i]) for i in range(k)]
        real = _run(scene, q, {j: Jet(qs[i], w[:, i].copy(), e[:, i].copy()) for i, j in enumerate(scene.inputs)})
        cols = [
            _run(scene, q, {j: Jet(qs[i], 1.0 if i == m else 0.0, 0.0) for i, j in enumerate(scene.inputs)})
            for m in range(k)
        ]
        ww, eps = np.float64(1.0), np.float64(0.0)
        scale = 1.0  # the jets are real motion
    spec = model.spec
    g = spec.gravity
    out = {}
    for m, name in enumerate(scene.inputs):
        col = cols[m]
        total: Any = 0.0
        bodies = {b.name: b for b in spec.bodies}
        for b in spec.bodies:
            if b.inert:
                continue
            mo, jc = body_motion(b, real, NUMPY), body_motion(b, col, NUMPY)
            if b.mass:
                a_g = accel(mo.center.d1, mo.center.d2, ww, eps)
                total = total + b.mass * dot(a_g - g, jc.center.d1)
            if b.inertia:
                total = total + b.inertia * accel(mo.theta1, mo.theta2, ww, eps) * jc.theta1
        for ld in spec.loads:
            if isinstance(ld, PointForce):
                total = total - dot(ld.force, col[ld.point].d1)
            elif isinstance(ld, Torque):
                total = total - ld.torque * body_motion(bodies[ld.body], col, NUMPY).theta1
            elif isinstance(ld, Spring):
                f = spring_force(ld, real, NUMPY)
                total = total - dot(f, col[ld.ends[0][1]].d1) + dot(f, col[ld.ends[1][1]].d1)
            elif isinstance(ld, TableForce):
                total = total - dot(table_force(ld, real, NUMPY), col[ld.point].d1)
            elif isinstance(ld, Damper):  # −c·q̇_j·∂q_j/∂q_m
                rate = real[ld.joint].d1 * scale
                total = total + ld.coefficient * rate * col[ld.joint].d1
        out[name] = np.broadcast_to(np.asarray(total, float), q.shape[:1]).copy()
    return out
