"""The numbers the message builder derives from a frame, traced once into straight-line code.

The URDF tree joints on ``joint_states`` (:mod:`linkage_ros.urdf.states`' own evaluation) and the
tips of the load arrows (``MessageBuilder.load_tips``) are run once on tracing values
(``solver._trace``, the compiled instant's tracer) read off a flat vector of a tick's numbers in
slot order (:mod:`linkage_ros.serialize`); what they did is recorded as lines of Python that
perform the same operations, so every bit is the evaluation's. :class:`TracedCode` is that
code, with the expression of each input number chosen by the caller (``read(i)``: ``"x[3]"``
for a function of the vector, a local name where :mod:`linkage_ros.instant` inlines the lines
into the tick's one generated function). None wherever the evaluation compares a traced value
or cannot be traced: then the builder's own evaluation runs per tick.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Sequence
from operator import itemgetter
from typing import Any, NamedTuple

from .frame import JointState, PointState
from .serialize import Slot

__all__ = ["TracedCode", "View", "compiled_tree", "compiled_view", "function_of", "tree_code", "view_code"]

#: ``read(i)``: the source text of the i-th number of the vector.
Read = Callable[[int], str]


class TracedCode(NamedTuple):
    """Lines of straight-line Python (no indentation), the expressions of the outputs in order,
    and the names the lines read (elementary functions, constants)."""

    lines: tuple[str, ...]
    outputs: tuple[str, ...]
    namespace: dict[str, Any]


def _vector(i: int) -> str:
    return f"x[{i}]"


def _rename(text: str, prefix: str) -> str:
    """The recorder's temporaries ``v12`` and constants ``k3`` as ``{prefix}v12``, ``{prefix}k3``
    (two pieces of traced code then share one function without a clash)."""
    return re.sub(r"\b([vk]\d+)\b", prefix + r"\1", text)


def _code(rec: Any, head: list[str], out: Sequence[Any], prefix: str) -> TracedCode | None:
    from solver._trace import Guard

    if any(isinstance(item, Guard) for item in rec.items):
        return None
    body = [f"{item.name} = {item.expr}" for item in rec.items]
    outputs = tuple(_rename(rec.atom(x)[0], prefix) for x in out)
    namespace: dict[str, Any] = {"complex": complex, "max": max, "abs": abs}
    namespace.update({n: getattr(math, n) for n in ("sqrt", "cos", "sin", "atan2", "tan")})
    namespace.update({prefix + name: value for name, value in rec.constants.values()})
    return TracedCode(tuple(head) + tuple(_rename(line, prefix) for line in body), outputs, namespace)


def tree_code(scene: Any, order: Sequence[Slot], values: tuple[Any, ...], *, read: Read = _vector,
              prefix: str = "") -> TracedCode | None:
    """The URDF tree joints' positions then velocities from the numbers in slot ``order``
    (traced at ``values``); None when the scene has no tree or the evaluation cannot be traced."""
    from solver._trace import TRACE, Recorder, TraceError

    from .urdf import exportable_model
    from .urdf.states import evaluate_tree, tree_inputs

    model = exportable_model(scene)
    if model is None:
        return None
    tree_points, tree_joints = tree_inputs(model)
    where = {slot: i for i, slot in enumerate(order)}
    rec = Recorder({})
    head: list[str] = []
    points: dict[str, tuple[Any, Any]] = {}
    joints: dict[str, tuple[Any, Any]] = {}
    try:
        for k, name in enumerate(tree_points):
            parts = []
            for kind in ("p", "v"):
                i, j = where[(kind, name, 0)], where[(kind, name, 1)]
                head.append(f"{prefix}point_{kind}{k} = complex({read(i)}, {read(j)})")
                parts.append(rec.input(f"{prefix}point_{kind}{k}", complex(values[i], values[j])))
            points[name] = (parts[0], parts[1])
        for k, name in enumerate(tree_joints):
            i, j = where[("j", name, 0)], where[("j", name, 1)]
            head += [f"{prefix}joint_q{k} = {read(i)}", f"{prefix}joint_dq{k} = {read(j)}"]
            joints[name] = (rec.input(f"{prefix}joint_q{k}", values[i]), rec.input(f"{prefix}joint_dq{k}", values[j]))
        q, dq = evaluate_tree(model, points, joints, atan2=TRACE.atan2, sin=TRACE.sin, cos=TRACE.cos,
                              floor=lambda x: TRACE.call(math.floor, x))
    except (TraceError, KeyError, TypeError):
        return None
    return _code(rec, head, (*q, *dq), prefix)


def view_code(produce: Callable[[Any], Sequence[Any]], view: View, values: tuple[Any, ...], *,
              read: Read = _vector, prefix: str = "") -> TracedCode | None:
    """``produce(view)`` (e.g. the builder's ``load_tips``) traced with the view reading the
    numbers (at ``values``); None when ``produce`` compares a traced value or needs a plain number."""
    from solver._trace import Recorder, TraceError

    rec = Recorder({})
    view.values = tuple(rec.input(read(i), v) for i, v in enumerate(values))
    try:
        out = tuple(produce(view))
    except (TraceError, TypeError, ValueError):
        return None
    finally:
        view.values = values
    return _code(rec, [], out, prefix)


def function_of(code: TracedCode | None, label: str) -> Callable[..., tuple[Any, ...]] | None:
    """``code`` (read with the default ``x[i]``) as ``f(x)`` giving its outputs as a tuple."""
    if code is None:
        return None
    outputs = "".join(o + ", " for o in code.outputs)
    source = "\n".join(["def derived(x):", *("    " + line for line in code.lines), f"    return ({outputs})"])
    namespace = dict(code.namespace)
    exec(compile(source, f"<{label}>", "exec"), namespace)
    return namespace["derived"]  # type: ignore[no-any-return]


def compiled_tree(scene: Any, order: Sequence[Slot], values: tuple[Any, ...]) -> Callable[..., tuple[Any, ...]] | None:
    """:func:`tree_code` as one function of the vector (None: see there)."""
    return function_of(tree_code(scene, order, values), f"tree joints of {scene.name}")


def compiled_view(produce: Callable[[Any], Sequence[Any]], view: View, values: tuple[Any, ...],
                  label: str) -> Callable[..., tuple[Any, ...]] | None:
    """:func:`view_code` as one function of the vector (None: see there)."""
    return function_of(view_code(produce, view, values), label)


class View:
    """A frame-like view of a flat vector (``.points``, ``.joints``: ``get`` / ``[]`` give the
    named tuples; ``.loads.get``: a load's (Fx, Fy, M)), read from the vector set last."""

    __slots__ = ("points", "joints", "loads", "values")

    def __init__(self, order: Sequence[Slot], dim: int) -> None:
        where = {slot: i for i, slot in enumerate(order)}

        def getter(kind: str, name: str) -> Callable[[Sequence[Any]], Any]:
            return itemgetter(*(where[(kind, name, c)] for c in range(dim)))

        self.values: tuple[Any, ...] = ()
        self.points = _Reader(self, {s[1]: (PointState, getter("p", s[1]), getter("v", s[1]))
                                     for s in order if s[0] == "p"})
        self.joints = _Reader(self, {s[1]: (JointState, itemgetter(where[("j", s[1], 0)]),
                                            itemgetter(where[("j", s[1], 1)]))
                                     for s in order if s[0] == "j"})
        self.loads = _Loads(self, {s[1]: itemgetter(*(where[("l", s[1], i)] for i in range(3)))
                                   for s in order if s[0] == "l" and s[2] == 0})


class _Loads:
    """``get``: a load's (Fx, Fy, M) from the view's vector."""

    __slots__ = ("_view", "_index")

    def __init__(self, view: View, index: dict[str, Any]) -> None:
        self._view, self._index = view, index

    def get(self, key: str, default: Any = None) -> Any:
        found = self._index.get(key)
        return default if found is None else found(self._view.values)


class _Reader:
    """``get`` / ``[]``: the position and velocity of one point or joint of the view's vector
    (the acceleration, which the tree joints do not read, is left empty)."""

    __slots__ = ("_view", "_index")

    def __init__(self, view: View, index: dict[str, Any]) -> None:
        self._view, self._index = view, index

    def get(self, name: str) -> Any:
        found = self._index.get(name)
        if found is None:
            return None
        kind, position, velocity = found
        values = self._view.values
        return kind(position(values), velocity(values), ())

    def __getitem__(self, name: str) -> Any:
        kind, position, velocity = self._index[name]
        values = self._view.values
        return kind(position(values), velocity(values), ())
