"""Input/expected pairs of the force reference with provenance: tests/data/forces_<scene>.json.

The mechanics are in forces_mp.py (50-digit Newton–Euler of every body, mpmath and PyYAML only,
never the solver); this module draws the random instants, checks each one's power balance,
writes the files (one line per sample) and compares regenerated files with the stored ones.

    python tests/reference/forces_mp.py SCENE.yaml [...]            # (re)write the files
    python tests/reference/forces_mp.py --check SCENE.yaml [...]    # compare, write nothing
"""

from __future__ import annotations

import argparse
import datetime
import hashlib
import json
import random
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import mpmath
from forces_mp import DPS, ROOT, Mechanism, Solution, _sub, digest, load, positions, power_residual, solve
from mpmath import mp, mpf

__all__ = ["DIGITS", "SAMPLES", "build", "compare", "main"]

DIGITS = 30
"""Significant digits written (the tests need 1e-9; 30 leaves the last digits to spare)."""
SAMPLES = 24
CHECK_TOL = mpf("1e-28")
"""The power balance of every written sample must hold to this (relative)."""
MIN_CONDITIONING = mpf("0.2")
"""Samples whose system's normalised determinant |det| / Π(row norms) is below this fraction of
the best over PROBES random instants (near a singular position, where forces grow without bound;
the measure shrinks with the system's size, hence relative) are drawn again."""
PROBES = 32
OMEGA_RANGE, EPSILON_RANGE = 6.0, 20.0
"""|ω| ≤ 6 rad/s, |ε| ≤ 20 rad/s² per input."""
DATA_DIR = ROOT / "tests" / "data"
SCRIPT = "tests/reference/forces_mp.py"


def _fmt(x: mpf) -> str:
    return mp.nstr(x, DIGITS, strip_zeros=False, min_fixed=-4, max_fixed=5)


def _draw(m: Mechanism, rng: random.Random) -> tuple[list[float], list[float], list[float]]:
    """One random instant: q (rad; five-bars in 40°..140° per input), ω, ε, as exact doubles."""
    k = len(m.inputs)
    low, high = (0.7, 2.44) if k > 1 else (-3.2, 9.5)  # one input: a turn and a half, and negatives
    q = [rng.uniform(low, high) for _ in range(k)]
    omega = [rng.uniform(-OMEGA_RANGE, OMEGA_RANGE) for _ in range(k)]
    epsilon = [rng.uniform(-EPSILON_RANGE, EPSILON_RANGE) for _ in range(k)]
    return q, omega, epsilon


def _sample(m: Mechanism, q: list[float], omega: list[float], epsilon: list[float]) -> tuple[dict, Solution]:
    mq, mw, me = ([mpf(x) for x in v] for v in (q, omega, epsilon))  # mpf(float) is exact
    sol = solve(m, mq, mw, me)
    power = power_residual(m, mq, mw, me, sol)
    assert abs(power) < CHECK_TOL, f"{m.name}: power balance off by {power} at q={q}"
    row = {
        "q": [repr(x) for x in q],
        "omega": [repr(x) for x in omega],
        "epsilon": [repr(x) for x in epsilon],
        "effort": {j: _fmt(v) for j, v in sol.effort.items()},
        "reactions": {p: {b: [_fmt(f[0]), _fmt(f[1])] for b, f in at.items()} for p, at in sol.reactions.items()},
        "slides": {b: {"force": [_fmt(f[0]), _fmt(f[1])], "couple": _fmt(c)} for b, (f, c) in sol.slides.items()},
    }
    return row, sol


def _scale_length(m: Mechanism) -> mpf:
    """The largest distance between two points of one body (m), at q = 1 rad per input if the
    scene assembles there, else at the first instant that does: the scale of torques / forces."""
    for trial in (1, 1.3, 1.6, 2.0):
        try:
            pts = positions(m, [mpf(trial)] * len(m.inputs))
            break
        except ValueError:
            continue
    return max(mp.hypot(*_sub(pts[a], pts[b])) for li in m.links.values() for a in li.points for b in li.points)


def _best_conditioning(m: Mechanism, rng: random.Random) -> mpf:
    best = mpf(0)
    for _ in range(PROBES):
        q, omega, epsilon = _draw(m, rng)
        try:
            best = max(best, solve(m, [mpf(x) for x in q], [mpf(0)] * len(q), [mpf(0)] * len(q)).conditioning)
        except ValueError:  # not assemblable there
            continue
    return best


def build(path: str | Path, count: int = SAMPLES, *, date: str | None = None) -> dict:
    """The JSON-ready reference of one scene: ``count`` random instants (seeded by the scene name),
    plus one at rest (ω = ε = 0) so statics are pinned too."""
    with mp.workdps(DPS):
        m = load(path)
        seed = int(hashlib.sha256(m.name.encode()).hexdigest()[:8], 16)
        floor = MIN_CONDITIONING * _best_conditioning(m, random.Random(seed + 1))
        rng = random.Random(seed)
        rows: list[dict] = []
        while len(rows) < count:
            q, omega, epsilon = _draw(m, rng)
            if len(rows) == 0:
                omega, epsilon = [0.0] * len(q), [0.0] * len(q)
            try:
                row, sol = _sample(m, q, omega, epsilon)
            except ValueError:  # not assemblable there
                continue
            if sol.conditioning >= floor:
                rows.append(row)
        scale = _fmt(_scale_length(m))
    try:
        rel = m.file.resolve().relative_to(ROOT).as_posix()
    except ValueError:
        rel = str(m.file)
    when = date or datetime.date.today().isoformat()
    return {
        "provenance": (
            f"{SCRIPT} (mpmath {mpmath.__version__}, mp.dps={DPS}, {DIGITS} digits written), {when}: "
            f"positions of {rel} in closed form in mpmath (never the solver), accelerations of centres and "
            "angular accelerations by mp.diff in time along q(t) = q + omega t + epsilon t^2/2, then the "
            "Newton-Euler equations of every moving body (with the scene's loads, gravity, flywheel inertia and "
            "damping couples) solved as one linear system for all pin forces, guide and slot actions and the input "
            "efforts; each sample's efforts also pass an energy "
            "(power balance) check. Random instants seeded by the scene name; q, omega, epsilon exact doubles."
        ),
        "scene": m.name,
        "scene_file": rel,
        "scene_mechanics_sha256": digest(m.file),
        "inputs": m.inputs,
        "scale_length": scale,
        "units": "q rad, omega rad/s, epsilon rad/s^2; forces N, torques N m (SI whatever the scene's units)",
        "conventions": (
            "effort: torque about +z of the actuator on its crank; reactions[P][X]: force on body X at pin P "
            "from the other body (or ground); slides[X]: force on slider block X from what it slides on (the "
            "fixed guide, or the slotted link), normal to the guide, and the couple about the block's point; "
            "the guide body gets the opposite of both"
        ),
        "samples": rows,
    }


def compare(stored: Any, fresh: Any, path: str = "") -> mpf:
    if isinstance(stored, dict):
        return max((compare(stored[k], fresh[k], f"{path}/{k}") for k in stored if k != "provenance"), default=mpf(0))
    if isinstance(stored, list):
        assert len(stored) == len(fresh), f"{path}: length differs"
        return max((compare(a, b, path) for a, b in zip(stored, fresh)), default=mpf(0))
    if isinstance(stored, str) and stored[:1] in "-0123456789" and not path.endswith("sha256"):
        return abs(mpf(stored) - mpf(fresh)) / max(abs(mpf(stored)), mpf(1))
    assert stored == fresh, f"{path}: {stored!r} != {fresh!r}"
    return mpf(0)


def _dumps(ref: dict) -> str:
    """JSON with one line per sample (small files, readable diffs)."""
    head = json.dumps({**ref, "samples": []}, indent=1)
    rows = ",\n  ".join(json.dumps(row, separators=(",", ":")) for row in ref["samples"])
    return head.replace('"samples": []', f'"samples": [\n  {rows}\n ]') + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Write or check tests/data/forces_<scene>.json")
    parser.add_argument("scenes", nargs="+", type=Path, help="scene files")
    parser.add_argument("--out", type=Path, default=DATA_DIR, help="folder for forces_<scene>.json")
    parser.add_argument("--count", type=int, default=SAMPLES, help="random instants per scene")
    parser.add_argument("--check", action="store_true", help="compare with the stored files, write nothing")
    args = parser.parse_args(argv)
    status = 0
    for path in args.scenes:
        ref = build(path, args.count)
        target = args.out / f"forces_{ref['scene']}.json"
        if args.check:
            with mp.workdps(DPS):
                diff = compare(json.loads(target.read_text()), ref)
            ok = diff < mpf(10) ** (1 - DIGITS)
            status |= not ok
            print(f"{target}: max relative difference {mp.nstr(diff, 3)} {'ok' if ok else 'MISMATCH'}")
            continue
        text = _dumps(ref)
        target.write_text(text)
        print(f"{target}: {len(ref['samples'])} samples, {len(text) / 1024:.0f} KiB")
    return status


if __name__ == "__main__":
    sys.exit(main())
