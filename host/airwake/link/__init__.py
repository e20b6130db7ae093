"""The host side of the serial links: the wire protocol's codecs (and, later, ports and
clock mapping).

- `messages` (generated): message records and their metadata,
- `framing`: `encode_frame(msg, seq, flags, board_time_us) -> bytes`,
- `decoder`: `StreamDecoder().feed(chunk) -> list[Frame]`,
- `batch`: `decode_capture(data) -> Capture` (numpy tables; imports numpy).
"""
