"""``synthesize``: path, function and motion generation from a template scene (docs/synthesis.md).

The task comes from the keywords: ``point=, through=`` (path; ``at=`` gives the input angle at
each target: with timing), ``joint=, pairs=`` (function: (φ, q) pairs, φ given), ``point=,
joint=, poses=`` (motion: (x, y, θ), θ the joint's value). Targets are in SI units (m, rad), as
the solver's outputs are; the template's free values are in the template's own units.
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from .._arguments import Arguments
from ..errors import SynthesisArgumentError, SynthesisError
from ..tolerances import EXACT_MISS
from .polish import polish
from .population import Goal, evaluate, objective
from .result import Design, SynthesisResult, check_design, distinct
from .search import Options, StartResult, short_starts, sweep
from .template import Template, load_template

__all__ = ["synthesize", "SAMPLES", "SHORT_SAMPLES"]

#: Input angles per candidate in the global search (the sweep of the required range).
SAMPLES = 180
#: The same for a task of short starts without timing (search.short_starts: a family of zeros,
#: no force terms; the input angles at the targets free): a target's miss is refined along the
#: curve from its nearest sample (population._untimed), so a coarser sweep still scores an exact
#: design near zero, and each generation costs 2/3. Issue 32's 20 seven-target instances: 197
#: starts in all with 120 samples against 272 with 180, a median of 2 against 5.5 (a few cases
#: needed more: the luck of a start moves either way); 90 samples needed more on the first cases
#: (docs/synthesis.md, Figures).
SHORT_SAMPLES = 120
#: Most starts of the multi-start sweep by default (each start is short: it ends when it stalls);
#: twice as many where the starts are short (search.short_starts: 35 generations).
STARTS = 32
#: Designs compared for distinct curves (the best, feasible first): the comparison is pairwise.
MAX_DESIGNS = 40
#: Evaluations of the last polish of the best designs when none is exact.
FINAL_NFEV = 400


def synthesize(
    template: str | os.PathLike[str] | Template | Mapping[str, Any],
    *,
    point: str | None = None,
    through: Sequence[Sequence[float]] | None = None,
    at: Sequence[float] | None = None,
    joint: str | None = None,
    pairs: Sequence[Sequence[float]] | None = None,
    poses: Sequence[Sequence[float]] | None = None,
    seed: int = 0,
    time_limit: float | None = None,
    workers: Any = None,
    input_range: tuple[float, float] | None = None,
    min_transmission: float = math.radians(30.0),
    max_ratio: float | None = None,
    effort_weight: float = 0.0,
    pin_weight: float = 0.0,
    efficiency_weight: float = 0.0,
    speed: float = 1.0,
    starts: int | None = None,
    samples: int | None = None,
    popsize: int = 20,
    maxiter: int | None = None,
    progress: Callable[[int, int, float], None] | None = None,
) -> SynthesisResult:
    """The design(s) of ``template`` that meet the task (module docstring, docs/synthesis.md).

    ``input_range`` (rad): the range the input must turn through, default a full turn;
    ``min_transmission`` (rad): the smallest transmission angle of every dyad over that range;
    ``max_ratio``: the longest link over the shortest at most this. ``effort_weight`` (per N·m,
    or per N for a slider input) and ``pin_weight`` (per N) add the peak input effort and the peak
    pin load over the range at ``speed`` (ω, rad/s) to the search's figure (the template needs
    bodies or loads, docs/forces.md); ``efficiency_weight`` adds weight · (1 − the worst
    instantaneous efficiency over the range at ``speed``) (the template needs ``friction:``,
    docs/forces.md#friction); the polish still hits the targets. ``starts``: multi-start
    sweep length (stopped at the first start that gives an exact design); ``workers``: a
    number of local processes or a ``dask.distributed.Client`` that run the starts, as many at
    once as there are (the result is the same as in one process: search._workers); ``maxiter``:
    generations of one start and ``starts`` the most starts (by default 35 and 64 where the task's
    zeros form a family — unknowns ≥ equations — and there are no force terms, else 300 and 32:
    search.short_starts; a path without timing whose zeros form a family of dimension ≥ 3 —
    6 targets of the four-bar or fewer — begins with 4 seeded stages: search.seeded). An expired
    ``time_limit`` (s) returns the best design so far, marked (``res.expired``).
    """
    t0 = time.monotonic()
    args = Arguments("synthesize", error=SynthesisArgumentError)  # each keyword's type and range (issue 30)
    if not isinstance(template, str | os.PathLike | Template | Mapping):
        args.fail("template", template, "must be a template scene: a path, a shipped name, a Template or its data")
    point, joint = args.name("point", point, none=True), args.name("joint", joint, none=True)
    if at is not None:
        args.numbers("at", at, unit="rad")  # (its count against the targets: make_goal)
    seed = args.integer("seed", seed, low=0)
    time_limit = args.number("time_limit", time_limit, low=0.0, low_open=True, unit="s", none=True)
    if isinstance(workers, int) and not isinstance(workers, bool):
        workers = args.integer("workers", workers, low=1)
    elif workers is not None and not all(hasattr(workers, m) for m in ("submit", "cancel", "scatter")):
        args.fail("workers", workers, "must be a number of local processes (≥ 1), a dask.distributed.Client or None")
    input_range = None if input_range is None else args.span("input_range", input_range, unit="rad")
    min_transmission = args.number("min_transmission", min_transmission, low=0.0, high=math.pi / 2, high_open=True,
                                   span="in [0, π/2)", unit="rad")
    max_ratio = args.number("max_ratio", max_ratio, low=1.0, none=True)
    effort_weight, pin_weight, efficiency_weight = (
        args.number(n, v, low=0.0) for n, v in (("effort_weight", effort_weight), ("pin_weight", pin_weight),
                                                ("efficiency_weight", efficiency_weight)))
    speed = args.number("speed", speed, low=0.0)
    starts = None if starts is None else args.integer("starts", starts, low=1)
    samples = None if samples is None else args.integer("samples", samples, low=8)
    popsize = args.integer("popsize", popsize, low=1)
    maxiter = None if maxiter is None else args.integer("maxiter", maxiter, low=1)
    progress = args.function_("progress", progress)
    tpl = load_template(template)

    def goal_of(count: int) -> Goal:
        return make_goal(tpl, point=point, through=through, at=at, joint=joint, pairs=pairs, poses=poses,
                         input_range=input_range, min_transmission=min_transmission, max_ratio=max_ratio,
                         samples=count)

    goal = goal_of(samples or SAMPLES)
    if effort_weight or pin_weight or efficiency_weight:
        goal = _weighted(tpl, goal, effort_weight, pin_weight, speed, efficiency=efficiency_weight)
    elif samples is None and goal.at is None and short_starts(tpl, goal):
        goal = goal_of(SHORT_SAMPLES)  # short starts without timing: a coarser sweep (SHORT_SAMPLES)
    if starts is None:
        starts = 2 * STARTS if short_starts(tpl, goal) else STARTS
    options = Options(popsize=popsize, maxiter=maxiter, starts=starts)
    found: list[Design] = []

    def done(r: StartResult) -> bool:
        for p in r.polished:
            d = check_design(tpl, goal, p.x, p.phases)
            if d is not None:
                found.append(d)
        return any(d.feasible and d.error <= EXACT_MISS for d in found)

    def rank(d: Design) -> tuple[bool, bool, float]:
        """Feasible first, then exact; among exact designs with force terms, the lowest figure."""
        exact = d.error <= EXACT_MISS
        if exact and goal.weighted:
            return (not d.feasible, False, float(objective(goal, evaluate(tpl, goal, d.x[None]))[0]))
        return (not d.feasible, not exact, d.error)

    results = sweep(tpl, goal, seed=seed, options=options, time_limit=time_limit, workers=workers, done=done,
                    progress=progress)
    expired = any(r.expired for r in results)
    found.sort(key=rank)
    if found and found[0].feasible and found[0].error > EXACT_MISS:
        # a last, longer polish of the best few (the search's polishes are kept short)
        for d in list(found[:3]):
            p = polish(tpl, goal, d.x, d.phases, max_nfev=FINAL_NFEV)
            again = check_design(tpl, goal, p.x, p.phases)
            if again is not None:
                found.append(again)
        found.sort(key=rank)
    # only designs that meet every constraint are returned, checked on their own scenes (result.py)
    designs = distinct([d for d in found if d.feasible][:MAX_DESIGNS], goal, key=rank)
    if not designs:
        what = "assembles over the required input range" + (  # a transmission angle is a dyad's
            f" with every transmission angle ≥ {math.degrees(goal.min_transmission):g}°" if goal.closures else "") \
            + (f" and links within {max_ratio:g}:1" if max_ratio else "")
        more = " before the time limit expired" if expired else f" in {len(results)} start(s)"
        raise SynthesisError(f"{tpl.file or 'template'}: no design found that {what}{more}; "
                             + ("give it more time (time_limit), " if expired else "")
                             + "widen the free ranges or relax the constraints")
    history = [h for r in results for h in r.history]
    return SynthesisResult(tpl, goal, designs, expired, history, time.monotonic() - t0, len(results))


def _targets(name: str, value: Any, width: int) -> np.ndarray:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise SynthesisError(f"{name} must be a list of {width}-number rows, got {str(value)[:60]}") from None
    if arr.ndim != 2 or arr.shape[1] != width or arr.shape[0] == 0:
        raise SynthesisError(f"{name} must be a list of {width}-number rows, got shape {arr.shape}")
    bad = np.argwhere(~np.isfinite(arr))
    if bad.size:
        raise SynthesisError(f"{name}[{bad[0][0]}] must be finite numbers, got {arr[bad[0][0]].tolist()}")
    return arr


def make_goal(tpl: Template, *, point: str | None, through: Any, at: Any, joint: str | None, pairs: Any,
              poses: Any, input_range: tuple[float, float] | None, min_transmission: float,
              max_ratio: float | None, samples: int) -> Goal:
    """The task of the keywords, checked (one SynthesisError line per fault)."""
    scene = tpl.template_scene
    given = [k for k, v in (("through", through), ("pairs", pairs), ("poses", poses)) if v is not None]
    if len(given) != 1:
        raise SynthesisError("give exactly one of through= (path), pairs= (function) or poses= (motion), got "
                             f"{', '.join(given) or 'none'}")
    kind = {"through": "path", "pairs": "function", "poses": "motion"}[given[0]]
    if kind in ("path", "motion") and (point is None or point not in scene.point_names):
        raise SynthesisError(f"point= must name a point of the template, got {point!r}; points: "
                             f"{', '.join(scene.point_names)}")
    if kind in ("function", "motion") and (joint is None or joint not in scene.joint_names):
        raise SynthesisError(f"joint= must name a joint of the template, got {joint!r}; joints: "
                             f"{', '.join(scene.joint_names)}")
    if kind == "path" and joint is not None:
        raise SynthesisError("path generation (through=) takes point= only; a body's angle too is motion (poses=)")
    if not 0.0 <= min_transmission < math.pi / 2:
        raise SynthesisError(f"min_transmission must be in [0, π/2) rad, got {min_transmission}")
    if max_ratio is not None and not max_ratio >= 1.0:
        raise SynthesisError(f"max_ratio must be ≥ 1, got {max_ratio}")
    if samples < 8:
        raise SynthesisError(f"samples must be at least 8, got {samples}")
    targets = _targets(given[0], {"path": through, "function": pairs, "motion": poses}[kind],
                       {"path": 2, "function": 2, "motion": 3}[kind])
    timing = None
    if kind == "function":
        timing = targets[:, 0].copy()
    elif at is not None:
        timing = np.asarray(at, float).ravel()
        if timing.size != len(targets) or not np.all(np.isfinite(timing)):
            raise SynthesisError(f"at= must give one finite input angle per target ({len(targets)}), got {timing.size}")
    if input_range is None:
        full, lo, hi = True, 0.0, 2.0 * math.pi
        sweep = np.linspace(0.0, 2.0 * math.pi, samples, endpoint=False)
    else:
        lo, hi = (float(v) for v in input_range)
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise SynthesisError(f"input_range must be (lo, hi) with lo < hi, got {input_range}")
        full = False
        sweep = np.linspace(lo, hi, samples)
    if timing is not None and not full and np.any((timing < lo) | (timing > hi)):
        raise SynthesisError(f"an input angle of the targets lies outside input_range [{lo:g}, {hi:g}] rad")
    if kind in ("path", "motion"):
        _check_reach(tpl, targets)
        xy = targets[:, :2]
        size = float(np.max(np.hypot(*(xy[:, None, :] - xy[None, :, :]).transpose(2, 0, 1)))) if len(xy) > 1 else 0.0
        scale = size if size > 0.0 else 1.0
    else:
        scale = 1.0
    units = scene.joint_units
    wraps = joint is not None and units.get(joint, "rad") == "rad"
    closures = tuple(g.point for g in scene.ordered if g.kind in ("rrr", "rrp"))  # type: ignore[attr-defined]
    return Goal(kind, point, joint, targets, timing, sweep, float(min_transmission), max_ratio, scale, wraps,
                closures, full)


def _weighted(tpl: Template, goal: Goal, effort: float, pin: float, speed: float, *, efficiency: float = 0.0) -> Goal:
    for name, value in (("effort_weight", effort), ("pin_weight", pin), ("speed", speed),
                        ("efficiency_weight", efficiency)):
        if not (math.isfinite(value) and value >= 0.0):
            raise SynthesisError(f"{name} must be a finite number ≥ 0, got {value}")
    if tpl.template_scene.forces is None:
        what = "effort_weight and pin_weight need" if effort or pin else "efficiency_weight needs"
        raise SynthesisError(f"{tpl.file or 'template'}: {what} a template with bodies, gravity or loads "
                             "(docs/forces.md)")
    if efficiency and not tpl.template_scene.has_friction:
        raise SynthesisError(f"{tpl.file or 'template'}: efficiency_weight needs a template with friction: "
                             "without it every design's efficiency is 1 (docs/forces.md#friction)")
    if efficiency and speed == 0.0:
        raise SynthesisError("efficiency_weight needs speed > 0: at rest no power flows, the efficiency is 1")
    return replace(goal, effort_weight=float(effort), pin_weight=float(pin), speed=float(speed),
                   efficiency_weight=float(efficiency))


def _check_reach(tpl: Template, targets: np.ndarray) -> None:
    """A target farther from the origin than any point of any design can be: refused up front.
    Every point hangs from a fixed point by a chain of links, so it lies within the farthest
    fixed point plus the sum of every length's upper bound."""
    u = tpl.units.length
    hi = tpl.template_scene._data
    far = 0.0
    for name, value in hi.fixed.items():
        frees = [f for f in tpl.free if f.path[:2] == ("fixed", name)]
        xy = [abs(value.real), abs(value.imag)] if isinstance(value, complex) else [float(np.max(np.abs(value)))] * 2
        for f in frees:
            xy[f.path[2]] = max(abs(f.lo), abs(f.hi)) * u
        far = max(far, math.hypot(*xy))
    total = 0.0
    free_groups = {f.path[1]: f for f in tpl.free if f.path[0] == "groups"}
    for i, g in enumerate(hi.groups):
        for _, _, length in g.rigid_pairs():
            total += abs(float(length))
        if i in free_groups or g.kind == "rrp":
            total += sum(max(abs(f.lo), abs(f.hi)) * u for f in tpl.free
                         if f.path[:2] == ("groups", i) and f.kind != "angle")
    reach = far + total
    for i, t in enumerate(targets):
        if math.hypot(t[0], t[1]) > reach:
            raise SynthesisError(f"target {i} ({t[0]:g}, {t[1]:g}) m is out of any reachable range: no design of "
                                 f"the template reaches beyond {reach:.3g} m of the origin")
