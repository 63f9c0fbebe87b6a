"""The traced paths of one compiled unit as a tree, written as Python (solver._codegen).

Paths agree line for line up to the guard where they part (:func:`merge` adds one to the tree);
:func:`prune` keeps the lines some output or guard needs; :func:`share` writes the common tail of
two sides of a branch once, after the if/else; :func:`emit` writes the tree, folding each
temporary read once into the expression that reads it (the same operations on the same operands
in the same order: Python evaluates operands left to right).
"""

from __future__ import annotations

import re
from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from ._trace import Guard, Let

__all__ = ["Node", "merge", "prune", "copy_tree", "share", "emit", "fold_single_use", "INLINE_DEPTH", "TUPLE_CHUNK"]


@dataclass
class Node:
    """Straight-line ``items``, then either a branch on a guard or the return of ``ret``."""

    items: list[Let | Guard]
    ret: tuple[str, ...] | None
    ret_uses: tuple[str, ...] = ()
    branch: tuple[Guard, dict[bool, Node]] | None = None
    live: list[Let | Guard] = field(default_factory=list)
    #: after the branch: the tail its two sides share (written once, after the if/else)
    after: Node | None = None


def merge(node: Node, items: list[Let | Guard], ret: tuple[str, ...], uses: tuple[str, ...]) -> bool:
    """Add one traced path to the tree; False when it cannot be placed (it then stays uncompiled)."""
    i = 0
    while True:
        for j, it in enumerate(node.items):
            k = i + j
            if k < len(items) and items[k] == it:
                continue
            other = items[k] if k < len(items) else None
            if isinstance(it, Guard) and isinstance(other, Guard) and it.expr == other.expr:
                tail = Node(node.items[j + 1:], node.ret, node.ret_uses, node.branch)
                new = Node(items[k + 1:], ret, uses)
                node.items, node.ret, node.ret_uses = node.items[:j], None, ()
                node.branch = (it, {it.outcome: tail, other.outcome: new})
                return True
            return False
        i += len(node.items)
        if node.branch is None:
            return False  # the same path again: nothing new
        guard, kids = node.branch
        other = items[i] if i < len(items) else None
        if not isinstance(other, Guard) or other.expr != guard.expr:
            return False
        if other.outcome not in kids:
            kids[other.outcome] = Node(items[i + 1:], ret, uses)
            return True
        node, i = kids[other.outcome], i + 1


def prune(node: Node) -> set[str]:
    """Keep the lines some output or guard needs; returns the names live on entry."""
    if node.branch is None:
        live = set(node.ret_uses)
    else:
        guard, kids = node.branch
        live = set(guard.uses)
        for kid in kids.values():
            live |= prune(kid)
    kept: list[Let | Guard] = []
    for it in reversed(node.items):
        if isinstance(it, Let):
            if it.name not in live:
                continue
            live.discard(it.name)
        live.update(it.uses)
        kept.append(it)
    node.live = kept[::-1]
    return live


def copy_tree(node: Node) -> Node:
    """The tree's nodes copied (the recorded lines themselves are immutable and shared)."""
    branch = None
    if node.branch is not None:
        guard, kids = node.branch
        branch = (guard, {k: copy_tree(v) for k, v in kids.items()})
    return Node(list(node.items), node.ret, node.ret_uses, branch)


def share(node: Node) -> None:
    """Two sides of a branch that end alike keep only their heads; the common tail follows the if."""
    if node.branch is None:
        return
    kids = node.branch[1]
    for kid in kids.values():
        share(kid)
    yes, no = kids[True], kids[False]
    if yes.branch is not None or no.branch is not None or yes.ret != no.ret or yes.ret is None:
        return
    shared = 0
    while (shared < min(len(yes.live), len(no.live))
           and yes.live[len(yes.live) - 1 - shared] == no.live[len(no.live) - 1 - shared]):
        shared += 1
    if shared:
        node.after = Node([], yes.ret, yes.ret_uses, None, yes.live[len(yes.live) - shared:])
        for kid in (yes, no):
            kid.live, kid.ret, kid.ret_uses = kid.live[: len(kid.live) - shared], None, ()


def _counts(node: Node, counts: Counter[str]) -> Counter[str]:
    """How often each name is read in the (pruned) subtree of ``node``."""
    texts = [it.expr for it in node.live]
    texts += list(node.ret or ()) if node.branch is None else [node.branch[0].expr]
    counts.update(u for text in texts for u in _NAME.findall(text))
    if node.branch is not None:
        for kid in node.branch[1].values():
            _counts(kid, counts)
    if node.after is not None:
        _counts(node.after, counts)
    return counts


_NAME = re.compile(r"\bv\d+\b")
#: how deep single-use temporaries are folded into the expression that reads them
INLINE_DEPTH = 6


def fold_single_use(
    lines: Sequence[tuple[str | None, str]],
    end: Sequence[str],
    *,
    names: re.Pattern[str] = _NAME,
    depth: int = INLINE_DEPTH,
    elsewhere: Mapping[str, int] | None = None,
) -> tuple[list[tuple[str | None, str]], list[str]]:
    """Straight-line ``lines`` (``(name, expression)``; a name of None: a line that binds nothing,
    such as a guard's condition, kept in its place) and the ``end`` expressions that read them,
    with each name read once, and only here (``elsewhere``: reads of the code that runs after),
    folded in parentheses into the one expression that reads it, at most ``depth`` deep:
    ``v9 = (v7.real * v7.real)`` instead of a name stored and loaded again. The same operations
    on the same operands in the same order (Python evaluates operands left to right; every name
    is bound once and every operation is pure). ``names`` matches the names to count."""
    outside = elsewhere or {}
    local: dict[str, int] = {}
    for text in [*(expr for _, expr in lines), *end]:
        for u in names.findall(text):
            local[u] = local.get(u, 0) + 1
    pending: dict[str, tuple[str, int]] = {}

    def fold(expr: str) -> tuple[str, int]:
        deepest = 0

        def one(m: re.Match[str]) -> str:
            nonlocal deepest
            held = pending.pop(m.group(0), None)
            if held is None:
                return m.group(0)
            deepest = max(deepest, held[1] + 1)
            return f"({held[0]})"

        return names.sub(one, expr), deepest

    kept: list[tuple[str | None, str]] = []
    for name, expr in lines:
        text, level = fold(expr)
        if name is not None and local.get(name, 0) == 1 and not outside.get(name) and level < depth:
            pending[name] = (text, level)
        else:
            kept.append((name, text))
    tail = [fold(text)[0] for text in end]
    kept += [(n, t) for n, (t, _) in pending.items()]  # (none are left where each is read here)
    return kept, tail


def _segment(items: list[Let | Guard], end: list[str], elsewhere: Counter[str]) -> tuple[list[str], list[str]]:
    """Lines of one straight-line segment, and its ``end`` expressions (the return's atoms or the
    branch's condition), temporaries read once folded into their reader (:func:`fold_single_use`);
    a guard is a line that binds nothing."""
    pairs = [(it.name if isinstance(it, Let) else None, it.expr) for it in items]
    kept, tail = fold_single_use(pairs, end, elsewhere=elsewhere)
    guards = iter(it for it in items if isinstance(it, Guard))
    lines: list[str] = []
    for name, text in kept:
        if name is not None:
            lines.append(f"{name} = {text}")
        elif next(guards).outcome:
            lines.append(f"if not ({text}): return {{miss}}")
        else:
            lines.append(f"if {text}: return {{miss}}")
    return lines, tail


#: CPython builds a tuple display of more than 30 items through a list, item by item; a sum of
#: displays of at most 30 is one BUILD_TUPLE each (the same items, in the same order)
TUPLE_CHUNK = 30


def _tuple(items: list[str]) -> str:
    """``(a, b, …)`` for the return, written as a sum of displays of at most TUPLE_CHUNK items."""
    parts = [items[i:i + TUPLE_CHUNK] for i in range(0, len(items), TUPLE_CHUNK)] or [[]]
    return " + ".join(f"({', '.join(p)}{',' if len(p) == 1 else ''})" for p in parts)


def emit(node: Node, pad: str, miss: str, out: list[str], outer: Counter[str]) -> None:
    """Write ``node``; ``outer``: the reads of the code that runs after it (its ancestors' tails)."""
    end = list(node.ret or ()) if node.branch is None else [node.branch[0].expr]
    later = outer + (_counts(node.after, Counter()) if node.after is not None else Counter())
    elsewhere = later.copy()
    if node.branch is not None:
        for kid in node.branch[1].values():
            elsewhere += _counts(kid, Counter())
    lines, tail = _segment(node.live, end, elsewhere)
    out.extend(pad + line.replace("{miss}", miss) for line in lines)
    if node.branch is None:
        if node.ret is None:  # the head of a branch whose tail follows the if/else
            if not lines:
                out.append(f"{pad}pass")
            return
        out.append(f"{pad}return {_tuple(tail)}")
        return
    kids = node.branch[1]
    out.append(f"{pad}if {tail[0]}:")
    emit(kids[True], pad + "    ", miss, out, later)
    out.append(f"{pad}else:")
    emit(kids[False], pad + "    ", miss, out, later)
    if node.after is not None:
        emit(node.after, pad, miss, out, outer)
