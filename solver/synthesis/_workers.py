"""Where the starts of the multi-start sweep run: here, on local processes, or on a Dask client.

``workers=None`` (or 1) runs each start in this process when its result is read, so no start is
computed that the sweep does not read. ``workers=N`` (N ≥ 2) keeps N starts running at once on a
pool of N local processes (``multiprocessing``, forked where the platform forks: the template
and the task are already in the children's memory, no import per process); ``workers=`` a
``dask.distributed.Client`` keeps one start per Dask worker running. In each case the results
are read **in start order** (a pipeline: when start i is read, start i + N is submitted), so the
sweep's stopping rule sees the same sequence of results as one process and returns the same
design; the starts still running when it stops are ended (the pool's processes terminated, the
Dask futures cancelled). The CPU those extra starts took is the price of the wall time saved.
"""

from __future__ import annotations

import multiprocessing
from collections.abc import Callable
from typing import Any, Protocol

__all__ = ["Runner", "runner"]


class _Handle(Protocol):
    def result(self) -> Any: ...


class Runner:
    """Runs ``fn(*args)`` for the sweep: :meth:`submit` returns a handle whose ``result()`` is
    the value; ``depth`` starts are kept running at once. Here: lazily, in this process."""

    depth = 1

    def submit(self, fn: Callable[..., Any], *args: Any) -> _Handle:
        return _Lazy(fn, args)

    def close(self) -> None:
        """End whatever still runs (nothing here)."""

    def __enter__(self) -> Runner:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class _Lazy:
    def __init__(self, fn: Callable[..., Any], args: tuple[Any, ...]) -> None:
        self.fn, self.args = fn, args

    def result(self) -> Any:
        return self.fn(*self.args)


class _Async:
    def __init__(self, value: Any) -> None:
        self.value = value

    def result(self) -> Any:
        return self.value.get()


class _Pool(Runner):
    """``count`` local processes; ended (terminated) when the sweep stops."""

    def __init__(self, count: int) -> None:
        methods = multiprocessing.get_all_start_methods()
        context = multiprocessing.get_context("fork" if "fork" in methods else "spawn")
        self.depth = count
        self.pool = context.Pool(count)

    def submit(self, fn: Callable[..., Any], *args: Any) -> _Handle:
        return _Async(self.pool.apply_async(fn, args))

    def close(self) -> None:
        self.pool.terminate()  # the starts still running are not read: their processes end now
        self.pool.join()


class _Dask(Runner):
    """One start per worker of a ``dask.distributed.Client``; the template and the task are
    scattered to every worker once (the first two arguments of each call)."""

    def __init__(self, client: Any) -> None:
        self.client = client
        self.depth = max(1, len(client.scheduler_info().get("workers", {})))
        self.shared: Any = None
        self.futures: list[Any] = []

    def submit(self, fn: Callable[..., Any], *args: Any) -> _Handle:
        if self.shared is None:
            self.shared = self.client.scatter(list(args[:2]), broadcast=True)
        future = self.client.submit(fn, *self.shared, *args[2:], pure=False)
        self.futures.append(future)
        return future  # type: ignore[no-any-return]

    def close(self) -> None:
        pending = [f for f in self.futures if not f.done()]
        if pending:
            self.client.cancel(pending)


def runner(workers: Any) -> Runner:
    """The runner of ``workers``: None or 1 (this process), an int N ≥ 2 (N local processes) or a
    Dask client (checked by ``synthesize``)."""
    if workers is None or (isinstance(workers, int) and workers <= 1):
        return Runner()
    if isinstance(workers, int):
        return _Pool(workers)
    return _Dask(workers)
