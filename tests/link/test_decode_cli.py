"""`airwake decode CAPTURE [--json]` on clean, corrupted, missing and unreadable captures."""

from __future__ import annotations

import json

from airwake.cli import main
from airwake.link.framing import encode_frame
from airwake.link.messages import Heartbeat, Imu, LosaPeaks


def _capture() -> bytes:
    frames = [encode_frame(Imu(), i, 2, i) for i in range(10)]
    frames += [encode_frame(LosaPeaks(), i, 1, i) for i in range(5)]
    frames[3] = frames[3][:20]                      # truncated
    frames[5] = frames[5][:10] + b"\x99" + frames[5][11:]  # flipped byte
    frames[7] = b""                                 # lost: a sequence gap
    return b"".join(frames) + b"garbage\x00" + encode_frame(Heartbeat(), 0, 2, 0)


def test_decode_json_counts_a_corrupted_capture(tmp_path, capsys):
    path = tmp_path / "port.bin"
    data = _capture()
    path.write_bytes(data)
    assert main(["decode", str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["bytes"] == len(data)
    assert out["frames"] == {"imu": 7, "losa_peaks": 5, "heartbeat": 1}
    errors = out["errors"]
    assert errors["crc_error"] + errors["cobs_error"] == 3  # truncated, flipped, garbage
    assert errors["seq_lost"] == 3 and out["lost"] == {"imu": 3}
    assert errors["bytes_dropped"] > 0


def test_decode_text_lists_messages_and_errors(tmp_path, capsys):
    path = tmp_path / "port.bin"
    path.write_bytes(_capture())
    assert main(["decode", str(path)]) == 0
    text = capsys.readouterr().out
    assert "imu" in text and "crc_error" in text and "bytes" in text


def test_decode_missing_file_is_one_clear_line(tmp_path, capsys):
    assert main(["decode", str(tmp_path / "nope.bin")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "no such file" in err and "nope.bin" in err


def test_decode_directory_is_a_clear_error(tmp_path, capsys):
    assert main(["decode", str(tmp_path)]) == 2
    assert "not a regular file" in capsys.readouterr().err
