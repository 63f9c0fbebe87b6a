"""Several inputs (k > 1): real motion, exact Jacobians and Hessians, assembly in k dimensions.

The groups propagate second-order jets along one direction, by the chain rule written out in
each group (solver.jet). Seeding every input crank i with the directional jet ``(q_i, u_i, s_i)``
— the path q(t) = q + u·t + s·t²/2 through the inputs — the same code yields, for every point
and joint r of the plan,

    dr/dt = J·u,        d²r/dt² = uᵀ·H·u + J·s,

with J = ∂r/∂q (dim × k) and H = ∂²r/∂q² (dim × k × k) exact, in closed form. Hence

* **real motion in one pass**: u = ω, s = ε gives v = J·ω and a = J·ε + ωᵀ·H·ω directly;
* **Jacobian and Hessian diagonal**: u = e_i, s = 0 gives the column J·e_i and H_ii;
* **mixed second derivatives by polarisation**: u = e_i + e_j gives H_ii + 2·H_ij + H_jj, so
  H_ij = ((e_i + e_j)ᵀ·H·(e_i + e_j) − H_ii − H_jj) / 2 — exact algebra on exact jets, with a
  rounding error of a few ulps of max(|H_ii|, |H_jj|) (a mixed term much smaller than the
  diagonal is exact to that absolute level, not relative to itself).

That is k + k(k−1)/2 passes for J and H, evaluated only when ``.jacobian`` or ``.hessian`` of an
output is first read (docs/inputs.md). A zero direction is the float 0.0, which the groups pass
through without array work, so a pass costs about one positions-and-analogs solve.

What stays single-input: singular samples (the derivatives are NaN there and the sample is
flagged: with k inputs the Jacobian is unbounded at a singularity, so no limit along one branch
defines it — solver.singular), change points followed in φ (rejected at load, solver._inputs),
and the closed-form unassemblable φ intervals (with several inputs the unassemblable set is a
region: :class:`SampleAssemblyError` names the failing samples, and :func:`assemblable` maps
the region on a grid).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, TypeAlias

import numpy as np

from ._arguments import Arguments
from ._backend import NUMPY, SCALAR
from .errors import SampleAssemblyError, SolverError
from .forces import ForceBuffers, ForceResult
from .groups import Context
from .groups.base import require_samples
from .jet import Jet
from .kinematics import Derivatives, InstantKinematics, Kinematics, empty_motion, fill_motion, motion_rows

#: a :class:`solver.scene.Scene`; not imported, since the scene sits above this module (it
#: calls this one): dependencies point one way, annotations included.
Scene: TypeAlias = Any

__all__ = [
    "SampleAssemblyError",
    "assemblable",
    "derivative_arrays",
    "directions",
    "instant_jets",
    "take_direction",
    "require_samples",
    "solve_instant",
    "solve_multi",
]

#: Samples per block of the vectorised path (as solver.scene.CHUNK).
CHUNK = 1 << 13

_SCALARS = (float, int, np.floating, np.integer)


# -- arguments ---------------------------------------------------------------------------------
def _finite(label: str, value: Any, scene: Scene) -> None:
    Arguments("solve", scene=scene.name).numbers(label, value)


def _rates(label: str, value: Any, k: int, n: int | None, scene: Scene) -> list[Any]:
    """ω or ε per input: k floats (a scalar broadcast to every input, or a (k,) vector), or, for a
    sweep, columns of an (N, k) array."""
    arr = Arguments("solve", scene=scene.name).numbers(label, value)
    if arr.ndim == 0:
        return [float(arr)] * k
    if arr.shape == (k,):
        return [float(x) for x in arr]
    if n is not None and arr.shape == (n, k):
        return [np.ascontiguousarray(arr[:, i]) for i in range(k)]
    want = f"a scalar, ({k},)" + (f" or ({n}, {k})" if n is not None else "")
    raise SolverError(f"{scene.name}: {label} of shape {arr.shape} must be {want} (inputs {', '.join(scene.inputs)})")


def _tick_rates(label: str, value: Any, k: int, scene: Scene) -> list[Any]:
    """``_rates`` for one instant, without numpy when given floats or a tuple of k floats."""
    if type(value) is float and math.isfinite(value):
        return [value] * k
    if type(value) is tuple and len(value) == k and all(type(x) is float and math.isfinite(x) for x in value):
        return list(value)
    return _rates(label, value, k, None, scene)


def solve_multi(scene: Scene, phi: Any, omega: Any, epsilon: Any, mask: bool) -> Kinematics:
    """``Scene.solve`` for k > 1 inputs: ``phi`` (N, k) — or (k,) for one instant, which takes
    the per-tick path in plain Python floats — and ``omega``, ``epsilon`` scalars (the same for
    every input), (k,) or (N, k)."""
    k = len(scene.inputs)
    if isinstance(phi, (tuple, list)) and len(phi) == k and all(isinstance(x, _SCALARS) for x in phi):
        q = tuple(float(x) for x in phi)  # the per-tick call: plain floats throughout
        if not all(map(math.isfinite, q)):
            _finite("phi", q, scene)
        return _solve_instant(scene, q, _tick_rates("omega", omega, k, scene),
                              _tick_rates("epsilon", epsilon, k, scene), mask)
    arr = Arguments("solve", scene=scene.name).numbers("phi", phi)
    if arr.shape == (k,):
        return _solve_instant(scene, tuple(arr.tolist()), _rates("omega", omega, k, None, scene),
                              _rates("epsilon", epsilon, k, None, scene), mask)
    if arr.ndim != 2 or arr.shape[1] != k:
        raise SolverError(
            f"{scene.name} has {k} inputs ({', '.join(scene.inputs)}): phi must have shape (N, {k}) or ({k},), "
            f"got {arr.shape}"
        )
    n = arr.shape[0]
    w = _rates("omega", omega, k, n, scene)
    e = _rates("epsilon", epsilon, k, n, scene)
    try:
        return _solve_sweep(scene, arr, w, e, mask)
    except SampleAssemblyError as exc:
        if mask:
            raise
        bad = ~_solve_sweep(scene, arr, w, e, True).valid  # every failing sample, not only the first block's
        raise SampleAssemblyError(group=exc.group, samples=arr[bad], inputs=scene.inputs, reason=exc.reason,
                                  scene=exc.scene, units=scene.input_units) from None


def _seeds(scene: Scene, q: Sequence[Any], u: Sequence[Any], s: Sequence[Any]) -> dict[str, Jet]:
    return {name: Jet(q[i], u[i], s[i]) for i, name in enumerate(scene.inputs)}


def _context(scene: Scene, phi: Any, seeds: dict[str, Jet], mask: bool, vectorised: bool) -> Context:
    return Context(phi=phi, xp=NUMPY if vectorised else SCALAR, mask=mask, scene=scene._label, owner=scene,
                   seeds=seeds)


def _as_rows(x: Any, rows: slice) -> Any:
    return x[rows] if isinstance(x, np.ndarray) else x


def _solve_sweep(scene: Scene, phi: np.ndarray, omega: list[Any], epsilon: list[Any], mask: bool) -> Kinematics:
    n, k = phi.shape
    cols = [np.ascontiguousarray(phi[:, i]) for i in range(k)]
    motions = {p: empty_motion(n, scene.dim) for p in scene.output_points}
    motions.update({j: empty_motion(n, None) for j in scene.output_joints})
    fills = [(p, motion_rows(motions[p], planar=scene.dim == 2)) for p in scene.output_points]
    fills += [(j, motion_rows(motions[j], planar=False)) for j in scene.output_joints]
    conditioning: dict[str, np.ndarray] = {}
    valid = np.ones(n, bool) if mask else None
    forces = None if scene.forces is None else ForceBuffers(scene.forces, n)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for lo in range(0, max(n, 1), CHUNK):
            rows = slice(lo, min(lo + CHUNK, n))
            seeds = _seeds(scene, [c[rows] for c in cols], [_as_rows(x, rows) for x in omega],
                           [_as_rows(x, rows) for x in epsilon])
            ctx = _context(scene, phi[rows], seeds, mask, True)
            scene.plan.run(ctx)
            for name, targets in fills:  # the jet is the real motion itself: v = J·ω, a = J·ε + ωᵀHω
                fill_motion(targets, rows, ctx.values[name], 1.0, 0.0)
            if forces is not None:  # the jets are real motion: ω = 1, ε = 0 (solver.forces.model)
                forces.put(rows, forces.model.evaluate(ctx.values, NUMPY, ctx.conditioning, 1.0, 0.0))
            for name, c in ctx.conditioning.items():
                if name not in conditioning:
                    conditioning[name] = np.empty(n)
                conditioning[name][rows] = c
            if valid is not None:
                valid[rows] = ~np.broadcast_to(ctx.invalid, (rows.stop - rows.start,))
    w = np.column_stack([np.broadcast_to(x, (n,)) for x in omega]) if k else np.empty((n, 0))
    e = np.column_stack([np.broadcast_to(x, (n,)) for x in epsilon]) if k else np.empty((n, 0))
    return Kinematics(
        phi=phi,
        omega=w,
        epsilon=e,
        motions=motions,
        points=scene.output_points,
        joints=scene.output_joints,
        conditioning=conditioning,
        valid=valid,
        derivatives=Derivatives(lambda: _sweep_derivatives(scene, phi)),
        inputs=scene.inputs,
        forces=None if forces is None else forces.result(valid),
    )


def _solve_instant(scene: Scene, q: tuple[float, ...], omega: list[Any], epsilon: list[Any], mask: bool) -> Kinematics:
    """One instant: the scene's compiled function (solver._codegen), or, where one of its guards
    trips, :func:`solve_instant` — today's scalar path (always, for a scene with friction: it is
    not compiled)."""
    if scene.has_friction:
        return solve_instant(scene, q, omega, epsilon, mask)
    derivatives = Derivatives(each=lambda name: _instant_derivatives(scene, q, name))
    unit = scene.compiled()
    flat = unit.core(*q, *omega, *epsilon)
    if flat is not None:
        return InstantKinematics.for_unit(unit, flat, (q, omega, epsilon), mask=mask, derivatives=derivatives)
    return solve_instant(scene, q, omega, epsilon, mask)


def solve_instant(scene: Scene, q: tuple[float, ...], omega: Sequence[Any], epsilon: Sequence[Any],
                  mask: bool = False) -> Kinematics:
    """One instant of several inputs on the scalar path (plain Python floats, the groups run in turn)."""
    ctx = _context(scene, q, _seeds(scene, q, omega, epsilon), mask, False)
    scene.plan.run(ctx)
    floats: dict[str, tuple[Any, Any, Any]] = {}
    for p in scene.output_points:
        z0, z1, z2 = ctx.values[p]
        z1, z2 = complex(z1), complex(z2)
        floats[p] = ((z0.real, z0.imag), (z1.real, z1.imag), (z2.real, z2.imag))
    for j in scene.output_joints:
        q0, q1, q2 = ctx.values[j]
        floats[j] = (float(q0), float(q1), float(q2))
    return Kinematics(
        phi=np.array(q),
        omega=np.array(omega, float),
        epsilon=np.array(epsilon, float),
        motions={},
        floats=floats,
        points=scene.output_points,
        joints=scene.output_joints,
        conditioning=ctx.conditioning,
        valid=np.array(not ctx.invalid) if mask else None,
        derivatives=Derivatives(each=lambda name: _instant_derivatives(scene, q, name)),
        inputs=scene.inputs,
        forces=None if scene.forces is None else ForceResult(
            scene.forces, scene.forces.evaluate(ctx.values, SCALAR, ctx.conditioning, 1.0, 0.0), None
        ),
    )


# -- Jacobians and Hessians ----------------------------------------------------------------------
def directions(k: int) -> list[tuple[tuple[int, ...], list[float]]]:
    """(inputs moved, unit seed) per pass: e_i for each i, then e_i + e_j for each i < j."""
    out: list[tuple[tuple[int, ...], list[float]]] = [
        ((i,), [1.0 if m == i else 0.0 for m in range(k)]) for i in range(k)
    ]
    out += [((i, j), [1.0 if m in (i, j) else 0.0 for m in range(k)]) for i in range(k) for j in range(i + 1, k)]
    return out


def take_direction(jac: list[Any], hess: list[list[Any]], moved: tuple[int, ...], jet: Jet) -> None:
    """One pass of :func:`directions` into an output's J and H: along e_i, J_i = d1 and
    H_ii = d2; along e_i + e_j (after every single input's pass), H_ij = H_ji = (d2 − H_ii − H_jj)/2."""
    if len(moved) == 1:
        (i,) = moved
        jac[i] = jet.d1
        hess[i][i] = jet.d2
    else:
        i, j = moved
        hess[i][j] = hess[j][i] = 0.5 * ((jet.d2 - hess[i][i]) - hess[j][j])


def _outputs(scene: Scene) -> list[tuple[str, bool]]:
    """Every output with whether it is a planar point (a complex jet)."""
    return [(p, True) for p in scene.output_points] + [(j, False) for j in scene.output_joints]


def _sweep_derivatives(scene: Scene, phi: np.ndarray) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """J and H of every output over the sweep, from k + k(k−1)/2 directional passes per block."""
    n, k = phi.shape
    names = _outputs(scene)
    out = {
        name: (np.empty((n, 2, k) if planar else (n, k)), np.empty((n, 2, k, k) if planar else (n, k, k)))
        for name, planar in names
    }
    cols = [np.ascontiguousarray(phi[:, i]) for i in range(k)]
    zero = [0.0] * k
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for lo in range(0, max(n, 1), CHUNK):
            rows = slice(lo, min(lo + CHUNK, n))
            m = rows.stop - rows.start
            diagonal: dict[tuple[str, int], Any] = {}  # H_ii per output, as its jet's d2 (complex for points)
            for moved, u in directions(k):
                ctx = _context(scene, phi[rows], _seeds(scene, [c[rows] for c in cols], u, zero), True, True)
                values = scene.plan.run(ctx).values
                for name, planar in names:
                    jac, hess = out[name]
                    jet = values[name]
                    if len(moved) == 1:
                        (i,) = moved
                        diagonal[name, i] = jet.d2
                        _put(jac[rows], (..., i), jet.d1, planar, m)
                        _put(hess[rows], (..., i, i), jet.d2, planar, m)
                    else:
                        i, j = moved
                        mixed = 0.5 * ((jet.d2 - diagonal[name, i]) - diagonal[name, j])
                        _put(hess[rows], (..., i, j), mixed, planar, m)
                        _put(hess[rows], (..., j, i), mixed, planar, m)
    return out


def _put(target: np.ndarray, index: tuple[Any, ...], x: Any, planar: bool, m: int) -> None:
    """Write a derivative into (m, 2, …) floats (a planar point's complex jet) or (m, …)."""
    if planar:
        target[(slice(None), 0, *index[1:])] = np.broadcast_to(np.real(x), (m,))
        target[(slice(None), 1, *index[1:])] = np.broadcast_to(np.imag(x), (m,))
    else:
        target[index] = np.broadcast_to(x, (m,))


def _instant_derivatives(scene: Scene, q: tuple[float, ...], name: str) -> tuple[np.ndarray, np.ndarray]:
    """J and H of the output ``name`` at one instant: from the scene's compiled derivatives
    (every output's, in one straight-line function of q, solver._codegen) or, where one of its
    guards trips, from :func:`instant_jets`."""
    unit = scene.compiled(derivatives=True)
    flat = unit.core(*q)
    if flat is None:
        jac, hess = instant_jets(scene, q, name)
    else:
        k = len(q)
        start = unit.index[name][0]
        jac = list(flat[start:start + k])
        hess = [list(flat[start + k * (1 + i):start + k * (2 + i)]) for i in range(k)]
    return derivative_arrays(jac, hess, name in scene.output_points)


def derivative_arrays(jac: list[Any], hess: list[list[Any]], planar: bool) -> tuple[np.ndarray, np.ndarray]:
    """(J, H) arrays from the derivatives' Python numbers (complex for a planar point)."""
    if planar:
        z1 = [complex(x) for x in jac]
        z2 = [[complex(x) for x in row] for row in hess]
        return (
            np.array([[z.real for z in z1], [z.imag for z in z1]]),
            np.array([[[z.real for z in row] for row in z2], [[z.imag for z in row] for row in z2]]),
        )
    return np.array(jac, float), np.array(hess, float)


def instant_jets(scene: Scene, q: tuple[float, ...], name: str) -> tuple[list[Any], list[list[Any]]]:
    """J and H of the output ``name`` at one instant on the scalar path, as Python numbers (rows of
    k), from the part of the plan that computes it: k + k(k−1)/2 directional passes."""
    k = len(q)
    zero = [0.0] * k
    names = [(name, name in scene.output_points)]
    plan = scene.plan_for((name,))
    jac: dict[str, list[Any]] = {name: [0.0] * k for name, _ in names}
    hess: dict[str, list[list[Any]]] = {name: [[0.0] * k for _ in range(k)] for name, _ in names}
    for moved, u in directions(k):
        values = plan.run(_context(scene, q, _seeds(scene, q, u, zero), True, False)).values
        for name, _ in names:
            take_direction(jac[name], hess[name], moved, values[name])
    return jac[name], hess[name]


# -- the assemblable region ------------------------------------------------------------------------
def assemblable(scene: Scene, axes: Sequence[Any]) -> np.ndarray:
    """Where ``scene`` can be assembled on the grid ``axes`` (one 1-D array of values per input,
    in the order of ``scene.inputs``): a bool array of shape (len(axes[0]), …, len(axes[k−1])).

    Exact per sample (each grid point is solved, not interpolated); the workspace map of
    ``linkage-solve --region``.
    """
    k = len(scene.inputs)
    if len(axes) != k:
        raise SolverError(f"{scene.name} has {k} inputs ({', '.join(scene.inputs)}): give {k} axes, got {len(axes)}")
    grids = np.meshgrid(*[np.asarray(a, float) for a in axes], indexing="ij")
    samples = np.stack([g.ravel() for g in grids], axis=-1)
    if k == 1:
        return np.asarray(scene.solve(samples[:, 0], mask=True).valid).reshape(grids[0].shape)
    return np.asarray(scene.with_outputs().solve(samples, mask=True).valid).reshape(grids[0].shape)
