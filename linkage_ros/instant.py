"""The node's hot path: one instant as one flat tuple of numbers, then one pack per topic.

A tick of ``mechanism_node`` (clock mode) or an answer of its relay (topic mode) at an ordinary
instant — assemblable, not near singular, not a hold of the motion, every number finite, no path
markers or diagnostics due — is::

    phi, omega, epsilon = motion.state(t)                  # the exact time law (clock mode)
    flat = solve(phi, omega, epsilon)                      # one compiled call: every point, joint
    values = (sec, nanosec) + flat + derived               # one tuple, in the slot order `order`
    packer(values)                                         # one struct.pack per topic

with no Frame, no result objects and no dicts of the tick's values. ``derived`` are the numbers
the builder computes from the frame's rather than copying them: the URDF tree joints on
``joint_states`` (:func:`compiled_tree`: their evaluation traced once into straight-line code)
and the tips of the load arrows (read off the flat tuple through a frame-like view).

Everything else — the first tick, a status change, an instant the guards hand back (``solve``
returns None: not assemblable, a guard of the compiled code, conditioning below
``near_singular_below``), a hold of the motion, the ticks that carry the path markers or
diagnostics (about once a second) — takes the Frame path (:meth:`~linkage_ros.engine.Engine.frame`
and :meth:`~linkage_ros.serialize.Serializer.render`), unchanged.

``solve`` comes from :func:`flat_solver`: the scene's compiled instant
(:meth:`solver.Scene.compiled`, ``.core``: None on a miss), its layout names translated once into
the slots of :mod:`linkage_ros.serialize` (``"B.vx"`` → ``("v", "B", 0)``, ``"rocker.ddq"`` →
``("j", "rocker", 2)``); in scenes with forces the efforts and loads are read off the same
tuple's force part, where a probe of :func:`linkage_ros.forces.frame_forces` found them once
(:func:`_force_reader`).

Safety: the first fast tick is also rendered the Frame way, and the fast path switches itself
off for good when the bytes differ (:attr:`FastPath.enabled`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from operator import itemgetter
from typing import Any

from solver.errors import AssemblyError

from .engine import Engine
from .frame import Frame, JointState, PointState
from .messages import NS_PER_S, MessageBuilder
from .motion import SEGMENT_HOLD
from .serialize import STAMP_SLOTS, Packer, Serializer, Slot

__all__ = ["FastPath", "flat_solver"]

#: ``solve(phi, omega, epsilon)``: the flat numbers of an ordinary instant, or None.
FlatSolve = Callable[[Any, Any, Any], "tuple[float, ...] | None"]


def flat_solver(engine: Engine) -> tuple[tuple[Slot, ...], FlatSolve]:
    """``(layout, solve)`` of ``engine``'s scene with every point and joint an output (and, in
    scenes with forces, every input's effort and every load: :mod:`linkage_ros.forces`):
    ``solve(phi, omega, epsilon)`` gives the flat numbers named by ``layout``, or None where a
    group cannot be assembled, a guard of the compiled code trips, or some group's conditioning
    is below the engine's ``near_singular_below`` (those instants take the Frame path, which
    reports them)."""
    scene = engine.scene.everything()
    near = engine.near_singular_below
    if hasattr(scene, "compiled"):
        return _compiled(engine, scene, near)
    return _scalar(engine, scene, near)


def _compiled(engine: Engine, scene: Any, near: float) -> tuple[tuple[Slot, ...], FlatSolve]:
    """The scene's compiled instant (:meth:`solver.Scene.compiled`): its flat tuple as it is, up
    to the conditioning figures that follow the outputs (checked, then cut off); in scenes with
    forces, the efforts and loads read off the force part after them (:func:`_force_reader`)."""
    unit = scene.compiled()
    n = unit.size
    forces = _force_reader(engine, scene) if getattr(engine, "forces", False) else None
    if getattr(engine, "forces", False) and forces is None:
        return _scalar(engine, scene, near)
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
        reader, force_slots = forces
        layout += force_slots
        size = n + len(scene.forces.layout)

        def solve_forces(phi: Any, omega: Any, epsilon: Any) -> tuple[float, ...] | None:
            flat = unit.core(*phi, *omega, *epsilon) if several else unit.core(phi, omega, epsilon)
            if flat is None:
                return None
            cut = len(flat) - size + n  # the conditioning figures sit between n and cut
            if cut > n and min(flat[n:cut]) < near:
                return None
            return flat[:n] + reader(flat[cut:])  # type: ignore[no-any-return]

        return tuple(layout), solve_forces

    def solve(phi: Any, omega: Any, epsilon: Any) -> tuple[float, ...] | None:
        flat = unit.core(*phi, *omega, *epsilon) if several else unit.core(phi, omega, epsilon)
        if flat is None or (len(flat) > n and min(flat[n:]) < near):
            return None
        return flat[:n]  # type: ignore[no-any-return]

    return tuple(layout), solve


def _force_reader(engine: Engine, scene: Any) -> tuple[Callable[[Any], tuple[float, ...]], list[Slot]] | None:
    """How the efforts and loads of :func:`linkage_ros.forces.frame_forces` sit in the compiled
    tuple's force part (``scene.forces.layout``): found once by running ``frame_forces`` on a
    probe whose every value is distinct, then read per tick by one generated expression (the
    same operations as ``frame_forces`` on the solver's result). None where a value cannot be
    placed (then the scalar path serves the scene)."""
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
    source = "lambda f: (" + "".join(found[x] + ", " for x in numbers) + ")"
    return eval(source, {"complex": complex, "float": float}), slots


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
        return tuple(out)

    return tuple(layout), solve


def compiled_tree(scene: Any, order: Sequence[Slot], values: tuple[Any, ...]) -> Callable[..., tuple[Any, ...]] | None:
    """The URDF tree joints' positions then velocities from a vector in slot ``order``, as one
    straight-line function: :mod:`linkage_ros.urdf.states`' own evaluation run once on tracing
    values (``solver._trace``, the compiled instant's tracer) at ``values``, so that every
    operation, and so every bit, is the evaluation's. None when the scene has no tree, or the
    evaluation compares a traced value (it does not today) or cannot be traced: then the builder's
    ``tree_states`` runs per tick."""
    from solver._trace import TRACE, Guard, Recorder, TraceError

    from .urdf import exportable_model
    from .urdf import states as tree_states

    model = exportable_model(scene)
    if model is None:
        return None
    plan = tree_states._plan(model)
    where = {slot: i for i, slot in enumerate(order)}
    rec = Recorder({})
    head: list[str] = []
    points: dict[str, tuple[Any, Any]] = {}
    joints: dict[str, tuple[Any, Any]] = {}
    try:
        for k, name in enumerate(plan.points):
            parts = []
            for kind in ("p", "v"):
                i, j = where[(kind, name, 0)], where[(kind, name, 1)]
                head.append(f"    point_{kind}{k} = complex(x[{i}], x[{j}])")
                parts.append(rec.input(f"point_{kind}{k}", complex(values[i], values[j])))
            points[name] = (parts[0], parts[1])
        for k, name in enumerate(plan.joint_inputs):
            i, j = where[("j", name, 0)], where[("j", name, 1)]
            head += [f"    joint_q{k} = x[{i}]", f"    joint_dq{k} = x[{j}]"]
            joints[name] = (rec.input(f"joint_q{k}", values[i]), rec.input(f"joint_dq{k}", values[j]))
        functions = tree_states._Functions(TRACE.atan2, TRACE.sin, TRACE.cos,
                                           lambda x: TRACE.call(math.floor, x))
        q, dq = tree_states._evaluate(plan, points, joints, functions)
    except (TraceError, KeyError, TypeError):
        return None
    if any(isinstance(item, Guard) for item in rec.items):
        return None
    body = [f"    {item.name} = {item.expr}" for item in rec.items]  # type: ignore[union-attr]
    outputs = ", ".join(rec.atom(x)[0] for x in (*q, *dq))
    source = "\n".join(["def tree(x):", *head, *body, f"    return ({outputs}{',' if outputs else ''})"])
    namespace: dict[str, Any] = {"complex": complex, "max": max}
    namespace.update({n: getattr(math, n) for n in ("sqrt", "cos", "sin", "atan2", "tan")})
    namespace.update({name: value for name, value in rec.constants.values()})
    exec(compile(source, f"<tree joints of {scene.name}>", "exec"), namespace)
    return namespace["tree"]  # type: ignore[no-any-return]


def compiled_view(produce: Callable[[Any], Sequence[Any]], view: _View, values: tuple[Any, ...],
                  label: str) -> Callable[..., tuple[Any, ...]] | None:
    """``produce(view)`` (e.g. the builder's ``load_tips``) as one straight-line function of the
    vector: run once with the view reading tracing values (``solver._trace``) at ``values``, so
    that the generated code performs the same operations, bit for bit. None when ``produce``
    compares a traced value or needs a plain number (then it runs per tick)."""
    from solver._trace import Guard, Recorder, TraceError

    rec = Recorder({})
    view.values = tuple(rec.input(f"x[{i}]", v) for i, v in enumerate(values))
    try:
        out = tuple(produce(view))
    except (TraceError, TypeError, ValueError):
        return None
    finally:
        view.values = values
    if any(isinstance(item, Guard) for item in rec.items):
        return None
    body = [f"    {item.name} = {item.expr}" for item in rec.items]  # type: ignore[union-attr]
    outputs = "".join(rec.atom(x)[0] + ", " for x in out)
    source = "\n".join(["def derived(x):", *body, f"    return ({outputs})"])
    namespace: dict[str, Any] = {"complex": complex, "max": max}
    namespace.update({n: getattr(math, n) for n in ("sqrt", "cos", "sin", "atan2", "tan")})
    namespace.update({name: value for name, value in rec.constants.values()})
    exec(compile(source, f"<{label}>", "exec"), namespace)
    return namespace["derived"]  # type: ignore[no-any-return]


class _View:
    """A frame-like view of a flat vector for the URDF tree joints (``.points``, ``.joints``:
    ``get`` / ``[]`` give the named tuples, read from the vector set last)."""

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

    def __init__(self, view: _View, index: dict[str, Any]) -> None:
        self._view, self._index = view, index

    def get(self, key: str, default: Any = None) -> Any:
        found = self._index.get(key)
        return default if found is None else found(self._view.values)


class _Reader:
    """``get`` / ``[]``: the position and velocity of one point or joint of the view's vector
    (the acceleration, which the tree joints do not read, is left empty)."""

    __slots__ = ("_view", "_index")

    def __init__(self, view: _View, index: dict[str, Any]) -> None:
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


class FastPath:
    """The ordinary instants of ``engine`` as bytes, from ``serializer``'s templates (see the
    module docstring). ``tick(t, stamp_ns)`` (clock mode: the motion law at ``t``) and
    ``answer(phi, omega, epsilon, stamp_ns)`` (topic mode) return the per-tick topics' bytes, or
    None: take the Frame path."""

    def __init__(self, engine: Engine, builder: MessageBuilder, serializer: Serializer) -> None:
        self.engine = engine
        self.builder = builder
        self.serializer = serializer
        layout, self.solve = flat_solver(engine)
        names = builder.tree_joint_names
        tips = 2 * len(getattr(engine, "load_pairs", ())) if getattr(engine, "forces", False) else 0
        order = (*STAMP_SLOTS, *layout)
        # the numbers the builder derives from the frame's: the URDF tree joints, the load arrows' tips
        self._view = _View(order, int(engine.scene.dim)) if names or tips else None
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

    def tick(self, t: float, stamp_ns: int) -> list[tuple[str, bytes]] | None:
        motion = self.engine.motion
        if not self.enabled or motion.segment_at(t).tag == SEGMENT_HOLD:
            return None
        phi, omega, epsilon = motion.state(t)
        messages = self._messages(t, phi, omega, epsilon, stamp_ns)
        if messages is not None:
            self.engine.mark_valid(t)
        return messages

    def answer(self, phi: Any, omega: Any, epsilon: Any, stamp_ns: int) -> list[tuple[str, bytes]] | None:
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
        bytes against the Frame path's; on any difference the fast path is off."""
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
        return messages
