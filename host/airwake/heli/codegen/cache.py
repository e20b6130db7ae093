"""Where compiled kernels are cached, and when a cached one is stale.

numba's own cache (`cache=True`) keys a function by its signature and the hash of its own
source file. A kernel also reads the context layout (`layout.Q`, frozen into the machine
code) and inlines helpers from other modules, so here a kernel's "source stamp" hashes
its own file, every file of `airwake.heli` and the files of the compiled helpers it calls
(recursively): editing any of them recompiles instead of loading stale code.

Directory: $AIRWAKE_KERNEL_CACHE, else $XDG_CACHE_HOME/airwake/heli-kernels (~/.cache/…),
else a per-user directory in the system temp dir. Deleting it is always safe.
"""

from __future__ import annotations

import hashlib
import inspect
import os
import sys
import tempfile
import threading
from functools import cache, lru_cache
from pathlib import Path

import numba
import numpy as np
from numba.core import caching

PACKAGE_DIR = Path(__file__).resolve().parents[1]  # airwake/heli, not only codegen/


@lru_cache(maxsize=1)
def cache_dir() -> Path:
    env = os.environ.get("AIRWAKE_KERNEL_CACHE")
    if env:
        candidates = [Path(env)]
    else:
        xdg = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
        candidates = [Path(xdg) / "airwake" / "heli-kernels"]
    uid = os.getuid() if hasattr(os, "getuid") else "user"
    candidates.append(Path(tempfile.gettempdir()) / f"airwake-heli-kernels-{uid}")
    for d in candidates:
        try:
            d.mkdir(parents=True, exist_ok=True)
            tempfile.TemporaryFile(dir=d).close()
            return d
        except OSError:
            continue
    raise OSError(f"no writable kernel cache directory among {[str(c) for c in candidates]}")


@cache
def _hash_file(path: str, mtime: float, size: int) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def file_hash(path: str) -> str:
    st = os.stat(path)
    return _hash_file(path, st.st_mtime, st.st_size)


def package_files() -> list[str]:
    return sorted(str(p) for p in PACKAGE_DIR.rglob("*.py"))


def dependency_files(fn, seen: set[str] | None = None) -> set[str]:
    """Source files of a (compiled or plain) function and of the numba-compiled functions
    it references by global name, recursively."""
    seen = set() if seen is None else seen
    py = getattr(fn, "py_func", fn)
    try:
        path = inspect.getsourcefile(py)
    except TypeError:
        path = None
    if path and os.path.exists(path):
        seen.add(os.path.abspath(path))
    code = getattr(py, "__code__", None)
    if code is None:
        return seen
    glb = getattr(py, "__globals__", {})
    for name in code.co_names:
        obj = glb.get(name)
        if isinstance(obj, numba.core.dispatcher.Dispatcher) and obj.py_func is not py:
            sub = os.path.abspath(inspect.getsourcefile(obj.py_func) or "")
            if sub not in seen:
                dependency_files(obj, seen)
    return seen


def fingerprint(functions=()) -> str:
    """Hash of the library versions, every file of `airwake.heli` and the source files of
    `functions` and what they call."""
    files: set[str] = set(package_files())
    for f in functions:
        files |= dependency_files(f)
    h = hashlib.sha256()
    for v in (sys.version, numba.__version__, np.__version__):
        h.update(v.encode())
    for f in sorted(files):
        h.update(f.encode())
        h.update(file_hash(f).encode())
    return h.hexdigest()


def write_once(path: Path, text: str) -> None:
    """Create `path` with `text` unless it exists (atomic: concurrent processes race
    safely, and an existing file keeps its mtime, which numba's cache index checks)."""
    if path.exists():
        if path.read_text() == text:
            return
        path.unlink()  # corrupt or a hash collision: rewrite
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{threading.get_ident()}.tmp")
    tmp.write_text(text)
    try:
        os.link(tmp, path)
    except FileExistsError:
        pass
    finally:
        tmp.unlink()


class KernelCacheLocator(caching._SourceFileBackedLocatorMixin, caching._CacheLocator):
    """numba cache locator for effect kernels: kept under cache_dir()/kernels/<fingerprint>,
    stamped with the dependency fingerprint (see module docstring)."""

    def __init__(self, py_func, py_file) -> None:
        self._py_func = py_func
        self._py_file = py_file
        self._lineno = py_func.__code__.co_firstlineno
        self._stamp = fingerprint([py_func])
        sub = self.get_suitable_cache_subpath(py_file)
        # the fingerprint in the path too: numba unpickles an index (whose entries name
        # the effects' modules) before it compares stamps, so a stale index is never read
        self._cache_path = str(cache_dir() / "kernels" / self._stamp[:16] / sub)

    def get_cache_path(self) -> str:
        return self._cache_path

    def get_source_stamp(self):
        return self._stamp

    @classmethod
    def from_function(cls, py_func, py_file):
        if not getattr(py_func, "_airwake_kernel", False) or not os.path.exists(py_file):
            return None
        self = cls(py_func, py_file)
        try:
            self.ensure_cache_path()
        except OSError:
            return None
        return self


_IMPL = getattr(caching, "CacheImpl", None) or caching._CacheImpl  # renamed in numba 0.6x
if KernelCacheLocator not in _IMPL._locator_classes:
    _IMPL._locator_classes.insert(0, KernelCacheLocator)
