"""Efforts and reactions of a solve, as the user reads them (``k.effort``, ``k.reaction``, ``k.slide``)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, NamedTuple

import numpy as np

from ..errors import SolverError
from .friction import efficiency
from .model import ForceModel

__all__ = ["ForceResult", "ForceBuffers", "SlideReaction"]


class SlideReaction(NamedTuple):
    """The whole reaction of a prismatic pair on its block: ``force`` (normal to the guide, N;
    (N, 2) or (2,)) acting at the block's pin, and ``couple`` (N·m about +z; (N,) or float),
    both from ``guide`` (the ground, or a slotted link) on ``body``. Its line of action lies at
    the signed distance couple/|force| from the pin, along the guide."""

    force: np.ndarray
    couple: Any
    body: str
    guide: str


def _vec(z: Any, n: int | None, *, negate: bool = False) -> np.ndarray:
    """``z`` (or ``−z``) as a (2,) vector, or as (N, 2) floats: one fresh contiguous complex array
    (never the result's own buffer) seen as float pairs — one pass, no stacking of parts."""
    if n is None:
        z = -complex(z) if negate else complex(z)
        return np.array([z.real, z.imag])
    arr = np.broadcast_to(np.asarray(z, np.complex128), (n,))
    arr = np.negative(arr) if negate else np.array(arr)
    return arr.view(np.float64).reshape(n, 2)


class ForceResult:
    """The force layer's values of one solve: a flat list in ``model.layout`` order — Python
    numbers for one instant (``samples=None``), (N,) arrays for a sweep."""

    def __init__(self, model: ForceModel, data: Sequence[Any], samples: int | None) -> None:
        self.model = model
        self._data = list(data)
        self._n = samples
        self._index = model.index

    def effort(self, joint: str) -> Any:
        """The input ``joint``'s effort: torque (N·m, about +z) on a crank from its actuator."""
        i = self._index.get(("effort", joint))
        if i is None:
            raise SolverError(f"'{joint}' is not an input joint; efforts are given for {list(self.model.inputs)}")
        x = self._data[i]
        return float(x) if self._n is None else np.broadcast_to(np.asarray(x, float), (self._n,))

    def reaction(self, point: str, *, on: str, by: str | None = None) -> np.ndarray:
        """The force (N, world frame) on body ``on`` at the pin ``point`` from the body ``by`` (the
        other side; needed only where three bodies meet at one point): (N, 2) or (2,)."""
        pins = self.model.spec.pins
        found = []
        for i, p in enumerate(pins):
            if p.point != point or (by is not None and by not in (p.body, p.other)):
                continue
            if p.body == on and p.other != on:
                found.append((i, 1.0, p.other))
            elif p.other == on:
                found.append((i, -1.0, p.body))
        if not found:
            here = [f"{p.body}–{p.other}" for p in pins if p.point == point]
            where = f"pins at {point}: {', '.join(here)}" if here else f"no pin at '{point}'"
            raise SolverError(f"no pin at '{point}' on body '{on}'{f' from {by!r}' if by else ''}; {where}")
        if len(found) > 1:
            others = ", ".join(o for _, _, o in found)
            raise SolverError(f"'{on}' has {len(found)} pins at '{point}' (with {others}): say which with by=")
        i, sign, _ = found[0]
        return _vec(self._data[self._index["pin", i]], self._n, negate=sign < 0)

    def slide_reaction(self, body: str) -> SlideReaction:
        """The prismatic pair of the slider block ``body``: its normal force and couple."""
        for i, s in enumerate(self.model.spec.slides):
            if s.body == body:
                c = self._data[self._index["couple", i]]
                couple = float(c) if self._n is None else np.broadcast_to(np.asarray(c, float), (self._n,))
                return SlideReaction(_vec(self._data[self._index["slide", i]], self._n), couple, s.body, s.guide)
        blocks = [s.body for s in self.model.spec.slides]
        raise SolverError(f"'{body}' is not a slider block; blocks: {blocks}")


    # -- friction (solver.forces.friction) ---------------------------------------------------------
    def _friction_value(self, key: tuple[str, Any]) -> Any:
        if self.model.friction is None:
            raise SolverError("this scene has no friction (none named, or every mu, radius and seal force zero): "
                              "its efforts are ideal (docs/forces.md#friction)")
        x = self._data[self._index[key]]
        return float(x) if self._n is None else np.broadcast_to(np.asarray(x, float), (self._n,))

    def ideal_effort(self, joint: str) -> Any:
        """The effort of input ``joint`` without friction (Q₀)."""
        self.effort(joint)  # the check of the name
        return self._friction_value(("effort0", joint))

    def friction_loss(self, name: str) -> Any:
        """The power (W, ≥ 0) friction dissipates at the pin(s) at point ``name``, in the slider
        block ``name``'s guide, or in the actuator ``name``'s seal."""
        f = self.model.friction
        if f is None:
            return self._friction_value(("loss", None))
        spec = self.model.spec
        keys: list[tuple[str, Any]] = [("loss", (e.kind, e.index)) for e in f.elements
                                        if (e.kind == "pin" and e.point == name)
                                        or (e.kind == "slide" and name in (e.body, spec.slides[e.index].body))]
        keys += [("loss", ("seal", s.joint)) for s in f.spec.seals if s.actuator == name]
        if not keys:
            known = [*dict.fromkeys(e.point if e.kind == "pin" else spec.slides[e.index].body for e in f.elements),
                     *(s.actuator for s in f.spec.seals)]
            raise SolverError(f"no friction at '{name}'; friction at: {', '.join(known)}")
        total = sum(self._friction_value(k) for k in keys)
        return total

    @property
    def friction_power(self) -> Any:
        """The power (W) all friction dissipates: Σ losses = (Q − Q₀)·q̇ summed over the inputs."""
        f = self.model.friction
        if f is None:
            return self._friction_value(("loss", None))
        return sum((self._friction_value(k) for kind, k, _ in f.layout if kind == "loss" for k in [("loss", k)]),
                   0.0 if self._n is None else np.zeros(self._n))

    @property
    def input_power(self) -> Any:
        """Σ Q·q̇ (W): the power the inputs put in (negative where the mechanism drives them)."""
        return self._friction_value(("power", None))

    @property
    def locked(self) -> Any:
        """True where the mechanism self-locks (no effort drives it; every value NaN there)."""
        x = self._friction_value(("locked", None))
        return bool(x == 1.0) if self._n is None else np.asarray(x) == 1.0

    @property
    def efficiency(self) -> Any:
        """Instantaneous efficiency from the input power P = Σ Q·q̇ and the ideal P₀ = Σ Q₀·q̇:
        P₀/P where the ideal mechanism takes power from its inputs (P₀ > 0: the inputs drive, η =
        Q₀/Q with one input); P/P₀ where it gives power to them (P₀ < 0: the loads drive, the
        back-driving efficiency; negative where friction still needs the input to push — the
        mechanism holds itself); where P₀ = 0, 1 if P = 0 (at rest) else 0. NaN only where
        ``locked`` or singular."""
        eta = efficiency(self.input_power, self._friction_value(("power0", None)))  # solver.forces.friction
        return float(eta) if self._n is None else eta


class ForceBuffers:
    """The (N,) arrays a sweep's blocks write their force values into: contiguous views of one
    allocation (one call to the allocator instead of one per value; a large one is backed by
    huge pages where the system offers them: far fewer page faults on the first write)."""

    def __init__(self, model: ForceModel, n: int) -> None:
        self.model = model
        self.n = n
        kinds = [cplx for _, _, cplx in model.layout]
        n_complex = sum(kinds)
        whole = np.empty(n * (2 * n_complex + len(kinds) - n_complex), np.float64)
        complex_part = whole[: 2 * n * n_complex].view(np.complex128)  # first: 16-byte aligned
        real_part = whole[2 * n * n_complex:]
        counts = [0, 0]
        self.arrays: list[np.ndarray] = []
        for cplx in kinds:
            i = counts[cplx]
            counts[cplx] += 1
            self.arrays.append(complex_part[i * n:(i + 1) * n] if cplx else real_part[i * n:(i + 1) * n])

    def put(self, rows: slice, values: Sequence[Any]) -> None:
        for arr, v in zip(self.arrays, values):
            arr[rows] = v

    def result(self, valid: np.ndarray | None = None) -> ForceResult:
        """The values; NaN at the samples ``valid`` marks unassemblable (mask mode)."""
        if valid is not None and not valid.all():
            for arr in self.arrays:
                arr[~valid] = np.nan
        return ForceResult(self.model, self.arrays, self.n)
