"""A small stand-in for the parts of rclpy (and generated message packages) that node.py uses.

Not a ROS implementation: enough to construct :class:`linkage_ros.node.MechanismNode`, tick its
timer, publish, and set parameters the way rclpy does (descriptor type and range checks, then
the on-set callbacks). Message classes are generated from rosbags' Jazzy type store and check
their fields as rosidl_generator_py's classes do: floats must be ``float``, integers ``int``,
``byte`` fields ``bytes`` of length 1, primitive sequences ``array.array`` of the right type code
or real Python sequences of the right element type (a numpy array is rejected), nested messages
instances of their class. :func:`install` puts the modules into ``sys.modules``.
"""

from __future__ import annotations

import array
import math
import sys
import types
from collections.abc import Callable, Sequence
from typing import Any

from rosbags.typesys import Stores, get_typestore
from rosbags.typesys.base import Nodetype

__all__ = ["FakeClock", "FakeNodeBase", "install", "MODULE_NAMES"]

_ARRAY_CODES = {
    "float64": "d", "float32": "f", "int8": "b", "uint8": "B", "int16": "h", "uint16": "H",
    "int32": "i", "uint32": "I", "int64": "q", "uint64": "Q",
}
_INTS = {"int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64", "char"}
_PACKAGES = (
    "builtin_interfaces", "std_msgs", "geometry_msgs", "sensor_msgs", "trajectory_msgs",
    "visualization_msgs", "diagnostic_msgs", "rcl_interfaces",
)
MODULE_NAMES = (
    "rclpy", "rclpy.node", "rclpy.qos", "rclpy.executors", "rclpy.parameter",
    "rclpy.serialization", "rclpy.logging", *(f"{p}.msg" for p in _PACKAGES), *_PACKAGES,
)


# ---------------------------------------------------------------------- message classes
def _check_base(kind: str, value: Any) -> bool:
    if kind in ("float64", "float32"):
        return isinstance(value, float)
    if kind in _INTS:
        return isinstance(value, int)
    if kind == "bool":
        return isinstance(value, bool)
    if kind == "byte":
        return isinstance(value, bytes) and len(value) == 1
    if kind == "string":
        return isinstance(value, str)
    raise AssertionError(f"unknown base type {kind}")


def _default_base(kind: str) -> Any:
    if kind in ("float64", "float32"):
        return 0.0
    if kind == "bool":
        return False
    if kind == "byte":
        return b"\x00"
    if kind == "string":
        return ""
    return 0


def _field_property(cls_name: str, name: str, spec: Any, registry: dict[str, type]) -> property:
    nodetype, detail = spec

    def check(value: Any) -> Any:
        if nodetype == Nodetype.BASE:
            assert _check_base(detail[0], value), f"{cls_name}.{name}: bad {detail[0]} {value!r}"
            return value
        if nodetype == Nodetype.NAME:
            assert isinstance(value, registry[detail]), f"{cls_name}.{name}: not a {detail}"
            return value
        (sub_type, sub_detail), _bound = detail
        if sub_type == Nodetype.BASE and sub_detail[0] in _ARRAY_CODES:
            code = _ARRAY_CODES[sub_detail[0]]
            if isinstance(value, array.array):
                assert value.typecode == code, f"{cls_name}.{name}: array typecode {value.typecode}"
                return value
            assert isinstance(value, Sequence) and not isinstance(value, str), (
                f"{cls_name}.{name}: must be a sequence or array.array('{code}'), got {type(value)}"
            )
            assert all(_check_base(sub_detail[0], v) for v in value), f"{cls_name}.{name}: element"
            return array.array(code, value)
        assert isinstance(value, Sequence) and not isinstance(value, str), f"{cls_name}.{name}"
        if sub_type == Nodetype.NAME:
            assert all(isinstance(v, registry[sub_detail]) for v in value), f"{cls_name}.{name}"
        else:
            assert all(_check_base(sub_detail[0], v) for v in value), f"{cls_name}.{name}"
        return value

    def getter(self: Any) -> Any:
        return getattr(self, "_" + name)

    def setter(self: Any, value: Any) -> None:
        object.__setattr__(self, "_" + name, check(value))

    return property(getter, setter)


def _default(spec: Any, registry: dict[str, type]) -> Any:
    nodetype, detail = spec
    if nodetype == Nodetype.BASE:
        return _default_base(detail[0])
    if nodetype == Nodetype.NAME:
        return registry[detail]()
    (sub_type, sub_detail), _bound = detail
    if sub_type == Nodetype.BASE and sub_detail[0] in _ARRAY_CODES:
        return array.array(_ARRAY_CODES[sub_detail[0]])
    return []


def _make_class(typename: str, fielddefs: Any, registry: dict[str, type]) -> type:
    consts, fields = fielddefs
    names = [f for f, _ in fields]
    cls_name = typename.split("/")[-1]

    def __init__(self: Any, **kwargs: Any) -> None:
        unknown = sorted(set(kwargs) - set(names))
        assert not unknown, f"Invalid arguments passed to constructor: {', '.join(unknown)}"
        for fname, spec in fields:
            value = kwargs[fname] if fname in kwargs else _default(spec, registry)
            setattr(self, fname, value)

    def __eq__(self: Any, other: Any) -> bool:
        return type(self) is type(other) and all(
            getattr(self, f) == getattr(other, f) for f in names
        )

    namespace: dict[str, Any] = {
        "__slots__": tuple("_" + f for f in names),
        "__init__": __init__,
        "__eq__": __eq__,
        "__hash__": None,
        "_fields_and_field_types": dict.fromkeys(names, ""),
        "ROS_TYPE": typename,
    }
    for cname, ctype, cvalue in consts:
        namespace[cname] = bytes([cvalue]) if ctype == "byte" else cvalue
    for fname, spec in fields:
        namespace[fname] = _field_property(cls_name, fname, spec, registry)
    return type(cls_name, (), namespace)


def message_modules() -> dict[str, types.ModuleType]:
    """``{"sensor_msgs.msg": module, ...}`` with rclpy-like classes of every type of _PACKAGES."""
    store = get_typestore(Stores.ROS2_JAZZY)
    registry: dict[str, type] = {}
    wanted = sorted(n for n in store.fielddefs if n.split("/")[0] in _PACKAGES and "/msg/" in n)

    def build(name: str) -> type:
        if name not in registry:
            for _, spec in store.fielddefs[name][1]:
                for dep in _names_in(spec):
                    build(dep)
            registry[name] = _make_class(name, store.fielddefs[name], registry)
        return registry[name]

    modules: dict[str, types.ModuleType] = {}
    for name in wanted:
        cls = build(name)
        package = name.split("/")[0]
        module = modules.setdefault(f"{package}.msg", types.ModuleType(f"{package}.msg"))
        setattr(module, cls.__name__, cls)
    return modules


def _names_in(spec: Any) -> list[str]:
    nodetype, detail = spec
    if nodetype == Nodetype.NAME:
        return [detail]
    if nodetype in (Nodetype.ARRAY, Nodetype.SEQUENCE):
        return _names_in(detail[0])
    return []


# ---------------------------------------------------------------------- rclpy pieces
class _Time:
    def __init__(self, nanoseconds: int) -> None:
        self.nanoseconds = int(nanoseconds)


class FakeClock:
    """The node clock; tests set ``ns``."""

    def __init__(self, ns: int = 1_700_000_000_000_000_000) -> None:
        self.ns = ns

    def now(self) -> _Time:
        return _Time(self.ns)


class _Logger:
    def __init__(self) -> None:
        self.records: list[tuple[str, str]] = []

    def _log(self, level: str, text: str) -> None:
        self.records.append((level, str(text)))

    def debug(self, text: str) -> None:
        self._log("debug", text)

    def info(self, text: str) -> None:
        self._log("info", text)

    def warning(self, text: str) -> None:
        self._log("warning", text)

    def warn(self, text: str) -> None:
        self._log("warning", text)

    def error(self, text: str) -> None:
        self._log("error", text)


class _Publisher:
    def __init__(self, msg_type: type, topic: str, qos: Any) -> None:
        self.msg_type, self.topic, self.qos = msg_type, topic, qos
        self.published: list[Any] = []

    def publish(self, message: Any) -> None:
        assert isinstance(message, self.msg_type), f"{self.topic}: {type(message)}"
        self.published.append(message)


class _Timer:
    def __init__(self, period: float, callback: Callable[[], None]) -> None:
        assert period > 0 and math.isfinite(period)
        self.period, self.callback, self.destroyed = period, callback, False


class InvalidParameterTypeException(Exception):
    """rclpy.exceptions.InvalidParameterTypeException."""


def _make_parameter_module(rcl_msg: Any) -> types.ModuleType:
    PT = rcl_msg.ParameterType

    class Parameter:
        """rclpy.parameter.Parameter: name, value and the type inferred like rclpy does."""

        def __init__(self, name: str, type_: Any = None, value: Any = None) -> None:
            self.name = name
            self.value = value
            self.type_ = type_ if type_ is not None else infer(value)

    def infer(value: Any) -> int:
        if value is None:
            return PT.PARAMETER_NOT_SET
        if isinstance(value, bool):
            return PT.PARAMETER_BOOL
        if isinstance(value, int):
            return PT.PARAMETER_INTEGER
        if isinstance(value, float):
            return PT.PARAMETER_DOUBLE
        if isinstance(value, str):
            return PT.PARAMETER_STRING
        if isinstance(value, (list, tuple, array.array)):
            # rclpy's order: an empty list counts as a byte array.
            if all(isinstance(v, bytes) for v in value):
                return PT.PARAMETER_BYTE_ARRAY
            if all(isinstance(v, bool) for v in value):
                return PT.PARAMETER_BOOL_ARRAY
            if all(isinstance(v, int) for v in value):
                return PT.PARAMETER_INTEGER_ARRAY
            if all(isinstance(v, float) for v in value):
                return PT.PARAMETER_DOUBLE_ARRAY
            if all(isinstance(v, str) for v in value):
                return PT.PARAMETER_STRING_ARRAY
        raise TypeError(f"cannot infer a parameter type for {value!r}")

    module = types.ModuleType("rclpy.parameter")
    module.Parameter = Parameter  # type: ignore[attr-defined]
    return module


class FakeNodeBase:
    """rclpy.node.Node, as far as MechanismNode uses it. ``parameter_overrides`` as in rclpy."""

    def __init__(self, node_name: str, *, parameter_overrides: Sequence[Any] = (), **_: Any) -> None:
        self.node_name = node_name
        self._overrides = {p.name: p for p in parameter_overrides}
        self._parameters: dict[str, Any] = {}
        self._descriptors: dict[str, Any] = {}
        self._callbacks: list[Callable[[list[Any]], Any]] = []
        self.publishers_by_topic: dict[str, _Publisher] = {}
        self.timers: list[_Timer] = []
        self.logger = _Logger()
        self.clock = FakeClock()
        self.destroyed = False

    # -- parameters
    def declare_parameter(self, name: str, value: Any = None, descriptor: Any = None) -> Any:
        Parameter = sys.modules["rclpy.parameter"].Parameter
        assert name not in self._parameters, f"parameter {name} declared twice"
        chosen = self._overrides[name].value if name in self._overrides else value
        parameter = Parameter(name, value=chosen)
        if descriptor is not None and descriptor.type != parameter.type_:
            raise InvalidParameterTypeException(
                f"Trying to set parameter '{name}' to '{chosen!r}' of type "
                f"'{parameter.type_}', expecting type '{descriptor.type}'"
            )
        self._parameters[name] = parameter
        self._descriptors[name] = descriptor
        return parameter

    def get_parameter(self, name: str) -> Any:
        return self._parameters[name]

    def add_on_set_parameters_callback(self, callback: Callable[[list[Any]], Any]) -> None:
        self._callbacks.insert(0, callback)

    def set_parameters(self, parameters: Sequence[Any]) -> list[Any]:
        """Like rclpy: one parameter at a time, descriptor checks first, then the callbacks."""
        return [self._set_one(p) for p in parameters]

    def _set_one(self, parameter: Any) -> Any:
        Result = sys.modules["rcl_interfaces.msg"].SetParametersResult
        descriptor = self._descriptors.get(parameter.name)
        if descriptor is not None:
            if descriptor.type != parameter.type_:
                return Result(successful=False, reason="Wrong parameter type, expected ...")
            if descriptor.floating_point_range:
                rng = descriptor.floating_point_range[0]
                if not rng.from_value <= parameter.value <= rng.to_value:
                    return Result(successful=False, reason="Parameter value is out of range")
        for callback in self._callbacks:
            result = callback([parameter])
            if not result.successful:
                return result
        self._parameters[parameter.name] = parameter
        return Result(successful=True, reason="")

    # -- publishing, timers, clock, logging
    def create_publisher(self, msg_type: type, topic: str, qos: Any) -> _Publisher:
        assert topic not in self.publishers_by_topic, f"publisher {topic} created twice"
        publisher = _Publisher(msg_type, topic, qos)
        self.publishers_by_topic[topic] = publisher
        return publisher

    def destroy_publisher(self, publisher: _Publisher) -> bool:
        del self.publishers_by_topic[publisher.topic]
        return True

    def create_timer(self, period: float, callback: Callable[[], None]) -> _Timer:
        timer = _Timer(period, callback)
        self.timers.append(timer)
        return timer

    def destroy_timer(self, timer: _Timer) -> bool:
        timer.destroyed = True
        self.timers.remove(timer)
        return True

    def get_clock(self) -> FakeClock:
        return self.clock

    def get_logger(self) -> _Logger:
        return self.logger

    def get_namespace(self) -> str:
        return "/"

    def destroy_node(self) -> None:
        self.destroyed = True

    # -- for tests
    def fire_timer(self) -> None:
        (timer,) = self.timers
        timer.callback()


class _InitContext:
    def __init__(self, state: dict[str, Any]) -> None:
        self.state = state

    def __enter__(self) -> _InitContext:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.state["shutdown"] = True


def install(monkeypatch: Any, *, spin: Callable[[Any], None] | None = None) -> dict[str, Any]:
    """Put the stand-in modules into ``sys.modules`` (undone by ``monkeypatch``); returns them."""
    modules: dict[str, Any] = dict(message_modules())
    for package in _PACKAGES:
        parent = types.ModuleType(package)
        parent.msg = modules[f"{package}.msg"]  # type: ignore[attr-defined]
        modules[package] = parent
    state: dict[str, Any] = {"init_args": None, "shutdown": False, "spun": []}
    rclpy = types.ModuleType("rclpy")

    def init(*, args: Any = None) -> _InitContext:
        state["init_args"] = args
        return _InitContext(state)

    def default_spin(node: Any) -> None:
        state["spun"].append(node)
        for _ in range(3):
            node.fire_timer()
            node.clock.ns += int(round(node.timers[0].period * 1e9))

    rclpy.init = init  # type: ignore[attr-defined]
    rclpy.spin = spin or default_spin  # type: ignore[attr-defined]
    rclpy.state = state  # type: ignore[attr-defined]
    node_module = types.ModuleType("rclpy.node")
    node_module.Node = FakeNodeBase  # type: ignore[attr-defined]
    qos = types.ModuleType("rclpy.qos")

    class QoSProfile:
        def __init__(self, **kwargs: Any) -> None:
            self.__dict__.update(kwargs)

    qos.QoSProfile = QoSProfile  # type: ignore[attr-defined]
    for policy, names in {
        "HistoryPolicy": ("KEEP_LAST", "KEEP_ALL"),
        "ReliabilityPolicy": ("RELIABLE", "BEST_EFFORT"),
        "DurabilityPolicy": ("VOLATILE", "TRANSIENT_LOCAL"),
    }.items():
        setattr(qos, policy, types.SimpleNamespace(**{n: n.lower() for n in names}))
    executors = types.ModuleType("rclpy.executors")

    class ExternalShutdownException(Exception):
        """rclpy.executors.ExternalShutdownException."""

    executors.ExternalShutdownException = ExternalShutdownException  # type: ignore[attr-defined]
    serialization = types.ModuleType("rclpy.serialization")
    serialization.serialize_message = lambda message: repr(message).encode()  # type: ignore[attr-defined]
    parameter = _make_parameter_module(modules["rcl_interfaces.msg"])
    logging_module = types.ModuleType("rclpy.logging")
    loggers: dict[str, _Logger] = {}
    logging_module.get_logger = lambda name: loggers.setdefault(name, _Logger())  # type: ignore[attr-defined]
    state["loggers"] = loggers
    rclpy.logging = logging_module  # type: ignore[attr-defined]
    rclpy.node = node_module  # type: ignore[attr-defined]
    rclpy.qos = qos  # type: ignore[attr-defined]
    rclpy.executors = executors  # type: ignore[attr-defined]
    rclpy.parameter = parameter  # type: ignore[attr-defined]
    rclpy.serialization = serialization  # type: ignore[attr-defined]
    modules.update({
        "rclpy": rclpy, "rclpy.node": node_module, "rclpy.qos": qos,
        "rclpy.executors": executors, "rclpy.parameter": parameter,
        "rclpy.serialization": serialization, "rclpy.logging": logging_module,
    })
    for name, module in modules.items():
        monkeypatch.setitem(sys.modules, name, module)
    monkeypatch.delitem(sys.modules, "linkage_ros.node", raising=False)
    return modules
