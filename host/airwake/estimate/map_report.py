"""`airwake wind map` end to end: wind table + flight -> MAPDIR, written all or nothing.

    summary = make_map(wind_table, flight_table, "MAPDIR", cell_m=0.5, score=True)

MAPDIR holds map.parquet (the cells, `airwake.estimate.airwake_map`), mean_flow.png,
turbulence.png, coverage.png (`map_plots`), summary.json (settings, headline numbers and
the score) and index.html (the figures and the numbers on one page). Everything is
written to a temporary sibling directory that replaces MAPDIR only once complete, so a
failure leaves the previous MAPDIR (or none) untouched; an existing MAPDIR is replaced only
when it is empty or an earlier map (it holds map.parquet or summary.json).
"""

from __future__ import annotations

import html
import shutil
import tempfile
from pathlib import Path

import numpy as np

from airwake.estimate.airwake_map import (
    build_map,
    check_same_flight,
    score_map,
    write_json,
    write_map,
)
from airwake.estimate.errors import WindEstimationError


def headline(amap) -> str:
    """One paragraph a person reads first."""
    c = amap.cells
    st = amap.settings
    where = "relative to the ship" if st["frame"] == "ship" else "in the site frame"
    t = float(c["seconds"].sum())
    spd = c["speed_m_s"].to_numpy()
    ti = c["ti"].to_numpy()
    top = c.iloc[int(np.argmax(ti))]
    text = (f"airwake map ({where}): {len(c)} cells of {st['cell_m']:g} m with {t:.0f} s of "
            f"data; mean flow {spd.min():.2f} ... {spd.max():.2f} m/s (U_ref "
            f"{st['reference_speed_m_s']:.2f} m/s); turbulence intensity "
            f"{ti.min():.2f} ... {ti.max():.2f}, highest at x = {top['x_m']:+.2f} m, "
            f"y = {top['y_m']:+.2f} m")
    if st["frame"] == "ship":
        lo = c[c["ti"] >= np.quantile(ti, 0.75)]
        text += (f"; the most turbulent quarter of the cells lies at x = "
                 f"{lo['x_m'].min():+.1f} ... {lo['x_m'].max():+.1f} m aft/fore of the hangar "
                 "step")
    return text


def make_map(wind, flight, out_dir, *, cell_m: float = 0.5, layer_m: float = 1.0,
             min_seconds: float = 0.5, u_ref: float | None = None, score: bool = False,
             ship=None, wind_name: str = "wind", flight_name: str = "flight") -> dict:
    """Build, score (optionally) and write the map; returns the summary (module doc).
    `wind`, `flight`: FlightTable-like (df, metadata)."""
    from airwake.estimate.map_plots import plot_map

    check_same_flight(wind.metadata, flight.df, wind_name, flight_name)
    out = Path(out_dir)
    check_map_dir(out, WindEstimationError)
    amap = build_map(wind.df, flight.df, wind_meta=wind.metadata, cell_m=cell_m,
                     layer_m=layer_m, min_seconds=min_seconds, u_ref=u_ref)
    if score:
        amap.score = score_map(amap, flight.df, flight.metadata)
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}-", dir=out.parent))
    try:
        meta = {"source": "airwake wind map", "wind": wind_name, "flight": flight_name,
                **amap.settings}
        write_map(amap.cells, tmp, meta)
        figs = plot_map(amap.cells, tmp, cell_m, amap.settings["frame"], ship)
        summary = {"headline": headline(amap), "out": str(out), **amap.settings,
                   "cells": len(amap.cells), "seconds": float(amap.cells["seconds"].sum()),
                   "figures": [p.name for p in figs.values()],
                   "estimate": {k: wind.metadata.get(k) for k in ("method", "model_spec",
                                                                      "anchor")}}
        if amap.score is not None:
            summary["score"] = {k: v for k, v in amap.score.items() if k != "truth_cells"}
        write_json(summary, tmp / "summary.json")
        (tmp / "index.html").write_text(_page(summary, amap))
        publish_dir(tmp, out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return summary


def check_map_dir(out: Path, error=WindEstimationError,
                  markers=("map.parquet", "summary.json")) -> None:
    """`error` unless `out` is absent, empty or an earlier map (holds one of `markers`)."""
    if out.exists() and (not out.is_dir() or (any(out.iterdir()) and not any(
            (out / m).exists() for m in markers))):
        raise error(f"--out {out}: exists and is not an earlier map (no {markers[0]}): "
                    "refusing to replace it")


def publish_dir(tmp: Path, out: Path) -> None:
    """Replace `out` by the complete directory `tmp` (renames: never half-written)."""
    if out.exists():
        old = Path(tempfile.mkdtemp(prefix=f".{out.name}-old-", dir=out.parent))
        old.rmdir()
        out.rename(old)
        tmp.rename(out)
        shutil.rmtree(old, ignore_errors=True)
    else:
        tmp.rename(out)


def _page(summary: dict, amap) -> str:
    """index.html: headline, figures, settings, score (self-contained but for the PNGs
    beside it)."""
    esc = html.escape
    rows = []
    for k in ("frame", "cell_m", "layer_m", "min_seconds", "reference_speed_m_s",
              "ins_velocity_std_m_s"):
        rows.append(f"<tr><th>{esc(k)}</th><td>{esc(str(summary[k]))}</td></tr>")
    figs = "".join(f'<figure><img src="{esc(f)}" alt="{esc(f)}"></figure>'
                   for f in summary["figures"])
    score = ""
    if "score" in summary:
        sc = summary["score"]
        lines = "".join(
            f"<tr><td>{esc(n)}</td><td>{sc['along_track'][n]['rms']:.3f}</td>"
            f"<td>{sc['field'][n]['rms']:.3f}</td><td>{sc['field'][n]['max_abs']:.3f}</td></tr>"
            for n in sc["field"])
        score = (f"<h2>Against the simulator's truth ({sc['cells']} cells with &ge; "
                 f"{sc['min_seconds']:g} s)</h2><table><tr><th>component</th>"
                 "<th>along-track RMS</th><th>field RMS</th><th>field max |error|</th></tr>"
                 f"{lines}</table>")
    return f"""<!doctype html><html><head><meta charset="utf-8"><title>airwake map</title>
<style>body{{font-family:sans-serif;max-width:60em;margin:2em auto}}img{{max-width:100%}}
table{{border-collapse:collapse}}td,th{{border:1px solid #ccc;padding:.2em .6em}}</style>
</head><body><h1>Airwake map</h1><p>{esc(summary['headline'])}</p>{figs}
<h2>Settings</h2><table>{''.join(rows)}</table>{score}
<p>Cells: map.parquet (docs/airwake-map.md).</p></body></html>
"""
