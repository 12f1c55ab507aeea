"""The drift estimator's whole state in a file, so that ``landmark_drift`` killed and
started again mid-walk keeps its landmarks, its hypotheses and its place in the walk
(issue 32; the node's ``state_file`` parameter, docs/nodes.md).

:func:`save_state` writes the :class:`~pdr_drift.streaming.StreamingDrift` (the estimator
with its corner buffer, flights, database or hypotheses, the walk's start and the last
step's stamp) with :mod:`pickle`, to a temporary file renamed over the old one, so a
kill during a write leaves the previous state whole. :func:`load_state` reads it back
and checks it: a file that cannot be read, is not a state of this version, or was saved
with another estimator configuration is refused with an :class:`~pdr_core.errors.InputError`
naming the file and the problem (the node then sets the file aside and starts afresh:
nothing is lost). The file is the node's own: pickle runs what a file holds, so do not
point it at a file from elsewhere.
"""
from __future__ import annotations

import os
import pickle
from pathlib import Path

from pdr_core.errors import InputError
from pdr_drift.config import DriftConfig
from pdr_drift.streaming import StreamingDrift

FORMAT = "pdr_drift.state/1"


def save_state(path: str | Path, stream: StreamingDrift) -> None:
    """Write ``stream`` to ``path`` atomically (module docstring)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    partial = path.with_name(path.name + ".partial")
    with open(partial, "wb") as f:
        pickle.dump({"format": FORMAT, "stream": stream}, f, protocol=pickle.HIGHEST_PROTOCOL)
    os.replace(partial, path)


def load_state(path: str | Path, config: DriftConfig) -> StreamingDrift:
    """The state saved in ``path``, for an estimator configured with ``config``
    (module docstring); InputError when it cannot be used."""
    try:
        with open(path, "rb") as f:
            saved = pickle.load(f)
    except (OSError, pickle.UnpicklingError, EOFError, AttributeError, ImportError,
            IndexError, TypeError, ValueError) as exc:
        raise InputError(path, f"not a drift estimator state: {exc}") from exc
    if not isinstance(saved, dict) or saved.get("format") != FORMAT:
        raise InputError(path, f"not a drift estimator state of format {FORMAT}")
    stream = saved["stream"]
    if not isinstance(stream, StreamingDrift):
        raise InputError(path, "not a drift estimator state: no estimator in it")
    if stream.config != config:
        changed = [k for k in vars(config) if getattr(config, k) != getattr(stream.config, k)]
        raise InputError(path, "saved with another configuration ("
                         + ", ".join(f"{k}: {getattr(stream.config, k)!r} there, "
                                     f"{getattr(config, k)!r} now" for k in changed) + ")")
    stream.restored_until_ns = stream.last_stamp_ns
    return stream
