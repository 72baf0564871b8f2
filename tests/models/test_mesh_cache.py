"""The mesh cache verifies what it loads, rebuilds what is damaged, writes atomically and is optional.

Every test meshes the ciliary beam at 4 mm (about 0.1 s of gmsh) into its own cache folder."""

import logging
import os
import shutil
import threading

import numpy as np
import pytest

from modalfe.geometry import BUILDERS
from modalfe.models import mesh as mesh_module
from modalfe.models.mesh import build_mesh, cache_dir


@pytest.fixture
def cache(monkeypatch, tmp_path):
    monkeypatch.setenv("MODALFE_CACHE", str(tmp_path / "cache"))
    mesh_module._memory_cache.clear()
    mesh_module._unwritable.clear()
    yield tmp_path / "cache"
    mesh_module._memory_cache.clear()


def _fresh(size=4e-3):
    """Build with an empty in-process cache (so the disk cache is what answers)."""
    mesh_module._memory_cache.clear()
    return build_mesh(BUILDERS["ciliary_beam"](), size=size)


def _same(a, b):
    np.testing.assert_array_equal(a.mesh.p, b.mesh.p)
    np.testing.assert_array_equal(a.mesh.t, b.mesh.t)
    assert a.parts.keys() == b.parts.keys() and a.faces.keys() == b.faces.keys()


def _no_gmsh(monkeypatch):
    def fail(*args, **kwargs):
        raise AssertionError("gmsh was called on a valid cache file")

    monkeypatch.setattr(mesh_module, "_gmsh_mesh", fail)


def _truncated(data):
    return data[: len(data) // 2]


def _bad_crc(data):
    i = len(data) // 3  # inside the stored (uncompressed) arrays: the zip CRC no longer matches
    return data[:i] + bytes([data[i] ^ 0xFF]) + data[i + 1:]


@pytest.mark.parametrize("damage", [_truncated, lambda data: b"", _bad_crc, lambda data: b"not a zip file"],
                         ids=["truncated", "empty", "bad-crc", "garbage"])
def test_a_damaged_file_is_rebuilt_with_a_warning_and_replaced(cache, monkeypatch, caplog, damage):
    first = _fresh()
    (path,) = (cache / "meshes").glob("*.npz")
    path.write_bytes(damage(path.read_bytes()))
    with caplog.at_level(logging.WARNING, logger="modalfe.models.mesh"):
        again = _fresh()
    assert again.seconds > 0 and "rebuilding" in caplog.text
    _same(again, first)
    _no_gmsh(monkeypatch)
    _same(_fresh(), first)  # the damaged file was replaced by a valid one


def test_a_valid_file_of_another_mesh_under_the_key_is_not_used(cache):
    coarse = _fresh(4e-3)
    (coarse_path,) = (cache / "meshes").glob("*.npz")
    fine = _fresh(2e-3)
    fine_path = next(p for p in (cache / "meshes").glob("*.npz") if p != coarse_path)
    shutil.copyfile(coarse_path, fine_path)  # a well-formed file, but of the 4 mm mesh
    again = _fresh(2e-3)
    assert again.seconds > 0  # rebuilt: the key stored inside the file is not this mesh's
    _same(again, fine)
    assert again.nelements > coarse.nelements


def test_concurrent_writers_use_unique_temporary_names(cache, monkeypatch):
    result = _fresh()
    (path,) = (cache / "meshes").glob("*.npz")
    sources, replace = [], os.replace

    def recording(src, dst):
        sources.append(str(src))
        replace(src, dst)

    monkeypatch.setattr(mesh_module.os, "replace", recording)
    start, errors = threading.Barrier(8), []

    def write():
        start.wait()
        try:
            for _ in range(5):
                mesh_module._save(path, result)
        except Exception as exc:  # any failure of a writer is the bug
            errors.append(exc)

    threads = [threading.Thread(target=write) for _ in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors and len(sources) == 40 and len(set(sources)) == 40
    assert [p.name for p in (cache / "meshes").iterdir()] == [path.name]  # no temporary file left behind
    _same(mesh_module._load(path, result.key, result.element, result.size), result)


def test_an_unwritable_cache_gives_one_warning_and_the_run_goes_on(monkeypatch, tmp_path, caplog):
    blocker = tmp_path / "file"
    blocker.write_text("a file where the cache folder should be")
    monkeypatch.setenv("MODALFE_CACHE", str(blocker / "cache"))  # cannot be created, even by root
    mesh_module._memory_cache.clear()
    mesh_module._unwritable.clear()
    with caplog.at_level(logging.WARNING, logger="modalfe.models.mesh"):
        a = _fresh(4e-3)
        b = _fresh(3e-3)
    assert a.nelements > 0 and b.nelements > a.nelements
    assert caplog.text.count("cannot write") == 1


def test_a_read_only_cache_file_system_does_not_abort(cache, monkeypatch, caplog):
    def read_only(*args, **kwargs):
        raise PermissionError(30, "Read-only file system")

    monkeypatch.setattr(mesh_module.np, "savez", read_only)
    with caplog.at_level(logging.WARNING, logger="modalfe.models.mesh"):
        assert _fresh().nelements > 0
    assert "cannot write" in caplog.text
    assert not any((cache / "meshes").iterdir())  # the temporary file was removed


@pytest.mark.parametrize("value", ["off", "OFF", "none", "0"])
def test_modalfe_cache_off_disables_the_disk_cache(monkeypatch, tmp_path, value):
    monkeypatch.setenv("MODALFE_CACHE", value)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.setenv("HOME", str(tmp_path))
    assert cache_dir() is None
    assert _fresh().nelements > 0
    assert not any(tmp_path.rglob("*.npz"))
