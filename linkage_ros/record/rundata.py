"""A whole run as arrays over its ticks: :class:`RunData`, and :class:`RunBuilder` that collects it.

Two sources give the same :class:`RunData`: the engine's frames, collected tick by tick by
:class:`RunBuilder` (``linkage-run``, :mod:`linkage_ros.record.run`), and the messages of a
recorded MCAP file (:mod:`linkage_ros.record.replay`). The rerun view
(:mod:`linkage_ros.record.rerun`) and the summaries read it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["Array", "RunBuilder", "RunData", "joint_units"]

Array = NDArray[np.float64]


@dataclass
class RunData:
    """A whole run as arrays over its N ticks."""

    scene: str
    dim: int
    t: Array  # (N,) s
    phi: Array  # (N,) rad; (N, k) for a scene with k > 1 inputs (columns in the order of ``inputs``)
    omega: Array  # (N,) rad/s; (N, k) likewise
    epsilon: Array  # (N,) rad/s²; (N, k) likewise
    positions: dict[str, Array]  # every moving point: (N, dim) m
    velocities: dict[str, Array]  # published points: (N, dim) m/s
    accelerations: dict[str, Array]  # published points: (N, dim) m/s²
    joints: dict[str, tuple[Array, Array, Array]]  # (N,) position, velocity, acceleration
    links: list[tuple[str, tuple[str, ...]]]
    fixed: dict[str, Array]  # (dim,)
    paths: dict[str, Array] = field(default_factory=dict)  # (M, dim)
    input_joint: str = ""
    note: str = ""
    inputs: tuple[str, ...] = ()
    """The input joints when there are several (then phi, omega, epsilon are (N, k)); else empty."""
    start_ns: int = 0
    """The stamp (ns) of the first tick, from which ``t`` counts (a replayed live recording's
    stamps are wall-clock times; a simulated run starts at 0)."""
    efforts: dict[str, Array] = field(default_factory=dict)  # input → (N,) N·m | N (forces only)
    loads: dict[str, Array] = field(default_factory=dict)  # load key → (N, 3) Fx, Fy N, M N·m
    load_pins: dict[str, tuple[str, str, str]] = field(default_factory=dict)  # key → (point, on, from)
    effort_units: dict[str, str] = field(default_factory=dict)  # input → "N·m" | "N"
    joint_units: dict[str, str] = field(default_factory=dict)
    """Joint → unit of its position, "rad" or "m" (a joint not listed: "rad"); the view plots
    angles and lengths apart."""
    cylinders: list[tuple[str, str, str, float]] = field(default_factory=list)
    """Each actuator as ``(name, base A, eye C, closed length m)``: drawn as barrel and rod."""
    friction: dict[str, Array] = field(default_factory=dict)
    """A scene with friction (``frame.friction``, the ``friction_power`` topic): per tick the power
    (W) friction dissipates, ``total`` first, then per element (pin point, slider block,
    actuator's seal); empty without friction."""
    energy: dict[str, Array] = field(default_factory=dict)
    """A dynamic run (``linkage-run --dynamics``, issue 22): per tick (J) ``kinetic``, ``gravity``,
    ``springs``, ``work_drive``, ``work_other`` (with friction ``work_friction``) and ``balance``
    (the energy balance's error, :meth:`solver.dynamics.Trajectory.energy`); empty for a kinematic run."""

    @property
    def n(self) -> int:
        return int(self.t.size)

    def input_series(self) -> list[tuple[str, str, Array]]:
        """``(kind, input, values)`` per plotted input quantity (kind = phi | omega | epsilon):
        one input gives input "" and (N,) values; several give one series per input."""
        out: list[tuple[str, str, Array]] = []
        for kind in ("phi", "omega", "epsilon"):
            values = getattr(self, kind)
            if values.ndim == 1:
                out.append((kind, "", values))
            else:
                names = self.inputs or tuple(f"q{i + 1}" for i in range(values.shape[1]))
                out += [(kind, q, values[:, i]) for i, q in enumerate(names)]
        return out

    def plotted_joint(self, name: str) -> tuple[Array, Array, Array]:
        """A joint's (position, velocity, acceleration) as plotted: an angle unwrapped over the
        run (a revolving joint draws one continuous line, as the summary reads it, instead of
        jumping by 2π), a slide as it is. Unassemblable ticks (NaN) stay NaN."""
        p, v, a = self.joints[name]
        if self.joint_units.get(name, "rad") != "rad":
            return p, v, a
        out = np.array(p, dtype=float)
        ok = np.isfinite(out)
        if int(ok.sum()) > 1:
            out[ok] = np.unwrap(out[ok])
        return out, v, a

    def extent(self) -> float:
        """Diagonal of the box holding every point of the run (m); 1 when degenerate."""
        chunks = [p.reshape(-1, self.dim) for p in self.positions.values()]
        chunks += [np.asarray(p).reshape(-1, self.dim) for p in self.fixed.values()]
        chunks += [p.reshape(-1, self.dim) for p in self.paths.values()]
        allp = np.concatenate(chunks) if chunks else np.zeros((1, self.dim))
        allp = allp[np.isfinite(allp).all(axis=1)]
        size = float(np.linalg.norm(allp.max(axis=0) - allp.min(axis=0))) if allp.size else 0.0
        return size if size > 0 else 1.0


class RunBuilder:
    """Collects engine frames tick by tick into a :class:`RunData` (preallocated arrays)."""

    def __init__(self, engine: Any, n: int) -> None:
        scene = engine.scene
        self.engine = engine
        self.n = n
        self.k = 0
        dim = int(scene.dim)
        self.dim = dim
        self.t = np.empty(n)
        inputs = tuple(getattr(engine, "inputs", ()))
        self.inputs = inputs if len(inputs) > 1 else ()
        shape = (n, len(inputs)) if self.inputs else (n,)
        self.phi = np.empty(shape)
        self.omega = np.empty(shape)
        self.epsilon = np.empty(shape)
        fixed = set(scene.fixed_points)
        self.pos = {p: np.empty((n, dim)) for p in engine.point_names if p not in fixed}
        self.vel = {p: np.empty((n, dim)) for p in engine.published_points}
        self.acc = {p: np.empty((n, dim)) for p in engine.published_points}
        self.jnt = {j: (np.empty(n), np.empty(n), np.empty(n)) for j in engine.joint_names}
        self.eff = {q: np.empty(n) for q in getattr(engine, "effort_units", {})}  # forces only
        self.lds = {p.key: np.empty((n, 3)) for p in getattr(engine, "load_pairs", ())}
        self.fri = {name: np.empty(n) for name in getattr(engine, "friction_names", ())}  # friction only

    def add(self, frame: Any) -> None:
        k = self.k
        self.t[k], self.phi[k], self.omega[k], self.epsilon[k] = (
            frame.t, frame.phi, frame.omega, frame.epsilon)
        for name, arr in self.pos.items():
            arr[k] = frame.points[name].position
        for name, arr in self.vel.items():
            arr[k] = frame.points[name].velocity
            self.acc[name][k] = frame.points[name].acceleration
        for name, (p, v, a) in self.jnt.items():
            js = frame.joints[name]
            p[k], v[k], a[k] = js.position, js.velocity, js.acceleration
        for name, e in self.eff.items():
            e[k] = frame.efforts[name]
        for key, f in self.lds.items():
            f[k] = frame.loads[key]
        for name, w in self.fri.items():
            w[k] = frame.friction[name]
        self.k += 1

    def build(self) -> RunData:
        k = self.k
        scene = self.engine.scene
        return RunData(
            scene=str(scene.name), dim=self.dim, t=self.t[:k], phi=self.phi[:k],
            omega=self.omega[:k], epsilon=self.epsilon[:k],
            positions={p: a[:k] for p, a in self.pos.items()},
            velocities={p: a[:k] for p, a in self.vel.items()},
            accelerations={p: a[:k] for p, a in self.acc.items()},
            joints={j: (p[:k], v[:k], a[:k]) for j, (p, v, a) in self.jnt.items()},
            links=[(str(link.name), tuple(link.points)) for link in scene.links],
            fixed={p: np.asarray(x, dtype=float) for p, x in scene.fixed_points.items()},
            paths={p: np.asarray(x, dtype=float) for p, x in self.engine.paths.items()},
            input_joint=str(getattr(scene, "input_joint", "")),
            inputs=self.inputs,
            efforts={q: e[:k] for q, e in self.eff.items()},
            loads={key: f[:k] for key, f in self.lds.items()},
            friction={name: w[:k] for name, w in self.fri.items()},
            load_pins={p.key: (p.point, p.body, p.other) for p in getattr(self.engine, "load_pairs", ())},
            effort_units=dict(getattr(self.engine, "effort_units", {})),
            joint_units=joint_units(scene, self.jnt),
            cylinders=[(str(g.name), str(g.base), str(g.point), float(g.stroke[0]))
                       for g in scene.ordered if getattr(g, "kind", "") == "actuator"],
        )


def joint_units(scene: Any, joints: Any) -> dict[str, str]:
    """The unit ("rad" or "m") of each of ``joints``' positions in ``scene``."""
    units = dict(getattr(scene, "joint_units", {}) or {})
    return {j: str(units.get(j, "rad")) for j in joints}
