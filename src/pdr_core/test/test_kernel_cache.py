"""Numba cache files of a module go when a module it calls into changes; a compilation
is announced, and each kernel compiled said with its seconds (issue 54)."""
import re

from pdr_core.maths.kernel_cache import forget_if_changed


def test_cache_files_are_forgotten_when_a_dependency_changes(tmp_path):
    module, dependency = tmp_path / "batch.py", tmp_path / "kernels.py"
    module.write_text("")
    dependency.write_text("def f(): return 1\n")
    cache = tmp_path / "__pycache__"
    cache.mkdir()

    def cached():
        for name in ("batch.run-10.py311.nbi", "batch.run-10.py311.1.nbc"):
            (cache / name).write_bytes(b"machine code")

    cached()
    forget_if_changed(str(module), str(dependency))  # first sight: no stamp, start afresh
    assert not list(cache.glob("batch.*.nb?"))
    cached()
    forget_if_changed(str(module), str(dependency))
    assert len(list(cache.glob("batch.*.nb?"))) == 2, "unchanged: kept"
    dependency.write_text("def f(): return 2\n")
    (cache / "other.run-3.py311.nbi").write_bytes(b"another module's")
    forget_if_changed(str(module), str(dependency))
    assert [p.name for p in cache.glob("*.nb?")] == ["other.run-3.py311.nbi"]


def test_a_compilation_is_announced_then_each_kernel_said_with_its_seconds(monkeypatch):
    """Issue 54: the first compile of ``make demo`` was 75 s of silence. A line says what
    is compiled and about how long it takes, before the first; one per callee compiled
    once PROGRESS_EVERY_S have passed (here 0: each); one per kernel at its end."""
    import io

    from numba import njit
    from numba.core import event

    from pdr_core.maths import kernel_cache
    from pdr_core.maths.kernel_cache import FIRST_COMPILE_S, CompileProgress

    monkeypatch.setattr(kernel_cache, "PROGRESS_EVERY_S", 0.0)

    @njit
    def inner(x):
        return x + 1.0

    @njit
    def outer(x):
        return inner(x) * 2.0

    stream = io.StringIO()
    with event.install_listener("numba:compile", CompileProgress(stream)):
        assert outer(1.0) == 4.0
        assert outer(2.0) == 6.0                # compiled already: nothing said
        assert inner(1) == 2.0                  # another signature: compiled, said
    first, progress, *kernels = stream.getvalue().splitlines()
    name = f"{__name__}.test_a_compilation_is_announced_then_each_kernel_said_with_its_seconds"
    assert first.startswith(f"[numba] compiling the workspace's kernels to machine code, "
                            f"once (starting with {name}.<locals>.outer): about "
                            f"{FIRST_COMPILE_S} s")
    assert re.fullmatch(rf"\[numba\]   so far \d+ s and 1 of the kernels it calls \(the "
                        rf"last: {re.escape(name)}.<locals>.inner\)", progress)
    assert len(kernels) == 2
    said = re.fullmatch(r"\[numba\] compiled (\S+) \(and 1 kernel it calls\) in "
                        r"(\d+\.\d) s", kernels[0])
    assert said and said[1] == f"{name}.<locals>.outer" and float(said[2]) < 30
    assert re.fullmatch(rf"\[numba\] compiled {re.escape(name)}.<locals>.inner in \d+\.\d s",
                        kernels[1])
