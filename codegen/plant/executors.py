"""Where verify's work runs: worker processes of this machine, or a Dask cluster (distributed) at its scheduler."""

from __future__ import annotations

import uuid
from collections.abc import Callable, Iterator, Sequence

import codegen
from codegen.verify.executor import Executor, LocalExecutor

__all__ = ["SCHEDULER_ENV", "ClusterError", "DaskExecutor", "Executor", "LocalExecutor", "executor_for"]

# distributed's own variable (dask's config key `scheduler-address`): a Client made without an address reads it too
SCHEDULER_ENV = "DASK_SCHEDULER_ADDRESS"
INSTALL = "pip install 'codegen[cluster]'"
CONNECT_SECONDS = 30  # a scheduler not answering by then is not there


class ClusterError(Exception):
    """No cluster to run on: distributed not installed, the scheduler not reached, a worker without this codegen, or
    a task whose workers kept dying."""


def executor_for(scheduler: str | None, jobs: int = 0) -> Executor:
    """A Dask cluster's executor where a scheduler address is given, else `jobs` worker processes here."""
    return DaskExecutor(scheduler) if scheduler else LocalExecutor(jobs)


class DaskExecutor:
    """Tasks on a Dask cluster, one per worker thread at a time. A worker that dies while it runs a task has the task
    run again by the scheduler on another (up to the scheduler's `distributed.scheduler.allowed-failures`, 3 by
    default); a task that raises is not tried again, its error being the program's, the same on every worker.
    Results come in the tasks' order. `client`: an open distributed.Client (left open) or an address."""

    def __init__(self, client, timeout: float = CONNECT_SECONDS) -> None:
        distributed = _distributed()
        self._own = isinstance(client, str)
        if self._own:
            try:
                client = distributed.Client(client, timeout=timeout, set_as_default=False)
            except (OSError, TimeoutError, ValueError) as exc:
                raise ClusterError(f"scheduler {client}: not reached ({exc})") from None
        self.client = client
        self._check_workers()

    @property
    def workers(self) -> int:
        return max(1, sum(self.client.nthreads().values()))

    def map(self, fn: Callable, tasks: Sequence, groups: Sequence[int] | None = None) -> Iterator:
        return self._results(fn, list(tasks), groups) if tasks else iter(())

    def _results(self, fn: Callable, tasks: list, groups: Sequence[int] | None) -> Iterator:
        # keys of their own: two equal tasks are two runs, and no key of another run is taken as this one's result
        prefix = f"codegen-{fn.__name__}-{uuid.uuid4().hex}"
        keys = [f"{prefix}-{i}" for i in range(len(tasks))]
        futures = self._submit(fn, tasks, keys, groups)
        step = self.workers  # results fetched a worker-count at a time: one round trip each, not one per task
        try:
            for start in range(0, len(futures), step):
                batch = futures[start : start + step]
                yield from self._gather(batch)
                for future in batch:
                    future.release()
        finally:  # after an error, or results not all taken: the cluster stops the rest
            self.client.cancel([f for f in futures if not f.done()])

    def _submit(self, fn: Callable, tasks: list, keys: list[str], groups: Sequence[int] | None) -> list:
        if groups is None:
            return self.client.map(fn, tasks, key=keys, pure=False)
        # a group's tasks asked of one worker (each loads its program once), others taking them if it is gone
        addresses = sorted(self.client.nthreads()) or [None]
        futures: list = [None] * len(tasks)
        for group in sorted(set(groups)):
            mine = [i for i, g in enumerate(groups) if g == group]
            where = addresses[group % len(addresses)]
            placed = self.client.map(
                fn,
                [tasks[i] for i in mine],
                key=[keys[i] for i in mine],
                pure=False,
                workers=None if where is None else [where],
                allow_other_workers=True,
            )
            for i, future in zip(mine, placed, strict=True):
                futures[i] = future
        return futures

    def _gather(self, futures: list) -> list:
        from distributed import KilledWorker

        try:
            return self.client.gather(futures)
        except KilledWorker as exc:
            raise ClusterError(f"a task's every worker died ({exc})") from None

    def _check_workers(self) -> None:
        """Each worker runs this codegen's version: its tasks unpickle into the same code."""
        versions = self.client.get_versions(packages=["codegen"])
        for address, info in sorted(versions["workers"].items()):
            theirs = (info or {}).get("packages", {}).get("codegen")
            if theirs != codegen.__version__:
                raise ClusterError(
                    f"worker {address}: codegen {theirs or 'not installed'}, not {codegen.__version__} as here "
                    f"(each worker needs this codegen and its cluster extra: {INSTALL})"
                )

    def close(self) -> None:
        if self._own:
            self.client.close()

    def __enter__(self) -> DaskExecutor:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _distributed():
    """The distributed package, or a ClusterError saying which extra brings it."""
    try:
        import distributed
    except ImportError:
        raise ClusterError(f"a Dask cluster needs the distributed package: {INSTALL}") from None
    return distributed
