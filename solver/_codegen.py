"""One instant in straight-line Python: a scene's plan traced, printed and ``compile()``d.

:class:`Compiled` runs a scene's plan on tracing values (solver._trace) — the groups' own code,
nothing written per scene or per group — at a few samples, merges the recorded paths into one
tree (paths agree line for line up to the guard where they part), drops what no output needs,
and compiles the result once. The function it yields takes the inputs, their rates and their
accelerations as floats and returns a flat tuple of floats (:attr:`Compiled.layout`, then the
groups' conditioning figures, :attr:`Compiled.conditioning`). It performs exactly the Python
operations the per-tick path performs for those outputs, on the same types and in the same order
(or a spelling of them that gives the same bits by construction: ``cmath.rect(1.0, a)`` for
``complex(cos a, sin a)``, a conditional for ``max(x, 0.0)`` and a float's ``abs``), so its
values are the scalar path's to the bit. For a single input it also builds the same code behind
the argument check of ``Scene.instant``, which the scene binds in place of that method.

Guards: every comparison the group code made on a traced value is checked again; when one comes
out otherwise (an assembly limit, a singular position, a branch not yet traced, a zero where the
scalar path takes a fast path), or an arithmetic exception occurs, the instant goes to ``miss``:
today's scalar path, whose values, flags and errors are then exactly today's. A miss at an
untraced branch is traced in turn (up to :data:`MAX_TRACES` traces, :data:`MAX_PATHS` paths) and
the function rebuilt. See docs/compiled.md.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable, Sequence
from operator import itemgetter
from typing import Any

from ._paths import Node, copy_tree, emit, merge, prune, share
from ._trace import TRACE, Recorder, TraceError, Tracer
from .errors import SolverError
from .groups.base import Context
from .jet import Jet
from .kinematics import FlatFloats
from .multi import directions, instant_jets, solve_instant, take_direction

__all__ = ["Compiled", "FlatFloats", "MAX_PATHS", "MAX_TRACES", "EAGER_SAMPLES", "layout_of"]

#: Paths kept in one compiled function, and traces tried (failed ones included) per function.
MAX_PATHS = 16
MAX_TRACES = 48
#: Single input: the angles traced when the function is first built (one turn, off the round angles;
#: an actuator's strokes across its range).
EAGER_SAMPLES = 12

_MATH = {"sqrt": math.sqrt, "cos": math.cos, "sin": math.sin, "atan2": math.atan2, "tan": math.tan}


def layout_of(scene: Any, order: int = 2) -> tuple[str, ...]:
    """Names of the outputs in the flat tuple: per point ``P.x, P.y[, P.z]``, then ``P.vx …`` and
    ``P.ax …`` (up to ``order``), then per joint ``J.q``, ``J.dq``, ``J.ddq`` (up to ``order``) —
    linkage-solve's CSV columns, in the same order."""
    axes = ("x", "y", "z")[: scene.dim]
    names: list[str] = []
    for p in scene.output_points:
        for prefix in ("", "v", "a")[: order + 1]:
            names.extend(f"{p}.{prefix}{a}" for a in axes)
    for j in scene.output_joints:
        names.extend(f"{j}.{s}" for s in ("q", "dq", "ddq")[: order + 1])
    return tuple(names)


def _as_float(rec: Recorder, x: Any) -> Any:
    if type(x) is Tracer:
        return x if type(x.value) is float else rec.let("float({0})", (x,), float(x.value))
    return float(x)


def _as_complex(rec: Recorder, x: Any) -> Any:
    if type(x) is Tracer:
        return x if type(x.value) is complex else rec.let("complex({0})", (x,), complex(x.value))
    return complex(x)


class Compiled:
    """The compiled one-instant function of one scene, output set and derivative order.

    ``function(*q, *omega, *epsilon)`` (k inputs: ``function(phi, omega, epsilon)`` for one)
    returns the flat tuple; on a miss it runs the scalar path and returns the same tuple from it
    (or raises its error). ``core`` is the same code returning ``None`` on a miss.
    ``source`` is the generated Python (``Scene.compiled_source()``).
    """

    def __init__(
        self,
        scene: Any,
        order: int = 2,
        *,
        derivatives: bool = False,
        entry: Callable[..., Any] | None = None,
        bind: Callable[[Callable[..., Any]], None] | None = None,
    ) -> None:
        if order not in (0, 1, 2):
            raise SolverError(f"{scene.name}: order must be 0, 1 or 2, got {order!r}")
        self.scene = scene
        self.order = order
        self.k = k = len(scene.inputs)
        #: with several inputs: a function of q alone giving every output's J and H (docs/inputs.md)
        self.derivatives = derivatives and k > 1
        self.layout = layout_of(scene, order)
        self.size = len(self.layout)
        #: output name → (start in the flat tuple, point width or 0 for a joint); for
        #: ``derivatives``: (start of J's k entries, followed by H's k×k row by row, k)
        self.index: dict[str, tuple[int, int]] = {}
        i = 0
        for p in scene.output_points:
            self.index[p] = (i, scene.dim) if not self.derivatives else (i, k)
            i += scene.dim * (order + 1) if not self.derivatives else k + k * k
        for j in scene.output_joints:
            self.index[j] = (i, 0) if not self.derivatives else (i, k)
            i += order + 1 if not self.derivatives else k + k * k
        #: output name → the (position, velocity, acceleration) reader of the flat tuple that
        #: ``Kinematics.floats`` returns (one C call: tuples of a point's axes, a joint's floats)
        self.readers: dict[str, Callable[[tuple[Any, ...]], tuple[Any, Any, Any]]] = {}
        if order == 2 and not self.derivatives:
            for name, (i, width) in self.index.items():
                self.readers[name] = (
                    itemgetter(i, i + 1, i + 2) if width == 0
                    else itemgetter(*(slice(i + a * width, i + (a + 1) * width) for a in range(3)))
                )
        #: one input: the readers of the output points and of the output joints apart, for
        #: ``k.point(name)`` and ``k.joint(name)`` of one instant (solver.kinematics.InstantMotion)
        self.point_readers = {n: self.readers[n] for n in scene.output_points if k == 1 and n in self.readers}
        self.joint_readers = {n: self.readers[n] for n in scene.output_joints if k == 1 and n in self.readers}
        if self.derivatives:
            self.layout = tuple(
                f"{name}.{part}" for name in (*scene.output_points, *scene.output_joints)
                for part in (*(f"J{a}" for a in range(k)), *(f"H{a}{b}" for a in range(k) for b in range(k)))
            )
            self.size = len(self.layout)
        self.conditioning: tuple[str, ...] | None = None
        if self.derivatives:
            self.args: tuple[str, ...] = tuple(f"q{i}" for i in range(k))
        elif k == 1:
            self.args = ("phi", "omega", "epsilon")
        else:
            self.args = (*(f"q{i}" for i in range(k)), *(f"w{i}" for i in range(k)), *(f"e{i}" for i in range(k)))
        self._constants: dict[Any, tuple[str, Any]] = {}
        self._root: Node | None = None
        self.paths = 0
        self.traces = 0
        self.source = ""
        self.core: Callable[..., Any] = self._no_code
        self.function: Callable[..., Any] = self._on_miss
        #: one input: ``entry`` (the scene's general ``instant``) and ``bind`` (what installs the
        #: checked function, :meth:`_build`) — the per-tick ``scene.instant`` in one call frame
        self._entry = entry if k == 1 and not self.derivatives else None
        self._bind = bind
        if k == 1 and not self.derivatives:
            # one turn, or an actuator's stroke [s_min, s_max] (m)
            span = getattr(scene, "input_ranges", (None,))[0] or (0.0, 2.0 * math.pi)
            for i in range(EAGER_SAMPLES):
                self._trace((span[0] + (span[1] - span[0]) * (i + 0.3819660112501051) / EAGER_SAMPLES, 1.3, 0.7))
        self._build()

    # -- the scalar path ------------------------------------------------------------------------
    def _no_code(self, *args: float) -> None:
        self._missed(args)
        return None

    def _on_miss(self, *args: float) -> tuple[float, ...]:
        out = self.fallback(*args)  # (an error of the scalar path leaves nothing to trace)
        self._missed(args)
        return out

    def fallback(self, *args: float) -> tuple[float, ...]:
        """The flat tuple from today's scalar path (what a miss of the compiled code returns)."""
        k = self.k
        scene = self.scene
        if self.derivatives:
            flat: list[Any] = []
            for name in (*scene.output_points, *scene.output_joints):
                jac, hess = instant_jets(scene, tuple(args), name)
                flat.extend(jac)
                for row in hess:
                    flat.extend(row)
            return tuple(flat)
        if k == 1:
            result = scene._solve_scalar(args[0], args[1], args[2], False, compiled=False)
        else:
            result = solve_instant(scene, tuple(args[:k]), args[k:2 * k], args[2 * k:])
        out: list[float] = []
        n = self.order + 1
        for p in scene.output_points:
            for part in result.floats(p)[:n]:
                out.extend(part)
        for j in scene.output_joints:
            out.extend(result.floats(j)[:n])
        if self.conditioning is None:  # no path traced yet (a triad's eigenvalues): the scalar path's names
            self.conditioning = tuple(result.conditioning)
        out.extend(result.conditioning[g] for g in self.conditioning)
        if result._forces is not None:
            out.extend(result._forces._data)
        return tuple(out)

    def _missed(self, args: Sequence[float]) -> None:
        if self.traces < MAX_TRACES and self.paths < MAX_PATHS and all(type(a) is float for a in args):
            if all(math.isfinite(a) for a in args) and self._trace(tuple(args)):
                self._build()

    # -- tracing --------------------------------------------------------------------------------
    def _trace(self, sample: tuple[float, ...]) -> bool:
        """Trace the plan at ``sample``; True when it added a path."""
        self.traces += 1
        rec = Recorder(self._constants)
        inputs = [rec.input(name, v) for name, v in zip(self.args, sample)]
        # a non-finite argument goes to the scalar path (which names it): 0·x is ±0 for finite x,
        # NaN for ±inf and NaN, and stays so along the product (which cannot overflow)
        rec.guard("0.0 * " + " * ".join(f"{{{i}}}" for i in range(len(inputs))) + " == 0.0", tuple(inputs), True)
        try:
            values, conditioning, forces = self._run(rec, inputs)
        except Exception:  # whatever stops a trace leaves that path to the scalar path
            return False
        names = tuple(conditioning)
        if self.conditioning is None:
            self.conditioning = names
        elif names != self.conditioning:
            return False
        atoms = [rec.atom(v) for v in (*values, *conditioning.values(), *forces)]
        ret = tuple(a for a, _ in atoms)
        uses = tuple(dict.fromkeys(u for _, us in atoms for u in us))
        if self._root is None:
            self._root = Node(rec.items, ret, uses)
            self.paths = 1
            return True
        if merge(self._root, rec.items, ret, uses):
            self.paths += 1
            return True
        return False

    def _run(self, rec: Recorder, inputs: list[Tracer]) -> tuple[list[Any], dict[str, Any], tuple[Any, ...]]:
        """The plan on traced inputs: the outputs, the conditioning figures, the force layer's values."""
        scene, k, n = self.scene, self.k, self.order + 1
        model = scene.forces
        if self.derivatives:
            return self._derivatives(inputs), {}, ()
        if k == 1:
            phi, w, e = inputs
            ctx = Context(phi=phi, xp=TRACE, scene=scene._label, find_intervals=scene._intervals, owner=scene)
            scene.plan.run(ctx)
            forces = () if model is None else model.evaluate(ctx.values, TRACE, ctx.conditioning, w, e)
            return self._single(rec, ctx.values, w, e, n), ctx.conditioning, tuple(forces)
        q, u, s = inputs[:k], inputs[k:2 * k], inputs[2 * k:]
        seeds = {name: Jet(q[i], u[i], s[i]) for i, name in enumerate(scene.inputs)}
        ctx = Context(phi=tuple(q), xp=TRACE, scene=scene._label, owner=scene, seeds=seeds)
        scene.plan.run(ctx)
        forces = () if model is None else model.evaluate(ctx.values, TRACE, ctx.conditioning, 1.0, 0.0)
        out: list[Any] = []
        for p in scene.output_points:
            z0, z1, z2 = ctx.values[p]
            z1, z2 = _as_complex(rec, z1), _as_complex(rec, z2)
            out.extend((z0.real, z0.imag, z1.real, z1.imag, z2.real, z2.imag)[: 2 * n])
        for j in scene.output_joints:
            out.extend(_as_float(rec, x) for x in ctx.values[j][:n])
        return out, ctx.conditioning, tuple(forces)

    def _derivatives(self, q: list[Tracer]) -> list[Any]:
        """Every output's J and H, as ``solver.multi.instant_jets`` computes them, in one function."""
        scene, k = self.scene, self.k
        zero = [0.0] * k
        names = (*scene.output_points, *scene.output_joints)
        jac: dict[str, list[Any]] = {name: [0.0] * k for name in names}
        hess: dict[str, list[list[Any]]] = {name: [[0.0] * k for _ in range(k)] for name in names}
        for moved, u in directions(k):
            seeds = {inp: Jet(q[i], u[i], zero[i]) for i, inp in enumerate(scene.inputs)}
            ctx = Context(phi=tuple(q), xp=TRACE, mask=True, scene=scene._label, owner=scene, seeds=seeds)
            values = scene.plan.run(ctx).values
            if ctx.invalid is not False:
                raise TraceError("unassemblable")
            for name in names:
                take_direction(jac[name], hess[name], moved, values[name])
        out: list[Any] = []
        for name in names:
            out.extend(jac[name])
            for row in hess[name]:
                out.extend(row)
        return out

    def _single(self, rec: Recorder, vals: Any, w: Any, e: Any, n: int) -> list[Any]:
        """The real motion of the outputs, as ``scene._scalar_floats`` computes it."""
        scene = self.scene
        out: list[Any] = []
        ww = w * w
        for p in scene.output_points:
            z0, z1, z2 = vals[p]
            if scene.dim == 2:
                v, a = z1 * w, z2 * ww + z1 * e
                out.extend((z0.real, z0.imag, v.real, v.imag, a.real, a.imag)[: 2 * n])
            elif type(z0) is tuple:
                parts = [z0, tuple(x * w for x in z1), tuple(x2 * ww + x1 * e for x1, x2 in zip(z1, z2))]
                for part in parts[:n]:
                    out.extend(part)
            else:
                out.extend([float(x) for x in z0] + [0.0] * (3 * (n - 1)))
        for j in scene.output_joints:
            q0, q1, q2 = vals[j]
            parts = [_as_float(rec, q0), _as_float(rec, q1 * w), _as_float(rec, q2 * ww + q1 * e)]
            out.extend(parts[:n])
        return out

    # -- code -----------------------------------------------------------------------------------
    def _build(self) -> None:
        if self._root is None:
            self.source = "# no path could be traced: every instant takes the scalar path\n"
            return
        root = copy_tree(self._root)  # pruning and sharing tails rewrite the tree: later traces merge into the original
        prune(root)
        share(root)
        args = ", ".join(self.args)
        miss = f"_miss({args})"
        consts = [name for name, _ in self._constants.values()]
        body: list[str] = ["        try:"]
        emit(root, " " * 12, miss, body, Counter())
        body += [
            "        except (ArithmeticError, ValueError) as exc:",
            "            if isinstance(exc, _SolverError):",
            "                raise",
            f"        return {miss}",
            "    return compiled_instant",
        ]
        head = f"def _factory(_miss, _SolverError, _entry, {', '.join([*_MATH, *consts])}):"
        named = [f"# {name} = {getattr(v, '__module__', None) or '?'}.{v.__qualname__}"
                 for name, v in self._constants.values() if callable(v) and hasattr(v, "__qualname__")]
        self.source = "\n".join([*named, head, f"    def compiled_instant({args}):", *body]) + "\n"
        values = [v for _, v in self._constants.values()]
        factory = self._compile(self.source)
        self.core = factory(self._no_code, SolverError, None, *_MATH.values(), *values)
        self.function = factory(self._on_miss, SolverError, None, *_MATH.values(), *values)
        if self._entry is not None and self._bind is not None:
            # the same body behind the check the scene's instant() makes before its fast path:
            # three floats and the default order, else the general entry (a call of the method)
            checked = "\n".join([
                head,
                "    def compiled_instant(phi, omega=1.0, epsilon=0.0, order=2):",
                "        if (phi.__class__ is not float or omega.__class__ is not float"
                " or epsilon.__class__ is not float or order != 2):",
                "            return _entry(phi, omega, epsilon, order=order)",
                *body,
            ]) + "\n"
            self._bind(self._compile(checked)(self._on_miss, SolverError, self._entry, *_MATH.values(), *values))

    def _compile(self, source: str) -> Callable[..., Any]:
        namespace: dict[str, Any] = {}
        exec(compile(source, f"<compiled {self.scene.name}>", "exec"), namespace)
        return namespace["_factory"]  # type: ignore[no-any-return]
