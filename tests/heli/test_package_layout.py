"""`airwake.heli` is one closed model package (ARCHITECTURE.md, heli/): imports run one way,
hil_sim and the analysis packages use heli and never the reverse, and heli's numba code
generator (`airwake.heli.codegen`) is private to it.

Read from the source (every import statement, inside functions too, and every
importlib.import_module / __import__ call), not from sys.modules: a lazy import in a
rarely run branch is exactly how the catalogue once loaded the analysis package back."""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
HELI = ROOT / "host" / "airwake" / "heli"
# what heli may import from this repository: itself and the shared error base class
HELI_MAY_IMPORT = ("airwake.heli", "airwake.errors")
# the packages above heli, named in the failure message (any other airwake.* fails too)
ABOVE_HELI = ("airwake.discrepancy", "airwake.calibrate", "airwake.estimate",
              "airwake.daemon", "hil_sim")
CODEGEN = "airwake.heli.codegen"
# code outside heli that may use the code generator: none. heli's own tests
# (tests/heli: the kernel cache, generated-module and composition-memo tests) are heli.
OUTSIDE_HELI = [ROOT / "host" / "airwake", ROOT / "hil_sim", ROOT / "tests"]
NOT_OUTSIDE = [HELI, ROOT / "tests" / "heli"]


def _module_of(path: Path) -> str:
    """Dotted module name of a source file (host/airwake/x/y.py -> airwake.x.y)."""
    rel = path.relative_to(ROOT / "host" if path.is_relative_to(ROOT / "host") else ROOT)
    parts = list(rel.with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def imports(path: Path):
    """(line, imported module, names taken from it) for every import in the file."""
    tree = ast.parse(path.read_text(), str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield node.lineno, alias.name, ()
        elif isinstance(node, ast.ImportFrom):
            if node.level:  # relative: resolve against the file's package
                package = _module_of(path)
                if path.name != "__init__.py":
                    package = package.rpartition(".")[0]
                base = package.split(".")
                base = base[:len(base) - (node.level - 1)]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module or ""
            yield node.lineno, module, tuple(a.name for a in node.names)
        elif isinstance(node, ast.Call):
            fn = node.func
            name = fn.attr if isinstance(fn, ast.Attribute) else getattr(fn, "id", "")
            if name in ("import_module", "__import__"):
                arg = node.args[0] if node.args else None
                target = arg.value if isinstance(arg, ast.Constant) else "<computed>"
                yield node.lineno, str(target), ()


def _files(roots, exclude=()):
    for root in roots:
        for path in sorted(root.rglob("*.py")):
            if not any(path.is_relative_to(e) for e in exclude):
                yield path


def _inside(module: str, package: str) -> bool:
    return module == package or module.startswith(package + ".")


def test_heli_imports_nothing_from_the_packages_that_use_it():
    # a lower package loading a higher one back (by import or importlib) is a hidden cycle
    bad = []
    for path in _files([HELI]):
        for line, module, _ in imports(path):
            ours = module.split(".")[0] in ("airwake", "hil_sim")
            if module == "<computed>" or (
                    ours and not any(_inside(module, ok) for ok in HELI_MAY_IMPORT)):
                bad.append(f"{path.relative_to(ROOT)}:{line} imports {module}")
    assert not bad, (f"airwake.heli may import only {HELI_MAY_IMPORT} of this repository "
                     f"(never {', '.join(ABOVE_HELI)}, ...):\n" + "\n".join(bad))


def test_nothing_outside_heli_reaches_into_its_code_generator_or_private_names():
    # hil_sim and the analysis packages step and evaluate through airwake.heli's public
    # API (HeliModel, Stepper, simulate, ...), never the generated functions
    bad = []
    for path in _files(OUTSIDE_HELI, NOT_OUTSIDE):
        for line, module, names in imports(path):
            if not _inside(module, "airwake.heli"):
                continue
            if _inside(module, CODEGEN) or (module == "airwake.heli" and "codegen" in names):
                bad.append(f"{path.relative_to(ROOT)}:{line} imports {CODEGEN}")
            private = [n for n in names if n.startswith("_")]
            if private:
                bad.append(f"{path.relative_to(ROOT)}:{line} imports {private} from {module}")
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if (isinstance(node, ast.Attribute) and node.attr == "fns"
                    and isinstance(node.value, ast.Attribute) and node.value.attr == "compiled"):
                bad.append(f"{path.relative_to(ROOT)}:{node.lineno} calls .compiled.fns "
                           "(use airwake.heli.Stepper / simulate / the model's methods)")
    assert not bad, "outside airwake.heli:\n" + "\n".join(bad)


@pytest.mark.parametrize("module", ["airwake.heli.kernel", "airwake.heli.effects.base"])
def test_the_effect_authors_modules_keep_their_names(module):
    # user plugins, docs/effects.md and hil_sim's hidden effects import these by path
    import importlib

    mod = importlib.import_module(module)
    names = {"airwake.heli.kernel": ("Q", "kernel", "kernel_function", "add_load", "cross",
                                     "air_velocity_at", "solve3"),
             "airwake.heli.effects.base": ("Effect", "Parameter", "State", "register_effect",
                                           "STAGES")}[module]
    assert [n for n in names if not hasattr(mod, n)] == []


def test_the_layout_scan_sees_imports_inside_functions_and_importlib(tmp_path):
    # the checks above are only as good as this scan
    src = tmp_path / "x.py"
    src.write_text("import importlib\n\n"
                   "def f():\n    from airwake.discrepancy import add\n"
                   "    importlib.import_module('hil_sim.world')\n")
    found = [m for _, m, _ in imports(src)]
    assert "airwake.discrepancy" in found and "hil_sim.world" in found
