"""docs/effects.md is generated from the registry and must list every effect."""

from pathlib import Path

from airwake.heli.catalogue import render_markdown
from airwake.heli.effects.base import effect_source, registered_effects

DOC = Path(__file__).resolve().parents[2] / "docs" / "effects.md"


def test_effects_doc_is_regenerated_output():
    # regenerate: .venv/bin/python -m airwake.heli.catalogue > docs/effects.md
    assert DOC.read_text() == render_markdown()


def test_effects_doc_lists_every_registered_effect_and_parameter():
    text = DOC.read_text()
    for name, cls in registered_effects().items():
        if effect_source(name) is None:
            assert f"### `{name}`" in text
            for p in cls.PARAMETERS:
                assert f"`{p.name}`" in text
