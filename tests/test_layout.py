"""The test tree itself: pytest imports a test module from a directory without
__init__.py under its bare file name, so two such modules with one name make the whole
suite fail to collect (it did once, in CI, and not in per-directory runs)."""

from collections import defaultdict
from pathlib import Path

TESTS = Path(__file__).resolve().parent


def test_test_modules_outside_packages_have_unique_basenames():
    seen = defaultdict(list)
    for path in TESTS.rglob("*.py"):
        if "__pycache__" in path.parts or path.name in ("__init__.py", "conftest.py"):
            continue
        if (path.parent / "__init__.py").exists():
            continue  # imported as package.module: names may repeat
        seen[path.stem].append(str(path.relative_to(TESTS)))
    clashes = {name: paths for name, paths in seen.items() if len(paths) > 1}
    assert not clashes, f"rename one of each: {clashes}"
