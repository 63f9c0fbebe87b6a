"""Independent 50-digit reference kinematics of the shipped actuator scenes (mpmath only).

Never imports the solver: the scene files (config/scenes/tipper.yaml, excavator.yaml) are read with
PyYAML, and each group is evaluated here in mpmath at ``mp.dps = 50`` — an actuator or an RRR dyad
as seed 003's circle intersection (C at s from A and l from O, A → C → O counter-clockwise for
M = +1), an attached point as its rigid offset along the link. Derivatives come from mpmath's
``diff`` of those position functions: d/ds and d²/ds² for the tipper's single stroke, the
Jacobian and Hessian in the three strokes for the excavator, and the real motion v = J·ω,
a = J·ε + ωᵀHω. That route shares nothing with the solver's jets.

``python tests/reference/mp_actuator.py`` rewrites ``tests/data/reference_actuators.json``;
``--check`` regenerates in memory and compares with the stored file. Every input value is an
exactly representable double, written to 50 significant digits.
"""

from __future__ import annotations

import argparse
import datetime
import itertools
import json
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import mpmath
import yaml
from mpmath import mp, mpf

__all__ = ["DPS", "OUT", "circle", "attached", "model", "build", "main", "TIPPER_STROKES", "EXCAVATOR_SAMPLES",
           "EXCAVATOR_MOTION"]

DPS = 50
ROOT = Path(__file__).resolve().parents[2]
OUT = ROOT / "tests" / "data" / "reference_actuators.json"
#: The tipper's strokes (m): nine across [0.74, 1.30].
TIPPER_STROKES = [0.74 + 0.07 * i for i in range(9)]
#: The excavator's samples of (boom_stroke, arm_stroke, bucket_stroke), m, and the motion (m/s, m/s²).
EXCAVATOR_SAMPLES = [(1.12, 1.41, 1.08), (1.3, 1.6, 1.2), (1.55, 1.85, 1.4)]
EXCAVATOR_MOTION = {"omega": (0.05, -0.08, 0.1), "epsilon": (0.3, 0.2, -0.5)}
TIPPER_OUTPUTS = ("C", "F", "L")
EXCAVATOR_OUTPUTS = ("C2", "E", "T")


def circle(a: Any, o: Any, s: Any, link: Any, mode: int) -> Any:
    """Seed 003's intersection: |C − A| = s, |C − O| = link, A → C → O counter-clockwise for M = +1."""
    d = o - a
    dd = abs(d) ** 2
    ac = (s * s - link * link + dd) / (2 * dd)
    h = mp.sqrt(s * s / dd - ac * ac)
    return a + d * (ac - 1j * mode * h)


def attached(base: Any, r: Any, q: Any, distance: Any, angle_deg: Any) -> Any:
    """A point at ``distance`` from ``base``, ``angle_deg`` from the direction R → Q."""
    v = q - r
    return base + distance * mp.expj(mp.radians(angle_deg)) * v / abs(v)


def _m(x: Any) -> mpf:
    return mpf(str(x))


def model(name: str) -> tuple[Callable[..., dict[str, Any]], list[str]]:
    """The scene's points as an mpmath function of its strokes, read from its file."""
    data = yaml.safe_load((ROOT / "config" / "scenes" / f"{name}.yaml").read_text(encoding="utf-8"))
    fixed = {k: mp.mpc(_m(v[0]), _m(v[1])) for k, v in data["fixed"].items()}
    inputs = [g["joint"] for g in data["groups"] if g["type"] == "actuator"]

    def points(*q: Any) -> dict[str, Any]:
        x = dict(fixed)
        stroke = dict(zip(inputs, q))
        for g in data["groups"]:
            if g["type"] == "actuator":
                x[g["point"]] = circle(x[g["base"]], x[g["pivot"]], stroke[g["joint"]], _m(g["length"]), int(g["M"]))
            elif g["type"] == "attached":
                x[g["point"]] = attached(x[g["base"]], x[g["along"][0]], x[g["along"][1]], _m(g["distance"]),
                                         _m(g.get("angle", 0)))
            elif g["type"] == "rrr":
                a, c = g["ends"]
                x[g["point"]] = circle(x[a], x[c], _m(g["lengths"][0]), _m(g["lengths"][1]), int(g["M"]))
        return x

    return points, inputs


def _s(x: Any) -> str:
    return str(mp.nstr(x, DPS, strip_zeros=False, min_fixed=-4, max_fixed=5))


def _exact(x: float) -> str:
    """A double's exact value to 50 significant digits."""
    return _s(mpf(x))


def _xy(z: Any) -> list[Any]:
    return [mp.re(z), mp.im(z)]


def _tipper() -> dict[str, Any]:
    points, _ = model("tipper")
    out: dict[str, Any] = {"s": [_exact(s) for s in TIPPER_STROKES], "points": {}}
    for name in TIPPER_OUTPUTS:
        rows = {"position": [], "d_ds": [], "d2_ds2": []}
        for s in TIPPER_STROKES:
            for order, key in enumerate(rows):
                rows[key].append([_s(mp.diff(lambda t, n=name, p=p: _xy(points(t)[n])[p], mpf(s), order))
                                  for p in (0, 1)])
        out["points"][name] = rows
    floor = {"position": [], "d_ds": [], "d2_ds2": []}
    for s in TIPPER_STROKES:
        for order, key in enumerate(floor):
            floor[key].append(_s(mp.diff(lambda t: mp.atan2(*reversed(_xy(points(t)["F"]))), mpf(s), order)))
    out["joints"] = {"floor": floor}
    return out


def _excavator() -> dict[str, Any]:
    points, inputs = model("excavator")
    w, e = (tuple(mpf(x) for x in EXCAVATOR_MOTION[k]) for k in ("omega", "epsilon"))
    out: dict[str, Any] = {"inputs": inputs, "q": [[_exact(x) for x in row] for row in EXCAVATOR_SAMPLES],
                           "motion": {k: [_exact(x) for x in v] for k, v in EXCAVATOR_MOTION.items()}, "points": {}}
    for name in EXCAVATOR_OUTPUTS:
        rows: dict[str, list[Any]] = {"position": [], "jacobian": [], "hessian": [], "velocity": [], "acceleration": []}
        for row in EXCAVATOR_SAMPLES:
            q = [mpf(x) for x in row]
            per = {k: [] for k in rows}
            for p in (0, 1):
                f = lambda *t, n=name, p=p: _xy(points(*t)[n])[p]
                jac = [mp.diff(f, q, tuple(int(j == m) for j in range(3))) for m in range(3)]
                hess = [[mp.diff(f, q, tuple((j == a) + (j == b) for j in range(3))) for b in range(3)]
                        for a in range(3)]
                per["position"].append(f(*q))
                per["jacobian"].append(jac)
                per["hessian"].append(hess)
                per["velocity"].append(sum(jac[a] * w[a] for a in range(3)))
                per["acceleration"].append(sum(jac[a] * e[a] for a in range(3)) + sum(
                    hess[a][b] * w[a] * w[b] for a, b in itertools.product(range(3), repeat=2)))
            for key, value in per.items():
                rows[key].append(json.loads(json.dumps(value, default=_s)))
        out["points"][name] = rows
    return out


def build(*, date: str | None = None) -> dict[str, Any]:
    """The whole reference file."""
    mp.dps = DPS
    stamp = date or datetime.date.today().isoformat()
    return {
        "provenance": (f"tests/reference/mp_actuator.py (mpmath {mpmath.__version__}, mp.dps={DPS}), {stamp}: "
                       "positions from seed 003's circle intersection and the attached points, read from "
                       "config/scenes/tipper.yaml and excavator.yaml with PyYAML; derivatives by mpmath.diff; "
                       "never the solver"),
        "units": "m, rad; the tipper's analogs per m of stroke, the excavator's J per m and H per m^2",
        "tipper": _tipper(),
        "excavator": _excavator(),
    }


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--check", action="store_true", help="compare with the stored file instead of writing it")
    args = p.parse_args(argv)
    stored = json.loads(OUT.read_text()) if args.check else None
    data = build(date=None if stored is None else stored["provenance"].split("), ")[1].split(":")[0])
    if stored is None:
        OUT.write_text(json.dumps(data, indent=1) + "\n")
        print(f"wrote {OUT}")
        return 0
    same = data == stored
    print("identical" if same else "differs")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
