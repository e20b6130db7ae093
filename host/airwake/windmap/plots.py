"""PNG slices of an anemometer wind map (matplotlib, Agg).

    paths = plot_windmap(wmap, out_dir)

- `slice_z<k>.png`: horizontal slices through the grid at the surveyed heights (up to
  four, the z values holding most locations): colour the measured speed, arrows the
  horizontal flow, north to the right, east down the page;
- `slice_y.png`: the vertical slice nearest y = 0 (north to the right, up is up):
  colour the speed, arrows the (north, up) flow;
- `model_error.png`: histogram of the eq 3.15 and eq 5.3 model errors in % of the
  source wind, the reference's 3-11 % band shaded (Fig 3.14B).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _slice(grid, axis: str, value: float):
    sel = np.isclose(grid[axis].to_numpy(), value, atol=1e-6)
    return grid[sel]


def _image(ax, df, a: str, b: str, values, vmax, arrows, label, flip_b=False):
    xs, ys = np.unique(df[a].to_numpy()), np.unique(df[b].to_numpy())
    img = np.full((ys.size, xs.size), np.nan)
    ia = np.searchsorted(xs, df[a].to_numpy())
    ib = np.searchsorted(ys, df[b].to_numpy())
    img[ib, ia] = values
    yplot = -ys if flip_b else ys
    mesh = ax.pcolormesh(xs, yplot, img, shading="nearest", vmin=0.0, vmax=vmax,
                         cmap="viridis")
    step = max(1, int(round(0.2 / max(np.min(np.diff(xs)) if xs.size > 1 else 0.2, 1e-6))))
    sub = (ia % step == 0) & (ib % step == 0)
    ax.quiver(df[a].to_numpy()[sub], (-1 if flip_b else 1) * df[b].to_numpy()[sub],
              arrows[0][sub], arrows[1][sub], color="w", scale=80, width=0.002)
    ax.set_aspect("equal")
    return mesh


def plot_windmap(wmap, out_dir) -> dict:
    """Write the PNGs (module docstring) into out_dir; returns {name: path}."""
    plt = _plt()
    out = Path(out_dir)
    grid = wmap.grid
    paths = {}
    vmax = float(np.nanmax(grid["speed_m_s"])) if len(grid) else 1.0
    zs = np.unique(grid["z_m"].to_numpy())
    loc_z = wmap.locations["z_m"].to_numpy()
    near = zs[np.argmin(np.abs(zs[None, :] - loc_z[:, None]), axis=1)]
    vals, counts = np.unique(near, return_counts=True)
    heights = np.sort(vals[np.argsort(counts)[::-1][:4]])
    for k, z in enumerate(heights):
        df = _slice(grid, "z_m", z)
        fig, ax = plt.subplots(figsize=(9.0, 4.0), dpi=110)
        mesh = _image(ax, df, "x_m", "y_m", df["speed_m_s"].to_numpy(), vmax,
                      (df["u_m_s"].to_numpy(), -df["v_m_s"].to_numpy()), "speed",
                      flip_b=True)
        ax.set_xlabel("north (m)")
        ax.set_ylabel("east (m, down the page)")
        ax.set_title(f"measured mean flow at {-z:.2f} m up (d = {z:+.2f} m)")
        fig.colorbar(mesh, ax=ax, label="speed (m/s)")
        fig.tight_layout()
        p = out / f"slice_z{k}.png"
        fig.savefig(p)
        plt.close(fig)
        paths[p.stem] = p
    ys = np.unique(grid["y_m"].to_numpy())
    y0 = ys[np.argmin(np.abs(ys))]
    df = _slice(grid, "y_m", y0)
    fig, ax = plt.subplots(figsize=(9.0, 3.5), dpi=110)
    mesh = _image(ax, df.assign(up_m=-df["z_m"]), "x_m", "up_m", df["speed_m_s"].to_numpy(),
                  vmax, (df["u_m_s"].to_numpy(), -df["w_m_s"].to_numpy()), "speed")
    ax.set_xlabel("north (m)")
    ax.set_ylabel("up (m)")
    ax.set_title(f"measured mean flow, vertical slice at east = {y0:+.2f} m")
    fig.colorbar(mesh, ax=ax, label="speed (m/s)")
    fig.tight_layout()
    p = out / "slice_y.png"
    fig.savefig(p)
    plt.close(fig)
    paths[p.stem] = p
    fig, ax = plt.subplots(figsize=(6.0, 4.0), dpi=110)
    lo, hi = wmap.model_error["reference_pct"]
    ax.axvspan(lo, hi, color="0.85", label="reference 3-11 %")
    top = float(np.nanpercentile(grid["m12_error_pct"], 99.5)) if len(grid) else 20.0
    bins = np.linspace(0.0, max(top, hi * 1.5), 50)
    ax.hist(grid["m12_error_pct"], bins=bins, histtype="step", lw=1.5, label="eq 3.15")
    ax.hist(grid["m6_error_pct"], bins=bins, histtype="step", lw=1.5, label="eq 5.3")
    ax.set_xlabel(f"|model - measured| (% of {wmap.settings['source_speed_m_s']:g} m/s)")
    ax.set_ylabel("grid points")
    ax.legend()
    fig.tight_layout()
    p = out / "model_error.png"
    fig.savefig(p)
    plt.close(fig)
    paths[p.stem] = p
    return paths
