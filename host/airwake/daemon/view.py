"""The daemon's compact terminal view of a status snapshot (one line per port / board)."""

from __future__ import annotations

from airwake.link.health import fmt_age

# Messages shown by name in the board lines (the rest are summed as "other").
MAIN_MESSAGES = ("losa_peaks", "imu", "marker_attitude", "anemometer", "ins", "rotor_speed",
                 "rtk_baseline", "pilot_inputs", "tail_servo")


def render(st: dict) -> str:
    rec = st["recording"]
    lines = [f"airwake daemon  t={st['t_s']:.0f}s  recording {rec['state']} "
             f"{rec['bytes'] / 1e6:.1f} MB in {rec['segments']} segment(s)"
             + (f"  ERROR: {rec['error']}" if rec["error"] else "")]
    for role, p in st["ports"].items():
        e = p["errors"]
        bad = sum(e[k] for k in ("crc_error", "unknown_id", "def_mismatch", "oversize",
                                 "cobs_error"))
        lines.append(f"port {role:<7} {p['state']:<7} {p['bytes_per_s'] / 1e3:6.1f} kB/s "
                     f"{p['frames_per_s']:6.0f} fr/s  bad {bad} ({e['crc_error']} crc) "
                     f"dropped {e['bytes_dropped']} B  seq lost {p['seq_lost']}  "
                     f"tx drop {p['tx_dropped']} B  reopen {max(0, p['opens'] - 1)}"
                     + (f"  [{p['last_error']}]" if p["state"] != "open" else ""))
    for name, b in st["boards"].items():
        rates = b["rates_hz"]
        shown = " ".join(f"{k}={rates[k]:.0f}" for k in MAIN_MESSAGES if k in rates)
        c = b["clock"]
        clock = (f"off {c['offset_ms']:.3f}ms drift {c['drift_ppm']:+.1f}ppm "
                 f"jit {c['jitter_ms']:.2f}ms" if "offset_ms" in c else "clock -")
        warn = "  SCHEMA MISMATCH" if b.get("schema_ok") is False else ""
        lines.append(f"board {name:<6} fw {b.get('fw_version', '?'):<6} hb "
                     f"{fmt_age(b['heartbeat_age_s']):>6} ep {c.get('epoch', 0)}  {shown}  "
                     f"lost {sum(b['seq_lost'].values())}  {clock}{warn}")
    m = st["marker_loop"]
    if m["commands_sent"]:
        pos = m["pos_tracker_m"]
        lines.append(f"marker loop: {m['commands_sent']} commands, LED {m['active_led']}, "
                     + (f"pos {pos[0]:+.3f} {pos[1]:+.3f} {pos[2]:+.3f} m "
                        f"({m.get('pos_source')})" if pos else "pos invalid"))
    tr = st.get("tracker")
    if tr:
        lines.append(
            f"tracker: {'valid' if tr.get('valid') else 'not valid'}, sigma "
            + " ".join(f"{1e3 * v:.1f}" for v in tr["pos_sigma_m"])
            + f" mm, accepted {tr['accepted']} gated {tr['gated']} late {tr['late']}"
            if tr["started"] else
            f"tracker: waiting ({'calibrated' if tr['calibrated'] else 'marker not calibrated'}"
            f", {tr['triangulated']} LOSA fixes)")
    return "\n".join(lines)
