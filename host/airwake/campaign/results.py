"""The campaign's results: OUT/summary.parquet, OUT/merged.parquet and OUT/index.html.

summary.parquet, one row per flight and per calibration flight (`role`): flight, role,
beta_deg, helicopter, day, source, status ("done" when every step finished, else
"failed"), failed_step, error, traceback; seconds_<step> (the compute time of each step,
also for results found in the store: what it cost when it ran); samples and duration_s
(the flight table); map_cells and map_deck_cells (cells with >= grid.min_seconds, all and
in the deck area); fit_rms_<channel> and fit_over_noise_<channel> (the model report's
comparison with the estimated wind as the model's input; a calibration's RMS after the
fit); and for simulated flights wind_error_rms_<component> and wind_coverage_90_<component>
(the estimate against the truth along the track: RMS error and how often the 90 %
interval holds the truth) and map_field_rms_<u|v|w> (the flight's map against the
simulator's field); map_page and report_page (paths relative to OUT).

merged.parquet, one row per heading: beta_deg, flights, cells, deck_coverage,
deck_cells_covered, field_rms_deck_<u|v|w> (simulated), page.

index.html links every flight's map and report and every merged map (tested in a browser).
"""

from __future__ import annotations

import html
import math
import os
from pathlib import Path

from airwake.campaign.plan import beta_subject

STEP_ORDER = ("export", "calibrate", "still_air_net", "estimate", "map", "report")


def _rel(store, rec: dict | None, out: Path, name: str = "page") -> str:
    if not rec or rec["status"] != "done" or name not in rec["outputs"]:
        return ""
    return os.path.relpath(store.output(rec, name), out)


def _row(subject: str, keys: dict, records: dict, store, out: Path) -> dict:
    row = {"status": "done", "failed_step": "", "error": "", "traceback": ""}
    for step in STEP_ORDER:
        rec = records.get(keys.get(step, ""))
        row[f"seconds_{step}"] = float(rec["seconds"]) if rec else math.nan
        if rec and rec["status"] != "done" and row["status"] == "done":
            row.update(status="failed", failed_step=step, error=rec["error"],
                       traceback=rec["traceback"])
    est = records.get(keys.get("estimate", ""), {}).get("summary", {})
    row["samples"] = est.get("flight_rows", math.nan)
    row["duration_s"] = est.get("duration_s", math.nan)
    for comp, e in (est.get("wind_error") or {}).items():
        row[f"wind_error_rms_{comp}"] = e["error_rms"]
        row[f"wind_coverage_90_{comp}"] = e["coverage_90"]
    mp = records.get(keys.get("map", ""))
    ms = (mp or {}).get("summary", {})
    row["map_cells"] = ms.get("cells", math.nan)
    row["map_deck_cells"] = ms.get("deck_cells_covered", math.nan)
    for comp, v in (ms.get("field_rms") or {}).items():
        row[f"map_field_rms_{comp}"] = v
    rep = records.get(keys.get("report", ""))
    for ch, m in ((rep or {}).get("summary", {}).get("fit") or {}).items():
        row[f"fit_rms_{ch}"] = m["rms"]
        row[f"fit_over_noise_{ch}"] = m["rms_over_noise"]
    cal = records.get(keys.get("calibrate", ""))
    for ch, v in ((cal or {}).get("summary", {}).get("rms_after") or {}).items():
        row[f"fit_rms_{ch}"] = v
    row["map_page"] = _rel(store, mp, out)
    row["report_page"] = _rel(store, rep, out)
    return row


def summary_table(campaign, plan, records: dict, store, out: Path):
    """(flights DataFrame, merged DataFrame): module docstring."""
    import pandas as pd

    rows = []
    for h in campaign.helicopters.values():
        if h.calibration is not None and h.name in plan.by_subject:
            keys = dict(plan.by_subject.get(f"calibration {h.name}", {}))
            keys.update(plan.by_subject[h.name])
            rows.append({"flight": f"calibration {h.name}", "role": "calibration",
                         "beta_deg": math.nan, "helicopter": h.name, "day": "",
                         "source": str(h.calibration.path),
                         **_row(h.name, keys, records, store, out)})
    for f in campaign.flights:
        rows.append({"flight": f.name, "role": "flight", "beta_deg": f.beta_deg,
                     "helicopter": f.helicopter, "day": f.day, "source": str(f.source.path),
                     **_row(f.name, plan.by_subject.get(f.name, {}), records, store, out)})
    merged = []
    for beta in campaign.betas:
        rec = records.get(plan.by_subject.get(beta_subject(beta), {}).get("merge", ""))
        if rec is None:
            continue
        s = rec.get("summary", {})
        row = {"beta_deg": beta, "status": rec["status"], "error": rec["error"],
               "flights": len(s.get("flights", [])), "cells": s.get("cells", 0),
               "deck_coverage": s.get("deck_coverage", math.nan),
               "deck_cells_covered": s.get("deck_cells_covered", 0),
               "deck_cells": s.get("deck_cells", 0), "page": _rel(store, rec, out)}
        for comp, v in (s.get("field_rms_deck") or {}).items():
            row[f"field_rms_deck_{comp}"] = v
        merged.append(row)
    return pd.DataFrame(rows), pd.DataFrame(merged)


def write_results(campaign, plan, records: dict, store, out: Path):
    """summary.parquet, merged.parquet and index.html into OUT; returns the summary."""
    import tempfile

    table, merged = summary_table(campaign, plan, records, store, out)
    for df, name in ((table, "summary.parquet"), (merged, "merged.parquet")):
        fd, tmp = tempfile.mkstemp(prefix=f".{name}-", dir=out)
        os.close(fd)
        df.to_parquet(tmp, index=False)
        os.replace(tmp, out / name)
    (out / "index.html").write_text(_page(campaign, table, merged, records, store, out),
                                    encoding="utf-8")
    return table


def _f(v, fmt: str = ".2f") -> str:
    return "" if v is None or (isinstance(v, float) and math.isnan(v)) else format(v, fmt)


def _page(campaign, table, merged, records, store, out: Path) -> str:
    esc = html.escape
    maps = []
    for _, m in merged.iterrows():
        link = m["page"]
        if not link:
            maps.append(f"<section><h3>beta {m['beta_deg']:g} deg: not merged</h3>"
                        f"<p>{esc(m['error'])}</p></section>")
            continue
        rms = ", ".join(f"{c[len('field_rms_deck_'):]} {m[c]:.2f}" for c in merged.columns
                        if c.startswith("field_rms_deck_") and not math.isnan(m[c]))
        img = Path(link).parent / "mean_flow.png"
        maps.append(
            f'<section><h3><a href="{esc(link)}">beta {m["beta_deg"]:g} deg</a></h3>'
            f"<p>{m['flights']} flights, {m['cells']} cells; deck area covered "
            f"{100 * m['deck_coverage']:.0f} % ({m['deck_cells_covered']} of "
            f"{m['deck_cells']} cells)" + (f"; error against the simulator's field (RMS, "
                                            f"m/s): {esc(rms)}" if rms else "") + "</p>"
            + (f'<a href="{esc(link)}"><img src="{esc(str(img))}" alt="merged map beta '
               f'{m["beta_deg"]:g}"></a>' if (out / img).is_file() else "") + "</section>")
    rows = []
    for _, r in table.iterrows():
        links = " ".join(f'<a href="{esc(r[k])}">{label}</a>'
                         for k, label in (("map_page", "map"), ("report_page", "report"))
                         if r[k])
        secs = " / ".join(_f(r[f"seconds_{s}"], ".1f") or "-" for s in STEP_ORDER)
        err = (f"<details><summary>{esc(r['failed_step'])}: {esc(r['error'][:160])}</summary>"
               f"<pre>{esc(r['traceback'])}</pre></details>" if r["status"] != "done" else "")
        rows.append(f"<tr class=\"{esc(r['status'])}\"><td class=l>{esc(r['flight'])}</td>"
                    f"<td>{_f(r['beta_deg'], 'g')}</td><td>{esc(r['helicopter'])}</td>"
                    f"<td>{esc(r['day'])}</td><td>{esc(r['status'])}{err}</td>"
                    f"<td>{secs}</td><td>{_f(r['map_cells'], '.0f')}</td>"
                    f"<td class=l>{links}</td></tr>")
    n_fail = int((table["status"] != "done").sum()) if len(table) else 0
    n_cal = int((table["role"] == "calibration").sum()) if len(table) else 0
    return f"""<!doctype html><html><head><meta charset="utf-8">
<title>campaign {esc(campaign.name)}</title>
<style>body{{font-family:sans-serif;max-width:72em;margin:2em auto;padding:0 1em}}
img{{max-width:48em}}table{{border-collapse:collapse;font-size:.92em}}
td,th{{border:1px solid #ccc;padding:.2em .5em;text-align:right}}.l{{text-align:left}}
tr.failed td{{background:#fde8e8}}pre{{text-align:left;white-space:pre-wrap;font-size:.85em}}
</style></head><body><h1>Campaign {esc(campaign.name)}</h1>
<p>{esc(campaign.description)}</p>
<p>{len(table) - n_cal} flights and {n_cal} calibration flight(s), {n_fail} failed; steps
{esc(', '.join(campaign.steps))};
grid {campaign.grid.cell_m:g} m cells, {campaign.grid.layer_m:g} m layers.
Numbers: summary.parquet, merged.parquet (docs/campaigns.md).</p>
<h2>Merged airwake maps</h2>{''.join(maps) or '<p>none (no map step)</p>'}
<h2>Flights</h2><table><tr><th class=l>flight</th><th>beta (deg)</th><th>helicopter</th>
<th>day</th><th>status</th><th>seconds: {' / '.join(STEP_ORDER)}</th>
<th>cells &ge; {campaign.grid.min_seconds:g} s</th><th class=l>pages</th></tr>
{''.join(rows)}</table></body></html>
"""
