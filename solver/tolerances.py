"""Named tolerances, in units of machine epsilon (spatialmath's habit).

Scale-free quantities (conditioning, relative errors) use these directly; lengths are scaled by
the scene's characteristic length before use.
"""

from __future__ import annotations

import numpy as np

__all__ = ["EPS", "ASSEMBLY_SLACK", "SINGULAR", "NEAR_SINGULAR"]

#: Machine epsilon of float64.
EPS: float = float(np.finfo(np.float64).eps)

#: A squared closure residual this far below zero, relative to the squares it is made of, is
#: rounding at a toggle position and is clamped to zero rather than reported as unassemblable.
ASSEMBLY_SLACK: float = 64 * EPS

#: Conditioning below this is a singular position: the analogs are not defined there.
SINGULAR: float = 1e6 * EPS

#: Conditioning below this is reported as "near singular".
NEAR_SINGULAR: float = 1e-3
