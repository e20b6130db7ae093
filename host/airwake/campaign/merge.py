"""The merged airwake map of one relative wind heading: every flight's cells on the
campaign grid, added up cell by cell.

    cells = merge_cells({"b15_01": cells_1, "b15_02": cells_2, ...})   # DataFrames
    summary = merge_beta({"b15_01": "cells.parquet", ...}, 15.0, grid, "OUT")

Per cell, flights f = 1..k with T_f seconds of data in it (the weight: the flight's
samples times their interval), mean m_f, std of that mean s_f and turbulence std
sigma_f per component (`airwake.estimate.airwake_map.grid_samples`); W = sum_f T_f:

    mean          m = sum_f T_f m_f / W
    its std       s = s_int * max(1, B)       s_int = sqrt(sum_f T_f^2 s_f^2) / W
                  B = sqrt(chi2 / (k - 1)),   chi2 = sum_f (m_f - m)^2 / s_f^2   (k >= 2)
    turbulence    sigma^2 = sum_f T_f (sigma_f^2 + (m_f - m)^2) / W
    spread        d = sqrt(sum_f T_f (m_f - m)^2 / W)           (how far flights disagree)

s_int is the error of the weighted mean of independent flights: it shrinks as flights
add data. B (the Birge ratio) compares the flights' scatter with what their own errors
allow: where they disagree beyond them (the airwake changed, or a flight's estimate is
off), the std is inflated by B, the scale factor of a weighted mean of inconsistent
measurements. The turbulence is the total variance of the flow in the cell: each
flight's own plus the spread of the flights' means. TI = sqrt(mean over u, v, w of
sigma^2) / U_ref with U_ref the flights' reference speeds weighted by their time; its
std as in a single flight's map, from N_eff = W / tau_e independent samples.

Simulated flights carry the simulator's field at each cell centre (`truth_*`, averaged
over the times the flight was in the cell); merged with the same weights, it scores the
merged map (`score_cells`).
"""

from __future__ import annotations

import html
import math
from pathlib import Path

import numpy as np

from airwake.estimate.airwake_map import ERROR_CORRELATION_S, FLOW_NAMES, ROT_NAMES

KEYS = ("ix", "iy", "iz")
COMPONENTS = (*FLOW_NAMES, *ROT_NAMES)
SIGMAS = ("sigma_u_m_s", "sigma_v_m_s", "sigma_w_m_s")


def std_name(name: str) -> str:
    """The std column of a component: u_m_s -> u_std_m_s, wx_rad_s -> wx_std_rad_s."""
    stem, unit = name.split("_", 1)
    return f"{stem}_std_{unit}"


def spread_name(name: str) -> str:
    stem, unit = name.split("_", 1)
    return f"{stem}_spread_{unit}"


def merge_cells(tables: dict, u_refs: dict | None = None, cell_m: float = 1.0,
                layer_m: float = 1.0):
    """One row per cell any flight visited (module docstring): ix, iy, iz, x_m, y_m, z_m,
    flights, samples, seconds, each component with its std and spread, sigma_u/v/w_m_s,
    ti, ti_std, speed_m_s, disagreement (sqrt of the mean chi2/(k-1) over u, v, w: the
    flights' scatter in units of their own errors, 0 with one flight) and, where every
    flight has them, truth_* columns. `tables`: flight -> its cells (DataFrame);
    `u_refs`: flight -> its reference speed (m/s)."""
    import pandas as pd

    frames = []
    for name, df in tables.items():
        if len(df):
            frames.append(df.assign(flight=name))
    if not frames:
        raise ValueError("no flight has a cell to merge")
    all_cells = pd.concat(frames, ignore_index=True)
    truth_cols = [f"truth_{n}" for n in COMPONENTS]
    has_truth = all(c in all_cells.columns for c in truth_cols) and not all_cells[
        truth_cols].isna().any().any()
    u_refs = u_refs or {}
    times = all_cells.groupby("flight")["seconds"].sum()
    known = [f for f in times.index if f in u_refs]
    u_ref = (float(sum(u_refs[f] * times[f] for f in known) / times[known].sum())
             if known else float(np.mean(all_cells["speed_m_s"])))
    rows = []
    for key, g in all_cells.groupby(list(KEYS), sort=True):
        t = g["seconds"].to_numpy(float)
        w = t.sum()
        k = len(g)
        row = {"ix": int(key[0]), "iy": int(key[1]), "iz": int(key[2]),
               "x_m": (key[0] + 0.5) * cell_m, "y_m": (key[1] + 0.5) * cell_m,
               "z_m": (key[2] + 0.5) * layer_m, "flights": k,
               "samples": int(g["samples"].sum()), "seconds": float(w)}
        chi_flow = []
        for name in COMPONENTS:
            m_f = g[name].to_numpy(float)
            s_f = np.maximum(g[std_name(name)].to_numpy(float), 1e-9)
            m = float(np.sum(t * m_f) / w)
            s_int = math.sqrt(float(np.sum(t**2 * s_f**2))) / w
            birge = 1.0
            if k >= 2:
                chi2 = float(np.sum((m_f - m) ** 2 / s_f**2))
                birge = math.sqrt(chi2 / (k - 1))
                if name in FLOW_NAMES:
                    chi_flow.append(chi2 / (k - 1))
            row[name] = m
            row[std_name(name)] = s_int * max(1.0, birge)
            row[spread_name(name)] = math.sqrt(float(np.sum(t * (m_f - m) ** 2) / w))
        sig2 = []
        for name, comp in zip(SIGMAS, FLOW_NAMES, strict=True):
            m_f = g[comp].to_numpy(float)
            v = float(np.sum(t * (g[name].to_numpy(float) ** 2 + (m_f - row[comp]) ** 2)) / w)
            row[name] = math.sqrt(v)
            sig2.append(v)
        ti = math.sqrt(float(np.mean(sig2))) / u_ref if u_ref > 0 else math.nan
        row["ti"] = ti
        row["ti_std"] = ti / math.sqrt(2.0 * max(w / ERROR_CORRELATION_S, 1.0))
        row["speed_m_s"] = float(np.linalg.norm([row[n] for n in FLOW_NAMES]))
        row["disagreement"] = math.sqrt(float(np.mean(chi_flow))) if chi_flow else 0.0
        if has_truth:
            for c in truth_cols:
                row[c] = float(np.sum(t * g[c].to_numpy(float)) / w)
        rows.append(row)
    out = pd.DataFrame(rows)
    out.attrs["reference_speed_m_s"] = u_ref
    return out


def score_cells(cells, grid) -> dict:
    """Coverage of the deck area (cells with >= grid.min_seconds) and, when the cells
    carry the simulator's field, the error against it per flow component: RMS over the
    covered deck-area cells and over every cell with enough data."""
    deck = set(grid.deck_cells())
    keys = list(zip(cells["ix"], cells["iy"], cells["iz"], strict=True))
    enough = cells["seconds"].to_numpy() >= grid.min_seconds - 1e-9
    in_deck = np.array([k in deck for k in keys], bool)
    out = {"min_seconds": grid.min_seconds, "deck_cells": len(deck),
           "deck_cells_covered": int((enough & in_deck).sum()),
           "deck_coverage": float((enough & in_deck).sum() / len(deck)),
           "cells_with_enough_data": int(enough.sum())}
    if "truth_u_m_s" in cells.columns:
        for label, sel in (("deck", enough & in_deck), ("all", enough)):
            err = {n: cells.loc[sel, n].to_numpy() - cells.loc[sel, f"truth_{n}"].to_numpy()
                   for n in FLOW_NAMES}
            out[f"field_rms_{label}"] = {
                n: float(np.sqrt(np.mean(e**2))) if e.size else float("nan")
                for n, e in err.items()}
            out[f"field_max_abs_{label}"] = {
                n: float(np.max(np.abs(e))) if e.size else float("nan")
                for n, e in err.items()}
    return out


def merge_beta(cell_files: dict, beta_deg: float, grid, out: Path,
               missing: list | None = None) -> dict:
    """Merge the flights' cells.parquet files of one heading into OUT: map.parquet (every
    cell, `merge_cells`), the figures of the cells with >= grid.min_seconds, summary
    numbers (`score_cells`) and index.html. `missing`: the heading's flights whose map
    did not finish (named on the page). Returns the summary."""
    from airwake.estimate.airwake_map import write_map
    from airwake.estimate.map_plots import plot_cell_values, plot_map
    from airwake.record.flight_table import read_flight_table

    tables, u_refs = {}, {}
    for name, path in sorted(cell_files.items()):
        df, meta = read_flight_table(path)
        tables[name] = df
        if meta.get("reference_speed_m_s"):
            u_refs[name] = float(meta["reference_speed_m_s"])
    cells = merge_cells(tables, u_refs, grid.cell_m, grid.layer_m)
    score = score_cells(cells, grid)
    u_ref = cells.attrs["reference_speed_m_s"]
    settings = {"beta_deg": beta_deg, "frame": "ship", "cell_m": grid.cell_m,
                "layer_m": grid.layer_m, "min_seconds": grid.min_seconds,
                "reference_speed_m_s": u_ref, "flights": sorted(tables),
                "missing": list(missing or [])}
    out.mkdir(parents=True, exist_ok=True)
    write_map(cells, out, {"source": "airwake campaign merge", **settings})
    shown = cells[cells["seconds"] >= grid.min_seconds - 1e-9]
    figures = []
    if len(shown):
        title = f"beta {beta_deg:g} deg, {len(tables)} flights: "
        ship = grid.ship()
        figures = [p.name for p in plot_map(shown, out, grid.cell_m, "ship", ship,
                                            title=title).values()]
        figures.append(plot_cell_values(
            shown, shown["u_std_m_s"], out / "uncertainty.png", grid.cell_m, "ship", ship,
            "std of the mean flow u (m/s)", title=f"{title}uncertainty").name)
        figures.append(plot_cell_values(
            shown, shown["disagreement"], out / "disagreement.png", grid.cell_m, "ship",
            ship, "flights' scatter / their own errors",
            title=f"{title}disagreement between flights").name)
    summary = {**settings, "cells": int(len(cells)), "figures": figures, **score}
    (out / "index.html").write_text(_page(summary), encoding="utf-8")
    return summary


def _page(s: dict) -> str:
    esc = html.escape
    figs = "".join(f'<figure><img src="{esc(f)}" alt="{esc(f)}"></figure>'
                   for f in s["figures"])
    score = ""
    if "field_rms_deck" in s:
        rows = "".join(
            f"<tr><td>{esc(n)}</td><td>{s['field_rms_deck'][n]:.3f}</td>"
            f"<td>{s['field_rms_all'][n]:.3f}</td><td>{s['field_max_abs_all'][n]:.3f}</td>"
            "</tr>" for n in s["field_rms_deck"])
        score = ("<h2>Against the simulator's field at the cell centres</h2><table><tr>"
                 "<th>component</th><th>RMS, deck area (m/s)</th><th>RMS, every cell</th>"
                 f"<th>max |error|</th></tr>{rows}</table>")
    return f"""<!doctype html><html><head><meta charset="utf-8">
<title>merged airwake map, beta {s['beta_deg']:g} deg</title>
<style>body{{font-family:sans-serif;max-width:60em;margin:2em auto}}img{{max-width:100%}}
table{{border-collapse:collapse}}td,th{{border:1px solid #ccc;padding:.2em .6em}}</style>
</head><body><h1>Merged airwake map, relative wind from {s['beta_deg']:g} deg</h1>
<p>{len(s['flights'])} flights; {s['cells_with_enough_data']} cells of {s['cell_m']:g} m
with at least {s['min_seconds']:g} s of data; the deck area (the flight deck and behind it,
{s['deck_cells']} cells) is covered to {100 * s['deck_coverage']:.0f} %
({s['deck_cells_covered']} cells). U_ref {s['reference_speed_m_s']:.2f} m/s.</p>
{figs}{score}
<p>Cells: map.parquet (mean flow and turbulence per cell with their std, the flights'
spread and disagreement; docs/campaigns.md).</p>
<p>Flights: {esc(', '.join(s['flights']))}</p>
{f"<p>Left out (their map did not finish): {esc(', '.join(s['missing']))}</p>"
 if s['missing'] else ''}</body></html>
"""
