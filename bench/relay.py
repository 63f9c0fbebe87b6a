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

Three rows per case (:data:`METHODS`), each ending in CDR bytes, as a node sends them:

* ``ours (node path)``: what mechanism_node does per incoming JointState in topic mode,
  :meth:`linkage_ros.runtime.Runtime.answer` (rosbags' Jazzy classes, no rclpy): the relay reads
  the input state off the message (ω from the message, ε = 0), then the generated tick of
  ``linkage_ros/instant.py`` — one function: the scene's compiled instant (every point and joint
  with velocities, accelerations and conditioning), its guards, the URDF tree joints, one
  ``struct`` pack per topic from the byte templates of ``linkage_ros/serialize.py`` (the Frame
  path where a guard hands the instant back; diagnostics and path markers, when due, the Frame
  way). "solve" is the time in ``Relay.read`` and the generated tick (or the Frame path's
  solve); "messages" the rest (the runtime's bookkeeping; the Frame path's bytes).
* ``ours, joint_states only``: the same read, then the generated tick for the node's
  joint_states alone (the same compiled call and guards, the passive scene joints and the URDF
  tree's joints, the efforts in scenes with forces; one pack); the run checks they are the
  node's joint_states bytes, message for message. This is the Gauss–Newton row's output, so the
  two rows compare like for like.
* ``Gauss–Newton (warm)``: the anchor's solve, then the bytes of one JointState of its two joints
  (:class:`JointStateBytes`, the same packing).

Timing: mean µs per message over the sequence (``perf_counter`` around each part), after
:data:`WARMUP` untimed messages, best of ``--repeat`` passes.

Errors: the passive joints (four-bar: coupler and rocker angles; harvester: finger angle and
eyelet slide), read back from each row's joint_states bytes, against a 50-digit reference:
positions from the closed-form geometry in mpmath (tests/reference/mp_reference.py for the
harvester finger; the same circle intersection for the four-bars), velocity analogs by solving
the differentiated closure at 50 digits. Angles in rad, slides in m; velocities relative to
max(|v_ref|, 1)·|ω|. "lost" counts messages whose position error exceeds ``LOST`` (another
assembly mode, or no convergence).

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
import struct
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:  # `python bench/relay.py` as well as `python -m bench.relay`
    sys.path.insert(0, str(ROOT))

from bench._common import _mp_reference, machine  # noqa: E402

__all__ = ["GAUSS_NEWTON", "GN_MAX_ITERATIONS", "GN_STEP_TOL", "METHODS", "NODE_PATH", "OURS_JOINT_STATES",
           "JointStateBytes", "Row", "main", "run"]

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


# ---------------------------------------------------------------- CDR bytes of one JointState
_SEC, _NSEC = 0x3A5B7C1D, 0x2C4D6E1F  # sentinel stamp (sec, nanosec)


def _sentinel(i: int) -> float:
    value: float = struct.unpack("<d", struct.pack("<Q", 0x7A5A_0000_0000_A5A5 | (i + 1) << 16))[0]
    return value


class JointStateBytes:
    """CDR bytes of a ``sensor_msgs/JointState`` with fixed ``names`` (empty effort), as the node
    sends them: one :class:`struct.Struct` compiled from rosbags' serialiser on a probe whose
    numbers are sentinels, padded to 4 bytes (the technique of ``linkage_ros/serialize.py``, written
    here so that both "joint_states only" rows render one message the same, cheapest way).
    Checked once against ``serialize_cdr`` when made."""

    def __init__(self, names: Sequence[str], *, frame_id: str = "world") -> None:
        import numpy as np

        from linkage_ros.serialize import pad4

        store = _typestore()
        self._store = store
        self._JointState = store.types["sensor_msgs/msg/JointState"]
        self._Header, self._Time = store.types["std_msgs/msg/Header"], store.types["builtin_interfaces/msg/Time"]
        self.names, self.frame_id, self._np = list(names), frame_id, np
        n = len(self.names)
        typename = self._JointState.__msgtype__
        probe = self._message(_SEC * NS + _NSEC, [_sentinel(i) for i in range(2 * n)][:n],
                              [_sentinel(i) for i in range(2 * n)][n:])
        raw = pad4(store.serialize_cdr(probe, typename))
        # (offset, struct code, index into (sec, nsec, *q, *dq))
        slots = [(raw.index(struct.pack("<i", _SEC)), "i", 0), (raw.index(struct.pack("<I", _NSEC)), "I", 1)]
        slots += [(raw.index(struct.pack("<d", _sentinel(i))), "d", 2 + i) for i in range(2 * n)]
        self._args: list[int | bytes] = []  # an int picks a number, bytes are a constant run
        fmt, pos = ["<"], 0
        for off, code, k in sorted(slots):
            if off > pos:
                fmt.append(f"{off - pos}s")
                self._args.append(raw[pos:off])
            fmt.append(code)
            self._args.append(k)
            pos = off + (8 if code == "d" else 4)
        if pos < len(raw):
            fmt.append(f"{len(raw) - pos}s")
            self._args.append(raw[pos:])
        self._struct = struct.Struct("".join(fmt))
        q, dq = [0.5 + i for i in range(n)], [-0.25 * i for i in range(n)]
        if self.pack(1_234_567_891_011, q, dq) != pad4(store.serialize_cdr(self._message(1_234_567_891_011, q, dq),
                                                                           typename)):
            raise RuntimeError("JointStateBytes: the template does not reproduce serialize_cdr")

    def _message(self, stamp_ns: int, q: Sequence[float], dq: Sequence[float]) -> Any:
        sec, nsec = divmod(stamp_ns, NS)
        return self._JointState(
            header=self._Header(stamp=self._Time(sec=sec, nanosec=nsec), frame_id=self.frame_id),
            name=self.names, position=self._np.array(q, dtype=float), velocity=self._np.array(dq, dtype=float),
            effort=self._np.empty(0),
        )

    def pack(self, stamp_ns: int, q: Sequence[float], dq: Sequence[float]) -> bytes:
        """The bytes of the message stamped ``stamp_ns`` with positions ``q``, velocities ``dq``."""
        numbers = (*divmod(stamp_ns, NS), *q, *dq)
        return self._struct.pack(*[numbers[a] if isinstance(a, int) else a for a in self._args])

    def decode(self, data: bytes) -> dict[str, tuple[float, float]]:
        """``{name: (position, velocity)}`` of JointState bytes (rosbags' deserialiser)."""
        msg = self._store.deserialize_cdr(data, self._JointState.__msgtype__)
        return {n: (float(q), float(v)) for n, q, v in zip(msg.name, msg.position, msg.velocity)}


def _typestore() -> Any:
    from rosbags.typesys import Stores, get_typestore

    return get_typestore(Stores.ROS2_JAZZY)


# ---------------------------------------------------------------- measurement
#: The rows of each case, in order.
NODE_PATH = "ours (node path)"
OURS_JOINT_STATES = "ours, joint_states only"
GAUSS_NEWTON = "Gauss–Newton (warm)"
METHODS = (NODE_PATH, OURS_JOINT_STATES, GAUSS_NEWTON)
#: Untimed messages at the first φ before each timed sequence (every method).
WARMUP = 8


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

    @property
    def total_us(self) -> float:
        """Mean µs per message, solve and messages."""
        return self.solve_us + self.build_us


#: One timed pass: ``(solve s, messages s, [joint_states bytes or None per message])``.
_Pass = tuple[float, float, list[bytes | None]]


class _Timed:
    """A callable with the time spent in it added up."""

    def __init__(self, fn: Any) -> None:
        self.fn = fn
        self.seconds = 0.0

    def __call__(self, *args: Any) -> Any:
        t0 = time.perf_counter()
        result = self.fn(*args)
        self.seconds += time.perf_counter() - t0
        return result


def _runtime(mech: FourBar | Finger, phis: Sequence[float]) -> Any:
    """mechanism_node's runtime in topic mode (rosbags' Jazzy classes, no rclpy), warmed up by
    :data:`WARMUP` messages at ``phis[0]`` stamped before the sequence (the byte templates are
    compiled and checked on the first, the fast path bound and checked on the next), and the
    compiled instant run once over the sequence (it traces each branch it meets once, a one-off
    cost of the scene, not of a message)."""
    from linkage_ros.runtime import Runtime

    store = _typestore()
    runtime = Runtime({"scene": mech.scene, "input_source": "topic", "phi0": phis[0]}, store.types,
                      serialize=store.serialize_cdr)
    assert runtime.relay is not None
    for k in range(WARMUP, 0, -1):
        runtime.answer([runtime.relay.input_joint], [phis[0]], [1.0], NS - k * STAMP_STEP_NS)
    path = runtime._fast_path
    if path is not None:
        for phi in phis:  # the compiled code traces each branch once
            path.solve(phi, 1.0, 0.0)
    return runtime


def _node_path(mech: FourBar | Finger, phis: Sequence[float]) -> tuple[_Pass, int]:
    """``Runtime.answer`` per message: the relay reads the input state, the generated tick
    solves it and packs every topic (the fast path; the Frame path where it hands back), then
    the CDR bytes of every topic. "solve" = the relay's read + the generated tick (its solve and
    packs: one function) or, where it hands back, the Frame path's solve."""
    runtime = _runtime(mech, phis)
    name = runtime.relay.input_joint
    path = runtime._fast_path
    timers = [_Timed(runtime.relay.read), _Timed(runtime.relay.solve)]
    runtime.relay.read, runtime.relay.solve = timers
    if path is not None:
        timers.append(_Timed(path.solve))
        path.solve = timers[-1]
        if path._emit is not None:
            timers.append(_Timed(path._emit))
            path._emit = timers[-1]
    out: list[bytes | None] = []
    clock = time.perf_counter
    total = 0.0
    for k, phi in enumerate(phis):
        t0 = clock()
        messages = runtime.answer([name], [phi], [1.0], NS + k * STAMP_STEP_NS)
        total += clock() - t0
        out.append(dict(messages).get("joint_states"))
    solve = sum(t.seconds for t in timers)
    return (solve, total - solve, out), len(runtime.topics)


def _joint_states_only(mech: FourBar | Finger, phis: Sequence[float]) -> _Pass:
    """The same read, then the node's joint_states bytes alone: the generated tick for that one
    topic (:meth:`linkage_ros.instant.FastPath.emitter`: the same compiled call, guards, tree
    joints and efforts, one pack); the Frame path where it hands back. "solve" = read + the
    generated tick (solve and bytes in one function), "messages" = the Frame path's bytes."""
    runtime = _runtime(mech, phis)
    relay, path = runtime.relay, runtime._fast_path
    assert relay is not None and path is not None
    name = relay.input_joint
    emit = path.emitter(["joint_states"])
    assert emit is not None, "no generated tick"
    out: list[bytes | None] = []
    clock = time.perf_counter
    solve_s = build_s = 0.0
    for k, phi in enumerate(phis):
        stamp = NS + k * STAMP_STEP_NS
        t0 = clock()
        reading = relay.read([name], [phi], [1.0], stamp)
        messages = emit(reading.phi, reading.omega, reading.epsilon, stamp)
        frame = None if messages is not None else relay.solve(reading).frame  # the Frame path
        t1 = clock()
        data = None
        if messages is not None:
            data = messages[0][1]
        elif frame is not None:
            data = dict(runtime.wire.render(frame, stamp, diagnostics=False))["joint_states"]
        t2 = clock()
        solve_s += t1 - t0
        build_s += t2 - t1
        out.append(data)
    return solve_s, build_s, out


def _gauss_newton(mech: FourBar | Finger, phis: Sequence[float], iterations: list[int]) -> _Pass:
    """Warm-started Gauss–Newton, then the bytes of one JointState of its two joints."""
    packer = JointStateBytes(mech.joints)
    warm = GaussNewton(mech, phis[0])  # the same warm-up as ours, on a throwaway solver
    for k in range(WARMUP):
        packer.pack(NS - k * STAMP_STEP_NS, *warm.solve(phis[0], 1.0)[:2])
    gn = GaussNewton(mech, phis[0])
    out: list[bytes | None] = []
    clock = time.perf_counter
    solve_s = build_s = 0.0
    iterations.clear()
    for k, phi in enumerate(phis):
        t0 = clock()
        q, dq, n = gn.solve(phi, 1.0)
        t1 = clock()
        data = packer.pack(NS + k * STAMP_STEP_NS, q, dq)
        t2 = clock()
        solve_s += t1 - t0
        build_s += t2 - t1
        out.append(data)
        iterations.append(n)
    return solve_s, build_s, out


def _best(passes: Sequence[_Pass], n: int) -> tuple[float, float, list[bytes | None]]:
    """Best-of-passes mean µs per message (solve, messages) and the last pass's bytes."""
    return (min(p[0] for p in passes) / n * 1e6, min(p[1] for p in passes) / n * 1e6, passes[-1][2])


def _published(mech: FourBar | Finger, data: Sequence[bytes | None]) -> list[Any]:
    """The passive joints (positions, velocities) read back from the joint_states bytes."""
    decode = JointStateBytes(mech.joints).decode
    out: list[Any] = []
    for item in data:
        if item is None:
            out.append(None)
            continue
        joints = decode(item)
        a, b = (joints[n] for n in mech.joints)
        out.append(((a[0], b[0]), (a[1], b[1])))
    return out


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


def _row(case: str, method: str, mech: FourBar | Finger, refs: Sequence[Any],
         timed: tuple[float, float, list[bytes | None]], note: str) -> Row:
    pos, vel, lost = _errors(refs, _published(mech, timed[2]), angles=isinstance(mech, FourBar))
    return Row(case, method, len(refs), timed[0], timed[1], pos, vel, lost, note)


def run(*, quick: bool = False, repeat: int = 3) -> list[Row]:
    """Three rows per case, in the order of :data:`METHODS`."""
    rows: list[Row] = []
    for case, (mech, phis) in sequences(quick).items():
        n = len(phis)
        refs = [reference(mech, phi) for phi in phis]
        node_passes = [_node_path(mech, phis) for _ in range(repeat)]
        topics = node_passes[0][1]
        node = _best([p for p, _ in node_passes], n)
        rows.append(_row(case, NODE_PATH, mech, refs, node, f"Runtime.answer: CDR bytes of all {topics} topics"))
        js = _best([_joint_states_only(mech, phis) for _ in range(repeat)], n)
        same = sum(a is not None and a == b for a, b in zip(js[2], node[2]))
        joints = len(JointStateBytes(mech.joints).decode(next(b for b in js[2] if b is not None)))
        rows.append(_row(case, OURS_JOINT_STATES, mech, refs, js,
                         f"one JointState of {joints} joints; bytes = the node's in {same}/{n}"))
        iterations: list[int] = []
        gn = _best([_gauss_newton(mech, phis, iterations) for _ in range(repeat)], n)
        rows.append(_row(case, GAUSS_NEWTON, mech, refs, gn,
                         f"{sum(iterations) / n:.1f} iterations/message (max {max(iterations)}); "
                         "one JointState of 2 joints"))
    return rows


HEADER = """\
Rows per case (mean µs per message over the sequence, best of the passes):
  ours (node path)        what mechanism_node does per incoming JointState in topic mode:
                          Runtime.answer = Relay.read + the generated tick (the compiled instant:
                          every point and joint, velocities, accelerations, conditioning; tree
                          joints; one pack per topic) (diagnostics and path markers when due);
                          "solve" is read + the generated tick, "msgs" the runtime's rest.
  ours, joint_states only the same read + the generated tick for the node's joint_states alone,
                          what the Gauss–Newton row outputs: one JointState (ours: the passive
                          scene joints and the URDF tree's joints, the node's own bytes, solve
                          and pack in one function, all under "solve"; Gauss–Newton: 2 joints).
  Gauss–Newton (warm)     the anchor: warm-started Gauss–Newton on the cut joint + the CDR bytes
                          of one JointState of its two joints (same template technique).
Errors: the passive joints read back from the joint_states bytes, against the 50-digit
reference; "lost": position error > 1e-6 (another assembly, or no convergence).
The closed form's cost per message does not depend on the step (no state, no iterations);
Gauss–Newton's grows with the step and near a toggle (iterations/message in the note), and on
large jumps its warm start can land on the other assembly ("lost"). Near the toggle ours costs
more too: the singular analysis runs for near-singular samples."""


def table(rows: Sequence[Row]) -> str:
    head = ("case", "method", "msgs", "solve µs", "msgs µs", "total µs", "pos err", "vel err (rel)", "lost",
            "note")
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        lines.append(
            f"| {r.case} | {r.method} | {r.messages} | {r.solve_us:.1f} | {r.build_us:.1f} | {r.total_us:.1f} | "
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
    print(HEADER)
    print(table(rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
