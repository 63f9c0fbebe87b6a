"""Independent 50-digit reference for forward dynamics: absolute coordinates and multipliers.

This module never imports the solver's formulas (the solver is asked only for a float guess of
the positions, which Newton then refines at 50 digits). Each body i has absolute coordinates
(xᵢ, yᵢ, θᵢ) of its centre of mass; pins and the piston's guide are constraints Φ(q) = 0; the
equations of motion are the index-1 form of the Lagrange equations with multipliers

    [ M   Φ_qᵀ ] [ q̈ ]   [ F ]
    [ Φ_q  0   ] [ λ  ] = [ γ ],     γ = −(Φ_q·q̇)_q·q̇,

solved by LU at ``mp.dps = 50``. Its crank's θ̈ is the input acceleration ε that
``solver.dynamics`` must give at the same (φ, ω) under the same drive: a formulation in other
coordinates, with no closed form, no kinetostatics and no reduced inertia.

Mechanisms (read from the shipped scene files with plain PyYAML): ``four_bar_loaded`` (gravity, a
force and a torque on the rocker) and ``engine`` (a slider-crank in mm: flywheel, brake damping,
the gas force read off its table of the crank angle over 720°, gravity).

Run ``python tests/reference/dynamics_mp.py`` to (re)write ``tests/data/dynamics_ref_*.json``:
input/expected pairs (φ, ω, Q_drive → ε) with their provenance.
"""

from __future__ import annotations

import json
import math
import random
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml
from mpmath import matrix, mp, mpf

__all__ = ["DPS", "epsilon", "mechanism", "main"]

DPS = 50
ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "config" / "scenes"
DATA = ROOT / "tests" / "data"


@dataclass
class Body:
    name: str
    mass: Any
    inertia: Any
    local: dict[str, tuple[Any, Any]]  # point → its coordinates in the body frame, relative to G


@dataclass
class Mechanism:
    bodies: list[Body]
    pins: list[tuple[str, str, str | None]]  # (point, body, other body or None = ground)
    fixed: dict[str, tuple[Any, Any]]
    guides: list[str]  # bodies that translate along x at y = 0 with θ = 0 (a piston)
    gravity: tuple[Any, Any]
    crank: str
    loads: Any  # f(q, qd, phi, omega) → generalised force vector contributions (list of mpf)


def _frame_points(points: dict[str, tuple[Any, Any]], origin: str, xaxis: str, center: tuple[Any, Any],
                  names: list[str]) -> dict[str, tuple[Any, Any]]:
    """The points' coordinates in a body frame (origin, x toward ``xaxis``) relative to G."""
    ox, oy = points[origin]
    ux, uy = points[xaxis][0] - ox, points[xaxis][1] - oy
    n = mp.sqrt(ux * ux + uy * uy)
    ux, uy = ux / n, uy / n
    out = {}
    for p in names:
        dx, dy = points[p][0] - ox, points[p][1] - oy
        out[p] = (dx * ux + dy * uy - center[0], -dx * uy + dy * ux - center[1])
    return out


def _rot(theta: Any, s: tuple[Any, Any]) -> tuple[Any, Any]:
    c, n = mp.cos(theta), mp.sin(theta)
    return (c * s[0] - n * s[1], n * s[0] + c * s[1])


def _scene_data(name: str) -> tuple[dict[str, Any], Any]:
    data = yaml.safe_load((SCENES / f"{name}.yaml").read_text(encoding="utf-8"))
    return data, mpf("0.001") if data["units"]["length"] == "mm" else mpf(1)


def _points(name: str, scene: Any, phi: float) -> dict[str, tuple[Any, Any]]:
    """Float positions of every point at φ from the solver (only Newton's starting guess)."""
    data, scale = _scene_data(name)
    k = scene.everything().solve(phi)
    pts = {p: tuple(mpf(str(v)) * scale for v in xy) for p, xy in data["fixed"].items()}
    for p in scene.everything().output_points:
        if p not in pts:
            pts[p] = tuple(mpf(float(v)) for v in k.point(p).position)
    return pts


def mechanism(name: str, scene: Any) -> Mechanism:
    """Bodies, pins, guides and loads of a shipped scene, its geometry taken at φ = 0.7 rad."""
    data, scale = _scene_data(name)
    g = tuple(mpf(str(v)) for v in data["gravity"])
    pts = _points(name, scene, 0.7)
    bodies = []
    for bname, b in data["bodies"].items():
        center = tuple(mpf(str(v)) * scale for v in b.get("center", [0, 0]))
        inertia = mpf(str(b.get("inertia", 0)))
        if bname == "crank" and "flywheel" in data:
            inertia += mpf(str(next(iter(data["flywheel"].values()))))
        if len(b["points"]) == 1:  # the piston: translating along x
            (p,) = b["points"]
            bodies.append(Body(bname, mpf(str(b["mass"])), inertia, {p: (-center[0], -center[1])}))
            continue
        o, x = b["points"]
        bodies.append(Body(bname, mpf(str(b["mass"])), inertia, _frame_points(pts, o, x, center, [o, x])))
    fixed = {p: tuple(mpf(str(v)) * scale for v in xy) for p, xy in data["fixed"].items()}
    owner: dict[str, str] = {}
    pins: list[tuple[str, str, str | None]] = []
    for b in bodies:
        for p in b.local:
            if p in fixed:
                pins.append((p, b.name, None))
            elif p in owner:
                pins.append((p, b.name, owner[p]))
            else:
                owner[p] = b.name
    guides = [b.name for b in bodies if len(b.local) == 1]
    return Mechanism(bodies, pins, fixed, guides, g, bodies[0].name, _loads(data, bodies))


def guess(name: str, scene: Any, m: Mechanism, phi: float) -> list[Any]:
    """Absolute coordinates of every body from the solver's float points at φ (Newton's start)."""
    data, scale = _scene_data(name)
    pts = _points(name, scene, phi)
    q: list[Any] = []
    for b, raw in zip(m.bodies, data["bodies"].values()):
        center = tuple(mpf(str(v)) * scale for v in raw.get("center", [0, 0]))
        if len(raw["points"]) == 1:
            (p,) = raw["points"]
            q += [pts[p][0] + center[0], pts[p][1] + center[1], mpf(0)]
            continue
        o, x = raw["points"]
        theta = mp.atan2(pts[x][1] - pts[o][1], pts[x][0] - pts[o][0])
        if b is m.bodies[0]:  # the crank's θ is φ itself, not wrapped (its constraint θ = φ is linear)
            theta += 2 * mp.pi * mp.nint((phi - theta) / (2 * mp.pi))
        gx, gy = _rot(theta, center)
        q += [pts[o][0] + gx, pts[o][1] + gy, theta]
    return q


def _loads(data: dict[str, Any], bodies: list[Body]) -> Any:
    index = {b.name: i for i, b in enumerate(bodies)}

    def loads(q: list[Any], qd: list[Any], phi: Any, omega: Any) -> list[Any]:
        f = [mpf(0)] * len(q)
        for ld in data.get("loads", []):
            i = index[ld["body"]]
            if "torque" in ld:
                f[3 * i + 2] += mpf(str(ld["torque"]))
                continue
            if "force" in ld:
                fx, fy = (mpf(str(v)) for v in ld["force"])
            else:  # a table of the crank angle (deg) over its period, linear between entries
                t = ld["table"]
                period = mp.radians(mpf(str(t.get("period", 360))))
                at = [mp.radians(mpf(str(v))) for v in t["at"]]
                x = (phi - at[0]) % period + at[0]
                j = max(i for i in range(len(at) - 1) if at[i] <= x)
                w = (x - at[j]) / (at[j + 1] - at[j])
                size = mpf(str(t["force"][j])) + w * (mpf(str(t["force"][j + 1])) - mpf(str(t["force"][j])))
                dx, dy = (mpf(str(v)) for v in ld["direction"])
                n = mp.sqrt(dx * dx + dy * dy)
                fx, fy = size * dx / n, size * dy / n
            sx, sy = _rot(q[3 * i + 2], bodies[i].local[ld["point"]])
            f[3 * i] += fx
            f[3 * i + 1] += fy
            f[3 * i + 2] += sx * fy - sy * fx
        for c in data.get("damping", {}).values():
            f[2] -= mpf(str(c)) * omega  # the crank's (the only damped joint of these scenes)
        return f

    return loads


def _constraints(m: Mechanism, q: list[Any]) -> list[Any]:
    out = []
    idx = {b.name: i for i, b in enumerate(m.bodies)}

    def point(body: str, p: str) -> tuple[Any, Any]:
        i = idx[body]
        sx, sy = _rot(q[3 * i + 2], m.bodies[i].local[p])
        return q[3 * i] + sx, q[3 * i + 1] + sy

    for p, b, other in m.pins:
        x, y = point(b, p)
        ox, oy = m.fixed[p] if other is None else point(other, p)
        out += [x - ox, y - oy]
    for b in m.guides:  # the piston's pin on the line y = 0, the piston not turning
        i = idx[b]
        out += [point(b, next(iter(m.bodies[i].local)))[1], q[3 * i + 2]]
    return out


def _jacobian(f: Any, q: list[Any]) -> Any:
    n = len(q)
    rows = [mp.diff(lambda *x, j=j: f(list(x))[j], q, tuple(1 if k == i else 0 for k in range(n)))
            for j in range(len(f(q))) for i in range(n)]
    m = len(rows) // n
    return matrix([[rows[j * n + i] for i in range(n)] for j in range(m)])


def epsilon(name: str, scene: Any, phi: float, omega: float, drive: float) -> Any:
    """The crank's angular acceleration (rad/s², 50 digits) at (φ, ω) under the drive torque."""
    mp.dps = DPS
    m = mechanism(name, scene)
    q = guess(name, scene, m, phi)
    n = len(q)
    crank = 2  # θ of the first body (the crank)
    phi_mp, w = mpf(phi), mpf(omega)
    for _ in range(60):  # positions: Φ(q) = 0 with θ_crank = φ
        res = [*_constraints(m, q), q[crank] - phi_mp]
        if max(abs(r) for r in res) < mpf(10) ** (-DPS + 5):
            break
        jac = _jacobian(lambda x: [*_constraints(m, x), x[crank] - phi_mp], q)
        dq = mp.lu_solve(jac, matrix(res))
        q = [q[i] - dq[i] for i in range(n)]
    jc = _jacobian(lambda x: _constraints(m, x), q)
    drive_row = matrix([[1 if i == crank else 0 for i in range(n)]])
    full = matrix(jc.rows + 1, n)
    for r in range(jc.rows):
        for c in range(n):
            full[r, c] = jc[r, c]
    for c in range(n):
        full[jc.rows, c] = drive_row[0, c]
    rhs = matrix([0] * jc.rows + [w])
    qd = mp.lu_solve(full, rhs)
    qd = [qd[i] for i in range(n)]
    # γ = −(Φ_q q̇)_q q̇: the second derivative of Φ along q̇ with q̈ = 0
    h = mpf(10) ** (-15)
    gamma = [-(a - 2 * b + c) / (h * h) for a, b, c in zip(
        _constraints(m, [q[i] + h * qd[i] for i in range(n)]), _constraints(m, q),
        _constraints(m, [q[i] - h * qd[i] for i in range(n)]))]
    mass = []
    for b in m.bodies:
        mass += [b.mass, b.mass, b.inertia]
    f = m.loads(q, qd, phi_mp, w)
    for i, b in enumerate(m.bodies):
        f[3 * i] += b.mass * m.gravity[0]
        f[3 * i + 1] += b.mass * m.gravity[1]
    f[crank] += mpf(drive)
    rows = jc.rows
    big = matrix(n + rows, n + rows)
    for i in range(n):
        big[i, i] = mass[i]
    for r in range(rows):
        for c in range(n):
            big[c, n + r] = jc[r, c]
            big[n + r, c] = jc[r, c]
    sol = mp.lu_solve(big, matrix([*f, *gamma]))
    return sol[crank]


def main() -> None:
    sys.path.insert(0, str(ROOT))
    import solver

    for name, rates, drives in (("four_bar_loaded", (-12.0, 12.0), (-3.0, 3.0)),
                                ("engine", (50.0, 400.0), (-30.0, 60.0))):
        scene = solver.load_scene(name)
        rng = random.Random(f"dynamics_mp/{name}")
        states = []
        for _ in range(8):
            phi = rng.uniform(0.0, 4 * math.pi)
            omega = rng.uniform(*rates)
            drive = rng.uniform(*drives)
            eps = epsilon(name, scene, phi, omega, drive)
            states.append({"phi": phi, "omega": omega, "drive": drive, "epsilon": mp.nstr(eps, 30)})
        out = {
            "provenance": ("tests/reference/dynamics_mp.py: Lagrange multipliers in absolute coordinates at "
                           f"{DPS} digits (mpmath), positions by Newton from the solver's float guess; the "
                           f"scene file config/scenes/{name}.yaml as shipped"),
            "scene": name,
            "states": states,
        }
        path = DATA / f"dynamics_ref_{name}.json"
        path.write_text(json.dumps(out, indent=1) + "\n", encoding="utf-8")
        print(f"wrote {path.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
