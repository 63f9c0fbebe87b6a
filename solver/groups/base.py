"""What every group shares: its names in the plan and the context it is solved in."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from .._backend import Backend
from ..errors import AssemblyError, SampleAssemblyError
from ..jet import Jet

__all__ = ["Group", "Context", "at_most_one", "require_samples"]


def at_most_one(x: Any) -> Any:
    """``min(x, 1)`` for a scalar or elementwise for an array."""
    return np.minimum(x, 1.0) if isinstance(x, np.ndarray) else min(x, 1.0)


Num = Any


@dataclass
class Context:
    """One evaluation of a plan: the crank angle(s), the evaluator, and the jets solved so far.

    Points and joints share one namespace, ``values``. ``conditioning`` collects each group's
    dimensionless conditioning figure (1 = well conditioned, 0 = singular). With
    ``mask=True`` unassemblable samples are recorded in ``invalid`` instead of raising.
    """

    phi: Num
    xp: Backend
    values: dict[str, Jet] = field(default_factory=dict)
    conditioning: dict[str, Num] = field(default_factory=dict)
    mask: bool = False
    invalid: Num = False
    scene: str | None = None
    find_intervals: Callable[[str], list[tuple[float, float]]] | None = None
    #: The Scene being solved, for the analyses that need its whole plan: a continuous branch's
    #: change points and the analogs' limit at a singular sample (solver.singular).
    owner: Any = None
    #: Several inputs (solver.multi): each input joint's directional jet ``(q, u, s)``, which the
    #: cranks start from instead of ``(φ, 1, 0)``; ``phi`` then holds the (N, k) samples (a
    #: k-tuple on the per-tick path). ``None`` for a single-input scene.
    seeds: Mapping[str, Jet] | None = None

    def input_units(self) -> tuple[str, ...]:
        """Each input's unit, "rad" (a crank's angle) or "m" (an actuator's stroke), from the owner."""
        units = getattr(self.owner, "input_units", None)
        return tuple(units) if units else ("rad",)

    def intervals_of(self, group: str) -> list[tuple[float, float]]:
        """The φ intervals in which ``group`` cannot be assembled, where the plan can tell."""
        return self.find_intervals(group) if self.find_intervals is not None else []

    def require(self, group: Group, ok: Num, *, reason: str = "cannot be assembled") -> None:
        """Stop (or, in mask mode, record) the samples where ``ok`` is false."""
        if self.seeds is not None:  # several inputs: the failing samples are rows of (q₁ … q_k)
            require_samples(self, group, ok, reason)
            return
        if not self.xp.vectorised:
            if not ok:
                if self.mask:
                    self.invalid = True
                    return
                raise AssemblyError(
                    group=group.name,
                    phi=[self.phi],
                    intervals=self.intervals_of(group.name),
                    reason=reason,
                    scene=self.scene,
                    unit=self.input_units()[0],
                )
            return
        if bool(np.all(ok)):
            return
        # (a constant ``ok`` — a group between fixed points — fails at every sample of the block)
        bad = np.broadcast_to(~np.asarray(ok, dtype=bool), np.shape(self.phi))
        if self.mask:
            self.invalid = self.invalid | bad
            return
        phi = np.broadcast_to(self.phi, bad.shape)
        raise AssemblyError(
            group=group.name,
            phi=phi[bad].tolist(),
            intervals=self.intervals_of(group.name),
            reason=reason,
            scene=self.scene,
            unit=self.input_units()[0],
        )


@dataclass(frozen=True)
class Group:
    """A structural group: solves some points and joints from others, in closed form.

    Subclasses state their loop equation, derivatives, linear system and branch rule in their
    module docstring, list what they read in :meth:`requires` and what they write in
    :meth:`provides`, and implement :meth:`solve`.
    """

    kind: ClassVar[str] = ""
    #: True for a group that takes an input coordinate (a crank); a scene has one per input.
    drives: ClassVar[bool] = False
    name: str

    def joints(self) -> tuple[str, ...]:
        """Which of the provided names are joint coordinates (the rest are points)."""
        return ()

    def hidden(self) -> tuple[str, ...]:
        """Provided names that are neither points nor joints: internal values (the vector model's parameters)."""
        return ()

    def rigid_pairs(self) -> tuple[tuple[str, str, float], ...]:
        """Pairs of points this group keeps at a fixed distance: ``(P, Q, |PQ|)``."""
        return ()

    def joint_units(self) -> dict[str, str]:
        """The unit of each provided joint coordinate: "rad" (the default) or "m"."""
        return {name: "rad" for name in self.joints()}

    def input_joint(self) -> str | None:
        """The joint whose coordinate is φ, for the driving group."""
        return None

    def input_range(self) -> tuple[float, float] | None:
        """The range of a driving group's input where it has one (an actuator's stroke, m);
        None for an angle, which turns."""
        return None

    def requires(self) -> tuple[str, ...]:
        raise NotImplementedError

    def provides(self) -> tuple[str, ...]:
        raise NotImplementedError

    def links(self) -> tuple[tuple[str, ...], ...]:
        """Polylines of point names that draw this group's bodies."""
        return ()

    def solve(self, ctx: Context) -> None:
        raise NotImplementedError

    def singular_names(self) -> tuple[str, ...]:
        """The provided names whose analogs come from a linear system that can be singular: the
        runner of the plan refines them there (solver.singular.refine_singular)."""
        return ()

    def restricted(self, wanted: set[str]) -> Group:
        """This group computing only what ``wanted`` needs of it (itself where it cannot narrow)."""
        return self


def require_samples(ctx: Context, group: Group, ok: Any, reason: str) -> None:
    """``Context.require`` with several inputs: stop at (or, in mask mode, record) the samples
    where ``ok`` is false, naming them as rows of (q₁ … q_k)."""
    assert ctx.seeds is not None
    if not ctx.xp.vectorised:
        if ok:
            return
        if ctx.mask:
            ctx.invalid = True
            return
        raise SampleAssemblyError(group=group.name, samples=[ctx.phi], inputs=list(ctx.seeds), reason=reason,
                                  scene=ctx.scene, units=ctx.input_units())
    if bool(np.all(ok)):
        return
    bad = ~np.asarray(ok, dtype=bool)
    if ctx.mask:
        ctx.invalid = ctx.invalid | bad
        return
    phi = np.asarray(ctx.phi)
    rows = phi[np.broadcast_to(bad, phi.shape[:1])]
    raise SampleAssemblyError(group=group.name, samples=rows, inputs=list(ctx.seeds), reason=reason, scene=ctx.scene,
                              units=ctx.input_units())
