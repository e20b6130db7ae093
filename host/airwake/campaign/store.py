"""Content-addressed step results: a result's name is the digest of what it was made from.

    key = task_key("estimate", {"flight": flight_digest, "model": calibrate_key,
                                "options": {...}, "code": code_version()})
    store = Store(out_dir / "store")
    store.done(key)                        # record.json present: finished earlier
    tmp = store.scratch(key)               # write the outputs here, then
    store.commit(key, tmp, record)         # record.json + one rename: all or nothing

A key hashes the step, the digests of its input files (a flight table's bytes, a
recording's files), the keys of the results it reads (so a changed calibration re-runs
every estimate that used it), the model spec's bytes, the step's options and the code
version (the sources of `airwake` and of the simulator that scores simulated flights: any
code change re-runs). A re-run finds
every unchanged result by its key and skips it; an interrupted run left only complete
results behind (a result directory appears by one rename, record.json inside), so it
resumes where it stopped. Two workers finishing the same task (a task re-run after its
worker died) race harmlessly: the first rename wins, the other copy is dropped.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import tempfile
from functools import lru_cache
from pathlib import Path

RECORD = "record.json"
_CHUNK = 1 << 20


def _hash_file(h, path: Path) -> None:
    with open(path, "rb") as fh:
        while chunk := fh.read(_CHUNK):
            h.update(chunk)


def path_digest(path: Path) -> str:
    """sha256 of a file's bytes, or of a directory's files (relative names and bytes, in
    name order)."""
    h = hashlib.sha256()
    path = Path(path)
    if path.is_dir():
        for f in sorted(p for p in path.rglob("*") if p.is_file()):
            h.update(str(f.relative_to(path)).encode() + b"\0")
            _hash_file(h, f)
    else:
        _hash_file(h, path)
    return h.hexdigest()


def _stat_stamp(path: Path) -> list:
    files = sorted(p for p in path.rglob("*") if p.is_file()) if path.is_dir() else [path]
    return [[str(f), f.stat().st_size, f.stat().st_mtime_ns] for f in files]


class DigestCache:
    """Input digests remembered by (name, size, mtime) in a JSON file, so a re-run does
    not read every flight again."""

    def __init__(self, file: Path) -> None:
        self.file = Path(file)
        try:
            self.known = json.loads(self.file.read_text())
        except (OSError, ValueError):
            self.known = {}
        self.changed = False

    def digest(self, path: Path) -> str:
        path = Path(path).resolve()
        stamp = _stat_stamp(path)
        hit = self.known.get(str(path))
        if hit and hit["stamp"] == stamp:
            return hit["digest"]
        d = path_digest(path)
        self.known[str(path)] = {"stamp": stamp, "digest": d}
        self.changed = True
        return d

    def save(self) -> None:
        if self.changed:
            self.file.parent.mkdir(parents=True, exist_ok=True)
            write_json_atomic(self.known, self.file)
            self.changed = False


@lru_cache(maxsize=1)
def code_version() -> str:
    """airwake's version and a digest of the sources of `airwake` and of the packages that
    score simulated flights (`airwake.estimate.truth.PROVIDERS`: the simulator)."""
    import importlib.util

    import airwake
    from airwake.estimate.truth import PROVIDERS

    h = hashlib.sha256()
    roots = [Path(airwake.__file__).resolve().parent]
    for top in sorted({name.split(".")[0] for name in PROVIDERS}):
        spec = importlib.util.find_spec(top)
        if spec is not None and spec.origin:
            roots.append(Path(spec.origin).resolve().parent)
    for root in roots:
        for f in sorted(p for p in root.rglob("*") if p.suffix in (".py", ".toml", ".html")
                        and "__pycache__" not in p.parts):
            h.update(f"{root.name}/{f.relative_to(root)}".encode() + b"\0")
            _hash_file(h, f)
    return f"{airwake.__version__}+{h.hexdigest()[:16]}"


def canonical(obj) -> str:
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), default=str)


def task_key(step: str, identity: dict) -> str:
    """`<step>-<digest>`: a Dask key and a directory name."""
    return f"{step}-{hashlib.sha256(canonical(identity).encode()).hexdigest()[:24]}"


def _plain(o):
    """numpy scalars and arrays as JSON values, anything else as its text."""
    return o.tolist() if hasattr(o, "tolist") else str(o)


def write_json_atomic(obj, path: Path) -> None:
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}-", dir=path.parent)
    with os.fdopen(fd, "w") as fh:
        json.dump(obj, fh, indent=1, default=_plain)
    os.replace(tmp, path)


class Store:
    """Result directories `<root>/<key>/` (module docstring)."""

    def __init__(self, root) -> None:
        self.root = Path(root)

    def dir(self, key: str) -> Path:
        return self.root / key

    def done(self, key: str) -> bool:
        return (self.root / key / RECORD).is_file()

    def load(self, key: str) -> dict:
        return json.loads((self.root / key / RECORD).read_text())

    def scratch(self, key: str) -> Path:
        self.root.mkdir(parents=True, exist_ok=True)
        return Path(tempfile.mkdtemp(prefix=f".{key}-", dir=self.root))

    def commit(self, key: str, tmp: Path, record: dict) -> None:
        write_json_atomic(record, tmp / RECORD)
        try:
            os.rename(tmp, self.root / key)
        except OSError:
            if not self.done(key):
                raise
            shutil.rmtree(tmp, ignore_errors=True)  # finished twice: the first one stays

    def output(self, record: dict, name: str) -> Path:
        """The absolute path of a record's output `name`."""
        return self.root / record["key"] / record["outputs"][name]
