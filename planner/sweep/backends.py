"""Where the runs of a sweep execute: local processes through joblib (loky), or a Dask
distributed cluster (an existing one by address, or a ``LocalCluster`` started here).

Each backend yields :class:`~planner.sweep.worker.Finished` results in completion order, so
the client installs every run directory as soon as it arrives. ``dask``/``distributed`` are
imported only when a Dask backend is asked for (``pip install hapex[cluster]``).
"""

from __future__ import annotations

import logging
import os
import uuid
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from typing import Any

from planner.errors import HapexError
from planner.sweep.worker import Finished, Task, lost_run, run_task

BACKENDS = ("joblib", "dask")

#: How long :func:`dask_client` tries to reach a scheduler given by address (a Dask duration).
SCHEDULER_TIMEOUT = "20s"


class SweepBackendError(HapexError):
    """The backend could not finish (a worker process died, the cluster failed); the runs
    complete so far are kept and the sweep resumes when started again."""


class SchedulerUnreachable(HapexError):
    """The Dask scheduler address is malformed, or nothing answers there in time.

    Attributes:
        address: the address as given.
        reason: what went wrong, one line.
    """

    def __init__(self, address: str, reason: str):
        super().__init__(f"scheduler {address!r}: {reason}")
        self.address, self.reason = address, reason


def default_jobs() -> int:
    """All cores this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


def joblib_results(tasks: Iterable[Task], jobs: int | None = None) -> Iterator[Finished]:
    """Run tasks in ``jobs`` loky worker processes (1: in this process, one after another)."""
    from joblib import Parallel, delayed

    n = default_jobs() if jobs is None else jobs
    par = Parallel(n_jobs=n, backend="loky", return_as="generator_unordered")
    try:
        yield from par(delayed(run_task)(t) for t in tasks)
    except Exception as exc:
        if type(exc).__name__ == "TerminatedWorkerError":
            raise SweepBackendError(
                f"a worker process died ({str(exc).splitlines()[0]}); complete runs are kept"
            ) from None
        raise


def _import_distributed():
    try:
        import distributed
    except ImportError:
        raise HapexError(
            "the Dask backend needs dask.distributed: pip install 'hapex[cluster]'"
        ) from None
    return distributed


@contextmanager
def dask_client(
    scheduler: str | None = None, workers: int | None = None, processes: bool = True
) -> Iterator[Any]:
    """A ``distributed.Client``: connected to ``scheduler`` (``tcp://host:8786``), or to a
    new ``LocalCluster`` of ``workers`` single-threaded workers, closed on exit.

    Raises:
        SchedulerUnreachable: ``scheduler`` is not an address, or no scheduler answers there
            within :data:`SCHEDULER_TIMEOUT`.
    """
    distributed = _import_distributed()
    if scheduler is not None:
        try:
            client = distributed.Client(scheduler, timeout=SCHEDULER_TIMEOUT)
        except ValueError as exc:  # distributed's address parser: "missing port number" ...
            first = str(exc).splitlines()[0]
            reason = f"not a Dask scheduler address ({first}); expected tcp://host:8786"
            raise SchedulerUnreachable(scheduler, reason) from None
        except (OSError, TimeoutError) as exc:
            first = str(exc).splitlines()[0]
            reason = f"no scheduler answers within {SCHEDULER_TIMEOUT} ({first})"
            raise SchedulerUnreachable(scheduler, reason) from None
        try:
            yield client
        finally:
            client.close()
        return
    cluster = distributed.LocalCluster(
        n_workers=workers or default_jobs(),
        threads_per_worker=1,
        processes=processes,
        dashboard_address=None,
        # no dashboard, but the scheduler still serves HTTP (health, metrics), on :8787 by
        # default: a free port instead, so two sweeps (or a user's own cluster) do not clash
        scheduler_kwargs={"dashboard_address": ":0"},
        silence_logs=logging.ERROR,
    )
    client = distributed.Client(cluster)
    try:
        yield client
    finally:
        client.close()
        cluster.close()


def dask_results(tasks: Iterable[Task], client: Any) -> Iterator[Finished]:
    """Submit every task to a Dask cluster and yield results as they complete.

    A worker that dies mid-run (killed, node lost) makes the scheduler run its tasks again
    elsewhere; a run that kills every worker it is given (``KilledWorker``) comes back as a
    failed run with that reason. Pending tasks are cancelled when the caller stops early.
    """
    distributed = _import_distributed()
    tag = uuid.uuid4().hex[:8]
    futures = {
        client.submit(run_task, t, key=f"hapex-run-{t.run_id}-{tag}", pure=False): t for t in tasks
    }
    try:
        for fut in distributed.as_completed(list(futures)):
            task = futures[fut]
            if fut.status == "finished":
                yield fut.result()
            elif fut.status == "error":
                exc = fut.exception()
                text = f"{type(exc).__name__}: {exc}".splitlines()[0]
                if type(exc).__name__ != "KilledWorker":  # not the run: the cluster
                    raise SweepBackendError(
                        f"the Dask cluster could not run {task.run_id}: {text} (is the same "
                        "hapex installed on every worker?); complete runs are kept"
                    )
                yield lost_run(task, f"every worker running it died ({text})")
            fut.release()
    finally:
        pending = [f for f in futures if not f.done()]
        if pending:
            client.cancel(pending)


__all__ = [
    "BACKENDS",
    "SCHEDULER_TIMEOUT",
    "SchedulerUnreachable",
    "SweepBackendError",
    "dask_client",
    "dask_results",
    "default_jobs",
    "joblib_results",
]
