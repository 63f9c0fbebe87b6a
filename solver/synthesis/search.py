"""The global search and the multi-start sweep: scipy's differential evolution, then the polish.

One *start* (seeded by ``seed + i``): ``differential_evolution`` with ``vectorized=True`` over
the free values within their bounds, every generation's whole population one array evaluation
(:func:`~.population.evaluate`, candidates × samples); it stops at its own convergence, at
``maxiter``, when it stalls (``Options.stall``), when its best figure is below
``Options.good_enough`` (the polish finishes from there), or at the deadline. Then the best
distinct members of its final population are polished (:func:`~.polish.polish`); where none
ends exact and feasible, an exact but infeasible one slides along the task's family of zeros to a
feasible zero (:func:`_slide`; the same for the trial polishes during the search). Where the
task's zeros form a family of dimension ≥ 3 (a path without timing: 6 targets of the four-bar or
fewer), the first four starts are *seeded stages* instead (:func:`_seeded_stage`): the best of 10,000
Latin-hypercube designs at the targets' scale polished together, the ends near a zero one by one,
feasible and infeasible in turn — zeros are plentiful there, and most stages end exact. Starts run in
order until one yields an exact design or ``starts`` are spent; on N local processes
(``workers=N``) or a Dask client (``workers=client``) N starts run at once (:mod:`._workers`),
and the results are read in start order with the same stopping rule, so whatever runs them the
answer is the same (only an expiring time limit depends on the machine).
"""

from __future__ import annotations

import math
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from scipy.optimize import differential_evolution

from ..tolerances import EXACT_MISS
from ._workers import runner
from .batch import Batch, polish_batch
from .polish import Polished, polish, residuals
from .population import INFEASIBLE, Goal, evaluate, objective, run
from .template import Template

__all__ = ["Options", "StartResult", "run_start", "seeded", "short_starts", "slack", "sweep"]

#: A batch polish's end whose RMS residual (relative to the targets' size) is under this is near
#: a zero: on trial, only such ends are polished one by one (to round-off, within the bounds).
NEAR_ZERO = 1e-4
#: The weight of the feasibility residuals against the targets' in :func:`_slide`.
SLIDE_WEIGHT = 1e-2


@dataclass(frozen=True)
class Options:
    popsize: int = 20  # scipy's multiplier: popsize × n candidates per generation
    #: generations of one start; None: by the task (:func:`start_length`)
    maxiter: int | None = None
    polish_count: int = 4  # best ends of the final batch polished one by one per start
    starts: int = 32
    #: below this best figure, every ``try_every`` generations, the best is polished on trial
    try_below: float = 1e-1
    try_every: int = 5
    trial_count: int = 24  # distinct best members polished together on trial (polish_batch)
    trial_iterations: int = 30
    trial_keep: int = 3  # the best of them polished to round-off
    batch_count: int = 64  # distinct final members polished together at a start's end
    batch_iterations: int = 60
    #: a start that improved its best figure by less than ``stall_gain`` in this many generations
    #: is stuck (a local minimum): it ends, and the next start begins elsewhere — short starts
    #: from new places find the basin of an exact design sooner than one start crawling on
    stall: int = 20
    stall_gain: float = 0.1
    #: a best figure (RMS miss over the task's size) at which the search hands over to the polish
    good_enough: float = 1e-3


#: A search whose figure holds force terms trials later and crawls on longer (the targets are
#: met by a whole family of designs; the force terms choose among them as the search goes on).
WEIGHTED = Options(try_below=5e-2, stall=40, stall_gain=0.05, polish_count=8, maxiter=300)
#: Generations of one start, and the stall window, for a task whose zeros form a family (unknowns
#: ≥ equations) and whose figure holds no force terms. There an exact design is found by a trial
#: polish within the first 15–35 generations of a start or, in most starts, not at all (issue 32:
#: 14 seven-target instances): many short starts from new places find it sooner than fewer long
#: ones (five targets too: 5.8 s CPU against 7.4 s for the three cases of the benchmark). An
#: over-determined task (10 targets: only the generating four-bar and its cognates fit) keeps the
#: long starts it was measured with.
SHORT = 35
SHORT_STALL = 12
#: Generations of one start otherwise.
LONG = 300

#: The seeded stage of a start (:func:`_seeded_stage`), for a path task without timing whose
#: family of zeros has at least this dimension (6 targets of the four-bar: 9 + 6 − 12 = 3; five
#: targets 4): zeros are plentiful there, and a batch polish straight from the best of many
#: Latin-hypercube designs reaches a feasible one in most starts (issue 32: 32 of 32 stages on the
#: four six-target cases × 8 seeds, against about 1 in 10 DE starts on case 0). Seven targets
#: (dimension 2) keep the DE starts they were measured with.
SEEDED_SLACK = 3
#: Designs of the stage's Latin hypercube (in the start box), screened by the search's figure.
SEEDED_DESIGNS = 10_000
#: Input angles of the screen's sweep (the figure only ranks the designs: a coarse sweep will do).
SEEDED_SAMPLES = 60
#: The best distinct screened designs polished together, and the batch's iterations: the family's
#: rank-deficient Jacobian makes the batch converge slowly near a zero (100 iterations left most
#: ends at 1e-6 of the targets' size, whose polish of 60 evaluations stalled there).
SEEDED_BATCH = 200
SEEDED_ITERATIONS = 150
#: Ends near a zero polished one by one, at most this many: feasible and infeasible ones in turn,
#: each kind by cost (an exact but infeasible polish slid along the family: :func:`_slide`). In
#: turn rather than the feasible ones first: on case 0 seed 1 of the six-target benchmark the four
#: feasible ends all crawl at 1e-5 of the size while the first infeasible ones end exact and slide
#: to a feasible zero (issue 32; docs/synthesis.md, Figures).
SEEDED_KEEP = 6
#: A one-by-one polish runs in chunks of ``SEEDED_CHUNK`` evaluations, at most ``SEEDED_CHUNKS``
#: of them, and stops after a chunk that lowered its RMS residual by less than ``SEEDED_GAIN``
#: times (:func:`_polish_while_falling`): an end that converges crawls down a factor 1.7–3 per
#: 100 evaluations before its last quadratic steps (a crawl from 1e-5 to 1e-7 of the size takes
#: 100–250), one that does not is flat (1e-5 → 1.2e-5, 5e-5 → 4e-5 over 300), so the failures
#: cost a third of what 300 evaluations did and the converging ones may run on to 600.
SEEDED_CHUNK = 100
SEEDED_CHUNKS = 6
SEEDED_GAIN = 1.5
#: Evaluations of the last polish after a slide on the targets alone (:func:`_slide`; a DE
#: start's slide keeps 60): a slid end is feasible but often 1e-6 – 1e-5 off, and crawls too.
SEEDED_NFEV = 300
#: Starts 0 … SEEDED_STARTS − 1 of such a task are seeded stages alone (a stage costs 1.3–2.9 s
#: CPU at load 1 and ended exact on case 0 of the six-target benchmark in 12 of 12 seeds, a DE
#: start about 1 s at 1 in 10); the later ones are DE starts, so that a task without an exact feasible
#: design (a stage that fails costs 3.0–3.5 s at load 1.7, 3.5–4.3 s at load 5–6: case 0 with a
#: minimum transmission angle of 80°) still
#: ends at the best approximate design the DE finds, having spent at most this many stages first.
SEEDED_STARTS = 4
#: Group kinds whose long rows a population solves design by design (no seeded stages with them).
_ONE_BY_ONE = ("triad", "slider_triad")


def slack(template: Template, goal: Goal) -> int:
    """Unknowns minus equations of the task: the dimension of its family of zeros."""
    width = goal.targets.shape[1] if goal.kind != "function" else 1
    unknowns = template.lo.size + (len(goal.targets) if goal.at is None else 0)
    return unknowns - width * len(goal.targets)


def short_starts(template: Template, goal: Goal) -> bool:
    """Whether the task's starts are short (``SHORT``)."""
    return not _weighted(goal) and slack(template, goal) >= 0


def seeded(template: Template, goal: Goal) -> bool:
    """Whether the first starts are seeded stages (``SEEDED_SLACK``, ``SEEDED_STARTS``;
    :func:`_seeded_stage`). Not with a triad: its sweep is solved design by design
    (solver.groups._triad_population), and a screen of ``SEEDED_DESIGNS`` would take minutes."""
    return (not _weighted(goal) and goal.kind == "path" and goal.at is None
            and slack(template, goal) >= SEEDED_SLACK
            and not any(g.kind in _ONE_BY_ONE for g in template.template_scene.ordered))


@dataclass
class StartResult:
    index: int
    polished: list[Polished]
    history: list[float] = field(default_factory=list)  # best figure per generation
    expired: bool = False
    generations: int = 0


def run_start(template: Template, goal: Goal, seed: int, index: int, options: Options,
              remaining: float | None) -> StartResult:
    """One start (module docstring); ``remaining`` seconds or None for no limit."""
    deadline = None if remaining is None else time.monotonic() + remaining
    if seeded(template, goal) and index < SEEDED_STARTS:  # the seeded stage instead of the DE
        polished, best = _seeded_stage(template, goal, np.random.default_rng([seed, index, _SEEDED_STREAM]), deadline)
        return StartResult(index, polished, [best], deadline is not None and time.monotonic() > deadline)
    if _weighted(goal):  # the force terms need the search to run on after the targets are near
        options = replace(options, try_below=WEIGHTED.try_below, stall=WEIGHTED.stall, stall_gain=WEIGHTED.stall_gain,
                          polish_count=WEIGHTED.polish_count)
    short = short_starts(template, goal)
    if short:
        options = replace(options, stall=min(options.stall, SHORT_STALL))
    maxiter = options.maxiter or (SHORT if short else LONG)
    bounds = list(zip(template.lo, template.hi))
    history: list[float] = []
    expired = [False]

    def f(xt: np.ndarray) -> np.ndarray:
        return objective(goal, evaluate(template, goal, xt.T))

    trials: list[Polished] = []
    tried: set[bytes] = set()
    width = template.hi - template.lo

    def callback(intermediate_result: Any) -> bool:
        best = float(intermediate_result.fun)
        history.append(best)
        if deadline is not None and time.monotonic() > deadline:
            expired[0] = True
            return True
        if best < options.try_below and len(history) % options.try_every == 0 and trial(intermediate_result):
            return True
        stalled = len(history) > options.stall and best > (1.0 - options.stall_gain) * history[-options.stall]
        return bool(best < options.good_enough or stalled)

    def trial(intermediate_result: Any) -> bool:
        """The best members handed over to the polish now (a member polished on an earlier trial
        is not again): whether one ends exact and feasible."""
        energies = np.asarray(intermediate_result.population_energies)
        ranked = np.asarray(intermediate_result.population)[np.argsort(energies)]
        members = _distinct(np.array([m for m in ranked if m.tobytes() not in tried]), width, options.trial_count)
        tried.update(m.tobytes() for m in members)
        if members.size:
            batch = _polished(template, goal, members, options.trial_iterations, keep=options.trial_keep)
            trials.extend(p for p in batch if _exact_and_feasible(template, goal, p))
            if not trials:
                slid = _slide(template, goal, batch, deadline)
                trials.extend(p for p in slid if _exact_and_feasible(template, goal, p))
        return bool(trials)

    rng = np.random.default_rng([seed, index])
    size = options.popsize * len(bounds)
    with np.errstate(all="ignore"):
        de = differential_evolution(
            f, bounds, vectorized=True, updating="deferred", popsize=options.popsize, maxiter=maxiter,
            seed=rng, polish=False, init=start_box(template, goal, rng, size), callback=callback,
            tol=1e-12, mutation=(0.5, 1.0), recombination=0.9,
        )
    if trials:  # the search ended on an exact design: the polish of the final members is not needed
        return StartResult(index, trials, history, expired[0], int(de.nit))
    ranked = de.population[np.argsort(de.population_energies)]
    members = _distinct(ranked, width, options.batch_count)
    phases0 = evaluate(template, goal, members).phases
    if _weighted(goal):  # the best members to their own nearest zeros, as ranked with the force terms
        ends = Batch(members, phases0, np.zeros(len(members)))
    else:
        ends = polish_batch(template, goal, members, phases0, iterations=options.batch_iterations)
    near = 0.5 * NEAR_ZERO**2 * goal.targets.size
    # the ends near a zero in the search's ranking (which holds the force terms), then the rest by cost
    close = [i for i in range(len(members)) if ends.cost[i] <= near]
    order = (close + [i for i in np.argsort(ends.cost) if i not in close])[: options.polish_count]
    out: list[Polished] = []
    for rank, i in enumerate(order):
        if deadline is not None and time.monotonic() > deadline and out:
            expired[0] = True
            break
        if rank and not ends.cost[i] <= near:  # far from a zero: kept as the batch left it
            out.append(Polished(ends.x[i], ends.phases[i], float(ends.cost[i])))
            continue
        p = polish(template, goal, ends.x[i], ends.phases[i])
        if goal.at is None and math.sqrt(2.0 * p.cost) * goal.scale > EXACT_MISS and rank == 0:
            p = _reseed(template, goal, p, deadline)
        out.append(p)
    if not any(_exact_and_feasible(template, goal, p) for p in out):
        out += _slide(template, goal, out, deadline)
    return StartResult(index, out, history, expired[0], int(de.nit))


#: The seeded stage's random stream of a start is ``[seed, index, _SEEDED_STREAM]`` (the DE's is
#: ``[seed, index]``, unchanged by the stage).
_SEEDED_STREAM = 6


def _seeded_stage(template: Template, goal: Goal, rng: np.random.Generator, deadline: float | None
                  ) -> tuple[list[Polished], float]:
    """A start's seeded stage (``SEEDED_*``): ``SEEDED_DESIGNS`` designs of a Latin hypercube in
    the start box (:func:`start_box`) screened by the search's figure on a coarse sweep; the
    ``SEEDED_BATCH`` best distinct ones polished together (:func:`~.batch.polish_batch`); of the
    ends near a zero, the feasible (the population's figure) and the infeasible ones in turn, each
    kind by cost (:func:`_seeded_order`), polished one by one while their residual falls
    (:func:`_polish_while_falling`; an exact but infeasible one slid along the family:
    :func:`_slide`) until one is exact and feasible. Returns the polished designs (the exact and feasible one
    last, where found) and the best figure of the screen."""
    box = start_box(template, goal, rng, SEEDED_DESIGNS)
    if not isinstance(box, np.ndarray):  # (a path task's box is always narrowed)
        box = rng.uniform(template.lo, template.hi, (SEEDED_DESIGNS, template.lo.size))
    coarse = replace(goal, sweep=goal.sweep[:: max(1, goal.sweep.size // SEEDED_SAMPLES)])
    chunk = 2500  # designs per pass: (chunk, samples) arrays of a few MB
    figure = np.concatenate([objective(coarse, evaluate(template, coarse, box[i : i + chunk]))
                             for i in range(0, len(box), chunk)])
    best = float(figure.min())
    members = _distinct(box[np.argsort(figure, kind="stable")], template.hi - template.lo, SEEDED_BATCH)
    out: list[Polished] = []
    if deadline is not None and time.monotonic() > deadline:
        return out, best
    ends = polish_batch(template, goal, members, evaluate(template, goal, members).phases,
                        iterations=SEEDED_ITERATIONS)
    near = np.flatnonzero(ends.cost <= 0.5 * NEAR_ZERO**2 * goal.targets.size)
    if not near.size:  # the best end, as the batch left it (an approximate design at least)
        i = int(np.argmin(ends.cost))
        return [Polished(ends.x[i], ends.phases[i], float(ends.cost[i]))], best
    ok = objective(goal, evaluate(template, goal, ends.x[near])) < INFEASIBLE
    order = _seeded_order(ends.cost, near, ok)[:SEEDED_KEEP]
    for i in order:
        if deadline is not None and time.monotonic() > deadline:
            break
        p = _polish_while_falling(template, goal, ends.x[i], ends.phases[i])
        out.append(p)
        if _exact_and_feasible(template, goal, p):
            break
        slid = _slide(template, goal, [p], deadline, max_nfev=SEEDED_NFEV)
        out += slid
        if any(_exact_and_feasible(template, goal, q) for q in slid):
            break
    return out, best


def _polish_while_falling(template: Template, goal: Goal, x: np.ndarray, phases: np.ndarray) -> Polished:
    """:func:`~.polish.polish` from (x, phases) in chunks of ``SEEDED_CHUNK`` evaluations while
    each chunk lowers the RMS residual ``SEEDED_GAIN`` times, at most ``SEEDED_CHUNKS``; the best
    end (each chunk restarts the trust region from where the last one ended)."""
    p = polish(template, goal, x, phases, max_nfev=SEEDED_CHUNK)
    for _ in range(SEEDED_CHUNKS - 1):
        if _exact(goal, p):
            break
        q = polish(template, goal, p.x, p.phases, max_nfev=SEEDED_CHUNK)
        falling = q.cost < p.cost / SEEDED_GAIN**2
        p = q if q.cost < p.cost else p
        if not falling:
            break
    return p


def _seeded_order(cost: np.ndarray, near: np.ndarray, ok: np.ndarray) -> list[int]:
    """The ends ``near`` (indices) in the order of their one-by-one polish: feasible (``ok``) and
    infeasible in turn, the feasible first, each kind by ``cost`` (``SEEDED_KEEP``)."""
    kinds = [list(near[ok][np.argsort(cost[near[ok]], kind="stable")]),
             list(near[~ok][np.argsort(cost[near[~ok]], kind="stable")])]
    out: list[int] = []
    for j in range(max(map(len, kinds))):
        out += [int(k[j]) for k in kinds if j < len(k)]
    return out


def start_box(template: Template, goal: Goal, rng: np.random.Generator, count: int) -> np.ndarray | str:
    """A Latin hypercube of ``count`` designs in the free values' bounds narrowed to the targets'
    size L (path and motion tasks): a fixed point's coordinate within 1.5 L of the targets'
    middle, a length under 3 L (each kept inside its bounds; a bound already narrower stays). The
    search may leave the box (its bounds are the template's): the box only makes it start at the
    targets' scale, so that a 0.3 m path does not give metre-scale linkages by default. Where
    nothing is narrowed (function generation), scipy's own Latin hypercube ("latinhypercube")."""
    lo, hi = template.lo.copy(), template.hi.copy()
    if goal.kind in ("path", "motion"):
        mid = 0.5 * (goal.targets[:, :2].min(axis=0) + goal.targets[:, :2].max(axis=0))
        unit = template.units.length
        span = goal.scale / unit
        for i, f in enumerate(template.free):
            if f.path[0] == "fixed":
                c = mid[f.path[2]] / unit
                a, b = max(f.lo, c - 1.5 * span), min(f.hi, c + 1.5 * span)
            elif f.kind == "length":
                a, b = f.lo, min(f.hi, max(3.0 * span, f.lo + 0.1 * (f.hi - f.lo)))
            else:
                continue
            if b > a:
                lo[i], hi[i] = a, b
    if np.array_equal(lo, template.lo) and np.array_equal(hi, template.hi):
        return "latinhypercube"  # nothing narrowed: scipy's own, over the bounds
    n = lo.size
    cells = (np.argsort(rng.random((count, n)), axis=0) + rng.random((count, n))) / count
    return lo + cells * (hi - lo)  # type: ignore[no-any-return]


def _weighted(goal: Goal) -> bool:
    """Whether the search's figure holds force terms: a batch polish (Levenberg–Marquardt with
    large steps along a family of zeros) would lose the preference they give, so each member
    goes to its own nearest zero instead (:func:`~.polish.polish`)."""
    return goal.weighted


def _polished(template: Template, goal: Goal, members: np.ndarray, iterations: int, *, keep: int) -> list[Polished]:
    """The members polished together (:func:`~.batch.polish_batch`); the ``keep`` best ends then
    polished one by one to round-off within the bounds (:func:`~.polish.polish`)."""
    if _weighted(goal):  # each member to its own nearest zero (the search's ranking holds the force terms)
        return [polish(template, goal, x, ph) for x, ph in zip(members[:keep], evaluate(template, goal,
                                                                                       members[:keep]).phases)]
    ends = polish_batch(template, goal, members, evaluate(template, goal, members).phases, iterations=iterations)
    near = 0.5 * (NEAR_ZERO**2) * goal.targets.size
    order = [i for i in range(len(members)) if ends.cost[i] <= near][:keep]  # in the search's ranking (force terms)
    return [polish(template, goal, ends.x[i], ends.phases[i]) for i in order]


def _slide(template: Template, goal: Goal, polished: list[Polished], deadline: float | None, *,
           max_nfev: int = 60) -> list[Polished]:
    """Where no polish ended exact and feasible: each exact but infeasible one polished again from
    where it ended with the feasibility residuals added at ``SLIDE_WEIGHT``, until one ends exact
    and feasible. An under-determined task (fewer equations than unknowns: 5 path targets and 9
    dimensions) has a family of zeros, and the polish ends at the nearest, which can have lost
    the full turn or the transmission angle its member had; the feasibility residuals, weighted
    low against the targets', move it along the family (the targets' residuals stay near zero)
    until the dyads are feasible again, where they vanish and the polish ends at round-off."""
    out: list[Polished] = []
    if not goal.closures:
        return out
    for p in polished:
        if deadline is not None and time.monotonic() > deadline:
            break
        if not _exact(goal, p) or _feasible(template, goal, p):
            continue
        q = polish(template, goal, p.x, p.phases, feasible=SLIDE_WEIGHT)
        if _feasible(template, goal, q):  # the last steps to round-off, on the targets alone
            again = polish(template, goal, q.x, q.phases, max_nfev=max_nfev)
            q = again if _exact_and_feasible(template, goal, again) else q
        out.append(q)
        if _exact_and_feasible(template, goal, q):
            break
    return out


def _exact(goal: Goal, p: Polished) -> bool:
    return math.sqrt(2.0 * p.cost) * goal.scale <= EXACT_MISS


def _feasible(template: Template, goal: Goal, p: Polished) -> bool:
    return bool(objective(goal, evaluate(template, goal, p.x[None]))[0] < INFEASIBLE)


def _distinct(members: np.ndarray, width: np.ndarray, count: int) -> np.ndarray:
    """The first ``count`` members (best first) apart by 1 % of a range in some value."""
    picked: list[np.ndarray] = []
    for member in members:
        if len(picked) >= count:
            break
        if all(np.max(np.abs(member - p) / np.maximum(width, 1e-300)) > 1e-2 for p in picked):
            picked.append(member)
    return np.array(picked)


def _reseed(template: Template, goal: Goal, p: Polished, deadline: float | None, tries: int = 3) -> Polished:
    """A polish that stopped short of zero, tried again with the worst target moved to another
    place where the curve passes near it (another local minimum of its distance along the sweep):
    a polish started from the nearest sample can settle with two targets on one arc of the curve."""
    ctx = run(template, p.x[None], goal.sweep, goal.names)
    z = np.broadcast_to(ctx.values[goal.point].value, (1, goal.sweep.size))[0]  # type: ignore[index]
    bad = np.broadcast_to(np.asarray(ctx.invalid, bool), (1, goal.sweep.size))[0]
    t = goal.targets
    r = residuals(template, goal, p.x[None], p.phases)[0][0]
    k_count = len(t)
    miss = np.hypot(r[:k_count], r[k_count : 2 * k_count])
    best = p
    for k in np.argsort(miss)[::-1][:2]:
        d = np.where(bad, np.inf, np.abs(z - complex(t[k, 0], t[k, 1])))
        minima = np.flatnonzero((d <= np.roll(d, 1)) & (d <= np.roll(d, -1)) & np.isfinite(d))
        for i in minima[np.argsort(d[minima])][:tries]:
            if deadline is not None and time.monotonic() > deadline:
                return best
            start = p.phases.copy()
            start[k] = goal.sweep[i]
            q = polish(template, goal, p.x, start)
            if q.cost < best.cost:
                best = q
            if math.sqrt(2.0 * best.cost) * goal.scale <= EXACT_MISS:
                return best
    return best


def _exact_and_feasible(template: Template, goal: Goal, p: Polished) -> bool:
    """A polished design's residual at round-off and its sweep feasible (the population's own
    figures; the returned designs are checked again on their loaded scenes)."""
    return _exact(goal, p) and _feasible(template, goal, p)


def sweep(template: Template, goal: Goal, *, seed: int, options: Options, time_limit: float | None,
          workers: Any, done: Callable[[StartResult], bool],
          progress: Callable[[int, int, float], None] | None = None) -> list[StartResult]:
    """Starts 0, 1, … in order until ``done(result)`` or ``options.starts`` (module docstring):
    on ``workers`` (:mod:`._workers`: None this process, N local processes, a Dask client) as
    many run at once as it has, and their results are read in start order."""
    t0 = time.monotonic()
    results: list[StartResult] = []
    with runner(workers) as run:
        pending: deque[Any] = deque()
        i = 0
        while True:
            remaining = None if time_limit is None else time_limit - (time.monotonic() - t0)
            out_of_time = remaining is not None and remaining <= 0.0
            while i < options.starts and len(pending) < run.depth and not out_of_time:
                pending.append(run.submit(run_start, template, goal, seed, i, options, remaining))
                i += 1
            if not pending:
                if out_of_time and results:
                    results[-1].expired = True
                return results
            r = pending.popleft().result()
            results.append(r)
            if progress is not None:
                best = min((h for s in results for h in s.history[-1:]), default=float("inf"))
                progress(len(results), options.starts, best)
            if r.expired or done(r):
                return results
