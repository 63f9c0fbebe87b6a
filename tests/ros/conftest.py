"""Fixtures of the ROS package tests: the real rclpy over DDS.

* ``ROS_DOMAIN_ID`` of this test session: 1 + (pid mod 100) unless ``LINKAGE_ROS_DOMAIN_ID`` is
  set, and ``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``, both set in this process's environment
  (so in every node process it starts) before rclpy is initialised: parallel runs never
  cross-talk.
* ``client``: an rclpy context, node and executor in the test process (subscribers, service
  clients, a /clock publisher), shared by the session.
* ``start_node``: starts the installed ``mechanism_node`` console script as its own process;
  every process it started is ended by PID when its test module ends (SIGKILL after a grace
  period).
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from collections import defaultdict
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pytest

HERE = Path(__file__).parent
if str(HERE) not in sys.path:  # the shared test scene, whatever the import mode
    sys.path.insert(0, str(HERE))

DOMAIN_ID = int(os.environ.get("LINKAGE_ROS_DOMAIN_ID", 1 + os.getpid() % 100))
os.environ["ROS_DOMAIN_ID"] = str(DOMAIN_ID)
os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
os.environ.pop("ROS_LOCALHOST_ONLY", None)

#: Seconds a node process gets to start and be discovered / to exit after a signal.
START_TIMEOUT_S = 30.0
EXIT_TIMEOUT_S = 15.0
CALL_TIMEOUT_S = 10.0


def node_executable() -> str:
    """The venv's mechanism_node console script (beside this Python), else the one on PATH, else
    a ROS workspace's ``lib/linkage_ros/mechanism_node`` (AMENT_PREFIX_PATH)."""
    candidates = [Path(sys.prefix) / "bin" / "mechanism_node"]
    on_path = shutil.which("mechanism_node")
    candidates += [Path(on_path)] if on_path else []
    candidates += [Path(p) / "lib" / "linkage_ros" / "mechanism_node"
                   for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
    for candidate in candidates:
        if candidate.is_file():
            return str(candidate)
    pytest.fail("mechanism_node is not installed (pip install -e '.[ros]')")


class NodeProcess:
    """One mechanism_node process; output goes to ``log``."""

    def __init__(self, argv: Sequence[str], log: Path, env: dict[str, str] | None = None) -> None:
        self.log = log
        self._out = open(log, "wb")
        self.popen = subprocess.Popen(
            list(argv), stdout=self._out, stderr=subprocess.STDOUT, env=env, start_new_session=True
        )
        self.pid = self.popen.pid

    def output(self) -> str:
        return self.log.read_text(encoding="utf-8", errors="replace")

    def wait(self, timeout: float = EXIT_TIMEOUT_S) -> int:
        return self.popen.wait(timeout=timeout)

    def stop(self, sig: int = signal.SIGINT, timeout: float = EXIT_TIMEOUT_S) -> int:
        """Send ``sig`` and wait for the exit status (SIGKILL, and a failure, after ``timeout``)."""
        if self.popen.poll() is None:
            os.kill(self.pid, sig)
        try:
            return self.popen.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            self.kill()
            pytest.fail(f"mechanism_node (pid {self.pid}) did not exit within {timeout} s of {sig!r}")
        finally:
            self._out.close()

    def kill(self) -> None:
        if self.popen.poll() is None:
            os.kill(self.pid, signal.SIGKILL)
            self.popen.wait(timeout=EXIT_TIMEOUT_S)
        self._out.close()


@pytest.fixture(scope="module")
def start_node(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Callable[..., NodeProcess]]:
    """``start_node(*ros_args, executable=..., env=...)`` → a running :class:`NodeProcess`; the
    processes a test module started end with the module (a node left ticking at 1 kHz would load
    the machine under every later module's timing)."""
    started: list[NodeProcess] = []
    logs = tmp_path_factory.mktemp("node_logs")

    def start(*ros_args: str, executable: str | None = None, env: dict[str, str] | None = None) -> NodeProcess:
        argv = [executable or node_executable(), "--ros-args", *ros_args]
        process = NodeProcess(argv, logs / f"node_{len(started)}.log", env=env)
        started.append(process)
        return process

    yield start
    for process in started:
        if process.popen.poll() is None:
            try:
                os.kill(process.pid, signal.SIGTERM)
                process.popen.wait(timeout=5)
            except (subprocess.TimeoutExpired, ProcessLookupError):
                pass
        process.kill()


class Listener:
    """Raw (CDR) messages of some topics as they arrive: ``(topic, bytes)`` in order."""

    def __init__(self) -> None:
        self.messages: list[tuple[str, bytes]] = []
        self.by_topic: dict[str, list[bytes]] = defaultdict(list)

    def callback(self, topic: str) -> Callable[[bytes], None]:
        def keep(data: bytes) -> None:
            self.messages.append((topic, data))
            self.by_topic[topic].append(data)

        return keep


class Client:
    """The test process's side of the DDS conversation."""

    def __init__(self, name: str = "linkage_test_client") -> None:
        import rclpy
        from rclpy.context import Context
        from rclpy.executors import SingleThreadedExecutor
        from rclpy.signals import SignalHandlerOptions

        self.context = Context()
        rclpy.init(context=self.context, signal_handler_options=SignalHandlerOptions.NO)
        self.node = rclpy.create_node(name, context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)

    def close(self) -> None:
        self.executor.shutdown(timeout_sec=1.0)
        self.node.destroy_node()
        self.context.try_shutdown()

    def spin_until(self, done: Callable[[], bool], timeout: float) -> bool:
        deadline = time.monotonic() + timeout
        while not done():
            if time.monotonic() > deadline:
                return False
            self.executor.spin_once(timeout_sec=0.05)
        return True

    def spin_until_latest(self, listener: Listener, topic: str, typename: str, holds: Callable[[Any], bool],
                          timeout: float = 20.0) -> bool:
        """Spin until the latest message on ``topic`` (decoded) ``holds``: after a parameter set, the
        messages already in flight on a loaded machine are read before the first with the new value."""
        def latest_holds() -> bool:
            messages = listener.by_topic[topic]
            return bool(messages) and holds(decode(messages[-1], typename))

        return self.spin_until(latest_holds, timeout)

    def spin_until_quiet(self, listener: Listener, topic: str, quiet: float, timeout: float = 20.0) -> bool:
        """Spin until no message has arrived on ``topic`` for ``quiet`` seconds."""
        deadline = time.monotonic() + timeout
        count, since = len(listener.by_topic[topic]), time.monotonic()
        while time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=0.02)
            if len(listener.by_topic[topic]) != count:
                count, since = len(listener.by_topic[topic]), time.monotonic()
            elif time.monotonic() - since >= quiet:
                return True
        return False

    def spin_for(self, seconds: float) -> None:
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=0.02)

    def listen(self, topics: dict[str, str], *, depth: int = 5000) -> Listener:
        """Subscribe (reliable, keep last ``depth``, raw bytes) to ``{absolute topic: type name}``."""
        from rclpy.qos import QoSProfile, ReliabilityPolicy

        from linkage_ros.node import message_classes

        listener = Listener()
        classes = message_classes(sorted(set(topics.values())))
        qos = QoSProfile(depth=depth, reliability=ReliabilityPolicy.RELIABLE)
        for topic, typename in topics.items():
            self.node.create_subscription(classes[typename], topic, listener.callback(topic), qos, raw=True)
        return listener

    def published_by(self, node_name: str, namespace: str) -> list[tuple[str, list[str]]]:
        """The topics ``node_name`` publishes, as far as discovery has got: none until the graph
        knows the node (its messages can arrive before its node entry does)."""
        from rclpy._rclpy_pybind11 import NodeNameNonExistentError

        try:
            return list(self.node.get_publisher_names_and_types_by_node(node_name, namespace))
        except NodeNameNonExistentError:
            return []

    def call(self, service_type: Any, name: str, request: Any, timeout: float = CALL_TIMEOUT_S) -> Any:
        client = self.node.create_client(service_type, name)
        try:
            assert self.spin_until(client.service_is_ready, timeout), f"service {name} not available"
            future = client.call_async(request)
            assert self.spin_until(future.done, timeout), f"no answer from {name}"
            return future.result()
        finally:
            self.node.destroy_client(client)

    def set_parameters(self, node: str, **values: Any) -> list[Any]:
        """Set parameters of ``node`` (fully qualified name) through its set_parameters service."""
        from rcl_interfaces.srv import SetParameters
        from rclpy.parameter import Parameter

        request = SetParameters.Request(
            parameters=[Parameter(k, value=v).to_parameter_msg() for k, v in values.items()]
        )
        return list(self.call(SetParameters, f"{node}/set_parameters", request).results)

    def get_parameters(self, node: str, *names: str) -> list[Any]:
        from rcl_interfaces.srv import GetParameters
        from rclpy.parameter import parameter_value_to_python

        response = self.call(GetParameters, f"{node}/get_parameters", GetParameters.Request(names=list(names)))
        return [(v.type, parameter_value_to_python(v)) for v in response.values]


@contextmanager
def solo_listener(topic: str, typename: str, *, depth: int = 5000) -> Iterator[tuple[Listener, Client]]:
    """A client of its own (context, node, executor) subscribed to one topic only: a rate counted
    at 1 kHz is not read through the session client's executor, whose wait set holds every
    subscription of the session so far (rebuilt at each spin: too slow for 1000 messages a
    second on 2 cores, so the node's keep-last writers drop what it has not read yet)."""
    solo = Client("linkage_test_solo_listener")
    try:
        listener = solo.listen({topic: typename}, depth=depth)
        assert solo.spin_until(lambda: bool(listener.by_topic[topic]), 20.0), f"no {topic} reached a new participant"
        yield listener, solo
    finally:
        solo.close()


@pytest.fixture(scope="session")
def client() -> Iterator[Client]:
    c = Client()
    try:
        yield c
    finally:
        c.close()


def decode(data: bytes, typename: str) -> Any:
    """rclpy's own reading of received bytes (what any ROS subscriber does)."""
    from rclpy.serialization import deserialize_message

    from linkage_ros.node import message_classes

    return deserialize_message(data, message_classes([typename])[typename])


def stamp_of(data: bytes) -> int:
    """The header stamp (ns) of a CDR message that starts with a std_msgs/Header, or a
    MarkerArray / DiagnosticArray's first header... read from the CDR bytes directly."""
    import struct

    sec, nanosec = struct.unpack_from("<iI", data, 4)
    return sec * 1_000_000_000 + nanosec
