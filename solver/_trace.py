"""The third evaluator of the group formulas: values that record every operation done to them.

A :class:`Tracer` stands for one Python ``float`` or ``complex`` of the per-tick path. It carries
the concrete value the scalar path would have at the traced sample (so the group code takes the
same branches it takes there) and a name in a :class:`Recorder`, which writes down each
operation as one line of straight-line Python: ``v7 = v3 * v5``. Operations among constants are
not recorded (constant folding is the group code's own: a fixed point's zero derivatives stay the
float ``0.0`` and the fast paths for them are taken, as on the scalar path).

The tracer reports its concrete value's class as its ``__class__``, so ``isinstance(x, float)``,
``x.__class__ is float`` and ``isinstance(x, complex)`` in the group code answer as they do on the
scalar path; the fast paths that test a value (``x.__class__ is float and x == 0.0``) then go
through a comparison, which the tracer records as a *guard*: a condition with the outcome seen at
the traced sample. The generated function checks every guard and hands the instant back to the
scalar path when one comes out differently, so the compiled code only ever runs on the path it was
traced on (solver._codegen).

Anything a tracer cannot record — a conversion to a plain number (``float(x)``, ``math.sqrt(x)``
instead of the backend's ``xp.sqrt``), a numpy call — raises :class:`TraceError`: that path is
then not compiled, and the scalar path serves it.
"""

from __future__ import annotations

import cmath
import math
import operator
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ._backend import SCALAR, Backend

__all__ = ["Tracer", "Recorder", "TraceError", "TRACE", "Let", "Guard"]


class TraceError(Exception):
    """The traced code needed a plain number (or numpy) where only a recorded operation will do."""


@dataclass(frozen=True)
class Let:
    """``name = expr``; ``uses`` the names it reads."""

    name: str
    expr: str
    uses: tuple[str, ...]


@dataclass(frozen=True)
class Guard:
    """``expr`` evaluated to ``outcome`` at the traced sample."""

    expr: str
    outcome: bool
    uses: tuple[str, ...]


class Recorder:
    """The lines of one trace, and the constants (shared by every trace of one compiled unit)."""

    def __init__(self, constants: dict[Any, tuple[str, Any]]) -> None:
        self.items: list[Let | Guard] = []
        self.constants = constants
        self._memo: dict[str, Tracer] = {}
        self._checked: set[tuple[str, bool]] = set()
        self._count = 0

    # -- atoms -------------------------------------------------------------------------------
    def atom(self, x: Any) -> tuple[str, tuple[str, ...]]:
        """The source text of an operand, and the names it reads."""
        if type(x) is Tracer:
            return x.name, (x.name,)
        cls = type(x)
        if cls is bool or cls is int:
            return repr(x), ()
        if cls is float and math.isfinite(x):
            text = repr(x)
            return (f"({text})" if text.startswith("-") else text), ()
        if cls is complex and x == 1j and math.copysign(1.0, x.real) > 0:
            return "1j", ()
        # (repr tells every float apart but the signs of a complex's zero parts)
        key: tuple[Any, ...] = (cls, repr(x))
        if cls is complex:
            key = (cls, repr(x), math.copysign(1.0, x.real), math.copysign(1.0, x.imag))
        if key not in self.constants:
            self.constants[key] = (f"k{len(self.constants)}", x)
        return self.constants[key][0], ()

    def _format(self, template: str, args: tuple[Any, ...]) -> tuple[str, tuple[str, ...]]:
        texts: list[str] = []
        uses: list[str] = []
        for a in args:
            text, names = self.atom(a)
            texts.append(text)
            uses.extend(names)
        return template.format(*texts), tuple(dict.fromkeys(uses))

    def let(self, template: str, args: tuple[Any, ...], value: Any) -> Tracer:
        expr, uses = self._format(template, args)
        hit = self._memo.get(expr)
        if hit is not None:  # the same operation on the same operands: the same bits
            return hit
        name = f"v{self._count}"
        self._count += 1
        self.items.append(Let(name, expr, uses))
        traced = Tracer(self, name, value)
        self._memo[expr] = traced
        return traced

    def guard(self, template: str, args: tuple[Any, ...], outcome: bool) -> None:
        expr, uses = self._format(template, args)
        if (expr, bool(outcome)) in self._checked:  # the same test again: the same outcome
            return
        self._checked.add((expr, bool(outcome)))
        if (len(args) == 2 and type(args[0]) is Tracer and type(args[1]) in (float, int) and args[1] == 0
                and template in _NONZERO.get(outcome, ())):
            # x > 0 (or x < 0) holds: so does x != 0, and x == 0 does not — no need to test them again
            name = args[0].name
            self._checked.update({(f"{name} != 0.0", True), (f"{name} == 0.0", False),
                                  (f"{name} != 0", True), (f"{name} == 0", False)})
        self.items.append(Guard(expr, bool(outcome), uses))

    def input(self, name: str, value: Any) -> Tracer:
        return Tracer(self, name, value)


#: comparisons with 0 whose outcome implies the value is not zero
_NONZERO = {True: ("{0} > {1}", "{0} < {1}", "{0} != {1}"), False: ("{0} == {1}",)}


def _is_one(x: Any) -> bool:
    """A constant one (float, int or True): multiplying a float by it changes no bit."""
    return type(x) in (float, int, bool) and x == 1


def _value(x: Any) -> Any:
    return x.value if type(x) is Tracer else x


def _recorder(a: Any, b: Any) -> Recorder:
    return a.rec if type(a) is Tracer else b.rec


def _binary(symbol: str, fn: Callable[[Any, Any], Any]) -> tuple[Callable[..., Any], Callable[..., Any]]:
    template = "{0} " + symbol + " {1}"

    def forward(self: Tracer, other: Any) -> Any:
        if not _number(other):
            return NotImplemented
        if symbol == "*" and type(self.value) is float and _is_one(other):
            return self  # x·1.0 (x·1, x·True) is x to the bit for a float x
        return self.rec.let(template, (self, other), fn(self.value, _value(other)))

    def reflected(self: Tracer, other: Any) -> Any:
        if not _number(other):
            return NotImplemented
        if symbol == "*" and type(self.value) is float and _is_one(other):
            return self
        return self.rec.let(template, (other, self), fn(_value(other), self.value))

    return forward, reflected


def _compare(symbol: str, fn: Callable[[Any, Any], Any]) -> Callable[..., Any]:
    template = "{0} " + symbol + " {1}"

    def compare(self: Tracer, other: Any) -> Any:
        if not _number(other):
            return NotImplemented
        result = fn(self.value, _value(other))
        self.rec.guard(template, (self, other), bool(result))
        return result

    return compare


def _number(x: Any) -> bool:
    return type(x) is Tracer or isinstance(x, (int, float, complex))


def _refuse(what: str) -> Callable[..., Any]:
    def refuse(self: Tracer, *args: Any) -> Any:
        raise TraceError(f"a traced value was used as {what}")

    return refuse


class Tracer:
    """A float or complex of the per-tick path, recorded (see the module docstring)."""

    __slots__ = ("rec", "name", "value")
    __array_ufunc__ = None  # numpy refuses it (TypeError) instead of making an object array

    def __init__(self, rec: Recorder, name: str, value: Any) -> None:
        self.rec = rec
        self.name = name
        self.value = value

    @property  # type: ignore[misc]
    def __class__(self) -> type:
        return type(self.value)

    __add__, __radd__ = _binary("+", operator.add)
    __sub__, __rsub__ = _binary("-", operator.sub)
    __mul__, __rmul__ = _binary("*", operator.mul)
    __truediv__, __rtruediv__ = _binary("/", operator.truediv)
    __pow__, __rpow__ = _binary("**", operator.pow)
    __mod__, __rmod__ = _binary("%", operator.mod)
    __lt__ = _compare("<", operator.lt)
    __le__ = _compare("<=", operator.le)
    __gt__ = _compare(">", operator.gt)
    __ge__ = _compare(">=", operator.ge)
    __eq__ = _compare("==", operator.eq)  # type: ignore[assignment]
    __ne__ = _compare("!=", operator.ne)  # type: ignore[assignment]
    __hash__ = object.__hash__
    __float__ = _refuse("a plain float")
    __complex__ = _refuse("a plain complex")
    __int__ = _refuse("an int")
    __index__ = _refuse("an index")
    __round__ = _refuse("round()")
    __array__ = _refuse("a numpy array")
    __iter__ = _refuse("a sequence")
    __len__ = _refuse("a sequence")

    def __bool__(self) -> bool:
        outcome = bool(self.value)
        self.rec.guard("{0}", (self,), outcome)
        return outcome

    def __neg__(self) -> Tracer:
        return self.rec.let("-{0}", (self,), -self.value)

    def __pos__(self) -> Tracer:
        return self.rec.let("+{0}", (self,), +self.value)

    def __abs__(self) -> Tracer:
        if type(self.value) is float:  # |x| without a call where x ≷ 0; abs() for ±0.0 and NaN
            return self.rec.let("({0} if {0} > 0.0 else (-{0} if {0} < 0.0 else abs({0})))", (self,), abs(self.value))
        return self.rec.let("abs({0})", (self,), abs(self.value))

    @property
    def real(self) -> Any:
        if type(self.value) is float:  # float.real is the float itself
            return self
        return self.rec.let("{0}.real", (self,), self.value.real)

    @property
    def imag(self) -> Any:
        if type(self.value) is float:  # float.imag is the constant 0.0
            return 0.0
        return self.rec.let("{0}.imag", (self,), self.value.imag)

    def conjugate(self) -> Any:
        if type(self.value) is float:
            return self
        return self.rec.let("{0}.conjugate()", (self,), self.value.conjugate())

    def __repr__(self) -> str:
        return f"Tracer({self.name}={self.value!r})"


def _function(template: str, fn: Callable[..., Any]) -> Callable[..., Any]:
    """A backend function: recorded when an argument is traced, evaluated when all are constants."""

    def call(*args: Any) -> Any:
        for a in args:
            if type(a) is Tracer:
                return a.rec.let(template, args, fn(*map(_value, args)))
        return fn(*args)

    return call


@dataclass(frozen=True)
class TraceBackend(Backend):
    """The per-tick backend's functions, recorded on traced values."""

    def cis(self, angle: Any) -> Any:
        if type(angle) is not Tracer:
            return SCALAR.cis(angle)
        value = SCALAR.cis(angle.value)
        if type(angle.value) is float and _same(cmath.rect(1.0, angle.value), value):
            # complex(cos a, sin a) in one call: cmath.rect(r, a) is (r·cos a, r·sin a) from the
            # same libm cos and sin for a finite a ≠ 0, and (r, r·a) for a = ±0 — with r = 1.0 the
            # same bits (checked here at the traced sample too); non-finite a: the scalar path.
            # (bound as a constant, as xp.call's functions: whoever runs the lines has it)
            rect, _ = angle.rec.atom(cmath.rect)
            return angle.rec.let(rect + "(1.0, {0})", (angle,), value)
        return angle.rec.let("complex({0}, {1})", (self.cos(angle), self.sin(angle)), value)

    def call(self, fn: Callable[..., Any], *args: Any) -> Any:
        """An opaque scalar function (its name bound in the generated code's namespace)."""
        for a in args:
            if type(a) is Tracer:
                name, _ = a.rec.atom(fn)
                slots = ", ".join("{" + str(i) + "}" for i in range(len(args)))
                return a.rec.let(f"{name}({slots})", args, fn(*map(_value, args)))
        return fn(*args)


def _same(a: complex, b: complex) -> bool:
    """The same bits (signed zeros told apart; NaN never the same)."""
    return (a == b and math.copysign(1.0, a.real) == math.copysign(1.0, b.real)
            and math.copysign(1.0, a.imag) == math.copysign(1.0, b.imag))


def _arg(z: Any) -> Any:
    return TRACE.atan2(z.imag, z.real)  # as the scalar path: atan2(Im z, Re z)


TRACE = TraceBackend(
    "trace",
    _function("sqrt({0})", math.sqrt),
    _function("cos({0})", math.cos),
    _function("sin({0})", math.sin),
    _function("atan2({0}, {1})", math.atan2),
    _function("tan({0})", math.tan),
    # max(x, 0.0) keeps x unless 0.0 > x (so −0.0 and NaN pass, as max's do): the same value
    # without a call
    _function("sqrt((0.0 if 0.0 > {0} else {0}))", SCALAR.sqrt0),
    _arg,
    _function("-{0}", operator.neg),
    False,
)
