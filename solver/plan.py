"""From a scene's groups to an ordered, pruned plan (structure apart from solving).

A plan holds only the groups that the requested outputs depend on, in an order where every
group's inputs are solved before it. Running the plan is a single pass over that list.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any

from .errors import SceneError
from .groups import Context, Group
from .jet import Jet, constant

__all__ = ["Plan", "order_groups", "build_plan"]


def order_groups(groups: Sequence[Group], known: Iterable[str], *, file: str | None = None) -> tuple[Group, ...]:
    """Groups in dependency order; a group whose inputs nothing provides is a SceneError."""
    available = set(known)
    pending = list(groups)
    ordered: list[Group] = []
    while pending:
        ready = [g for g in pending if set(g.requires()) <= available]
        if not ready:
            providers = {n for g in pending for n in g.provides()}
            g = pending[0]
            missing = sorted(set(g.requires()) - available)
            unknown = [m for m in missing if m not in providers]
            if unknown:
                raise SceneError(
                    f"unknown point or joint {', '.join(repr(u) for u in unknown)}",
                    file=file,
                    entry=f"{g.kind} '{g.name}'",
                )
            raise SceneError(
                "groups depend on each other in a cycle: "
                + ", ".join(f"'{p.name}' needs {sorted(set(p.requires()) - available)}" for p in pending),
                file=file,
                entry="groups",
            )
        for g in ready:
            pending.remove(g)
            ordered.append(g)
            available.update(g.provides())
    return tuple(ordered)


@dataclass(frozen=True)
class Plan:
    """Groups in dependency order, pruned to what ``targets`` need."""

    groups: tuple[Group, ...]
    fixed: Mapping[str, Any]  # name → complex (planar) or ndarray (spatial)
    targets: tuple[str, ...]

    @cached_property
    def fixed_jets(self) -> dict[str, Jet]:
        return {name: constant(value) for name, value in self.fixed.items()}

    def run(self, ctx: Context) -> Context:
        ctx.values.update(self.fixed_jets)
        for group in self.groups:
            group.solve(ctx)
        return ctx

    @property
    def group_names(self) -> tuple[str, ...]:
        return tuple(g.name for g in self.groups)


def build_plan(ordered: Sequence[Group], fixed: Mapping[str, Any], targets: Iterable[str]) -> Plan:
    """Keep the groups that the targets depend on, transitively, in the given order."""
    targets = tuple(dict.fromkeys(targets))
    provider = {n: g for g in ordered for n in g.provides()}
    needed: set[str] = set()
    keep: set[str] = set()
    stack = [t for t in targets if t not in fixed]
    while stack:
        name = stack.pop()
        if name in needed:
            continue
        needed.add(name)
        g = provider[name]
        if g.name not in keep:
            keep.add(g.name)
            stack.extend(r for r in g.requires() if r not in fixed)
    wanted = needed | {r for g in ordered if g.name in keep for r in g.requires()}
    kept = tuple(g.restricted(wanted) for g in ordered if g.name in keep)
    used_fixed = {n: v for n, v in fixed.items() if any(n in g.requires() for g in kept) or n in targets}
    return Plan(kept, used_fixed, targets)
