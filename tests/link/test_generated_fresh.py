"""Generated protocol files are committed: regenerating must change nothing, and the
generator must refuse definitions that break the protocol's rules."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

from .conftest import REPO

GENERATOR = REPO / "protocol/codegen/generate.py"


def _generator_module(name: str):
    spec = importlib.util.spec_from_file_location(f"_aw_codegen_{name}",
                                                  REPO / f"protocol/codegen/{name}.py")
    sys.path.insert(0, str(GENERATOR.parent))
    try:
        module = importlib.util.module_from_spec(spec)
        sys.modules[spec.name] = module  # dataclasses resolve annotations through it
        spec.loader.exec_module(module)
    finally:
        sys.path.remove(str(GENERATOR.parent))
    return module


def test_generated_files_are_fresh(tmp_path):
    # a definition edited without `make gen` would leave C and Python disagreeing
    subprocess.run([sys.executable, str(GENERATOR), "--out", str(tmp_path)], check=True,
                   capture_output=True)
    generated = sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*") if p.is_file())
    assert len(generated) == 7
    stale = [str(rel) for rel in generated if not (REPO / rel).is_file()
             or (REPO / rel).read_bytes() != (tmp_path / rel).read_bytes()]
    assert not stale, f"stale generated files, run `make gen`: {stale}"


def test_check_mode_reports_a_stale_file(tmp_path):
    subprocess.run([sys.executable, str(GENERATOR), "--out", str(tmp_path)], check=True,
                   capture_output=True)
    (tmp_path / "docs/protocol.md").write_text("edited by hand\n")
    result = subprocess.run([sys.executable, str(GENERATOR), "--out", str(tmp_path), "--check"],
                            capture_output=True, text=True)
    assert result.returncode == 1 and "docs/protocol.md" in result.stderr


def test_generated_files_say_do_not_edit():
    for rel in ("firmware/common/aw_messages.h", "firmware/common/aw_messages.c",
                "host/airwake/link/messages.py", "docs/protocol.md",
                "firmware/tests/test_proto_vectors.h"):
        head = (REPO / rel).read_text().splitlines()[:3]
        assert any("generated from protocol/messages by protocol/codegen" in line
                   for line in head), rel


MINIMAL = '''name = "{name}"
id = {id}
description = "d"
time = "t"
[rate_hz]
rover = 1
[[fields]]
name = "{field}"
type = "f32"
unit = "{unit}"
description = "d"
'''


def _protocol_dir(tmp_path: Path, **messages: str) -> Path:
    (tmp_path / "messages").mkdir()
    (tmp_path / "links.toml").write_text((REPO / "protocol/links.toml").read_text())
    for name, text in messages.items():
        (tmp_path / "messages" / f"{name}.toml").write_text(text)
    return tmp_path


@pytest.mark.parametrize(("messages", "error"), [
    ({"a": MINIMAL.format(name="a", id=16, field="speed", unit="m/s")}, "end with '_m_s'"),
    ({"a": MINIMAL.format(name="a", id=16, field="x_m", unit="m"),
      "b": MINIMAL.format(name="b", id=16, field="y_m", unit="m")}, "already used"),
    ({"a": MINIMAL.format(name="a", id=0, field="x_m", unit="m")}, "0 is reserved"),
    ({"a": MINIMAL.format(name="b", id=16, field="x_m", unit="m")}, "equal the file name"),
    ({"a": MINIMAL.format(name="a", id=16, field="seq", unit="1")}, "not one of"),
    ({"a": MINIMAL.format(name="a", id=16, field="x_m", unit="m") + "frozen_hash = 1\n"},
     "frozen"),
])
def test_generator_rejects_broken_definitions(tmp_path, messages, error):
    schema = _generator_module("schema")
    with pytest.raises(schema.SchemaError, match=error) as info:
        schema.load_schema(_protocol_dir(tmp_path, **messages))
    assert "a.toml" in str(info.value) or "b.toml" in str(info.value)


def test_frozen_messages_keep_their_hash():
    # heartbeat and schema_entry must decode across every schema version
    schema = _generator_module("schema")
    messages, _ = schema.load_schema(REPO / "protocol")
    frozen = {m.name: m.def_hash for m in messages if m.frozen}
    assert frozen == {"heartbeat": 0x8DE3D5E4, "schema_entry": 0xA4D7A680}
