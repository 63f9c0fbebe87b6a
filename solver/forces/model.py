"""The force layer of a scene: route 2 (Assur groups in reverse plan order) on a plan run's jets.

``ForceModel.evaluate`` reads the jets a kinematics pass has just computed (no second pass),
puts every body's d'Alembert load, gravity and applied loads into its wrench, then solves the
groups from the last to the first (solver.forces.crank, .actuator, .rrr, .rrp, .slotted, .triad), each handing
the reactions at the pins it shares with earlier groups back to them, sign flipped. Closed form,
no iteration; the same source runs on numpy arrays and on Python scalars (solver._backend).
At samples where a group of the mechanism is singular (conditioning < tolerances.SINGULAR) every
effort and reaction is NaN and ``Kinematics.singular`` is True there.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from .._backend import Backend
from .._trace import TraceError
from ..groups import RRP, RRR, Actuator, CoupledCrank, Crank, SliderTriad, Slotted, Triad
from ..jet import Jet
from ..tolerances import SINGULAR
from .actuator import ActuatorForces
from .crank import CrankForces
from .frames import accel, inertial_wrench, spring_force, table_force
from .friction import FrictionModel
from .rrp import RRPForces
from .rrr import RRRForces
from .slider_triad import SliderTriadForces
from .slotted import SlottedForces
from .spec import Body, Damper, ForceSpec, PointForce, Spring, TableForce, Torque
from .state import ForcePass
from .structure import GROUND
from .triad import TriadForces

__all__ = ["ForceModel", "Step"]

Step = CrankForces | ActuatorForces | RRRForces | RRPForces | SlottedForces | TriadForces | SliderTriadForces


@dataclass(frozen=True)
class ForceModel:
    """A scene's force layer: its spec, the route-2 steps in plan order, and the inputs."""

    spec: ForceSpec
    inputs: tuple[str, ...]

    @cached_property
    def friction(self) -> FrictionModel | None:
        """The scene's Coulomb friction (solver.forces.friction), None without any."""
        f = self.spec.friction
        return None if f is None or f.empty else FrictionModel(f, self.spec.structure, self.inputs)

    @cached_property
    def steps(self) -> tuple[Step, ...]:
        st = self.spec.structure
        pin_index = {(p.point, p.body): i for i, p in enumerate(st.pins)}
        slide_index = {s.body: i for i, s in enumerate(st.slides)}
        owner = {(p.point, p.body): p.other for p in st.pins}
        out: list[Step] = []
        coupled: dict[str, list[tuple[str, float]]] = {}
        for g in st.groups:
            if isinstance(g, CoupledCrank):
                coupled.setdefault(g.source, []).append((g.joint, g.ratio))
        for g in st.groups:
            if isinstance(g, Crank):
                out.append(CrankForces(g.name, g.center, g.joint, pin_index[g.center, g.name], g.sign,
                                       tuple(coupled.get(g.joint, ()))))
            elif isinstance(g, Actuator):
                cyl = f"{g.name}.cylinder"
                out.append(ActuatorForces(g.name, cyl, g.base, g.pivot, g.point, g.joint,
                                          (owner[g.base, cyl], owner[g.pivot, g.name]),
                                          (pin_index[g.pivot, g.name], pin_index[g.base, cyl],
                                           pin_index[g.point, cyl])))
            elif isinstance(g, RRR):
                one, two = f"{g.name}.1", f"{g.name}.2"
                (a, c), b = g.ends, g.point
                out.append(RRRForces((one, two), (a, c), b, (owner[a, one], owner[c, two]),
                                     (pin_index[a, one], pin_index[c, two], pin_index[b, one])))
            elif isinstance(g, Triad):
                arms = (f"{g.name}.1", f"{g.name}.2", f"{g.name}.3")
                (a, b, c), (d, e, f) = g.ends, g.points
                out.append(TriadForces(arms, g.name, g.ends, g.points,
                                       (owner[a, arms[0]], owner[b, arms[1]], owner[c, arms[2]]),
                                       (pin_index[a, arms[0]], pin_index[b, arms[1]], pin_index[c, arms[2]],
                                        pin_index[d, arms[0]], pin_index[e, arms[1]], pin_index[f, arms[2]])))
            elif isinstance(g, SliderTriad):
                two, three, block = f"{g.name}.2", f"{g.name}.3", f"{g.name}.block"
                (b, c), (d, e, f) = g.ends, g.points
                pin = d if g.block_at is None else g.block_at
                guide = next(x.guide for x in st.slides if x.body == block)
                out.append(SliderTriadForces((two, three), g.name, block, g.ends, g.points,
                                             (owner[b, two], owner[c, three]), g.direction,
                                             (pin_index[b, two], pin_index[c, three], pin_index[e, two],
                                              pin_index[f, three], pin_index[pin, block]), slide_index[block],
                                             carrier=g.carrier,
                                             carrier_body=None if g.carrier is None or guide == GROUND else guide,
                                             block_at=g.block_at,
                                             block_owner=None if g.block_at is None else owner[g.block_at, block]))
            elif isinstance(g, RRP):
                block = f"{g.name}.block"
                out.append(RRPForces(g.name, block, g.end, g.point, owner[g.end, g.name], g.direction,
                                     (pin_index[g.end, g.name], pin_index[g.point, g.name]), slide_index[block]))
            elif isinstance(g, Slotted):
                block = f"{g.name}.block"
                out.append(SlottedForces(g.name, block, g.pivot, g.through,
                                         (owner[g.pivot, g.name], owner[g.through, block]),
                                         (pin_index[g.pivot, g.name], pin_index[g.through, block]),
                                         slide_index[block]))
        return tuple(out)

    @cached_property
    def targets(self) -> tuple[str, ...]:
        """The points and joints the force layer reads, and only those: the pins, the frames of
        the bodies that carry inertia or a torque, the loads' points, the tables' joints."""
        st = self.spec.structure
        turned = {ld.body for ld in self.spec.loads if isinstance(ld, Torque)}
        names = [p.point for p in st.pins]
        for b in self.spec.bodies:
            if not b.inert or b.name in turned:
                names += b.link.along or b.frame
        for ld in self.spec.loads:
            if isinstance(ld, Spring):
                names += [ld.ends[0][1], ld.ends[1][1]]
            elif isinstance(ld, (PointForce, TableForce)):
                names.append(ld.point)
            if isinstance(ld, (TableForce, Damper)):
                names.append(ld.joint)
        if self.friction is not None:
            names += [*self.friction.targets, *(s.joint for s in self.friction.spec.seals), *self.inputs]
        return tuple(dict.fromkeys(names))

    @cached_property
    def link_of(self) -> Mapping[str, str]:
        """A body's name → its link's (default) name, the key of the pass's wrenches."""
        return {b.name: b.link.name for b in self.spec.bodies}

    @cached_property
    def _loaded(self) -> tuple[Body, ...]:
        return tuple(b for b in self.spec.bodies if not b.inert)

    @cached_property
    def _lengths(self) -> dict[str, float]:
        """|frame vector| of the bodies whose two frame points are a rigid pair of the groups."""
        rigid = self.spec.structure.rigid
        return {b.name: rigid[frozenset(b.frame)] for b in self._loaded if frozenset(b.frame) in rigid}

    @cached_property
    def groups(self) -> tuple[str, ...]:
        return tuple(g.name for g in self.spec.structure.groups)

    @cached_property
    def refs(self) -> dict[str, str]:
        """Each link → the point its group takes moments about (its wrench's reference point)."""
        return {link: point for step in self.steps for link, point in step.refs().items()}

    def evaluate(self, values: Any, xp: Backend, conditioning: Mapping[str, Any], omega: Any, epsilon: Any) -> tuple:
        """Efforts (in ``inputs`` order), pin forces, slide forces and couples, as one flat tuple
        (see :meth:`layout`), from the jets ``values`` of a plan run at the rates ω, ε (with
        several inputs the jets are real motion: ω = 1, ε = 0)."""
        out = self.respond(values, xp, lambda s: self._apply_loads(s, omega, epsilon))
        if self.friction is not None:  # Coulomb friction: Newton on the affine responses
            if xp.name == "trace":
                raise TraceError("friction is not compiled: one instant is solved on the scalar path")
            out = self.friction.apply(self, values, xp, omega, epsilon, out)
        return _flag(tuple(out), conditioning, self.groups, xp)

    def respond(self, values: Any, xp: Backend, load: Callable[[ForcePass], None]) -> list[Any]:
        """The groups solved in reverse plan order under the loads that ``load`` puts on a fresh
        pass: efforts, pins, slides and couples (the base :attr:`layout`), unflagged."""
        n_pins, n_slides = self._counts
        s = ForcePass(values, xp, self.refs, n_pins, n_slides)
        load(s)
        for step in self._reversed_steps:
            step.solve(s)
        efforts = s.efforts
        out = [efforts.get(j, 0.0) for j in self.inputs]
        out += s.pins
        if n_slides:
            out += [f for f, _ in s.slides]
            out += [c for _, c in s.slides]
        return out

    @cached_property
    def _counts(self) -> tuple[int, int]:
        return len(self.spec.structure.pins), len(self.spec.structure.slides)

    @cached_property
    def _reversed_steps(self) -> tuple[Step, ...]:
        return self.steps[::-1]

    def _apply_loads(self, s: ForcePass, omega: Any, epsilon: Any) -> None:
        values = s.values
        ww = omega * omega
        acc: dict[str, Any] = {}  # real accelerations of the frames' points, each computed once

        def a_of(name: str) -> Any:
            a = acc.get(name)
            if a is None:
                jet = values[name]
                a = acc[name] = accel(jet.d1, jet.d2, ww, epsilon)
            return a

        def a_of_jet(jet: Jet) -> Any:
            return accel(jet.d1, jet.d2, ww, epsilon)

        lengths, gravity = self._lengths, self.spec.gravity
        for b in self._loaded:
            f, moment = inertial_wrench(b, s, a_of, a_of_jet, gravity, lengths.get(b.name))
            s.add_wrench(b.link.name, f, moment)
        link = self.link_of
        for ld in self.spec.loads:
            if isinstance(ld, PointForce):
                s.add(link[ld.body], ld.force, ld.point)
            elif isinstance(ld, Torque):
                s.couple(link[ld.body], ld.torque)
            elif isinstance(ld, Spring):
                f = spring_force(ld, values, s.xp)
                (b0, p0), (b1, p1) = ld.ends
                s.add(link.get(b0, GROUND), f, p0)
                s.add(link.get(b1, GROUND), f, p1, subtract=True)
            elif isinstance(ld, Damper):  # −c·s·q̇ on the body, the opposite on the other
                torque = values[ld.joint].d1 * (-ld.coefficient * ld.sign * omega)
                s.couple(link[ld.body], torque)
                if ld.other != GROUND:
                    s.couple(link[ld.other], -torque)
            else:
                s.add(link[ld.body], table_force(ld, values, s.xp), ld.point)

    @cached_property
    def layout(self) -> tuple[tuple[str, Any, bool], ...]:
        """What :meth:`evaluate` returns, in order: (kind, key, complex?) — ("effort", joint,
        False), ("pin", index, True), ("slide", index, True), ("couple", index, False)."""
        extra = () if self.friction is None else self.friction.layout
        return (*self.base_layout, *extra)

    @cached_property
    def base_layout(self) -> tuple[tuple[str, Any, bool], ...]:
        """The layout without friction's values (what :meth:`respond` returns)."""
        st = self.spec.structure
        return (
            *(("effort", j, False) for j in self.inputs),
            *(("pin", i, True) for i in range(len(st.pins))),
            *(("slide", i, True) for i in range(len(st.slides))),
            *(("couple", i, False) for i in range(len(st.slides))),
        )

    @cached_property
    def base_index(self) -> dict[tuple[str, Any], int]:
        return {(kind, key): i for i, (kind, key, _) in enumerate(self.base_layout)}


    @cached_property
    def index(self) -> dict[tuple[str, Any], int]:
        """(kind, key) → position in :attr:`layout`."""
        return {(kind, key): i for i, (kind, key, _) in enumerate(self.layout)}


def _flag(out: tuple, conditioning: Mapping[str, Any], groups: tuple[str, ...], xp: Backend) -> tuple:
    """NaN at the samples where a group is singular (unbounded there: flagged, never wrong)."""
    bad: Any = False
    for name in groups:
        c = conditioning.get(name)
        if c is None:
            continue
        if not xp.vectorised:
            if not c >= SINGULAR:
                return tuple(complex(math.nan, math.nan) if isinstance(x, complex) else math.nan for x in out)
            continue
        if np.size(c) and not np.min(c) >= SINGULAR:  # one pass (NaN included); the mask only when needed
            bad = bad | ~(np.asarray(c) >= SINGULAR)
    if bad is False:
        return out
    return tuple(np.where(bad, complex(math.nan, math.nan) if np.iscomplexobj(x) else math.nan, x) for x in out)
