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
]

#: Machine epsilon of float64.
EPS: float = float(np.finfo(np.float64).eps)

#: A squared closure residual this far below zero, relative to the squares it is made of, is
#: rounding at a toggle position and is clamped to zero rather than reported as unassemblable.
ASSEMBLY_SLACK: float = 64 * EPS

#: Conditioning below this is a singular position: the analogs are not defined there.
SINGULAR: float = 1e6 * EPS

#: Conditioning below this is reported as "near singular".
NEAR_SINGULAR: float = 1e-3

#: Step (rad) of the symmetric Richardson extrapolation that gives the analogs' limit at a
#: singular sample from the exact analogs at φ ± δ, ±2δ, ±4δ: truncation ~ δ⁶, rounding
#: ~ EPS/δ² in the acceleration analogs (which divide twice by a conditioning of order δ); 1e-2
#: balances them at about 1e-11 relative (measured on the parallelogram's change points).
LIMIT_STEP: float = 1e-2

#: The left and right limits of the analogs at a singular sample must agree to this, relative to
#: their size, for the limit to exist; otherwise the analogs there are undefined (NaN, flagged).
#: (Each one-sided estimate is a quadratic extrapolation, good to about δ³.)
LIMIT_AGREEMENT: float = 1e-4

#: s + l and p + q of a four-bar closer than this (relative to the longest link) are equal: a
#: change-point (Grashof-neutral) four-bar.
GRASHOF_EQUAL: float = 64 * EPS

#: Bisection steps that refine a root in φ ∈ [0, 2π] to the last bit (2π/2⁶⁰ < EPS).
ROOT_ITERATIONS: int = 80
