"""The executor interface verify's tasks go through, and its local form: worker processes on this machine."""

from __future__ import annotations

import multiprocessing
import os
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from typing import Protocol


class Executor(Protocol):
    """Where tasks run, `workers` at a time. `map(fn, tasks, groups)` gives fn(task) for each task as an iterator in
    the tasks' order, whatever order they end in, so what is merged from them does not depend on where or when they
    ran. fn is a module-level function and the tasks picklable; a task may run more than once (where a worker is
    lost), so fn has no effect but its result. groups (optional): a group number per task, a hint that a group's
    tasks share one worker (each loads its program once). Used as a context manager: leaving it frees the
    workers."""

    workers: int

    def map(self, fn: Callable, tasks: Sequence, groups: Sequence[int] | None = None) -> Iterator: ...

    def __enter__(self) -> Executor: ...

    def __exit__(self, *exc) -> None: ...


@dataclass
class LocalExecutor:
    """Worker processes of this machine: `jobs` of them (0: one per core); one worker or one task runs in this
    process. A pool lives for one map."""

    jobs: int = 0

    @property
    def workers(self) -> int:
        return self.jobs or os.cpu_count() or 1

    def map(self, fn: Callable, tasks: Sequence, groups: Sequence[int] | None = None) -> Iterator:
        if self.workers <= 1 or len(tasks) <= 1:
            return map(fn, tasks)
        if groups is not None:
            return _pinned(fn, tasks, groups, self.workers)
        return _pooled(fn, tasks, self.workers)

    def __enter__(self) -> LocalExecutor:
        return self

    def __exit__(self, *exc) -> None:
        return None


def _pooled(fn: Callable, tasks: Sequence, workers: int) -> Iterator:
    with ProcessPoolExecutor(max_workers=workers, mp_context=_fork()) as pool:
        yield from pool.map(fn, tasks)


def _pinned(fn: Callable, tasks: Sequence, groups: Sequence[int], workers: int) -> Iterator:
    """Each group's tasks in one worker process of their own (one single-process pool each)."""
    pools = [ProcessPoolExecutor(max_workers=1, mp_context=_forkserver()) for _ in range(workers)]
    try:
        futures = [pools[group % workers].submit(fn, task) for task, group in zip(tasks, groups, strict=True)]
        for future in futures:
            yield future.result()
    finally:  # after an error, without waiting for the other workers' tasks
        for pool in pools:
            pool.shutdown(wait=False, cancel_futures=True)


def _fork():
    """Workers forked where the system can (they start at once, with the parent's modules)."""

    return multiprocessing.get_context("fork") if "fork" in multiprocessing.get_all_start_methods() else None


def _forkserver():
    """Workers started from a clean server process where the system has one: a pool's worker forked from this
    process after another pool's threads started could inherit a lock one of them held."""

    if "forkserver" not in multiprocessing.get_all_start_methods():
        return None
    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload(["codegen.verify.runner"])  # imported once, in the server
    return context
