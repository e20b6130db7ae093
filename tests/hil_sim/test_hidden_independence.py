"""The truth world never borrows the physics it is meant to test: no module under hil_sim/
imports the host's discrepancy package or its catalogue of effects (whose formulas the
hidden effects must not copy), and the independent blade-element helicopter
(hil_sim/world/rotorcraft/) imports nothing of the host's model, calibration, estimators
or discrepancy workflow — at any depth, in any import form."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

HIL_SIM = Path(__file__).resolve().parents[2] / "hil_sim"
FORBIDDEN = ("airwake.discrepancy", "airwake.heli.effects.catalogue")
ROTORCRAFT = HIL_SIM / "world" / "rotorcraft"
ROTORCRAFT_FORBIDDEN = ("airwake.heli", "airwake.calibrate", "airwake.estimate",
                        "airwake.discrepancy")


def imported_modules(tree: ast.AST) -> list[tuple[int, str]]:
    """(line, dotted name) of everything a module imports, anywhere in it (inside
    functions and classes too): `import a.b`, `from a.b import c` (as a.b and a.b.c),
    `from a import b` (as a and a.b), `importlib.import_module("a.b")` /
    `__import__("a.b")` with a literal name. Relative imports stay inside hil_sim."""
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            out.append((node.lineno, node.module))
            out += [(node.lineno, f"{node.module}.{alias.name}") for alias in node.names]
        elif isinstance(node, ast.Call) and node.args and isinstance(
                node.args[0], ast.Constant) and isinstance(node.args[0].value, str):
            fn = node.func
            name = fn.attr if isinstance(fn, ast.Attribute) else getattr(fn, "id", "")
            if name in ("import_module", "__import__"):
                out.append((node.lineno, node.args[0].value))
    return out


def forbidden(name: str, banned: tuple[str, ...] = FORBIDDEN) -> bool:
    return any(name == f or name.startswith(f + ".") for f in banned)


def test_the_scan_sees_every_import_form():
    # a scan that misses a form would pass vacuously
    src = '''
import airwake.discrepancy.fit
from airwake.heli.effects.catalogue import GroundEffect
from airwake.heli.effects import catalogue
from airwake import discrepancy as d
def later():
    import importlib
    importlib.import_module("airwake.discrepancy.add")
    from airwake.discrepancy.candidates import CANDIDATES
class K:
    __import__("airwake.heli.effects.catalogue.servo_lag")
from airwake.heli.effects.base import Effect
from airwake.heli import kernel
'''
    lines = {line for line, name in imported_modules(ast.parse(src)) if forbidden(name)}
    assert lines == {2, 3, 4, 5, 8, 9, 11}
    assert not forbidden("airwake.heli.effects.base") and not forbidden("airwake.heli.kernel")
    assert not forbidden("airwake.discrepancy_other")


MODULES = sorted(HIL_SIM.rglob("*.py"))


@pytest.mark.parametrize("path", MODULES, ids=[str(p.relative_to(HIL_SIM)) for p in MODULES])
def test_hil_sim_module_does_not_import_the_discrepancy_catalogue(path):
    tree = ast.parse(path.read_text(), filename=str(path))
    bad = [f"line {line}: {name}" for line, name in imported_modules(tree) if forbidden(name)]
    assert not bad, f"{path.relative_to(HIL_SIM.parent)} imports {bad}"


def test_the_scan_covers_the_hidden_effects():
    names = {p.relative_to(HIL_SIM).as_posix() for p in MODULES}
    assert {"world/hidden/ground_effect.py", "world/hidden/servo.py", "world/run.py",
            "world/truth.py"} <= names


ROTORCRAFT_MODULES = sorted(ROTORCRAFT.rglob("*.py"))


@pytest.mark.parametrize("path", ROTORCRAFT_MODULES,
                         ids=[str(p.relative_to(HIL_SIM)) for p in ROTORCRAFT_MODULES])
def test_blade_element_truth_imports_nothing_of_the_host_model(path):
    tree = ast.parse(path.read_text(), filename=str(path))
    bad = [f"line {line}: {name}" for line, name in imported_modules(tree)
           if forbidden(name, ROTORCRAFT_FORBIDDEN)]
    assert not bad, f"{path.relative_to(HIL_SIM.parent)} imports {bad}"


def test_the_rotorcraft_scan_covers_every_part():
    names = {p.name for p in ROTORCRAFT_MODULES}
    assert {"main_rotor.py", "flybar.py", "inflow.py", "tail_rotor.py", "fuselage.py",
            "drive.py", "servos.py", "dynamics.py"} <= names
    src = "from airwake.heli.trim import linearize\nimport airwake.calibrate.lsq\n"
    hits = [n for _, n in imported_modules(ast.parse(src)) if forbidden(n, ROTORCRAFT_FORBIDDEN)]
    assert hits == ["airwake.heli.trim", "airwake.heli.trim.linearize", "airwake.calibrate.lsq"]


def test_the_rotorcraft_shares_no_constant_with_the_host_model():
    """No number of the host's shipped model specs with three or more significant digits
    appears as a literal in the truth (a copied constant would be shared physics; round
    one- and two-digit values such as 0.3 coincide by chance and are not counted)."""
    import re
    import tomllib

    host_specs = Path(__file__).resolve().parents[2] / "host" / "airwake" / "heli" / "specs"
    host_values = set()
    for spec in host_specs.glob("*.toml"):
        for table in tomllib.loads(spec.read_text()).get("effects", {}).values():
            for v in table.values():
                if isinstance(v, float) and len(f"{abs(v):.6g}".replace(".", "").lstrip(
                        "0")) >= 3:
                    host_values.add(abs(v))
    assert host_values, "no host values found: the scan would pass vacuously"
    shared = []
    for path in [*ROTORCRAFT_MODULES, *ROTORCRAFT.glob("*.toml")]:
        for m in re.finditer(r"(?<![\w.])\d+\.\d+(?:e-?\d+)?", path.read_text()):
            if float(m.group()) in host_values:
                shared.append(f"{path.name}: {m.group()}")
    assert not shared, f"host model constants in the truth: {shared}"
