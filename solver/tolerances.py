"""Named tolerances, in units of machine epsilon (spatialmath's habit).

Scale-free quantities (conditioning, relative errors) use these directly; lengths are scaled by
the scene's characteristic length before use.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "EPS",
    "ASSEMBLY_SLACK",
    "SINGULAR",
    "NEAR_SINGULAR",
    "LIMIT_STEP",
    "LIMIT_AGREEMENT",
    "GRASHOF_EQUAL",
    "ROOT_ITERATIONS",
    "STATIONARY",
    "REFINE_BELOW",
    "LIMIT_NODE",
    "CLOSURE_ROUNDING",
    "ZERO_TO_ROUNDING",
    "DYNAMICS_TOGGLE",
    "DYNAMICS_KINK_AIM",
    "DYNAMICS_KINK_MISS",
    "EXACT_MISS",
]

#: Machine epsilon of float64.
EPS: float = float(np.finfo(np.float64).eps)

#: A squared closure residual this far below zero, relative to the squares it is made of, is
#: rounding at a toggle position and is clamped to zero rather than reported as unassemblable.
ASSEMBLY_SLACK: float = 64 * EPS

#: Conditioning below this is a singular position: the analogs are not defined there, or not
#: resolvable in double precision. Next to a toggle the conditioning grows like √|φ − φ_toggle|,
#: so one ulp of φ from the toggle already gives about √EPS; 64·√EPS ≈ 1e-6 takes in the samples
#: within about 1e-12 rad of a toggle, where the analogs (∝ 1/conditioning) would be 1e6 times
#: their typical size and carry no correct digits.
SINGULAR: float = 64 * float(np.sqrt(EPS))

#: Conditioning below this is reported as "near singular".
NEAR_SINGULAR: float = 1e-3

#: Step (rad) of the symmetric Richardson extrapolation that gives the analogs' limit at a
#: singular sample from the exact analogs at φ ± δ, ±2δ, ±4δ: truncation ~ δ⁶, rounding
#: ~ EPS/δ² in the acceleration analogs (which divide twice by a conditioning of order δ); 1e-2
#: balances them at about 1e-11 relative (measured on the parallelogram's change points).
LIMIT_STEP: float = 1e-2

#: The left and right limits of the analogs at a singular sample must agree to this, relative to
#: their size, for the limit to exist; otherwise the analogs there are undefined (NaN, flagged).
#: (Each one-sided estimate is a quadratic extrapolation, good to about δ³; the bound grows as
#: (h/δ)³ when a larger step h is used.) At a kink the two differ by O(1).
LIMIT_AGREEMENT: float = 1e-3

#: s + l and p + q of a four-bar closer than this (relative to the longest link) are equal: a
#: change-point (Grashof-neutral) four-bar.
GRASHOF_EQUAL: float = 64 * EPS

#: Bisection steps that refine a root in φ ∈ [0, 2π] to the last bit (2π/2⁶⁰ < EPS).
ROOT_ITERATIONS: int = 80

#: A joint whose velocity analog stays below this over the whole turn (rad/rad or m/rad) does not
#: move (a parallelogram's coupler angle): it has no dead centres, only rounding noise.
STATIONARY: float = 1e6 * EPS

#: Below this conditioning c the analogs are taken from their limit along the branch (when it
#: exists) rather than from the group's linear system, whose rounding error grows as EPS/c for
#: the velocity and EPS/c² for the acceleration analogs (measured on the parallelogram: 1e-7
#: relative at c = 1e-3, 1e-2 at c = 1e-5); the limit (see LIMIT_STEP) is good to about 1e-11
#: relative on either side of a change point.
REFINE_BELOW: float = 1e-2

#: The nodes of that limit must be conditioned at least this well (the system's acceleration
#: analogs are good to about 4e-11 relative there); otherwise a step of 2δ, then 4δ, is tried.
#: Measured on the parallelogram over 1e-12 ≤ |φ − φ_change| ≤ 0.3: velocity and acceleration
#: analogs within 4e-10 relative of the exact B' = A', B'' = A''.
LIMIT_NODE: float = 1e-2

#: An RRR dyad's closure h²·4D⁴ = ((l₁+l₂)² − D²)·(D² − (l₁−l₂)²) a little below zero is rounding
#: at a toggle, not a failure to assemble, when it is within this many units of its own rounding
#: bound: each factor is a difference of magnitudes — (l₁ ± l₂)², D², and 2·D·S for D² taken
#: from coordinates of size S = |A| + |C| (the conditioning of D) — and rounds to EPS times their
#: sum. Relative to the lengths and to that conditioning, so that a folded dyad (|l₁ − l₂| tiny)
#: is held to its own scale: a miss of the circles' intersection beyond rounding is refused
#: (solver/groups/rrr.py, tests/stability/test_stability_folded_boundary.py).
CLOSURE_ROUNDING: float = 16 * EPS

#: In a summary, a quantity whose largest magnitude over a sweep is at most this fraction of the
#: scale it is made of (the largest of its kind, or the products it sums) is printed as "zero to
#: rounding": e.g. a fixed point's speed, or the input power Σ Q·ω of a sweep at rest.
ZERO_TO_ROUNDING: float = 1e-12


#: A friction element's relative velocity analog (rad/rad at a pin, m/rad at a slide) at most this
#: times the rates it is a difference of (the two links' |dθ/dφ|, or the block's and its guide
#: point's |dB/dφ|) is a zero rounded (a four-bar's coupler and rocker turn alike where the crank
#: lies on the line of the fixed pivots: 3e-17 apart): the friction takes the direction of the
#: relative acceleration there (solver.forces.friction), not the sign of the rounding.
RELATIVE_REST: float = 1024 * EPS

#: Forward dynamics stops where a group's conditioning falls below this: next to a toggle the
#: reduced inertia grows like 1/conditioning², the motion reaches the toggle in finite time and
#: the inputs cannot drive through it (solver.dynamics). At 1e-3 (NEAR_SINGULAR) the equation is
#: still well resolved in double precision (M within about 1e6 of its typical size), so the
#: integrator's event locates the stop to its tolerance instead of failing on a stiff step.
DYNAMICS_TOGGLE: float = NEAR_SINGULAR

#: Breakpoints (solver.dynamics._breaks): an adaptive step toward a table's kink is aimed this
#: fraction past its predicted crossing (q + q̇τ + ½q̈τ² + ⅙q⃛τ³, off by O(τ⁴)). 0: at it — a step
#: that ends within √rtol of its move from the kink lands on it (an error O(δ²·Δslope)), one past
#: it by more is cut on its dense output (three more evaluations), one short of it by more is
#: followed by a short step. (1e-3, always past and cut: 16 evaluations a kink against 12.)
DYNAMICS_KINK_AIM: float = 0.0
#: A fixed (RK4) step that ends within this fraction of its move from a kink counts as on it (the
#: next piece is taken from there: an error O(miss²·Δslope), below RK4's own); beyond, the step is
#: tried once more to the crossing of its cubic Hermite interpolant.
DYNAMICS_KINK_MISS: float = 1.0e-6

#: Synthesis (solver.synthesis): a design whose largest miss of its targets, checked by solving the
#: returned scene, is at most this (m, or the joint's unit: rad, m) is "exact" — the round-off of
#: the closed forms at a linkage of about 1 m is ~1e-16·(a few hundred operations) ≪ this.
EXACT_MISS: float = 1e-9
