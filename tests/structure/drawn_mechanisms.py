"""Random drawings of four-bars, slider-cranks, Watt II and Stephenson III six-bars, and an
independent continuation solve: Newton on the rigid links' distances, stepped from the drawn pose
(no groups, no assembly modes: what the drawing says, as constraints on the points)."""

from __future__ import annotations

import cmath
import math
import random
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

KINDS = ("four_bar", "slider_crank", "watt_ii", "stephenson_iii")


def _c(z: complex) -> list[float]:
    return [z.real, z.imag]


def _sin_at(a: complex, b: complex, c: complex) -> float:
    """|sin| of the angle at b between b→a and b→c."""
    p, q = a - b, c - b
    return abs((p.conjugate() * q).imag) / (abs(p) * abs(q))


def _reflect(b: complex, a: complex, c: complex) -> complex:
    """b mirrored in the line a–c."""
    u = (c - a) / abs(c - a)
    w = (b - a) / u
    return a + w.conjugate() * u


def _dyad_point(rng: random.Random, a: complex, c: complex, mode: int) -> complex:
    """A point b well away from the line a–c, on the side ``mode`` (sign of the area a, b, c)."""
    while True:
        b = a + (c - a) * complex(rng.uniform(-0.3, 1.3), rng.uniform(0.25, 1.2))
        if _sin_at(a, b, c) > 0.25:
            break
    area = ((b - a).conjugate() * (c - a)).imag
    return b if (area > 0) == (mode > 0) else _reflect(b, a, c)


def drawing(kind: str, seed: int, modes: Sequence[int]) -> dict[str, Any]:
    """A random drawn scene (m, rad) of ``kind`` with its dyads in ``modes``."""
    rng = random.Random(f"{kind}-{seed}")
    size = 10 ** rng.uniform(-2, 1)
    o = 0j
    c = cmath.rect(size * rng.uniform(0.8, 1.2), rng.uniform(-0.4, 0.4))
    a = o + cmath.rect(size * rng.uniform(0.15, 0.3), rng.uniform(0, 2 * math.pi))
    pts: dict[str, complex] = {"O": o, "A": a}
    links: dict[str, list[str]] = {"crank": ["O", "A"]}
    ground = ["O"]
    slides: dict[str, Any] = {}
    if kind == "slider_crank":
        g1 = cmath.rect(size * rng.uniform(0.0, 0.2), rng.uniform(0, 2 * math.pi))
        e = cmath.rect(1.0, rng.uniform(-0.5, 0.5))
        g2 = g1 + e * size
        w = a - g1
        t, n = (w * e.conjugate()).real, (w * e.conjugate()).imag
        length = size * rng.uniform(0.6, 1.2)
        b = g1 + e * (t + modes[0] * math.sqrt(length**2 - n**2))
        pts.update(G1=g1, G2=g2, B=b)
        ground += ["G1", "G2"]
        links["rod"] = ["A", "B"]
        slides["piston"] = {"point": "B", "on": "ground", "along": ["G1", "G2"]}
    else:
        b = _dyad_point(rng, a, c, modes[0])
        pts.update(C=c, B=b)
        ground.append("C")
        links.update(coupler=["A", "B"], rocker=["C", "B"])
        if kind in ("watt_ii", "stephenson_iii"):
            carrier = "rocker" if kind == "watt_ii" else "coupler"
            base = pts[links[carrier][0]]
            d = base + (b - base) * complex(rng.uniform(0.2, 0.9), rng.uniform(-0.8, 0.8))
            f = c + cmath.rect(size * rng.uniform(0.5, 1.0), rng.uniform(-1.5, 1.5))
            e_ = _dyad_point(rng, d, f, modes[1])
            pts.update(D=d, F=f, E=e_)
            ground.append("F")
            links[carrier] = [*links[carrier], "D"]
            links.update(link=["D", "E"], output=["F", "E"])
    dr: dict[str, Any] = {"points": {k: _c(v) for k, v in pts.items()}, "ground": ground, "links": links,
                          "inputs": ["crank"]}
    if slides:
        dr["slides"] = slides
    moving = [p for p in pts if p not in ground]
    return {"scene": f"{kind}_{seed}", "units": {"length": "m", "angle": "rad"}, "drawing": dr,
            "outputs": {"points": moving}}


def constraints(dr: Mapping[str, Any]) -> tuple[list[str], Callable[[np.ndarray, float], np.ndarray]]:
    """The unknown points (every moving point but the crank's) and the residual of the drawing's
    rigid links and slides at input φ: ``residual(x, φ)`` for x of shape (m, 2·unknowns)."""
    pts = {k: complex(*v) for k, v in dr["points"].items()}
    ground = set(dr["ground"])
    crank = dr["links"][dr["inputs"][0]]
    o, a = crank
    arm = abs(pts[a] - pts[o])
    unknown = [p for p in pts if p not in ground and p != a]
    col = {p: i for i, p in enumerate(unknown)}
    rows: list[tuple[Any, ...]] = []
    for pl in dr["links"].values():
        p0, p1 = pl[0], pl[1]
        frame = pts[p1] - pts[p0]
        if pl is not crank:  # (the input link's frame is driven: A = O + |OA|·e^{jφ})
            rows.append(("dist", p0, p1, abs(frame) ** 2))
        for q in pl[2:]:
            w = pts[q] - pts[p0]
            rows.append(("dot", p0, p1, q, (w * frame.conjugate()).real))
            rows.append(("cross", p0, p1, q, (frame.conjugate() * w).imag))
    for s in dr.get("slides", {}).values():
        rows.append(("line", *s["along"], s["point"]))

    def residual(x: np.ndarray, phi: float) -> np.ndarray:
        z = x[:, 0::2] + 1j * x[:, 1::2]

        def at(name: str) -> Any:
            if name in col:
                return z[:, col[name]]
            if name == a:
                return pts[o] + arm * cmath.exp(1j * phi)
            return pts[name]

        out = []
        for r in rows:
            if r[0] == "dist":
                out.append(np.abs(at(r[2]) - at(r[1])) ** 2 - r[3])
            elif r[0] == "dot":
                out.append(((at(r[3]) - at(r[1])) * np.conj(at(r[2]) - at(r[1]))).real - r[4])
            elif r[0] == "cross":
                out.append((np.conj(at(r[2]) - at(r[1])) * (at(r[3]) - at(r[1]))).imag - r[4])
            else:
                out.append((np.conj(at(r[2]) - at(r[1])) * (at(r[3]) - at(r[1]))).imag)
        return np.stack([np.broadcast_to(v, z.shape[:1]) for v in out], 1)

    assert len(rows) == 2 * len(unknown), (rows, unknown)
    return unknown, residual


def newton(residual: Callable[[np.ndarray, float], np.ndarray], x0: np.ndarray, phi: float, scale: float
           ) -> tuple[np.ndarray, float]:
    """Newton from ``x0`` with a central-difference Jacobian; the solution and the Jacobian's
    condition number there (inf when it did not converge)."""
    x = x0.copy()
    n = x.size
    h = 1e-6 * scale
    for _ in range(30):
        probe = np.vstack([x, x + h * np.eye(n), x - h * np.eye(n)])
        r = residual(probe, phi)
        jac = (r[1 : n + 1] - r[n + 1 :]).T / (2 * h)
        step = np.linalg.solve(jac, -r[0])
        x = x + step
        if np.max(np.abs(step)) <= 1e-15 * scale:
            return x, float(np.linalg.cond(jac))
    return x, math.inf


def follow(dr: Mapping[str, Any], phis: Sequence[float]) -> tuple[list[str], list[np.ndarray | None]]:
    """The unknown points along ``phis`` (a path from the drawn input value), by continuation;
    None from where Newton stops converging or the Jacobian is ill-conditioned."""
    unknown, residual = constraints(dr)
    pts = dr["points"]
    x = np.array([c for p in unknown for c in pts[p]], float)
    scale = max(abs(complex(*v)) for v in pts.values())
    out: list[np.ndarray | None] = []
    prev = None
    for phi in phis:
        guess = x if prev is None else 2 * x - prev
        sol, cond = newton(residual, guess, phi, scale)
        if not math.isfinite(cond) or cond > 1e6:
            out += [None] * (len(phis) - len(out))
            break
        prev, x = x, sol
        out.append(sol.copy())
    return unknown, out
