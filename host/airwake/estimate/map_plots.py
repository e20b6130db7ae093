"""PNG maps of an airwake map (matplotlib, Agg): mean flow, turbulence intensity, coverage.

    paths = plot_map(cells, out_dir, frame="ship", ship=ShipOutline())

Each figure shows one layer (the one holding most of the flight's time; its z in the
title), cells as squares seen from above: on a ship a plan view with the bow to the right
and starboard down the page, the flight deck and hangar outlined; elsewhere north to the
right and east down (the same plan view of the NED frame).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np


@dataclass(frozen=True)
class ShipOutline:
    """Plan-view outline in the ship frame (x forward of the hangar step, y starboard):
    flight deck x in [-deck_length, 0], |y| <= beam / 2; hangar x in [0, hangar_length],
    |y| <= hangar_width / 2. Defaults: a YP676-like patrol craft (reference §4.5)."""

    deck_length_m: float = 6.0
    beam_m: float = 7.3
    hangar_length_m: float = 8.0
    hangar_width_m: float = 6.0

    def draw(self, ax) -> None:
        from matplotlib.patches import Rectangle

        ax.add_patch(Rectangle((-self.deck_length_m, -self.beam_m / 2), self.deck_length_m,
                               self.beam_m, fill=False, lw=1.2, ec="0.3", ls="--",
                               label="flight deck"))
        ax.add_patch(Rectangle((0.0, -self.hangar_width_m / 2), self.hangar_length_m,
                               self.hangar_width_m, fc="0.75", ec="0.2", lw=1.2,
                               label="hangar"))


def main_layer(cells) -> int:
    """The z layer index holding the most seconds."""
    by = cells.groupby("iz")["seconds"].sum()
    return int(by.idxmax())


def _axes(frame: str):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8.0, 6.0), dpi=110)
    ax.set_aspect("equal")
    if frame == "ship":
        ax.set_xlabel("x (m, forward of the hangar step)")
        ax.set_ylabel("y (m, starboard)")
    else:
        ax.set_xlabel("north (m)")
        ax.set_ylabel("east (m)")
    # plan view from above: x (bow, north) to the right, y (starboard, east) down the page
    ax.invert_yaxis()
    return fig, ax


def _cells_image(ax, cells, values, cell_m, cmap, label, vmin=None, vmax=None):
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Rectangle

    rects = [Rectangle((x - cell_m / 2, y - cell_m / 2), cell_m, cell_m)
             for x, y in zip(cells["x_m"], cells["y_m"], strict=True)]
    pc = PatchCollection(rects, cmap=cmap)
    pc.set_array(np.asarray(values, float))
    if vmin is not None or vmax is not None:
        pc.set_clim(vmin, vmax)
    ax.add_collection(pc)
    ax.figure.colorbar(pc, ax=ax, label=label, shrink=0.8)
    return pc


def _frame_limits(ax, cells, cell_m, ship):
    xs, ys = cells["x_m"].to_numpy(), cells["y_m"].to_numpy()
    x0, x1 = xs.min() - cell_m, xs.max() + cell_m
    y0, y1 = ys.min() - cell_m, ys.max() + cell_m
    if ship is not None:
        x0, x1 = min(x0, -ship.deck_length_m - 1), max(x1, ship.hangar_length_m + 1)
        y0, y1 = min(y0, -ship.beam_m / 2 - 1), max(y1, ship.beam_m / 2 + 1)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y1, y0) if ax.yaxis_inverted() else ax.set_ylim(y0, y1)


def plot_map(cells, out_dir, cell_m: float, frame: str, ship: ShipOutline | None,
             title: str = "") -> dict:
    """Write mean_flow.png, turbulence.png, coverage.png; returns {name: path}."""
    import matplotlib.pyplot as plt

    out = Path(out_dir)
    paths = {}
    if len(cells) == 0:
        return paths
    iz = main_layer(cells)
    layer = cells[cells["iz"] == iz]
    z = float(layer["z_m"].iloc[0])
    where = (f"layer centred {-z:.1f} m above the deck" if frame == "ship" else
             f"layer centred at down = {z:+.1f} m")
    ship = ship if frame == "ship" else None

    fig, ax = _axes(frame)
    _cells_image(ax, layer, layer["w_m_s"], cell_m, "coolwarm",
                 "vertical flow w (m/s, down +)",
                 *(np.array([-1, 1]) * max(float(np.abs(layer["w_m_s"]).max()), 0.1)))
    if ship is not None:
        ship.draw(ax)
    q = ax.quiver(layer["x_m"], layer["y_m"], layer["u_m_s"], layer["v_m_s"],
                  angles="xy", scale_units="xy",
                  scale=max(float(layer["speed_m_s"].max()), 1e-3) / (0.9 * cell_m),
                  width=0.004, color="k")
    ref = max(round(float(layer["speed_m_s"].median()), 1), 0.1)
    ax.quiverkey(q, 0.85, 1.03, ref, f"{ref:g} m/s", labelpos="W")
    _frame_limits(ax, layer, cell_m, ship)
    ax.set_title(f"{title}mean flow relative to the {'ship' if frame == 'ship' else 'site'}"
                 f"\n{where}", fontsize=10)
    paths["mean_flow"] = out / "mean_flow.png"
    fig.savefig(paths["mean_flow"], bbox_inches="tight")
    plt.close(fig)

    for name, values, cmap, label, vmax, what in (
            ("turbulence", layer["ti"], "viridis", "turbulence intensity",
             max(float(layer["ti"].max()), 0.05), "turbulence intensity (sigma / U_ref)"),
            ("coverage", layer["seconds"], "magma_r", "seconds of data", None,
             "sample coverage")):
        fig, ax = _axes(frame)
        _cells_image(ax, layer, values, cell_m, cmap, label, 0.0, vmax)
        if ship is not None:
            ship.draw(ax)
        _frame_limits(ax, layer, cell_m, ship)
        ax.set_title(f"{title}{what}\n{where}", fontsize=10)
        paths[name] = out / f"{name}.png"
        fig.savefig(paths[name], bbox_inches="tight")
        plt.close(fig)
    return paths


def plot_cell_values(cells, values, path, cell_m: float, frame: str,
                     ship: ShipOutline | None, label: str, title: str = "",
                     cmap: str = "viridis", symmetric: bool = False) -> Path:
    """One PNG of per-cell `values` over the main layer (see module doc); `symmetric`
    centres the colour scale on zero. Returns the path."""
    import matplotlib.pyplot as plt

    values = np.asarray(values, float)
    iz = main_layer(cells)
    sel = (cells["iz"] == iz).to_numpy()
    layer = cells[sel]
    z = float(layer["z_m"].iloc[0])
    where = (f"layer centred {-z:.1f} m above the deck" if frame == "ship" else
             f"layer centred at down = {z:+.1f} m")
    ship = ship if frame == "ship" else None
    v = values[sel]
    lim = (None, None)
    if symmetric and np.isfinite(v).any():
        m = max(float(np.nanmax(np.abs(v))), 1e-12)
        lim = (-m, m)
    fig, ax = _axes(frame)
    _cells_image(ax, layer, v, cell_m, cmap, label, *lim)
    if ship is not None:
        ship.draw(ax)
    _frame_limits(ax, layer, cell_m, ship)
    ax.set_title(f"{title}\n{where}", fontsize=10)
    path = Path(path)
    fig.savefig(path, bbox_inches="tight")
    plt.close(fig)
    return path
