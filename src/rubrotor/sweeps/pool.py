"""The local process pool of sweeps: workers that die with their parent, lost tasks retried once.

A sweep's worker can die under it (killed, out of memory); ``concurrent.futures.ProcessPoolExecutor``
then fails every unfinished task with ``BrokenProcessPool``. :func:`run_pool` runs those tasks
again in a fresh pool (then alone, if that pool breaks too) and hands the tasks whose worker
died alone to the caller (or raises :class:`LostTasks`, one line). The workers of :func:`local_pool` end when the process that
started them ends, however it ends (``kill -9`` included): on Linux the kernel signals them
(``prctl(PR_SET_PDEATHSIG)``), elsewhere a thread in each worker watches the parent's pid.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
import time
from collections.abc import Iterator, Sequence

from rubrotor.errors import RubrotorError

__all__ = ["LostTasks", "local_pool", "run_pool"]

_PR_SET_PDEATHSIG = 1  # linux/prctl.h


class LostTasks(RubrotorError):
    """Tasks whose worker process died in two pools in a row (killed, out of memory).

    Parameters
    ----------
    tasks : list
        The lost tasks.
    """

    def __init__(self, tasks: list):
        self.tasks = tasks
        super().__init__(
            f"{len(tasks)} task(s) lost: their worker process died twice (killed, or out of "
            "memory); run again to compute them"
        )


def _watch_parent(parent: int) -> None:
    while True:
        time.sleep(1.0)
        if os.getppid() != parent:
            os._exit(1)


def _worker_init(parent: int) -> None:
    """Make this worker end with its parent (pid ``parent``)."""
    if sys.platform.startswith("linux"):
        try:
            import ctypes

            libc = ctypes.CDLL(None, use_errno=True)
            if libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0) == 0:
                if os.getppid() != parent:  # the parent died before prctl took effect
                    os._exit(1)
                return
        except (OSError, AttributeError):
            pass
    threading.Thread(target=_watch_parent, args=(parent,), daemon=True).start()


def _noop() -> int:
    return os.getpid()


def _pool(n: int):
    from concurrent.futures import ProcessPoolExecutor

    pool = ProcessPoolExecutor(max_workers=n, initializer=_worker_init, initargs=(os.getpid(),))
    for f in [pool.submit(_noop) for _ in range(n)]:
        f.result()
    pool.rubrotor_workers = n
    return pool


def local_pool(workers: int, n_tasks: int):
    """A started process pool of ``min(workers, n_tasks)`` workers (``None`` for one).

    The pool uses the platform's default start method (``fork`` on Linux with Python < 3.14)
    and its workers are started here, before the zarr store starts its I/O thread, so no
    thread is forked. Scripts using ``spawn``/``forkserver`` need the usual
    ``if __name__ == "__main__":`` guard. The workers end with this process.

    Parameters
    ----------
    workers : int
        Worker processes wanted (>= 1).
    n_tasks : int
        Tasks to run (no more workers are started).

    Returns
    -------
    concurrent.futures.ProcessPoolExecutor or None
    """
    if workers == 1 or n_tasks <= 1:
        return None
    return _pool(min(workers, n_tasks))


def _drain(pool, fn, tasks: Sequence, failed: list) -> Iterator:
    """``fn(task)`` of every task on ``pool`` as they complete; tasks whose worker died (the
    pool broke) are appended to ``failed``."""
    from concurrent.futures import FIRST_COMPLETED, wait
    from concurrent.futures.process import BrokenProcessPool

    try:
        futures = {pool.submit(fn, t): t for t in tasks}
    except BrokenProcessPool:
        failed.extend(tasks)
        return
    try:
        while futures:
            finished, _ = wait(futures, return_when=FIRST_COMPLETED)
            for fut in finished:
                task = futures.pop(fut)
                try:
                    result = fut.result()
                except BrokenProcessPool:
                    failed.append(task)
                    continue
                yield result
    finally:
        for fut in futures:
            fut.cancel()


def run_pool(fn, tasks: Sequence, pool, lost: list | None = None) -> Iterator:
    """``fn(task)`` for every task, in process (``pool`` None) or on a process pool.

    When a worker dies, every unfinished task fails with it; those are run again in a fresh
    pool, and any that fail there too run once more alone in a one-worker pool (so that the task
    killing its worker is told apart from those that died with it). Tasks whose worker died
    alone are appended to ``lost`` (the caller reports them), or, without ``lost``, raise
    :class:`LostTasks` once every other task has been yielded.

    Parameters
    ----------
    fn : callable
        Module-level function of one task.
    tasks : sequence
        Picklable tasks.
    pool : concurrent.futures.ProcessPoolExecutor or None
        From :func:`local_pool`.
    lost : list, optional
        Receives the tasks lost twice.

    Yields
    ------
    object
        ``fn(task)``, in completion order.
    """
    if pool is None:
        for t in tasks:
            yield fn(t)
        return
    failed: list = []
    yield from _drain(pool, fn, tasks, failed)
    if not failed:
        return
    again: list = []
    yield from _in_fresh_pool(fn, failed, again, getattr(pool, "rubrotor_workers", 2))
    gone: list = []
    for task in again:  # alone, so that a task killing its worker takes no other with it
        yield from _in_fresh_pool(fn, [task], gone, 1)
    if gone and lost is None:
        raise LostTasks(gone)
    if gone:
        lost.extend(gone)


def _in_fresh_pool(fn, tasks: list, failed: list, workers: int) -> Iterator:
    pool = _pool(min(workers, len(tasks)))
    try:
        yield from _drain(pool, fn, tasks, failed)
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
