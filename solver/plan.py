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
    # In rounds, as a scan of the pending list would take them (each round: every pending group
    # whose inputs are available, in scene order), but in linear time: each group counts its
    # unmet inputs, and a name that becomes available releases only the groups waiting for it.
    waiting: dict[str, list[int]] = {}
    unmet: list[int] = []
    for i, g in enumerate(pending):
        need = set(g.requires()) - available
        unmet.append(len(need))
        for n in need:
            waiting.setdefault(n, []).append(i)
    ready = [i for i, count in enumerate(unmet) if count == 0]
    while ready:
        ordered.extend(pending[i] for i in ready)
        released: list[int] = []
        for i in ready:
            for n in pending[i].provides():
                if n not in available:
                    available.add(n)
                    for k in waiting.pop(n, ()):
                        unmet[k] -= 1
                        if unmet[k] == 0:
                            released.append(k)
        ready = sorted(released)
    if len(ordered) < len(pending):
        placed = {id(g) for g in ordered}
        pending = [g for g in pending if id(g) not in placed]
        if pending:
            providers = {n for g in pending for n in g.provides()}
            g = pending[0]
            missing = sorted(set(g.requires()) - available)
            unknown = [m for m in missing if m not in providers]
            if unknown:
                raise SceneError(
                    f"unknown point or joint {', '.join(repr(u) for u in unknown)} (nothing provides it: "
                    "a misspelt name, or too few inputs — no input moves it)",
                    file=file,
                    entry=f"{g.kind} '{g.name}'",
                )
            more = f" and {len(pending) - 8} more" if len(pending) > 8 else ""
            raise SceneError(
                "groups depend on each other in a cycle: "
                + ", ".join(f"'{p.name}' needs {sorted(set(p.requires()) - available)}" for p in pending[:8])
                + more,
                file=file,
                entry="groups",
            )
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

    @cached_property
    def _steps(self) -> tuple[tuple[Group, bool], ...]:
        return tuple((g, bool(g.singular_names())) for g in self.groups)

    def run(self, ctx: Context) -> Context:
        """Solve the groups in order. After each group that can be singular, the context's owner
        (the Scene) refines its analogs there: ``owner.refine_group(ctx, group)``
        (solver.singular); the groups themselves never look beyond their inputs."""
        ctx.values.update(self.fixed_jets)
        refine = getattr(ctx.owner, "refine_group", None)
        for group, singular in self._steps:
            group.solve(ctx)
            if singular and refine is not None:
                refine(ctx, group)
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
