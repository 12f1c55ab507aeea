"""Numba cache files of a module go when a module it calls into changes."""
from pdr_core.kernel_cache import forget_if_changed


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
