"""One summary of a sweep or a run, read at a glance by a mechanism engineer (pure: numpy only).

``linkage-solve`` (a sweep over φ, or over a grid of several inputs) and ``linkage-run`` (ticks on
simulated time) all describe their outputs with :func:`summary_lines`, in one vocabulary:

* **position**, **velocity**, **acceleration** for points and joints alike;
* angles (φ, joint angles) in degrees, everything else SI (m, m/s, m/s², rad/s, rad/s²); an
  actuator's stroke input s in m (its rates m/s, m/s²: ``Sweep.units``);
* a joint angle is unwrapped over the samples: a joint that turns a whole revolution is said to
  make a "full turn" (with the net angle), one that swings back and forth gives its range; over a
  grid of several inputs (samples in no order) the range is the shortest arc holding them all;
* a quantity that does not change over the samples is said to be "constant" (never "a maximum at
  an arbitrary φ"), one within rounding of zero "zero"; a maximum that does vary is given with the
  φ (and t) where it occurs;
* extremes are refined to the closed form where the output can be evaluated at any φ
  (:class:`Output` ``evaluate``; :mod:`solver._extremes`); those that are not are said to be read
  off the samples (a note, or ``≈`` where only some are);
* an input joint is one line of position (its velocity and acceleration are the law in the heading);
* every point and joint carries its one-line description from the scene (``descriptions:``).

The summary is a list of sections (:data:`SECTIONS`, then the caller's ``sections``): each a
function of the :class:`Sweep` returning lines, so more (forces, …) are added without touching
these. The CSV and the API are unchanged (SI, rad): this is text for people.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ._extremes import Evaluate, Extreme, Quantity, extreme
from .tolerances import ZERO_TO_ROUNDING

__all__ = [
    "Output", "Sweep", "Section", "SECTIONS", "summary_lines", "motion_line", "format_phi", "provenance_lines",
    "CONSTANT_RTOL",
    "ZERO_RTOL",
]

TWO_PI = 2.0 * math.pi
AXES = "xyz"
#: A quantity whose spread over the samples is at most this fraction of its magnitude (plus
#: rounding) is "constant": 1e-9 is ~10⁷ ulps, far above rounding and far below any real variation.
CONSTANT_RTOL = 1e-9
#: A rate whose largest value is at most this fraction of the largest of its kind in the same
#: summary (joint velocities against joint velocities, …) is rounding noise about zero ("zero").
ZERO_RTOL = ZERO_TO_ROUNDING  # (solver.tolerances)
#: A net joint rotation within this of a whole number of turns (relative) is that many full turns.
TURN_RTOL = 1e-6


@dataclass(frozen=True)
class Output:
    """One output over the samples: a point ((N, dim) arrays) or a joint ((N,) arrays).

    ``evaluate``: the output at any φ (one input; NaN where not assemblable), to refine extremes.
    """

    name: str
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    unit: str = "m"  # a joint's unit: "rad" or "m"; points are "m"
    description: str = ""
    evaluate: Evaluate | None = None


@dataclass(frozen=True)
class Sweep:
    """The samples to summarise.

    ``phi`` in rad, (N,) or (N, k) for k inputs named by ``inputs``; ``t`` in s for a run on time
    (None for a sweep); ``periodic`` when the samples are one whole turn of the input with the last
    wrapping to the first (linkage-solve's default grid), so a joint's net rotation over the turn
    includes the closing step; ``wraps``: the samples are taken from one turn that wraps (even if
    some are missing), ``gaps``: (N,) True after a sample whose successor is missing (not
    assemblable), ``edges``: (N, 2) the exact φ where the gap before / after a sample begins (NaN
    where none) — for refining extremes; ``sampling``: how the samples were taken, for
    the note on extremes that are read off them (default: from ``t`` or the step of ``phi``).
    """

    phi: np.ndarray
    points: Sequence[Output] = ()
    joints: Sequence[Output] = ()
    t: np.ndarray | None = None
    periodic: bool = False
    extra: Mapping[str, str] = field(default_factory=dict)
    inputs: Sequence[str] = ()
    wraps: bool = False
    gaps: np.ndarray | None = None
    edges: np.ndarray | None = None
    sampling: str | None = None
    #: each input's unit, in the order of ``inputs``: "rad" (an angle, the default) or "m" (a stroke)
    units: Sequence[str] = ()


#: A section of the summary: lines from the sweep.
Section = Callable[[Sweep], list[str]]


def format_phi(phi: Any, inputs: Sequence[str] = (), units: Sequence[str] = ()) -> str:
    """φ as an angle in the turn, degrees in [0, 360) (a stroke, ``units`` "m": in m); several
    inputs as a tuple of them."""
    if np.ndim(phi):
        values = np.asarray(phi, float).reshape(-1)
        unit = list(units) if len(units) == len(values) else ["rad"] * len(values)
        if len(inputs) == len(values):
            return "(" + ", ".join(f"{q} = {format_phi(p, units=(u,))}" for q, p, u in zip(inputs, values, unit)) + ")"
        return "(" + ", ".join(format_phi(p, units=(u,)) for p, u in zip(values, unit)) + ")"
    if tuple(units) == ("m",):
        return f"{float(phi):.4f} m"
    deg = math.degrees(float(phi)) % 360.0
    return f"{0.0 if round(deg, 2) == 360.0 else deg:.2f}°"


def provenance_lines(provenance: str) -> list[str]:
    """The first sentence of a scene's provenance, in parentheses (none without one)."""
    if not provenance:
        return []
    first = _SENTENCE_END.split(provenance, maxsplit=1)[0].rstrip(".")
    return [f"  ({first}.)"]


#: The end of a sentence: a full stop and a space, not after "i.e", "e.g" or "cf".
_SENTENCE_END = re.compile(r"(?<!\bi\.e)(?<!\be\.g)(?<!\bcf)\.\s")


def motion_line(omega: float, epsilon: float, unit: str = "rad") -> str:
    """What ω and ε mean for the numbers that follow (``unit`` "m": a stroke's ṡ and s̈)."""
    if unit == "m":
        text = f"ṡ = {omega:g} m/s, s̈ = {epsilon:g} m/s²"
        if omega == 1.0 and epsilon == 0.0:
            text += " (velocities and accelerations are the analogs d/ds, d²/ds², per m of the stroke)"
        return text + "; angles in degrees, everything else SI"
    text = f"ω = {omega:g} rad/s, ε = {epsilon:g} rad/s²"
    if omega == 1.0 and epsilon == 0.0:
        text += (" (at 1 rad/s the velocities and accelerations below, in m/s and m/s², are also the analogs "
                 "d/dφ, d²/dφ² in m/rad and m/rad²)")
    elif omega != 0.0 and epsilon == 0.0:
        text += f" ({abs(omega) / TWO_PI:.4g} turn/s)"
    return text + "; angles in degrees, everything else SI"


class _Context:
    """One pass of formatting: the sweep, each output's extremes (found once), and whether any
    is read off the samples (so that the notes say so)."""

    def __init__(self, sweep: Sweep) -> None:
        self.sweep = sweep
        self.cache: dict[tuple[str, str, bool], Extreme] = {}
        self.mark = False  # write ≈ before the extremes read off the samples
        self.scales = _scales(sweep)

    def find(self, out: Output, key: str, values: np.ndarray, quantity: Quantity, *, largest: bool) -> Extreme:
        slot = (out.name, key, largest)
        if slot not in self.cache:
            s = self.sweep
            self.cache[slot] = extreme(
                values, largest=largest, phi=None if s.t is not None else s.phi, evaluate=out.evaluate,
                quantity=quantity, periodic=s.wraps, gaps=s.gaps, edges=s.edges)
        return self.cache[slot]

    def approx(self, e: Extreme) -> str:
        return "≈" if self.mark and not e.exact else ""

    def where(self, e: Extreme) -> str:
        s = self.sweep
        if s.t is not None:
            where = _phi_text(s, s.phi[e.sample])
            return f"at t = {float(s.t[e.sample]):.4g} s {where if where.startswith('(') else f'({where})'}"
        return f"at {_phi_text(s, s.phi[e.sample] if e.phi is None else e.phi)}"


def _phi_text(sweep: Sweep, phi: Any) -> str:
    if np.ndim(phi):
        return format_phi(phi, sweep.inputs, sweep.units)
    return f"s = {format_phi(phi, units=sweep.units)}" if tuple(sweep.units) == ("m",) else f"φ = {format_phi(phi)}"


def _scales(sweep: Sweep) -> dict[str, float]:
    """What "large" is for each kind of rate ("point m v", "joint rad a", …; inputs left out): the
    largest |rate| of the kind, and for accelerations at least v²/L (L the largest |position| in
    m, 1 for angles), so that a kind that is all rounding noise is still measured against its
    scale (a parallelogram's coupler turns at 1e-13 rad/s² while its rocker turns at 1 rad/s)."""
    out: dict[str, float] = {}
    length = 0.0
    for outputs, kind in ((sweep.points, "point"), (sweep.joints, "joint")):
        for o in outputs:
            if o.name in sweep.inputs:
                continue
            if o.unit == "m":
                p = np.abs(np.asarray(o.position, float))
                length = max(length, float(p[np.isfinite(p)].max(initial=0.0)))
            for what, arr in (("v", o.velocity), ("a", o.acceleration)):
                a = np.abs(np.asarray(arr, float))
                key = f"{kind} {o.unit} {what}"
                out[key] = max(out.get(key, 0.0), float(a[np.isfinite(a)].max(initial=0.0)))
    for key in [k for k in out if k.endswith(" a")]:
        unit = key.split()[1]
        span = 1.0 if unit == "rad" else length
        if span > 0.0:
            out[key] = max(out[key], out.get(key[:-1] + "v", 0.0) ** 2 / span)
    return out


def _constant(values: np.ndarray) -> bool:
    if values.size == 0:
        return True
    lo, hi = float(values.min()), float(values.max())
    scale = max(abs(lo), abs(hi))
    return hi - lo <= CONSTANT_RTOL * scale + 1e-300


def _norm(kind: str) -> Quantity:
    def magnitude(p: np.ndarray, v: np.ndarray, a: np.ndarray) -> np.ndarray:
        x = np.asarray(v if kind == "v" else a, float)
        return np.linalg.norm(x, axis=-1) if x.ndim > 1 else np.abs(x)

    return magnitude


def _magnitude_line(ctx: _Context, out: Output, kind: str, label: str, symbol: str, unit: str) -> str:
    """``velocity: max |v| = … at φ = …``, ``… constant …`` or ``zero``."""
    raw = np.asarray(out.velocity if kind == "v" else out.acceleration, float)
    values = np.linalg.norm(raw, axis=-1) if raw.ndim > 1 else np.abs(raw)
    finite = values[np.isfinite(values)]
    if values.size == 0 or not finite.size:
        return f"    {label}: no finite value"
    top = float(finite.max())
    if top == 0.0:
        return f"    {label}: zero"
    scale = ctx.scales.get(f"{'point' if raw.ndim > 1 else 'joint'} {out.unit} {kind}", top)
    if top <= ZERO_RTOL * scale:
        return f"    {label}: zero to rounding (at most {top:.2g} {unit})"
    if _constant(finite):
        return f"    {label}: {symbol} constant {top:.6g} {unit}"
    e = ctx.find(out, kind, values, _norm(kind), largest=True)
    if math.isinf(e.value):  # a toggle at the edge of an unassemblable range
        return f"    {label}: {symbol} grows without bound toward the gap's edge at {_phi_text(ctx.sweep, e.phi)}"
    return f"    {label}: max {symbol} {ctx.approx(e) or '='} {e.value:.6g} {unit} {ctx.where(e)}"


def _span(
    ctx: _Context, out: Output, key: str, values: np.ndarray, quantity: Quantity
) -> tuple[str, str, float, float]:
    lo = ctx.find(out, key, values, quantity, largest=False)
    hi = ctx.find(out, key, values, quantity, largest=True)
    return ctx.approx(lo), ctx.approx(hi), lo.value + 0.0, hi.value + 0.0


def _range(ctx: _Context, out: Output, key: str, values: np.ndarray, quantity: Quantity, unit: str) -> str:
    finite = values[np.isfinite(values)]
    if _constant(finite):
        return f"constant {float(finite.min()) + 0.0:.6g} {unit}"
    a, b, lo, hi = _span(ctx, out, key, values, quantity)
    return f"{a}{lo:.6g} … {b}{hi:.6g} {unit}"


def _title(kind: str, out: Output, suffix: str = "") -> str:
    return f"  {kind} {out.name}" + (f" — {out.description}" if out.description else "") + suffix


def _coordinate(i: int) -> Quantity:
    return lambda p, v, a: p[:, i]


def _point_lines(ctx: _Context, p: Output) -> list[str]:
    pos = np.asarray(p.position, float)
    dim = pos.shape[1] if pos.ndim == 2 else 1
    coords = ", ".join(f"{a} {_range(ctx, p, a, pos[:, i], _coordinate(i), 'm')}" for i, a in enumerate(AXES[:dim]))
    return [
        _title("point", p),
        f"    position: {coords}",
        _magnitude_line(ctx, p, "v", "velocity", "speed |v|", "m/s"),
        _magnitude_line(ctx, p, "a", "acceleration", "|a|", "m/s²"),
    ]


def _turns(sweep: Sweep, q: np.ndarray) -> tuple[float, np.ndarray]:
    """The net rotation over the samples (rad; over the whole turn when periodic) and q unwrapped."""
    u = np.unwrap(q)
    net = float(u[-1] - u[0])
    if sweep.periodic and q.size > 1:
        net += math.remainder(float(q[0] - q[-1]), TWO_PI)
    return net, u


def _near(ref: float) -> Quantity:
    """A joint angle as the value within half a turn of ``ref`` (the unwrapped sample)."""
    return lambda p, v, a: ref + np.remainder(np.asarray(p, float) - ref + math.pi, TWO_PI) - math.pi


def _arc(q: np.ndarray) -> tuple[float, float, float]:
    """The shortest arc holding every angle of ``q`` (samples in no order): start, end (rad,
    start in (−π, π]) and the largest gap between samples."""
    s = np.sort(np.mod(q, TWO_PI))
    steps = np.diff(np.concatenate([s, s[:1] + TWO_PI]))
    j = int(np.argmax(steps))
    start = float(s[(j + 1) % len(s)])
    start = start - TWO_PI if start > math.pi else start
    return start, start + TWO_PI - float(steps[j]), float(steps[j])


def _median_gap(q: np.ndarray) -> float:
    s = np.unique(np.mod(q, TWO_PI))
    return float(np.median(np.diff(np.concatenate([s, s[:1] + TWO_PI])))) if s.size > 1 else TWO_PI


def _angle_position(ctx: _Context, j: Output, q: np.ndarray) -> str:
    sweep = ctx.sweep
    if _constant(q) or float(np.ptp(q)) <= ZERO_RTOL:  # (rounding noise on an angle of order 1 rad)
        return f"constant {math.degrees(float(np.mean(q))) + 0.0:.4f}°"
    if np.ndim(sweep.phi) > 1 and sweep.t is None:  # a grid: no order to unwrap along
        if j.name in sweep.inputs:
            return f"{math.degrees(float(q.min())):.2f}° … {math.degrees(float(q.max())):.2f}° (the samples' values)"
        lo, hi, gap = _arc(q)
        if gap <= 1.5 * _median_gap(q):  # spread round the whole circle
            return f"takes every direction over the samples (the largest gap between them {math.degrees(gap):.2f}°)"
        return f"swings {math.degrees(lo):.2f}° … {math.degrees(hi):.2f}° (a range of {math.degrees(hi - lo):.2f}°)"
    net, u = _turns(sweep, q)
    k = round(net / TWO_PI)
    # a joint that turns takes every angle: its unwrapped span is where the samples start and end
    lo, hi = math.degrees(float(u.min())), math.degrees(float(u.max()))
    if k != 0 and abs(net - k * TWO_PI) <= TURN_RTOL * abs(net):
        per = " per turn of the input" if sweep.periodic else " over the run" if sweep.t is not None else ""
        what = "a full turn" if abs(k) == 1 else f"{abs(k)} full turns"
        return f"makes {what}{per} ({math.degrees(net):+.1f}°; the samples unwrapped {lo:.2f}° … {hi:.2f}°)"
    if abs(net) >= TWO_PI:
        return f"turns {math.degrees(net):+.1f}° over the samples (unwrapped {lo:.2f}° … {hi:.2f}°)"
    lo_e = ctx.find(j, "q", u, _near(float(u[int(np.argmin(u))])), largest=False)
    hi_e = ctx.find(j, "q", u, _near(float(u[int(np.argmax(u))])), largest=True)
    a, b = ctx.approx(lo_e), ctx.approx(hi_e)
    lo, hi = math.degrees(lo_e.value), math.degrees(hi_e.value)
    return f"swings {a}{lo:.2f}° … {b}{hi:.2f}° (a range of {hi - lo:.2f}°)"


def _joint_lines(ctx: _Context, j: Output) -> list[str]:
    q = np.asarray(j.position, float)
    if j.unit == "rad":
        position = _angle_position(ctx, j, q)
        rate, acc = "rad/s", "rad/s²"
    else:
        position = _range(ctx, j, "q", q, lambda p, v, a: np.asarray(p, float), j.unit)
        rate, acc = f"{j.unit}/s", f"{j.unit}/s²"
    if j.name in ctx.sweep.inputs:  # its velocity and acceleration are the law in the heading
        return [_title("joint", j, " (an input)"), f"    position: {position}"]
    return [
        _title("joint", j),
        f"    position: {position}",
        _magnitude_line(ctx, j, "v", "velocity", "|velocity|", rate),
        _magnitude_line(ctx, j, "a", "acceleration", "|acceleration|", acc),
    ]


def points_section(sweep: Sweep, ctx: _Context | None = None) -> list[str]:
    """Per point: position ranges, the largest speed and acceleration and where they occur."""
    ctx = ctx or _Context(sweep)
    return [line for p in sweep.points for line in _point_lines(ctx, p)]


def joints_section(sweep: Sweep, ctx: _Context | None = None) -> list[str]:
    """Per joint: its motion (full turn, swing, range), velocity and acceleration."""
    ctx = ctx or _Context(sweep)
    return [line for j in sweep.joints for line in _joint_lines(ctx, j)]


#: The summary's own sections, in order.
SECTIONS: tuple[Callable[[Sweep, _Context], list[str]], ...] = (points_section, joints_section)


def sampling_of(sweep: Sweep) -> str:
    """How the samples were taken, in words, for the note on extremes read off them."""
    if sweep.sampling:
        return sweep.sampling
    if sweep.t is not None and len(sweep.t) > 1:
        return f"the ticks (every {float(np.median(np.diff(sweep.t))):.4g} s)"
    phi = np.asarray(sweep.phi, float)
    if phi.ndim == 1 and len(phi) > 1:
        steps = np.diff(phi)
        if np.allclose(steps, steps[0], rtol=1e-9, atol=0.0) and steps[0] > 0:
            if tuple(sweep.units) == ("m",):
                return f"the samples (every {float(steps[0]):.4g} m)"
            return f"the samples (every {math.degrees(float(steps[0])):.4g}°)"
    return "the samples"


def summary_lines(sweep: Sweep, *, sections: Sequence[Section] = ()) -> list[str]:
    """Per point: position ranges, velocity and acceleration magnitudes; per joint: its motion;
    then each of ``sections``. A note says which extremes are read off the samples."""
    if np.asarray(sweep.phi).size == 0:
        return ["  no samples"]
    ctx = _Context(sweep)
    for own in SECTIONS:  # a first pass finds every extreme: the notes depend on them all
        own(sweep, ctx)
    found = list(ctx.cache.values())
    sampled = sum(not e.exact for e in found)
    ctx.mark = 0 < sampled < len(found)
    lines: list[str] = []
    if sampled and not ctx.mark:
        lines.append(f"  extremes read off {sampling_of(sweep)}")
    elif ctx.mark:
        lines.append(f"  ≈: an extreme read off {sampling_of(sweep)} (beside a gap, or not finite around it); "
                     "the others are exact (refined in closed form)")
    for own in SECTIONS:
        lines += own(sweep, ctx)
    for section in sections:
        lines += section(sweep)
    return lines
