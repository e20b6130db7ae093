#!/usr/bin/env python3
"""`make gen`: protocol/messages/*.toml → C, Python, docs and golden vectors.

    generate.py                 write the generated files into the repository
    generate.py --out DIR       write them under DIR (same relative paths)
    generate.py --check         exit 1 and name every generated file that is stale

stdlib only (tomllib): it runs before anything is installed.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import emit_c  # noqa: E402
import emit_docs  # noqa: E402
import emit_py  # noqa: E402
import vectors  # noqa: E402
from schema import SchemaError, load_schema, schema_hash  # noqa: E402

ROOT = HERE.parents[1]
GENERATED_NOTE = "generated from protocol/messages by protocol/codegen — do not edit"


def render(protocol_dir: Path = ROOT / "protocol") -> dict[str, str]:
    """Every generated file: repository-relative path → text."""
    messages, links = load_schema(protocol_dir)
    by_name = {m.name: m for m in messages}
    frames, values = vectors.frame_vectors(messages, links)
    streams = vectors.stream_vectors(messages, links, frames)
    head = {"generated": GENERATED_NOTE, "schema_hash": f"0x{schema_hash(messages):08X}"}
    frames_json = {**head, "note": "frame_hex is the whole wire frame: 0x00, COBS, 0x00. "
                   "Float fields: JSON numbers, or \"nan\", \"inf\", \"-inf\".",
                   "vectors": frames}
    streams_json = {**head, "note": "hex is a byte stream; expect.counters is what a decoder "
                    "must count after reading all of it, expect.frames what it must deliver.",
                    "streams": streams}
    py_header = f"# ruff: noqa: E501\n# {GENERATED_NOTE}\n"
    return {
        "firmware/common/aw_messages.h": emit_c.header(messages, links),
        "firmware/common/aw_messages.c": emit_c.source(messages),
        "firmware/tests/test_proto_vectors.h": emit_c.vectors_header(frames, streams, by_name,
                                                                     values),
        "host/airwake/link/messages.py": py_header + emit_py.module(messages, links),
        "docs/protocol.md": emit_docs.document(messages, links),
        "protocol/vectors/frames.json": json.dumps(frames_json, indent=1) + "\n",
        "protocol/vectors/streams.json": json.dumps(streams_json, indent=1) + "\n",
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT, help="root to write under")
    parser.add_argument("--check", action="store_true",
                        help="compare with the files under --out instead of writing")
    args = parser.parse_args(argv)
    try:
        files = render()
    except SchemaError as exc:
        print(f"generate: {exc}", file=sys.stderr)
        return 2
    stale = []
    for rel, text in files.items():
        path = args.out / rel
        if args.check:
            if not path.is_file() or path.read_text() != text:
                stale.append(rel)
            continue
        path.parent.mkdir(parents=True, exist_ok=True)
        if not path.is_file() or path.read_text() != text:
            path.write_text(text)
            print(f"generate: wrote {rel}")
    if stale:
        print("generate: stale generated files (run `make gen`): " + ", ".join(stale),
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
