"""Parallel work on a Dask cluster, and runs that do not depend on how they are split.

Two kinds of job share it: ``pdr-eval`` (a recording per task) and the Monte-Carlo
studies (a batch of runs per task: ``pdr-ekf montecarlo``, ``pdr-ekf study sweep``). On a
cluster (``--scheduler ADDRESS``) the tasks go to Dask distributed, its scheduler, its
workers and its protocol; every task runs with one numba thread, the parallelism being over
tasks. Without one, the batches run here, in order, each on all of numba's threads.

A Monte-Carlo run draws its noise from its own generator, seeded from the study's seed and
the run's index (:func:`run_generator`), never from a stream shared with the runs before
it: a study split into batches, here or on any number of workers, equals the unsplit one.
"""
from __future__ import annotations

import os
import uuid
from collections.abc import Callable, Iterator, Sequence
from typing import Any

import numpy as np


def one_numba_thread() -> None:
    """One numba thread in this worker: the parallelism is over tasks."""
    os.environ["NUMBA_NUM_THREADS"] = "1"
    import numba

    numba.set_num_threads(1)


def run_generator(seed: int, run: int) -> np.random.Generator:
    """The generator of run ``run`` of a study seeded ``seed``: NumPy's child stream
    ``SeedSequence(seed).spawn(run + 1)[run]``, independent of every other run's."""
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(run,)))


def on_one_thread(function: Callable, *args: Any) -> Any:
    """``function(*args)`` with one numba thread (:func:`one_numba_thread`)."""
    one_numba_thread()
    return function(*args)


def cluster_map(scheduler: str, function: Callable, items: Sequence[tuple], name: str
                ) -> Iterator[tuple[int, Any]]:
    """``function(*item)`` for every item on the Dask scheduler at ``scheduler``
    (tcp://HOST:8786), one numba thread per task; yields (index of the item, result) as
    the tasks end. ``function`` (a partial may carry a study's arrays) is sent to every
    worker once, the items with their tasks; both are pickled, so they must be importable
    there (the same workspace) and paths in them reachable (a shared filesystem)."""
    from distributed import Client, as_completed

    job = uuid.uuid4().hex[:8]
    with Client(scheduler) as client:
        shared = client.scatter(function, broadcast=True, hash=False)
        futures = {client.submit(on_one_thread, shared, *item, pure=False,
                                 key=f"{name}-{job}-{index}"): index
                   for index, item in enumerate(items)}
        for future in as_completed(futures):
            yield futures[future], future.result()


def run_batches(function: Callable[[int, int], Any], runs: int, batch: int,
                scheduler: str | None = None, progress: Callable[[int, int], None] | None = None,
                name: str = "runs") -> list:
    """``function(first, count)`` over the runs 0 … runs − 1 in batches of ``batch`` runs,
    here in order or on the Dask ``scheduler`` (:func:`cluster_map`); the results in the
    runs' order. ``progress(done, runs)`` after each batch."""
    if batch < 1:
        raise ValueError(f"batch must be >= 1, got {batch}")
    spans = [(first, min(batch, runs - first)) for first in range(0, runs, batch)]
    ended = (enumerate(function(*span) for span in spans) if scheduler is None
             else cluster_map(scheduler, function, spans, name))
    results: list = [None] * len(spans)
    done = 0
    for index, result in ended:
        results[index] = result
        done += spans[index][1]
        if progress is not None:
            progress(done, runs)
    return results
