"""The tree itself: pytest imports a test module from a directory without __init__.py
under its bare file name, so two such modules with one name make the whole suite fail to
collect (it did once, in CI, and not in per-directory runs); and the repository stands
alone: what a user reads points only to files it has."""

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


def test_docs_readme_and_help_point_only_to_files_the_repository_has():
    # a fresh clone stands alone: `airwake bench --help` once sent users to a file that
    # was never in the repository (issue 22)
    import argparse
    import re

    from airwake.cli import build_parser

    root = Path(__file__).resolve().parents[1]
    texts = {p.relative_to(root): p.read_text() for p in [root / "README.md",
                                                         *(root / "docs").glob("*.md")]}

    def helps(parser, path):
        # argparse wraps lines after a hyphen: docs/model-\n  discrepancy.md
        yield " ".join(path), re.sub(r"-\n\s*", "-", parser.format_help())
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                for name, sub in action.choices.items():
                    yield from helps(sub, [*path, name])

    texts.update(dict(helps(build_parser(), ["airwake"])))
    missing = set()
    for where, text in texts.items():
        for ref in re.findall(r"[A-Za-z0-9_./-]+\.md\b", text):
            if not ((root / ref).is_file() or (root / "docs" / ref).is_file()):
                missing.add((str(where), ref))
    assert not missing, sorted(missing)
