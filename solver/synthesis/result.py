"""What a synthesis returns: every distinct design found, each checked by solving its own scene.

A design is checked the way a user would check it: its free values are written into the
template, the file is loaded as any scene (:meth:`Template.scene`), solved at its phases, and
its misses are measured on that solve; it must assemble over the input's whole required range
with every dyad's transmission angle above the limit (a sweep of ``CHECK_SAMPLES`` angles).

Distinct designs are compared by their curves, not their numbers (docs/synthesis.md): two designs
whose traced curves (the point's; with motion the pose's; with function generation q(φ)) agree
within ``CURVE_TOLERANCE`` of the task's size are the same curve — the same design when their
values agree too, else cognates (Roberts–Chebyshev: three four-bars trace one coupler curve).
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import yaml

from .._fields import ANGLE_UNITS, LENGTH_UNITS
from ..assembly import gaps
from ..classify import grashof, transmission_range
from ..errors import SolverError
from ..scene import Scene
from ..tolerances import EXACT_MISS
from .population import Goal, evaluate, group_of, link_ratio, wrap
from .template import Template

__all__ = ["Design", "SynthesisResult", "check_design", "meets_constraints", "same_curve", "curve_of", "CHECK_SAMPLES"]

#: An issue citation in a template's provenance (not for a user's design file).
_ISSUE = re.compile(r"\s*\((?:see )?issues? \d+[^)]*\)|\bissues? \d+[,;:]?\s*", re.IGNORECASE)
#: Input angles of the feasibility check of a returned design.
CHECK_SAMPLES = 720
#: Two curves closer than this (relative to the task's size) everywhere are one curve.
CURVE_TOLERANCE = 1e-4


@dataclass
class Design:
    """One checked design: free values (scene units), phases (rad) and its misses per target."""

    x: np.ndarray
    values: dict[str, float]
    phases: np.ndarray
    misses: np.ndarray  # (K,) m (or the joint's unit); motion: the position's miss
    angle_misses: np.ndarray | None  # motion: the body angle's miss (rad) per target
    feasible: bool
    curve: np.ndarray  # (CHECK_SAMPLES,) complex (or real for function generation), NaN where it fails
    scene: Scene
    cognate_of: int | None = None  # index in the result's designs of a design with the same curve

    @property
    def error(self) -> float:
        worst = float(np.max(self.misses))
        if self.angle_misses is not None:
            worst = max(worst, float(np.max(self.angle_misses)))
        return worst


def curve_of(scene: Scene, goal: Goal, phi: np.ndarray) -> tuple[np.ndarray, Any]:
    """The traced curve over ``phi`` (NaN where the scene cannot be assembled), and the solve."""
    names = [n for n in (goal.point,) if n is not None]
    joints = [n for n in (goal.joint,) if n is not None]
    k = scene.with_outputs(points=names, joints=joints, forces=False).solve(phi, mask=True)
    if goal.kind == "function":
        curve = np.where(k.valid, k.joint(goal.joint).position, np.nan)  # type: ignore[arg-type]
    else:
        xy = k.point(goal.point).position  # type: ignore[arg-type]
        curve = np.where(k.valid, xy[:, 0] + 1j * xy[:, 1], np.nan)
    return curve, k


def check_design(template: Template, goal: Goal, x: np.ndarray, phases: np.ndarray) -> Design | None:
    """Load the design's scene, solve it at its phases and over the required range (module docstring)."""
    try:
        scene = template.scene(x)
    except SolverError:
        return None
    phases = np.asarray(phases, float)
    if goal.at is None:
        lo = goal.sweep[0]
        phases = lo + np.mod(phases - lo, 2.0 * math.pi) if goal.full_turn else phases
    names = [n for n in (goal.point,) if n is not None]
    joints = [n for n in (goal.joint,) if n is not None]
    k = scene.with_outputs(points=names, joints=joints, forces=False).solve(phases, mask=True)
    t = goal.targets
    angle_misses = None
    if goal.kind == "function":
        d = k.joint(goal.joint).position - t[:, 1]  # type: ignore[arg-type]
        misses = np.abs(wrap(d) if goal.joint_wraps else d)
    else:
        xy = k.point(goal.point).position  # type: ignore[arg-type]
        misses = np.hypot(xy[:, 0] - t[:, 0], xy[:, 1] - t[:, 1])
        if goal.kind == "motion":
            angle_misses = np.abs(wrap(k.joint(goal.joint).position - t[:, 2]))  # type: ignore[arg-type]
    valid = bool(np.all(k.valid))
    check = np.linspace(goal.sweep[0], goal.sweep[-1] if not goal.full_turn else goal.sweep[0] + 2 * math.pi,
                        CHECK_SAMPLES, endpoint=not goal.full_turn)
    curve, kc = curve_of(scene, goal, check)
    swept = scene.with_outputs(points=[p for p in goal.closures], joints=[], forces=False).solve(check, mask=True)
    feasible = valid and bool(np.all(swept.valid))
    held = {group_of(template, p) for p in goal.closures}  # the dyads' (a triad's figure is no transmission angle)
    figures = [c for name, c in swept.conditioning.items() if name in held]
    if feasible and figures:
        worst = min(float(np.min(c)) for c in figures)
        feasible = worst >= math.sin(goal.min_transmission) * (1.0 - 1e-9)
    feasible = feasible and meets_constraints(scene, goal) is None
    if not np.all(np.isfinite(misses)):
        return None
    return Design(np.asarray(x, float), template.values_of(x), phases, misses, angle_misses, feasible, curve, scene)


def meets_constraints(scene: Scene, goal: Goal) -> str | None:
    """Why the loaded design ``scene`` breaks a constraint of ``goal``, or None: checked on the
    scene itself, not on samples — the exact intervals where a group cannot be assembled
    (:func:`solver.assembly.gaps`) against the required input range, every RRR dyad's exact
    transmission angle range over a full turn (:func:`solver.classify.transmission_range`), the
    link ratio of its own lengths."""
    lo = float(goal.sweep[0])
    hi = lo + 2.0 * math.pi if goal.full_turn else float(goal.sweep[-1])
    for group, intervals in gaps(scene).items():
        for a, b in intervals:
            for shift in (-2.0 * math.pi, 0.0, 2.0 * math.pi):  # intervals are given within one turn
                if a + shift < hi and b + shift > lo:
                    return (f"group '{group}' cannot be assembled for φ in ({math.degrees(a):.1f}°, "
                            f"{math.degrees(b):.1f}°)")
    if goal.full_turn:
        for g in scene.plan.groups:
            mu = transmission_range(scene, g) if g.kind == "rrr" else None
            # |sin μ| is concave on [0, π]: its least value over a range of μ is at an end
            if mu is not None and min(math.sin(mu[0]), math.sin(mu[1])) < math.sin(goal.min_transmission) * (1 - 1e-9):
                return (f"the transmission angle of '{g.name}' spans {math.degrees(mu[0]):.2f}° … "
                        f"{math.degrees(mu[1]):.2f}°, under {math.degrees(goal.min_transmission):g}°")
    if goal.max_ratio is not None:
        ratio = float(link_ratio(scene.plan, 1)[0])
        if ratio > goal.max_ratio * (1.0 + 1e-12):
            return f"the longest link over the shortest is {ratio:.4g}, over {goal.max_ratio:g}"
    return None


def same_curve(a: np.ndarray, b: np.ndarray, tolerance: float) -> bool:
    """Whether two sampled curves are one curve: every sample of each within ``tolerance`` of the
    other's polyline (a symmetric Hausdorff distance, samples joined by straight segments)."""
    return _one_way(a, b, tolerance) <= tolerance and _one_way(b, a, tolerance) <= tolerance


def _one_way(a: np.ndarray, b: np.ndarray, tolerance: float = 0.0) -> float:
    """The largest distance from a sample of ``a`` to ``b``'s polyline; beyond ``tolerance`` on a
    sparse subsample of ``a`` already, that first (larger-than-tolerance) figure is returned."""
    a, b = a[np.isfinite(a)], b[np.isfinite(b)]
    if tolerance > 0.0 and a.size > 64:
        coarse = _one_way(a[:: a.size // 32], b)
        if coarse > tolerance:
            return coarse
    if a.size == 0 or b.size == 0:
        return math.inf if a.size != b.size else 0.0
    if not np.iscomplexobj(a):
        a, b = a + 0j, b + 0j
    p, q = b, np.roll(b, -1)  # segments of b's (closed) polyline
    seg = q - p
    worst = 0.0
    for chunk in np.array_split(a, max(1, a.size // 256)):
        w = chunk[:, None] - p[None, :]
        with np.errstate(all="ignore"):
            s = np.clip((w.real * seg.real + w.imag * seg.imag) / (np.abs(seg) ** 2), 0.0, 1.0)
        s = np.nan_to_num(s)
        d = np.abs(w - s * seg).min(axis=1)
        worst = max(worst, float(d.max()))
    return worst


@dataclass
class SynthesisResult:
    """``solver.synthesize``'s answer (docs/synthesis.md)."""

    template: Template
    goal: Goal
    designs: list[Design]
    expired: bool
    history: list[float] = field(default_factory=list)
    seconds: float = 0.0
    starts: int = 0

    @property
    def best(self) -> Design:
        return self.designs[0]

    @property
    def scene(self) -> Scene:
        return self.best.scene

    @property
    def error(self) -> float:
        return self.best.error

    @property
    def phases(self) -> np.ndarray:
        return self.best.phases

    @property
    def values(self) -> dict[str, float]:
        return self.best.values

    @property
    def exact(self) -> bool:
        return self.best.feasible and self.error <= EXACT_MISS

    @property
    def solutions(self) -> list[Design]:
        """Every distinct design found, best first (cognates included, marked ``cognate_of``)."""
        return self.designs

    def save(self, path: str | os.PathLike[str], design: int = 0) -> None:
        """Write the design as a complete scene file (the template with every free value set)."""
        d = self.designs[design]
        data = self.template.filled(d.x)
        note = (f"Synthesized (solver.synthesize, {self.goal.kind} generation) from template "
                f"{self.template.file or '(data)'}: largest miss {d.error:.3g} {self.unit}.")
        prov = _ISSUE.sub("", str(data.get("provenance", ""))).strip()
        data["provenance"] = f"{prov} {note}".strip()
        with open(path, "w", encoding="utf-8") as fh:
            yaml.safe_dump(data, fh, sort_keys=False, default_flow_style=None, allow_unicode=True, width=100)

    @property
    def unit(self) -> str:
        """The unit of a miss: m (path, motion; a slide's function generation) or rad."""
        return "rad" if self.goal.kind == "function" and self.goal.joint_wraps else "m"

    def exactness(self) -> str:
        """One line: how exact the result is."""
        d = self.best
        unit = self.unit
        mark = " (time limit expired: best so far)" if self.expired else ""
        if not d.feasible:
            return f"NOT FEASIBLE: largest miss {d.error:.3g} {unit}; the design breaks a constraint{mark}"
        if self.exact:
            return f"exact: largest miss {d.error:.2g} {unit} ≤ {EXACT_MISS:g} (round-off){mark}"
        return f"approximate: largest miss {d.error:.3g} {unit} (> {EXACT_MISS:g}, no exact design found){mark}"

    def summary(self) -> str:
        """Dimensions, the miss at each target, transmission angle range, Grashof type."""
        d = self.best
        units = self.template.units
        angle_unit = next((k for k, v in ANGLE_UNITS.items() if v == units.angle), "rad")
        lines = [f"{self.goal.kind} generation: {len(d.misses)} targets, {len(self.designs)} distinct design(s), "
                 f"{self.starts} start(s), {self.seconds:.2f} s"]
        lines.append("dimensions (scene units):")
        length_unit = next((k for k, v in LENGTH_UNITS.items() if v == units.length), "m")
        for f, v in zip(self.template.free, d.x):
            unit = angle_unit if f.kind == "angle" else length_unit
            lines.append(f"  {f.place:24s} {self.template.label(f):24s} {v:.12g} {unit}")
        lines.append(f"targets:  phase (rad)   miss ({self.unit})")
        for i, (ph, m) in enumerate(zip(d.phases, d.misses)):
            extra = "" if d.angle_misses is None else f"  angle miss {d.angle_misses[i]:.3g} rad"
            lines.append(f"  {i:2d}  {ph: .9f}   {m:.3g}{extra}")
        for g in d.scene.ordered:
            mu = transmission_range(d.scene, g)
            if mu is not None:
                lo, hi = math.degrees(mu[0]), math.degrees(mu[1])
                lines.append(f"  transmission angle of {g.name}: {lo:.2f}° … {hi:.2f}°")
            gr = grashof(d.scene, g)
            if gr is not None:
                lines.append(f"  four-bar {g.name}: {gr}")
        if self.goal.weighted:
            ev = evaluate(self.template, self.goal, d.x[None])
            worst = "" if ev.efficiency is None else f", worst efficiency {float(ev.efficiency[0]):.4g}"
            lines.append(f"  at ω = {self.goal.speed:g} rad/s: peak input effort {float(ev.effort[0]):.4g}, "  # type: ignore[index]
                         f"peak pin load {float(ev.pin_load[0]):.4g} N{worst}")  # type: ignore[index]
        cognates = [i for i, e in enumerate(self.designs) if e.cognate_of is not None]
        if cognates:
            lines.append(f"cognates (same curve, other dimensions): designs {cognates}")
        lines.append(self.exactness())
        return "\n".join(lines)


def distinct(designs: Sequence[Design], goal: Goal, key: Callable[[Design], Any] | None = None) -> list[Design]:
    """Designs sorted (by ``key``; by default feasible first, then by error), duplicates dropped,
    cognates marked."""
    ordered = sorted(designs, key=key or (lambda d: (not d.feasible, d.error)))
    out: list[Design] = []
    tol = CURVE_TOLERANCE * goal.scale
    for d in ordered:
        twin = None
        for i, e in enumerate(out):
            if same_curve(d.curve, e.curve, tol):
                twin = i
                break
        if twin is None:
            out.append(d)
            continue
        e = out[twin]
        width = np.maximum(np.abs(e.x), 1.0)
        if np.max(np.abs(d.x - e.x) / width) <= 1e-6:
            continue  # the same design
        d.cognate_of = twin if e.cognate_of is None else e.cognate_of
        out.append(d)
    return out
