"""A compiled kernel with one line changed, for the NumPy twins' mutant tests
(docs/testing.md, "The twins can fail"): any package's tests import it (pytest's
``pythonpath`` holds this folder)."""
from __future__ import annotations

import inspect
import textwrap
from types import ModuleType


def perturbed(kernel, module: ModuleType, old: str, new: str, calls: dict | None = None):
    """``kernel`` (an njit function of ``module``) made afresh from its own source, with
    ``old`` replaced by ``new`` in the one line that holds it, as plain Python (what numba
    compiles, without the seconds compiling costs): it calls the module's other compiled
    kernels, and ``calls`` besides (a perturbed helper, for a plain copy of its caller),
    and the module itself is left alone."""
    lines = textwrap.dedent(inspect.getsource(kernel.py_func)).splitlines()
    rows = [i for i, line in enumerate(lines) if old in line]
    assert len(rows) == 1, f"{old!r} is in {len(rows)} lines of {kernel.__name__}, not one"
    lines[rows[0]] = lines[rows[0]].replace(old, new)
    source = "\n".join(line for line in lines if not line.startswith("@njit"))
    namespace = dict(vars(module)) | (calls or {})
    exec(compile(source, f"<{kernel.__name__}, perturbed>", "exec"), namespace)
    return namespace[kernel.__name__]
