"""The numbers the message builder derives from a frame, traced once into straight-line code.

The URDF tree joints on ``joint_states`` (:mod:`linkage_ros.urdf.states`' own evaluation) and the
tips of the load arrows (``MessageBuilder.load_tips``) are run once on tracing values
(:mod:`solver.tracing`, the compiled instant's tracer) read off a flat vector of a tick's numbers in
slot order (:mod:`linkage_ros.serialize`); what they did is recorded as lines of Python that
perform the same operations, so every bit is the evaluation's. :class:`TracedCode` is that
code, with the expression of each input number chosen by the caller (``read(i)``: ``"x[3]"``
for a function of the vector, a local name where :mod:`linkage_ros.instant` inlines the lines
into the tick's one generated function). None wherever the evaluation compares a traced value
or cannot be traced: then the builder's own evaluation runs per tick.

The recorded lines are then cut down without changing an operation (:func:`_split`: sums and
differences of complex numbers part by part, no ``x - 0.0``, no dead lines; :func:`_inline`:
each temporary read once written into its reader): the harvester finger's tree joints ≈ 2 → 1.2 µs;
``tests/ros/test_ros_fast_path.py`` checks the result against the lines as recorded, bit for bit.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Sequence
from operator import itemgetter
from typing import Any, NamedTuple

from solver.tracing import TRACE, Guard, Recorder, TraceError, fold_single_use

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


def _code(rec: Any, head: list[str], out: Sequence[Any], prefix: str, simplify: bool = True) -> TracedCode | None:
    if any(isinstance(item, Guard) for item in rec.items):
        return None
    lines = [(line.partition(" = ")[0], line.partition(" = ")[2]) for line in head]
    lines += [(item.name, item.expr) for item in rec.items]
    outputs = [rec.atom(x)[0] for x in out]
    types = getattr(rec, "types", None)
    if simplify and types is not None:
        types.update({name: type(value) for name, value in rec.constants.values()})
        lines, outputs = _split(lines, outputs, types)
    if simplify:
        lines, outputs = _inline(lines, outputs)
    body = [f"{name} = {expr}" for name, expr in lines]
    renamed = tuple(_rename(text, prefix) for text in outputs)
    namespace: dict[str, Any] = {"complex": complex, "max": max, "abs": abs}
    namespace.update({n: getattr(math, n) for n in ("sqrt", "cos", "sin", "atan2", "tan")})
    namespace.update({prefix + name: value for name, value in rec.constants.values()})
    return TracedCode(tuple(_rename(line, prefix) for line in body), renamed, namespace)


_NAME = re.compile(r"[A-Za-z_]\w*")
_COMPLEX = re.compile(r"complex\(([^,()]+), ([^,()]+)\)")
_SUM = re.compile(r"(\w+) ([-+]) (\w+)")
_PART = re.compile(r"(\w+)\.(real|imag)")
#: a name or an item of the vector (``x[3]``): the parts ``complex(x, y)`` is read as
_READ = re.compile(r"[A-Za-z_]\w*(\[\d+\])?")


#: the deepest nesting of parentheses :func:`_inline` writes (far below the parser's limit)
_DEPTH = 24


def _inline(lines: list[tuple[str, str]], outputs: list[str]) -> tuple[list[tuple[str, str]], list[str]]:
    """Each name read once written into the one expression that reads it, in parentheses
    (:func:`solver.tracing.fold_single_use`, every name of the code counted)."""
    kept, tail = fold_single_use(lines, outputs, names=_NAME, depth=_DEPTH)
    return [(name, expr) for name, expr in kept if name is not None], tail


class _TypedRecorder(Recorder):
    """A :class:`solver.tracing.Recorder` that also keeps the class (float, complex) of the value
    of every name it hands out: what :func:`_split` needs to know which lines are complex."""

    def __init__(self) -> None:
        super().__init__({})
        self.types: dict[str, type] = {}

    def let(self, template: str, args: tuple[Any, ...], value: Any) -> Any:
        traced = super().let(template, args, value)
        self.types[traced.name] = type(value)
        return traced

    def input(self, name: str, value: Any) -> Any:
        self.types[name] = type(value)
        return super().input(name, value)


def _split(lines: list[tuple[str, str]], outputs: list[str],
           types: dict[str, type]) -> tuple[list[tuple[str, str]], list[str]]:
    """The same operations on the same bits, with fewer complex numbers: a sum or difference of
    two complex numbers is taken part by part (``(a ± b).real`` is ``a.real ± b.real`` exactly:
    CPython's complex ``+`` and ``-`` of two complex numbers are those two float operations), a
    complex number built by ``complex(x, y)`` is read as ``x`` and ``y``, ``z.real`` / ``z.imag``
    of such a number is its part, ``x - 0.0`` of a float ``x`` is ``x`` (for every x, −0.0
    included) and a name bound to another name is that name; a complex number is built (by
    ``complex(re, im)``: the same two floats) only where something else reads it, and lines no
    output needs are dropped."""
    alias: dict[str, str] = {}
    parts: dict[str, tuple[str, str]] = {}
    fresh = 1 + max((int(name[1:]) for name, _ in lines if re.fullmatch(r"v\d+", name)), default=-1)
    new: list[tuple[str, str]] = []

    def swap(text: str) -> str:
        return _NAME.sub(lambda m: alias.get(m.group(0), m.group(0)), text)

    def part(name: str, k: int) -> str:
        return parts[name][k] if name in parts else f"{name}.{('real', 'imag')[k]}"

    for name, expr in lines:
        expr = swap(expr)
        complex_ = types.get(name) is complex
        if _NAME.fullmatch(expr):
            alias[name] = expr
        elif (complex_ and (m := _COMPLEX.fullmatch(expr))
              and all(_READ.fullmatch(x) and types.get(x, float) is float for x in m.groups())):
            parts[name] = (m.group(1), m.group(2))
            new.append((name, expr))
        elif (complex_ and (m := _SUM.fullmatch(expr)) and types.get(m.group(1)) is complex
              and types.get(m.group(3)) is complex and (m.group(1) in parts or m.group(3) in parts)):
            a, sign, b = m.groups()
            made = []
            for k in range(2):
                made.append(f"v{fresh}")
                new.append((f"v{fresh}", f"{part(a, k)} {sign} {part(b, k)}"))
                fresh += 1
            parts[name] = (made[0], made[1])
            new.append((name, f"complex({made[0]}, {made[1]})"))
        elif (m := _PART.fullmatch(expr)) and m.group(1) in parts:
            alias[name] = parts[m.group(1)][m.group(2) == "imag"]
        elif types.get(name) is float and expr.endswith(" - 0.0") and _NAME.fullmatch(expr[:-6]) \
                and types.get(expr[:-6]) is float:
            alias[name] = expr[:-6]
        else:
            new.append((name, expr))
    outputs = [swap(text) for text in outputs]
    needed = {m.group(0) for text in outputs for m in _NAME.finditer(text)}
    kept: list[tuple[str, str]] = []
    for name, expr in reversed(new):
        if name in needed:
            kept.append((name, expr))
            needed.update(m.group(0) for m in _NAME.finditer(expr))
    return kept[::-1], outputs


def tree_code(scene: Any, order: Sequence[Slot], values: tuple[Any, ...], *, read: Read = _vector,
              prefix: str = "", simplify: bool = True) -> TracedCode | None:
    """The URDF tree joints' positions then velocities from the numbers in slot ``order``
    (traced at ``values``); None when the scene has no tree or the evaluation cannot be traced.
    ``simplify``: the recorded lines with fewer complex numbers and temporaries (:func:`_split`,
    :func:`_inline`: the same operations on the same bits); False: as recorded."""
    from .urdf import exportable_model
    from .urdf.states import evaluate_tree, tree_inputs

    model = exportable_model(scene)
    if model is None:
        return None
    tree_points, tree_joints = tree_inputs(model)
    where = {slot: i for i, slot in enumerate(order)}
    rec = _TypedRecorder()
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
    return _code(rec, head, (*q, *dq), prefix, simplify)


def view_code(produce: Callable[[Any], Sequence[Any]], view: View, values: tuple[Any, ...], *,
              read: Read = _vector, prefix: str = "") -> TracedCode | None:
    """``produce(view)`` (e.g. the builder's ``load_tips``) traced with the view reading the
    numbers (at ``values``); None when ``produce`` compares a traced value or needs a plain number."""
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
