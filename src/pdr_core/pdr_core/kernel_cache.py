"""Keep numba's on-disk cache honest across modules.

numba checks a cached function against its own source file only: a kernel that calls
into another module (the smoother and the Monte-Carlo batches calling
:mod:`pdr_ins_ekf.compiled_filter`, every caller of :mod:`pdr_core.small_matrix`) keeps
running its old machine code, inlined callees
and all, after that module changed. Found the hard way: an edit of
``compiled_filter.compensate`` left the cached Monte-Carlo batch on the old equations,
and the batch no longer equalled the single run.

:func:`forget_if_changed`, called at the import of such a module, removes its cache files
when the sources it depends on differ from those it was last compiled against.
"""
from __future__ import annotations

import hashlib
from pathlib import Path


def forget_if_changed(module_file: str, *dependencies: str) -> None:
    """Delete the numba cache files of ``module_file`` (``__pycache__/<stem>.*.nbi|nbc``
    beside it) when the contents of ``dependencies`` (source files) have changed since
    the last call; record their fingerprint. A cache directory that cannot be written
    is left alone (numba then keeps no cache there either)."""
    source = Path(module_file)
    cache = source.parent / "__pycache__"
    digest = hashlib.sha256()
    for dependency in dependencies:
        digest.update(Path(dependency).read_bytes())
    stamp = cache / f"{source.stem}.dependencies.sha256"
    try:
        if stamp.is_file() and stamp.read_text() == digest.hexdigest():
            return
        for stale in [*cache.glob(f"{source.stem}.*.nbi"), *cache.glob(f"{source.stem}.*.nbc")]:
            stale.unlink(missing_ok=True)
        cache.mkdir(exist_ok=True)
        stamp.write_text(digest.hexdigest())
    except OSError:
        return
