"""The node's hot path: one instant as one generated function, from the solve to the bytes.

A tick of ``mechanism_node`` (clock mode) or an answer of its relay (topic mode) at an ordinary
instant — assemblable, not near singular, not a hold of the motion, every number finite, no path
markers or diagnostics due — is::

    phi, omega, epsilon = motion.moving_state(t)           # the exact time law (clock mode)
    emit(phi, omega, epsilon, stamp_ns)                    # the generated tick: [(topic, bytes)]

with no Frame, no result objects, no dicts and no vector of the tick's values. ``emit``
(:meth:`FastPath.emitter`, source: :func:`emit_source`) is built once per scene, on the first
ordinary instant, from the same pieces the reference path below uses: one call of the scene's
compiled instant (:meth:`solver.Scene.compiled`, ``.core``: None on a miss), its tuple unpacked
into locals, the conditioning and finiteness checks, the efforts and loads read off its force
part (:func:`_force_reader`), the numbers the builder derives (the URDF tree joints and the load
arrows' tips: :mod:`linkage_ros._derived`, their evaluation traced once into lines inlined here),
and one ``struct`` pack per topic straight from those locals (:meth:`Packer.source
<linkage_ros.serialize.Packer.source>`). It returns None where the reference path does.

The reference path, which the first fast tick runs and checks, and which serves when the
generated tick cannot be built (the scalar path, an untraceable derived number)::

    flat = solve(phi, omega, epsilon)                      # one compiled call: every point, joint
    values = (sec, nanosec) + flat + derived               # one tuple, in the slot order `order`
    packer(values)                                         # one struct.pack, one slice per topic

Everything else — the first tick, a status change, an instant the guards hand back (``solve``
returns None: not assemblable, a guard of the compiled code, conditioning below
``near_singular_below``), a hold of the motion, the ticks that carry the path markers or
diagnostics (about once a second) — takes the Frame path (:meth:`~linkage_ros.engine.Engine.frame`
and :meth:`~linkage_ros.serialize.Serializer.render`), unchanged.

``solve`` comes from :func:`flat_solver`: the scene's compiled instant, its layout names
translated once into the slots of :mod:`linkage_ros.serialize` (``"B.vx"`` → ``("v", "B", 0)``,
``"rocker.ddq"`` → ``("j", "rocker", 2)``); in scenes with forces the efforts and loads are read
off the same tuple's force part, where a probe of :func:`linkage_ros.forces.frame_forces` found
them once (:func:`_force_reader`).

Safety: the first fast tick is rendered three ways — the reference path, the generated tick and
the Frame path; the fast path switches itself off for good when the reference bytes differ from
the Frame path's (:attr:`FastPath.enabled`), and the generated tick is bound only when its bytes
are the same too (``tests/ros/test_ros_fast_path.py`` compares it with the reference path over
sweeps, near a toggle included).
"""

from __future__ import annotations

import math
import re
from collections import Counter
from collections.abc import Callable, Sequence
from typing import Any, NamedTuple

from solver.errors import AssemblyError

from ._derived import View, compiled_tree, compiled_view, tree_code, view_code
from .engine import Engine, every_output
from .frame import Frame
from .messages import NS_PER_S, MessageBuilder
from .serialize import STAMP_SLOTS, Packer, Serializer, Slot
from .topics import DIAGNOSTICS, JOINT_STATES

__all__ = ["Emit", "FastPath", "compiled_tree", "emit_source", "flat_solver"]

#: ``solve(phi, omega, epsilon)``: the flat numbers of an ordinary instant, or None.
FlatSolve = Callable[[Any, Any, Any], "tuple[float, ...] | None"]


class _Shape(NamedTuple):
    """Where the numbers sit in the compiled instant's tuple, for the generated tick: ``n``
    outputs, then the conditioning figures (``unit.conditioning``, known once traced), then the
    force part (``forces`` entries, read into efforts and loads by the expressions ``reader`` of
    ``f[i]``); ``inputs``: k."""

    unit: Any
    n: int
    forces: int
    reader: tuple[str, ...]
    inputs: int
    near: float


def flat_solver(engine: Engine) -> tuple[tuple[Slot, ...], FlatSolve]:
    """``(layout, solve)`` of ``engine``'s scene with every point and joint an output (and, in
    scenes with forces, every input's effort and every load: :mod:`linkage_ros.forces`):
    ``solve(phi, omega, epsilon)`` gives the flat numbers named by ``layout``, or None where a
    group cannot be assembled, a guard of the compiled code trips, or some group's conditioning
    is below the engine's ``near_singular_below`` (those instants take the Frame path, which
    reports them)."""
    layout, solve, _ = _flat(engine)
    return layout, solve


def _flat(engine: Engine) -> tuple[tuple[Slot, ...], FlatSolve, _Shape | None]:
    """:func:`flat_solver`, and the shape of the compiled tuple (None on the scalar path)."""
    scene = every_output(engine.scene)
    near = engine.near_singular_below
    if hasattr(scene, "compiled") and not getattr(scene, "has_friction", False):  # friction: not compiled
        return _compiled(engine, scene, near)
    return (*_scalar(engine, scene, near), None)


def _compiled(engine: Engine, scene: Any, near: float) -> tuple[tuple[Slot, ...], FlatSolve, _Shape | None]:
    """The scene's compiled instant (:meth:`solver.Scene.compiled`): its flat tuple as it is, up
    to the conditioning figures that follow the outputs (checked, then cut off); in scenes with
    forces, the efforts and loads read off the force part after them (:func:`_force_reader`)."""
    unit = scene.compiled()
    n = unit.size
    forces = _force_reader(engine, scene) if getattr(engine, "forces", False) else None
    if getattr(engine, "forces", False) and forces is None:
        return (*_scalar(engine, scene, near), None)
    kinds = {"": "p", "v": "v", "a": "a"}
    layout: list[Slot] = []
    for name in unit.layout:  # "P.x", "P.vx", "P.ax", "J.q", "J.dq", "J.ddq"
        owner, _, part = name.rpartition(".")
        if part in ("q", "dq", "ddq"):
            layout.append(("j", owner, ("q", "dq", "ddq").index(part)))
        else:
            layout.append((kinds[part[:-1]], owner, "xyz".index(part[-1])))
    several = len(scene.inputs) > 1
    if forces is not None:
        reader, force_slots, exprs = forces
        layout += force_slots
        size = n + len(scene.forces.layout)
        shape = _Shape(unit, n, len(scene.forces.layout), exprs, len(scene.inputs), near)

        def solve_forces(phi: Any, omega: Any, epsilon: Any) -> tuple[float, ...] | None:
            flat = unit.core(*phi, *omega, *epsilon) if several else unit.core(phi, omega, epsilon)
            if flat is None:
                return None
            cut = len(flat) - size + n  # the conditioning figures sit between n and cut
            if cut > n and min(flat[n:cut]) < near:
                return None
            return flat[:n] + reader(flat[cut:])  # type: ignore[no-any-return]

        return tuple(layout), solve_forces, shape

    def solve(phi: Any, omega: Any, epsilon: Any) -> tuple[float, ...] | None:
        flat = unit.core(*phi, *omega, *epsilon) if several else unit.core(phi, omega, epsilon)
        if flat is None or (len(flat) > n and min(flat[n:]) < near):
            return None
        return flat[:n]  # type: ignore[no-any-return]

    shape = _Shape(unit, n, 0, (), len(scene.inputs), near)
    return tuple(layout), solve, shape


def _force_reader(engine: Engine, scene: Any) -> tuple[Callable[[Any], tuple[float, ...]], list[Slot],
                                                      tuple[str, ...]] | None:
    """How the efforts and loads of :func:`linkage_ros.forces.frame_forces` sit in the compiled
    tuple's force part (``scene.forces.layout``): found once by running ``frame_forces`` on a
    probe whose every value is distinct, then read per tick by one generated expression (the
    same operations as ``frame_forces`` on the solver's result; its expressions of ``f[i]`` are
    the third item). None where a value cannot be placed (then the scalar path serves the scene)."""
    from solver.forces import ForceResult

    from .forces import frame_forces

    model = scene.forces
    probe = [complex(4 * i + 1, 4 * i + 3) if cplx else float(4 * i + 1) for i, (_, _, cplx) in enumerate(model.layout)]
    inputs, pairs = tuple(engine.inputs), tuple(engine.load_pairs)
    efforts, loads = frame_forces(ForceResult(model, probe, None), inputs, pairs)
    slots: list[Slot] = [("e", q) for q in inputs] + [("l", pair.key, i) for pair in pairs for i in range(3)]
    found: dict[float, str] = {0.0: "0.0"}
    for i, value in enumerate(probe):
        for sign, text in ((1.0, f"f[{i}]"), (-1.0, f"-f[{i}]")):
            z = sign * value
            if isinstance(value, complex):
                found[complex(z).real] = f"float(complex({text}).real)"
                found[complex(z).imag] = f"float(complex({text}).imag)"
            else:
                found[sign * float(value)] = f"float({text})"
    numbers = [*efforts.values(), *(x for load in loads.values() for x in load)]
    if any(x not in found for x in numbers):
        return None
    exprs = tuple(found[x] for x in numbers)
    source = "lambda f: (" + "".join(x + ", " for x in exprs) + ")"
    return eval(source, {"complex": complex, "float": float}), slots, exprs


def _scalar(engine: Engine, scene: Any, near: float) -> tuple[tuple[Slot, ...], FlatSolve]:
    """Today's scalar path (``scene.solve`` at one instant), flattened; with the efforts and
    loads of scenes with forces (:func:`linkage_ros.forces.frame_forces`)."""
    points, joints, dim = tuple(scene.output_points), tuple(scene.output_joints), int(scene.dim)
    layout: list[Slot] = []
    for p in points:
        layout += [(kind, p, c) for kind in "pva" for c in range(dim)]
    layout += [("j", j, i) for j in joints for i in range(3)]
    names = points + joints
    forces = bool(getattr(engine, "forces", False))
    if forces:
        from .forces import frame_forces

        inputs, pairs = tuple(engine.inputs), tuple(engine.load_pairs)
        layout += [("e", q) for q in inputs] + [("l", pair.key, i) for pair in pairs for i in range(3)]
    friction = tuple(getattr(engine, "friction_names", ()))
    if friction:
        from .forces import frame_friction

        layout += [("f", name) for name in friction]

    def solve(phi: Any, omega: Any, epsilon: Any) -> tuple[float, ...] | None:
        try:
            k = scene.solve(phi, omega=omega, epsilon=epsilon)
        except AssemblyError:
            return None
        conditioning = k.conditioning
        if conditioning and min(conditioning.values()) < near:
            return None
        floats = k.floats
        out: list[float] = []
        for name in names:
            for part in floats(name):
                if type(part) is float:
                    out.append(part)
                else:
                    out += part
        if forces:
            efforts, loads = frame_forces(k, inputs, pairs)
            out += efforts.values()
            for load in loads.values():
                out += load
        if friction:
            out += frame_friction(k, friction).values()
        return tuple(out)

    return tuple(layout), solve


class FastPath:
    """The ordinary instants of ``engine`` as bytes, from ``serializer``'s templates (see the
    module docstring). ``tick(t, stamp_ns)`` (clock mode: the motion law at ``t``) and
    ``answer(phi, omega, epsilon, stamp_ns)`` (topic mode) return the per-tick topics' bytes, or
    None: take the Frame path."""

    def __init__(self, engine: Engine, builder: MessageBuilder, serializer: Serializer) -> None:
        self.engine = engine
        self.builder = builder
        self.serializer = serializer
        layout, self.solve, self._shape = _flat(engine)
        names = builder.tree_joint_names
        tips = 2 * len(getattr(engine, "load_pairs", ())) if getattr(engine, "forces", False) else 0
        order = (*STAMP_SLOTS, *layout)
        # the numbers the builder derives from the frame's: the URDF tree joints, the load arrows' tips
        self._view = View(order, int(engine.scene.dim)) if names or tips else None
        self._derived = (bool(names), bool(tips))
        self.order: tuple[Slot, ...] = (*order, *(("tq", k) for k in range(len(names))),
                                        *(("tv", k) for k in range(len(names))),
                                        *(("lt", k) for k in range(tips)))
        self._packer: Packer | None = None
        #: False once the fast path gave other bytes than the Frame path, or cannot bind.
        self.enabled = True
        self._checked = False
        self._state: tuple[float, Any, Any, Any] | None = None
        self._tree_function: Callable[..., tuple[Any, ...]] | None = None
        self._tree_traced = False
        self._tips_function: Callable[..., tuple[Any, ...]] | None = None
        self._tips_traced = False
        #: the generated tick (:meth:`emitter`), bound on the first fast tick; None: not (yet) bound
        self._emit: Emit | None = None
        self._sample: tuple[Any, ...] | None = None  # the numbers of the first fast tick
        #: the generated tick of every per-tick topic, the arguments of its first tick, the topics
        #: asked for (:meth:`want`) and the generated ticks of such subsets, by their topics
        self._every: Emit | None = None
        self._first_args: tuple[Any, Any, Any, int] | None = None
        self._wanted: frozenset[str] | None = None
        self._subsets: dict[tuple[str, ...], Emit | None] = {}

    def tick(self, t: float, stamp_ns: int) -> list[tuple[str, bytes]] | None:
        state = self.engine.motion.moving_state(t) if self.enabled else None
        if state is None:  # off, or a hold of the motion
            return None
        phi, omega, epsilon = state
        emit = self._emit
        if emit is None:
            messages = self._messages(t, phi, omega, epsilon, stamp_ns)
        else:
            messages = emit(phi, omega, epsilon, stamp_ns)
            self._state = (t, phi, omega, epsilon)
        if messages is not None:
            self.engine.mark_valid(t)
        return messages

    def answer(self, phi: Any, omega: Any, epsilon: Any, stamp_ns: int) -> list[tuple[str, bytes]] | None:
        emit = self._emit
        if emit is not None:
            self._state = (stamp_ns / NS_PER_S, phi, omega, epsilon)
            return emit(phi, omega, epsilon, stamp_ns)
        if not self.enabled:
            return None
        return self._messages(stamp_ns / NS_PER_S, phi, omega, epsilon, stamp_ns)

    def values(self, phi: Any, omega: Any, epsilon: Any, stamp_ns: int) -> tuple[Any, ...] | None:
        """The numbers of an ordinary instant in the slot order :attr:`order` (stamp, the flat
        instant, the numbers the builder derives), or None."""
        flat = self.solve(phi, omega, epsilon)
        if flat is None or not math.isfinite(sum(flat)):
            return None
        return self.complete(flat, stamp_ns)

    def complete(self, flat: tuple[float, ...], stamp_ns: int) -> tuple[Any, ...]:
        """The stamp, ``flat`` (what :attr:`solve` gave) and the numbers the builder derives
        from them, in the slot order :attr:`order`."""
        values = divmod(stamp_ns, NS_PER_S) + flat
        if self._view is not None:
            self._view.values = values
            tree, tips = self._derived
            if tree:
                if self._tree_function is None and not self._tree_traced:
                    self._tree_traced = True
                    self._tree_function = compiled_tree(self.engine.scene, self.order, values)
                if self._tree_function is not None:
                    values += self._tree_function(values)
                else:
                    states = self.builder.tree_states(self._view)  # type: ignore[arg-type]
                    assert states is not None
                    values += tuple(states.position) + tuple(states.velocity)
            if tips:
                if self._tips_function is None and not self._tips_traced:
                    self._tips_traced = True
                    self._tips_function = compiled_view(self.builder.load_tips, self._view, values,
                                                        f"load arrow tips of {self.engine.scene.name}")
                if self._tips_function is not None:
                    values += self._tips_function(values)
                else:
                    values += self.builder.load_tips(self._view)  # type: ignore[arg-type]
        return values

    def emitter(self, topics: Sequence[str] | None = None) -> Emit | None:
        """The generated tick: ``emit(phi, omega, epsilon, stamp_ns)`` gives what :meth:`answer`
        gives at an ordinary instant — the bytes of every per-tick topic (or of ``topics``), or
        None — as one function (:func:`emit_source`): one compiled call, its guards, the
        efforts and loads, the tree joints and arrow tips traced once, one pack. None before the
        first fast tick (it supplies the tracing values), on the scalar path, or when a derived
        number cannot be traced."""
        packer = self.serializer.packer(self.order, topics)
        if self._sample is None or self._shape is None or packer is None:
            return None
        built = emit_source(self, self._shape, self._sample, packer)
        if built is None:
            return None
        source, namespace = built
        exec(compile(source, f"<tick of {self.engine.scene.name}>", "exec"), namespace)
        return namespace["emit"]  # type: ignore[no-any-return]

    def _messages(self, t: float, phi: Any, omega: Any, epsilon: Any,
                  stamp_ns: int) -> list[tuple[str, bytes]] | None:
        values = self.values(phi, omega, epsilon, stamp_ns)
        if values is None:
            return None
        self._state = (t, phi, omega, epsilon)
        packer = self._packer
        if packer is None or not self._checked:
            return self._first(t, phi, omega, epsilon, stamp_ns, values)
        return packer(values)

    def last_frame(self) -> Frame | None:
        """The Frame of the last instant this path answered (solved again, the Frame way)."""
        if self._state is None:
            return None
        t, phi, omega, epsilon = self._state
        frame = self.engine.frame_at(phi, omega, epsilon, t=t)
        return frame if isinstance(frame, Frame) else None

    def _first(self, t: float, phi: Any, omega: Any, epsilon: Any, stamp_ns: int,
               values: tuple[Any, ...]) -> list[tuple[str, bytes]] | None:
        """The first fast tick: bind the templates (verified on a frame before) and check the
        bytes against the Frame path's; on any difference the fast path is off. Then the
        generated tick (:meth:`emitter`) is bound when it gives the same bytes here too."""
        if not self.serializer.verified:
            return None
        try:
            self._packer = packer = self.serializer.packer(self.order)
        except KeyError:  # a number the templates need is not in the flat instant
            self._packer = packer = None
        frame = self.engine.frame_at(phi, omega, epsilon, t=t)
        if packer is None or not isinstance(frame, Frame):
            self.enabled = False
            return None
        messages = packer(values)
        self._checked = True
        if messages != self.serializer.render(frame, stamp_ns, diagnostics=False):
            self.enabled = False
            return None
        self._sample = values
        emit = self.emitter()
        if emit is not None and emit(phi, omega, epsilon, stamp_ns) == messages:
            self._emit = self._every = emit
            self._first_args = (phi, omega, epsilon, stamp_ns)
            self._subset()
        return messages

    def want(self, topics: frozenset[str] | None) -> None:
        """From the next tick on, the generated tick renders only ``topics`` (with
        ``joint_states``, whose bytes carry the guards' verdict as the others do) — the node's
        topics with a subscriber, none recorded — or, None, every per-tick topic. A subset's tick
        is bound once it gave the full tick's bytes of those topics at the first fast tick's
        instant; until then, or where it cannot be built, every topic is rendered."""
        if topics != self._wanted:
            self._wanted = topics
            self._subset()

    def _subset(self) -> None:
        every = self._every
        if every is None:
            return
        wanted = self._wanted
        all_topics = [t for t in self.serializer.types if t != DIAGNOSTICS]
        chosen = all_topics if wanted is None else [t for t in all_topics if t in wanted or t == JOINT_STATES]
        key = tuple(chosen)
        if key == tuple(all_topics):
            self._emit = every
            return
        if key not in self._subsets:
            emit = self.emitter(chosen)
            args = self._first_args
            if emit is not None and args is not None:
                full = every(*args)
                if full is None or emit(*args) != [m for m in full if m[0] in key]:
                    emit = None
            self._subsets[key] = emit
        self._emit = self._subsets[key] or every


#: The generated tick (:meth:`FastPath.emitter`).
Emit = Callable[[Any, Any, Any, int], "list[tuple[str, bytes]] | None"]


#: ``f[3]`` in a force reader's expression, the local ``f3`` in the generated tick.
_FORCE_PART = re.compile(r"f\[(\d+)\]")
_PART_OF = re.compile(r"float\(complex\((-?f\[\d+\])\)\.(real|imag)\)")
_AS_FLOAT = re.compile(r"float\((-?f\[\d+\])\)")
#: a plain name (the pack reads it as it is), one in parentheses
_NAMED = re.compile(r"[A-Za-z_]\w*")
_PARENTHESIZED = re.compile(r"\([A-Za-z_]\w*\)")


def _plain(expr: str) -> str:
    """A force reader's expression without its conversions: ``(f[3]).real`` for
    ``float(complex(f[3]).real)`` and ``(f[3])`` for ``float(f[3])`` — the same bits for a float
    or complex ``f[3]`` (``.real`` and ``.imag`` of a float are itself and 0.0), and ``struct``
    packs an int as the float it converts to."""
    return _AS_FLOAT.sub(r"(\1)", _PART_OF.sub(r"(\1).\2", expr))


def emit_source(path: FastPath, shape: _Shape, values: tuple[Any, ...],
                packer: Packer) -> tuple[str, dict[str, Any]] | None:
    """The source of ``path``'s generated tick and its namespace (None: something cannot be
    traced). Every number of :attr:`FastPath.order` is a local ``x{i}``::

        def emit(phi, w, e, stamp_ns):
            flat = _unit.core(phi, w, e)              # (q1, …, qk, ω1, …, εk) with k inputs
            if flat is None or len(flat) != L: return None
            x2, …, c0, …, f0, … = flat                # outputs, conditioning, force part
            if min(c0, …) < _near: return None        # as FastPath.solve
            x40 = float(f3) …                         # efforts and loads (_force_reader)
            if not _isfinite(_sum(flat[:n]) + x40 + …): return None
            x0, x1 = divmod(stamp_ns, 1000000000)
            …                                         # tree joints, arrow tips (linkage_ros._derived)
            _pdata = _ppack(_pk0, x0, x1, …)           # Packer.source
            return [('joint_states', _pdata[0:232]), …]
    """
    unit = shape.unit
    if unit.conditioning is None:
        return None
    n, k = shape.n, shape.inputs
    kinematics = [f"x{2 + i}" for i in range(n)]
    conditioning = [f"c{i}" for i in range(len(unit.conditioning))]
    force_part = [f"f{i}" for i in range(shape.forces)]
    size = n + len(conditioning) + shape.forces
    call = "phi, w, e" if k == 1 else ", ".join(f"{a}[{i}]" for a in ("phi", "w", "e") for i in range(k))
    lines = [f"flat = _unit.core({call})",
             f"if flat is None or len(flat) != {size}: return None",
             f"{', '.join([*kinematics, *conditioning, *force_part])}, = flat"]
    if conditioning:
        lowest = conditioning[0] if len(conditioning) == 1 else f"min({', '.join(conditioning)})"
        lines.append(f"if {lowest} < _near: return None")
    used = set(packer.reads())
    reads = Counter(int(i) for i in re.findall(r"\bx(\d+)\b", " ".join(packer.source(lambda i: f"x{i}")[0])))
    tree, tips = path._derived

    def local(i: int) -> str:
        return f"x{i}"

    pieces = []
    if tree:
        pieces.append(tree_code(path.engine.scene, path.order, values, read=local, prefix="T_"))
    if tips:
        assert path._view is not None
        pieces.append(view_code(path.builder.load_tips, path._view, values, read=local, prefix="L_"))
    if any(code is None for code in pieces):
        return None
    where = 2 + n + len(shape.reader)
    spans = []  # per piece: the slots of its outputs, and whether the pack reads one of them
    for code in pieces:
        assert code is not None
        outputs = range(where, where + len(code.outputs))
        where += len(code.outputs)
        wanted = not used.isdisjoint(outputs)  # e.g. not the arrow tips when only joint_states is packed
        spans.append((outputs, wanted))
        if wanted:  # the numbers its lines read (a load under an arrow's tip) are needed as locals too
            used.update(int(i) for i in re.findall(r"\bx(\d+)\b", " ".join(code.lines)))
    terms: list[str] = []  # values()'s finiteness check's sum less its + 0.0 (finite iff the sum is)
    named: dict[int, str] = {}  # numbers the pack reads as an expression, not a local x{i}
    for i, expr in enumerate(shape.reader, start=2 + n):
        expr = _FORCE_PART.sub(r"f\1", _plain(expr))
        expr = expr[1:-1] if _PARENTHESIZED.fullmatch(expr) else expr  # (f0): f0 itself
        if i in used and not _NAMED.fullmatch(expr):
            lines.append(f"x{i} = {expr}")
            expr = f"x{i}"
        named[i] = expr
        terms += [expr] if expr != "0.0" else []
    lines += [f"if not _isfinite(_sum(flat[:{n}]){''.join(' + ' + x for x in terms)}): return None",
              f"x0, x1 = divmod(stamp_ns, {NS_PER_S})"]
    namespace: dict[str, Any] = {"_unit": unit, "_near": shape.near, "_isfinite": math.isfinite, "_sum": sum,
                                 "complex": complex, "float": float, "min": min, "divmod": divmod}
    for code, (outputs, wanted) in zip(pieces, spans):
        assert code is not None
        if not wanted:
            continue
        lines += code.lines
        named.update((i, e) for i, e in zip(outputs, code.outputs) if _NAMED.fullmatch(e) or reads[i] == 1)
        lines += [f"x{i} = {e}" for i, e in zip(outputs, code.outputs) if i not in named]
        namespace.update(code.namespace)
    if where != len(path.order):
        return None
    pack, names = packer.source(lambda i: named.get(i, f"x{i}"))
    namespace.update(names)
    return "\n".join(["def emit(phi, w, e, stamp_ns):", *("    " + line for line in lines + pack)]) + "\n", namespace
