"""Generate docs/effects.md from the effect registry.

    .venv/bin/python -m airwake.heli.catalogue > docs/effects.md

tests/heli/test_catalogue.py fails when the committed file differs from this output.
"""

from __future__ import annotations

import inspect
from pathlib import Path

from airwake.heli.effects.base import effect_info, effect_source, registered_effects

PREAMBLE = (Path(__file__).resolve().parent / "catalogue_preamble.md").read_text()


def _fmt(v: float) -> str:
    return f"{v:.6g}"


def render_markdown() -> str:
    out = [PREAMBLE.rstrip().removesuffix("## Effects").rstrip() + "\n", _quantities(),
           "## Effects\n"]
    for name in registered_effects():
        if effect_source(name) is not None:
            continue  # plugins document themselves
        info = effect_info(name)
        out.append(f"### `{name}` — {info.cls.__name__}\n")
        out.append(f"Stages: {', '.join(info.stages) or '—'}. "
                   f"Module: `{inspect.getmodule(info.cls).__name__}`.\n")
        if info.cls.REQUIRES:
            out.append(f"Requires: {', '.join(info.cls.REQUIRES)}.\n")
        out.append("```text\n" + inspect.cleandoc(info.doc) + "\n```\n")
        if info.parameters:
            out.append("| parameter | default | unit | bounds | source | fixed |")
            out.append("|---|---|---|---|---|---|")
            for p in info.parameters:
                fixed = "yes" if p.fixed else ""
                doc = f" — {p.doc}" if p.doc else ""
                bounds = f"[{_fmt(p.bounds[0])}, {_fmt(p.bounds[1])}]"
                out.append(f"| `{p.name}` | {_fmt(p.default)} | {p.unit} | {bounds} | "
                           f"{p.source}{doc} | {fixed} |")
            out.append("")
        if info.states:
            out.append("States: " + ", ".join(f"`{s.name}` ({s.unit})" for s in info.states) + "\n")
    return "\n".join(out).rstrip() + "\n"


def _quantities() -> str:
    """The context layout (airwake.heli.layout) as a table."""
    from airwake.heli.layout import OFFSETS, QUANTITIES

    out = ["## Context quantities",
           "Shared intermediate quantities of one row (`ctx.<name>` in numpy, "
           "`q[Q.<name>]` in a kernel; vectors occupy `width` consecutive slots).\n",
           "| name | slot | width | unit | written by | meaning |", "|---|---|---|---|---|---|"]
    for name, width, unit, who, doc in QUANTITIES:
        out.append(f"| `{name}` | {OFFSETS[name]} | {width} | {unit} | {who} | {doc} |")
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    print(render_markdown(), end="")
