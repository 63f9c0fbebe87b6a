"""Topic mode against the anchor: our relay beside a warm-started Gauss–Newton loop closure.

    .venv/bin/python -m bench.relay            # the full measurement (quiet machine, ~1 min)
    .venv/bin/python -m bench.relay --quick    # a smoke run: few messages, one repetition

The anchor is the method of solidworks_urdf_exporter2's loop-closure relay (2026), written here
from its description: forward kinematics of the URDF spanning tree, Gauss–Newton on the cut
joint's residual (the two sides of the cut pin must meet), warm-started from the previous
message's joint values. Its tree is the one ``linkage-urdf`` writes:

* four-bar (``four_bar``, and ``hard/double_rocker`` for the toggle): crank φ; coupler
  ``q₁`` relative to the crank at A; rocker ``q₂`` about C; cut pin B:
  ``r(q) = A(φ) + L_AB·e^{j(φ+q₁)} − C − L_CB·e^{jq₂}``.
* harvester finger: drum φ; finger link ``ψ`` about A; eyelet slide ``s`` along it; cut eyelet
  pin B on the drum: ``r(q) = A + s·e^{jψ} − O − R·e^{jφ}``.

Each step solves ``J Δ = −r`` (2 residuals, 2 unknowns: Gauss–Newton's normal equations
``JᵀJ Δ = −Jᵀr`` have the same solution), in plain Python floats as our per-tick path is, until
``|Δ|∞ ≤ GN_STEP_TOL`` (at most ``GN_MAX_ITERATIONS``). Its joint velocities come from the
implicit function theorem at the converged point, ``q' = −J⁻¹ ∂r/∂φ``, times ω (the anchor
publishes positions; we give it velocities for a like-for-like comparison).

Ours: :meth:`linkage_ros.relay.Relay.answer` (closed form, every point and joint, ω from the
message, ε = 0), then the node's messages for that frame (``MessageBuilder.build`` with rosbags'
Jazzy typestore classes, every topic). For the anchor, "messages" is one JointState (what it
publishes). Timing: mean µs per message over the sequence (``perf_counter`` around each part),
best of ``--repeat`` passes.

Errors: the passive joints (four-bar: coupler and rocker angles; harvester: finger angle and
eyelet slide) against a 50-digit reference: positions from the closed-form geometry in mpmath
(tests/reference/mp_reference.py for the harvester finger; the same circle intersection for the
four-bars), velocity analogs by solving the differentiated closure at 50 digits. Angles in rad,
slides in m; velocities relative to max(|v_ref|, 1)·|ω|. "lost" counts messages whose position
error exceeds ``LOST`` (another assembly mode, or no convergence).

Sequences (φ in rad, ω = 1 rad/s, stamps 1 ms apart):
* ``0.1° steps``: φ₀ + k·0.1°, one turn (``--quick``: 60 messages);
* ``10° steps``: k·10° + 0.3°, three turns (a jump, as after dropped messages); ``60°`` and
  ``90° steps`` (36 messages): where the warm start stops keeping the assembly;
* ``toggle``: ``hard/double_rocker`` approaching its toggle φ_t = acos(−0.40625) from below,
  φ_t − δ with δ from 0.1 rad down to 1e-12 rad geometrically, then back out.
"""

from __future__ import annotations

import argparse
import cmath
import math
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:  # `python bench/relay.py` as well as `python -m bench.relay`
    sys.path.insert(0, str(ROOT))

from bench._common import _mp_reference, machine  # noqa: E402

__all__ = ["GN_MAX_ITERATIONS", "GN_STEP_TOL", "Row", "main", "run"]

#: Gauss–Newton stops when the largest step is below this (rad or m; rounding floor ≈ 1e-16).
GN_STEP_TOL = 1e-14
GN_MAX_ITERATIONS = 50
#: A passive-joint position error above this (rad or m) is a lost assembly (or no convergence).
LOST = 1e-6
NS = 1_000_000_000
STAMP_STEP_NS = 1_000_000
DEG = math.pi / 180.0


# ---------------------------------------------------------------- the mechanisms
@dataclass(frozen=True)
class FourBar:
    scene: str
    crank: float
    coupler: float
    rocker: float
    ground: float  # C = (ground, 0), O = (0, 0)
    mode: int
    joints: tuple[str, str] = ("coupler", "rocker")


@dataclass(frozen=True)
class Finger:
    scene: str = "harvester_finger"
    drum: float = 0.20
    pivot: complex = complex(0.04, -0.03)
    joints: tuple[str, str] = ("finger", "eyelet")


FOUR_BAR = FourBar("four_bar", 0.1, 0.4, 0.3, 0.4, +1)
DOUBLE_ROCKER = FourBar("hard/double_rocker", 0.1, 0.25, 0.2, 0.4, +1)
HARVESTER = Finger()


# ---------------------------------------------------------------- the anchor: Gauss–Newton
class GaussNewton:
    """Warm-started Gauss–Newton on the cut joint's residual of one mechanism's URDF tree."""

    def __init__(self, mech: FourBar | Finger, phi0: float) -> None:
        self.mech = mech
        self.q = _initial(mech, phi0)  # the assembly it is given once, as a relay is configured
        self.iterations = 0

    def _residual(self, phi: float, q: tuple[float, float]) -> tuple[complex, complex, complex]:
        """``r``, ``∂r/∂q₁``, ``∂r/∂q₂`` (complex: x + jy)."""
        m = self.mech
        if isinstance(m, FourBar):
            arm = cmath.exp(1j * phi)
            e1 = cmath.exp(1j * (phi + q[0]))
            e2 = cmath.exp(1j * q[1])
            r = m.crank * arm + m.coupler * e1 - m.ground - m.rocker * e2
            return r, 1j * m.coupler * e1, -1j * m.rocker * e2
        e = cmath.exp(1j * q[0])
        r = m.pivot + q[1] * e - m.drum * cmath.exp(1j * phi)
        return r, 1j * q[1] * e, e

    def _d_phi(self, phi: float, q: tuple[float, float]) -> complex:
        m = self.mech
        if isinstance(m, FourBar):
            return 1j * m.crank * cmath.exp(1j * phi) + 1j * m.coupler * cmath.exp(1j * (phi + q[0]))
        return -1j * m.drum * cmath.exp(1j * phi)

    def solve(self, phi: float, omega: float) -> tuple[tuple[float, float], tuple[float, float], int]:
        """Passive joints (the scene's joints: absolute angles / slide), their velocities, and the
        iterations used."""
        q1, q2 = self.q
        n = 0
        while n < GN_MAX_ITERATIONS:
            n += 1
            r, j1, j2 = self._residual(phi, (q1, q2))
            det = j1.real * j2.imag - j1.imag * j2.real
            if det == 0.0:
                break
            d1 = -(r.real * j2.imag - r.imag * j2.real) / det
            d2 = -(j1.real * r.imag - j1.imag * r.real) / det
            q1 += d1
            q2 += d2
            if max(abs(d1), abs(d2)) <= GN_STEP_TOL:
                break
        self.q = (q1, q2)
        _, j1, j2 = self._residual(phi, (q1, q2))
        b = -self._d_phi(phi, (q1, q2))
        det = j1.real * j2.imag - j1.imag * j2.real
        v1 = (b.real * j2.imag - b.imag * j2.real) / det if det else math.nan
        v2 = (j1.real * b.imag - j1.imag * b.real) / det if det else math.nan
        if isinstance(self.mech, FourBar):  # coupler = φ + q₁ (absolute), rocker = q₂
            return (_wrap(phi + q1), _wrap(q2)), ((1.0 + v1) * omega, v2 * omega), n
        return (_wrap(q1), q2), (v1 * omega, v2 * omega), n


def _initial(mech: FourBar | Finger, phi: float) -> tuple[float, float]:
    """The tree's joint values at φ on the scene's assembly (double precision, closed form)."""
    if isinstance(mech, FourBar):
        a = mech.crank * cmath.exp(1j * phi)
        c = complex(mech.ground)
        d = abs(c - a)
        e = (c - a) / d
        along = (mech.coupler**2 - mech.rocker**2 + d * d) / (2 * d)
        across = math.sqrt(max(mech.coupler**2 - along * along, 0.0))
        b = a + along * e - mech.mode * across * 1j * e  # as the reference: M = +1 puts B right of A→C
        return (cmath.phase(b - a) - phi, cmath.phase(b - c))
    b = mech.drum * cmath.exp(1j * phi)
    return (cmath.phase(b - mech.pivot), abs(b - mech.pivot))


def _wrap(x: float) -> float:
    y = math.remainder(x, 2.0 * math.pi)
    return math.pi if y == -math.pi else y


# ---------------------------------------------------------------- the 50-digit reference
def reference(mech: FourBar | Finger, phi: float) -> tuple[tuple[float, float], tuple[float, float]]:
    """Passive joints and their analogs d/dφ at φ, at 50 digits, rounded to float."""
    mp = _mp_reference().mp
    with mp.workdps(50):
        f = mp.mpf(phi)
        if isinstance(mech, FourBar):
            oa, ab, cb, g = (mp.mpf(str(x)) for x in (mech.crank, mech.coupler, mech.rocker, mech.ground))
            ax, ay = oa * mp.cos(f), oa * mp.sin(f)
            dx, dy = g - ax, -ay
            d = mp.hypot(dx, dy)
            ex, ey = dx / d, dy / d
            along = (ab**2 - cb**2 + d**2) / (2 * d)
            h2 = ab**2 - along**2
            if h2 < 0:
                raise ValueError(f"{mech.scene}: no assembly at φ = {phi!r}")
            across = mp.sqrt(h2)
            s = -mech.mode  # as tests/reference/mp_reference.py: M = +1 takes s = −1
            bx = ax + along * ex - s * across * ey
            by = ay + along * ey + s * across * ex
            t1, t2 = mp.atan2(by - ay, bx - ax), mp.atan2(by, bx - g)
            # differentiated closure: L1·j·e^{jθ₁}·θ₁' − L2·j·e^{jθ₂}·θ₂' = −j·OA·e^{jφ}
            u1 = (-ab * mp.sin(t1), ab * mp.cos(t1))
            u2 = (cb * mp.sin(t2), -cb * mp.cos(t2))
            rhs = (oa * mp.sin(f), -oa * mp.cos(f))
            det = u1[0] * u2[1] - u1[1] * u2[0]
            v1 = (rhs[0] * u2[1] - rhs[1] * u2[0]) / det
            v2 = (u1[0] * rhs[1] - u1[1] * rhs[0]) / det
            return (float(t1), float(t2)), (float(v1), float(v2))
        geo = _mp_reference().harvester_finger(f)
        bx, by = geo.points["B"]
        px, py = mp.mpf("0.04"), mp.mpf("-0.03")
        psi = mp.atan2(by - py, bx - px)
        s_len = mp.hypot(bx - px, by - py)
        # B' = j·R·e^{jφ} = s'·e^{jψ} + s·j·e^{jψ}·ψ'  →  s' = B'·e^{jψ}, ψ' = (B' × e^{jψ})/s … in components
        r = mp.mpf("0.20")
        bdx, bdy = -r * mp.sin(f), r * mp.cos(f)
        cx, cy = mp.cos(psi), mp.sin(psi)
        s_dot = bdx * cx + bdy * cy
        psi_dot = (cx * bdy - cy * bdx) / s_len
        return (float(psi), float(s_len)), (float(psi_dot), float(s_dot))


# ---------------------------------------------------------------- sequences
def sequences(quick: bool) -> dict[str, tuple[FourBar | Finger, list[float]]]:
    """Input sequences per case: ``{label: (mechanism, φ list)}``."""
    fine = 60 if quick else 3600
    jumps = 12 if quick else 108
    out: dict[str, tuple[FourBar | Finger, list[float]]] = {}
    for mech in (FOUR_BAR, HARVESTER):
        out[f"{mech.scene} 0.1° steps"] = (mech, [0.3 + k * 0.1 * DEG for k in range(fine)])
        for step in (10.0, 60.0, 90.0):  # jumps, as after dropped messages
            count = jumps if step == 10.0 else jumps // 3
            out[f"{mech.scene} {step:.0f}° steps"] = (mech, [0.3 * DEG + k * step * DEG for k in range(count)])
    toggle = math.acos(-0.40625)
    count = 12 if quick else 111
    deltas = [0.1 * 10.0 ** (-11.0 * k / (count - 1)) for k in range(count)]
    out[f"{DOUBLE_ROCKER.scene} toggle"] = (DOUBLE_ROCKER, [toggle - d for d in (*deltas, *reversed(deltas))])
    return out


# ---------------------------------------------------------------- measurement
@dataclass(frozen=True)
class Row:
    case: str
    method: str
    messages: int
    solve_us: float
    build_us: float
    position_error: float
    velocity_error: float
    lost: int
    note: str


def _ours(mech: FourBar | Finger, phis: Sequence[float], repeat: int) -> tuple[list[Any], float, float, str]:
    from linkage_ros.engine import Engine
    from linkage_ros.motion import Motion
    from linkage_ros.relay import Relay

    engine = Engine(mech.scene, Motion(phi0=phis[0], omega=1.0))
    name = engine.scene.input_joint
    builder, note = _builder(engine)
    best_solve = best_build = math.inf
    answers: list[Any] = []
    for _ in range(repeat):
        relay = Relay(engine)
        answers = []
        solve_s = build_s = 0.0
        clock = time.perf_counter
        for k, phi in enumerate(phis):
            stamp = NS + k * STAMP_STEP_NS
            t0 = clock()
            answer = relay.answer([name], [phi], [1.0], stamp)
            t1 = clock()
            if builder is not None and answer.frame is not None:
                builder(answer.frame, stamp)
            t2 = clock()
            solve_s += t1 - t0
            build_s += t2 - t1
            answers.append(answer)
        best_solve = min(best_solve, solve_s)
        best_build = min(best_build, build_s)
    n = len(phis)
    return answers, best_solve / n * 1e6, (best_build / n * 1e6 if builder else math.nan), note


def _builder(engine: Any) -> tuple[Callable[[Any, int], Any] | None, str]:
    """The node's message builder (all topics) with rosbags' Jazzy classes, if it can be made."""
    try:
        from rosbags.typesys import Stores, get_typestore

        from linkage_ros.messages import MessageBuilder

        builder = MessageBuilder(engine, get_typestore(Stores.ROS2_JAZZY).types, frame_id="world")
        return builder.build, "all topics, MessageBuilder"
    except Exception as error:  # the builder is being reworked (issue 11): report, do not fail
        return None, f"messages not timed: {error}"


def _joint_state_builder() -> Callable[[tuple[float, float], tuple[float, float], int], Any] | None:
    try:
        import numpy as np
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        return None
    t = get_typestore(Stores.ROS2_JAZZY).types
    JointState, Header = t["sensor_msgs/msg/JointState"], t["std_msgs/msg/Header"]
    Time = t["builtin_interfaces/msg/Time"]

    def build(q: tuple[float, float], dq: tuple[float, float], stamp: int) -> Any:
        sec, nsec = divmod(stamp, NS)
        return JointState(
            header=Header(stamp=Time(sec=sec, nanosec=nsec), frame_id="world"),
            name=["a", "b"],
            position=np.array(q),
            velocity=np.array(dq),
            effort=np.empty(0),
        )

    return build


def _anchor(
    mech: FourBar | Finger, phis: Sequence[float], repeat: int
) -> tuple[list[tuple[tuple[float, float], tuple[float, float], int]], float, float]:
    build = _joint_state_builder()
    best_solve = best_build = math.inf
    results: list[tuple[tuple[float, float], tuple[float, float], int]] = []
    for _ in range(repeat):
        gn = GaussNewton(mech, phis[0])
        results = []
        solve_s = build_s = 0.0
        clock = time.perf_counter
        for k, phi in enumerate(phis):
            t0 = clock()
            q, dq, n = gn.solve(phi, 1.0)
            t1 = clock()
            if build is not None:
                build(q, dq, NS + k * STAMP_STEP_NS)
            t2 = clock()
            solve_s += t1 - t0
            build_s += t2 - t1
            results.append((q, dq, n))
        best_solve = min(best_solve, solve_s)
        best_build = min(best_build, build_s)
    n = len(phis)
    return results, best_solve / n * 1e6, (best_build / n * 1e6 if build else math.nan)


def _errors(
    refs: Sequence[tuple[tuple[float, float], tuple[float, float]]],
    got: Sequence[tuple[tuple[float, float], tuple[float, float]] | None],
    *,
    angles: bool,
) -> tuple[float, float, int]:
    """Worst position error, worst relative velocity error and lost messages; ``angles``: the
    second joint is an angle (else a slide)."""
    pos = vel = 0.0
    lost = 0
    for (q_ref, v_ref), item in zip(refs, got):
        if item is None:
            lost += 1
            continue
        q, v = item
        e = max(abs(_wrap(q[0] - q_ref[0])), abs(_wrap(q[1] - q_ref[1]) if angles else q[1] - q_ref[1]))
        if not math.isfinite(e) or e > LOST:
            lost += 1
            continue
        pos = max(pos, e)
        for a, b in zip(v, v_ref):
            vel = max(vel, abs(a - b) / max(abs(b), 1.0))
    return pos, vel, lost


def run(*, quick: bool = False, repeat: int = 3) -> list[Row]:
    rows: list[Row] = []
    for case, (mech, phis) in sequences(quick).items():
        refs = [reference(mech, phi) for phi in phis]
        answers, solve_us, build_us, note = _ours(mech, phis, repeat)
        ours = []
        for a in answers:
            if a.frame is None:
                ours.append(None)
                continue
            j = [a.frame.joints[n] for n in mech.joints]
            ours.append(((j[0].position, j[1].position), (j[0].velocity, j[1].velocity)))
        angles = isinstance(mech, FourBar)
        pos, vel, lost = _errors(refs, ours, angles=angles)
        rows.append(Row(case, "ours (closed form)", len(phis), solve_us, build_us, pos, vel, lost, note))
        results, solve_us, build_us = _anchor(mech, phis, repeat)
        pos, vel, lost = _errors(refs, [(q, dq) for q, dq, _ in results], angles=angles)
        iterations = sum(n for _, _, n in results) / len(results)
        rows.append(Row(case, "Gauss–Newton (warm)", len(phis), solve_us, build_us, pos, vel, lost,
                        f"{iterations:.1f} iterations/message; one JointState"))
    return rows


def table(rows: Sequence[Row]) -> str:
    head = ("case", "method", "msgs", "solve µs", "msgs µs", "pos err", "vel err (rel)", "lost", "note")
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        lines.append(
            f"| {r.case} | {r.method} | {r.messages} | {r.solve_us:.1f} | {r.build_us:.1f} | "
            f"{r.position_error:.1e} | {r.velocity_error:.1e} | {r.lost} | {r.note} |"
        )
    return "\n".join(lines)


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="bench.relay", description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="a smoke run: few messages, one repetition")
    p.add_argument("--repeat", type=int, default=None, help="timing passes, best kept (default 3, --quick 1)")
    args = p.parse_args(argv)
    repeat = args.repeat if args.repeat is not None else (1 if args.quick else 3)
    rows = run(quick=args.quick, repeat=repeat)
    info = machine()
    print(f"# relay vs Gauss–Newton{' (--quick: a smoke run, not a measurement)' if args.quick else ''}")
    print(f"measured on {info['cpu']}, {info['cores']} cores, Python {info['python']}, load {info['load']}")
    print(table(rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
