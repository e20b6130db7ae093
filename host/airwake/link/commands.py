"""`airwake decode CAPTURE [--json]`: decode a raw byte capture of one link."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from airwake.errors import AirwakeError

CHUNK_BYTES = 1 << 20


class CaptureError(AirwakeError):
    """The capture file cannot be read."""


def decode_file(path: Path, progress: bool = True) -> dict:
    """Counters of a whole capture file (StreamDecoder.counters() + schema problems)."""
    from airwake.link.decoder import StreamDecoder
    from airwake.progress import Progress

    if not path.exists():
        raise CaptureError(f"capture '{path}': no such file")
    if not path.is_file():
        raise CaptureError(f"capture '{path}': not a regular file")
    try:
        size = path.stat().st_size
        decoder = StreamDecoder()
        bar = Progress(f"decode {path.name}", size / 1e6, unit=" MB", enabled=progress)
        with path.open("rb") as f:
            while chunk := f.read(CHUNK_BYTES):
                decoder.feed(chunk)
                bar.update(decoder.bytes_total / 1e6)
    except OSError as exc:
        raise CaptureError(f"capture '{path}': cannot read: {exc.strerror or exc}") from exc
    if size > CHUNK_BYTES:
        bar.finish()
    summary = decoder.counters()
    summary["pending_bytes"] = decoder.pending_bytes
    summary["schema_problems"] = decoder.schema_problems()
    return summary


def _print_text(path: Path, s: dict) -> None:
    print(f"{path}: {s['bytes']} bytes, {sum(s['frames'].values())} frames")
    width = max([len(n) for n in s["frames"]] + [len(k) for k in s["errors"]] + [8])
    for name, n in sorted(s["frames"].items()):
        lost = s["lost"].get(name)
        print(f"  {name:<{width}} {n:>10}" + (f"   ({lost} lost by seq)" if lost else ""))
    print("errors:")
    for kind, n in s["errors"].items():
        print(f"  {kind:<{width}} {n:>10}")
    if s["pending_bytes"]:
        print(f"  {'pending (unfinished last frame)':<{width}} {s['pending_bytes']:>10}")
    for line in s["schema_problems"]:
        print(f"warning: {line}")


def _handle(args: argparse.Namespace) -> int:
    path = Path(args.capture)
    summary = decode_file(path, progress=not args.json and sys.stderr.isatty())
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        _print_text(path, summary)
    return 0


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "decode", help="decode a raw byte capture of one link: per-message counts and errors",
        description="Decode a raw byte capture (the bytes one serial port delivered) and "
        "print per-message frame counts, error counters (CRC, unknown id, definition "
        "mismatch, oversize, COBS, bytes dropped, frames lost by sequence gaps) and bytes.")
    p.add_argument("capture", metavar="CAPTURE", help="raw capture file")
    p.add_argument("--json", action="store_true",
                   help='print {"frames": {...}, "errors": {...}, "bytes": N, ...}')
    p.set_defaults(func=_handle)
