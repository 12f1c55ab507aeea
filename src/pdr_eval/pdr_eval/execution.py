"""Where the recordings of a dataset run go: a pool of processes on this machine (one per
core by default), or a Dask cluster (``--scheduler ADDRESS``, Dask distributed: its
scheduler, its workers, its protocol). Every worker runs one recording at a time with one
numba thread (pdr_core.evaluation.parallel), and compiles the kernels once, from the on-disk
cache (pdr_core.maths.kernel_cache). Inputs and outputs are paths: on a cluster, the workers
must reach them (a shared filesystem).

:func:`run_all` returns the outcomes in the recordings' order, showing one progress bar
over them as they end (done, failed, time left).
"""
from __future__ import annotations

from collections.abc import Callable, Iterable
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

from tqdm import tqdm

from pdr_core.evaluation.parallel import cluster_map, on_one_thread
from pdr_eval.job import Outcome, run_recording
from pdr_eval.recordings import Recording


def _progress(total: int) -> tqdm:
    return tqdm(total=total, unit="recording", desc="pdr-eval", dynamic_ncols=True)


def _collect(done: Iterable[Outcome], recordings: list[Recording],
             tell: Callable[[str], None]) -> list[Outcome]:
    """The outcomes as they end, with the bar; then in the recordings' order."""
    by_name: dict[str, Outcome] = {}
    failed = 0
    with _progress(len(recordings)) as bar:
        for outcome in done:
            by_name[outcome.recording.name] = outcome
            if outcome.report is None:
                failed += 1
                tell(f"failed: {outcome.recording.name}: {outcome.error}")
            bar.set_postfix(failed=failed)
            bar.update()
    return [by_name[r.name] for r in recordings]


def run_all(recordings: list[Recording], out: Path, config: Path | None, overwrite: bool,
            workers: int, scheduler: str | None, tell: Callable[[str], None]
            ) -> list[Outcome]:
    """Every recording, in parallel: on ``scheduler`` (a Dask scheduler's address) or a
    pool of ``workers`` processes here (see the module)."""
    if scheduler:
        ended = cluster_map(scheduler, run_recording,
                            [(r, out, config, overwrite) for r in recordings], "pdr-eval")
        return _collect((outcome for _, outcome in ended), recordings, tell)
    with ProcessPoolExecutor(max_workers=workers) as pool:
        futures = [pool.submit(on_one_thread, run_recording, r, out, config, overwrite)
                   for r in recordings]
        return _collect((f.result() for f in as_completed(futures)), recordings, tell)
