"""An effect outside the catalogue (a tail-thrust error growing with airspeed, added to the
truth by the test) shows up in the sparse named regression on the right channel and
physical variable, and a user plugin written here fixes it; the HTML report opens in a
real headless browser with every figure loaded."""

from __future__ import annotations

import numpy as np
from airwake.discrepancy.add import add_effect
from airwake.discrepancy.diagnose import diagnose
from airwake.discrepancy.report import write_report
from airwake.record.flight_table import write_flight_table
from browser import images_loaded

from .flights import analysed, noise_floor

USER_PLUGIN = '''
import numpy as np
from airwake.heli import Effect, Parameter, register_effect


@register_effect("tail_airspeed_error")
class TailAirspeedError(Effect):
    """Tail thrust grows with airspeed: dY = -k (V/5 m/s)^2 T_tail at the tail rotor."""

    PARAMETERS = (Parameter("k", 0.0, "-", (-1.0, 1.0), "fitted"),)
    REQUIRES = ("tail_rotor",)

    def forces(self, ctx, p):
        v = np.asarray(ctx.vel_b_m_s)
        v2 = (v[:, 0] ** 2 + v[:, 1] ** 2) / 25.0
        fy = -p.k * v2 * np.asarray(ctx.tail_thrust_n)
        tail = ctx.model["tail_rotor"].parameters()
        f = np.zeros((ctx.n, 3))
        f[:, 1] = fy
        m = np.zeros((ctx.n, 3))
        m[:, 0] = tail["height_m"] * fy
        m[:, 2] = -tail["arm_m"] * fy
        ctx.add_load(self.name, f, m)
'''


def test_out_of_catalogue_effect_points_at_rdot_and_airspeed_and_a_plugin_fixes_it(
        flights, baseline, tmp_path):
    ft = flights("tail_airspeed")
    d = diagnose(baseline, ft, refine_top=2)
    channels = d.sindy["channels"]
    worst = max(channels, key=lambda c: channels[c]["rms_over_noise"])
    assert worst in ("rdot_rad_s2", "acc_y_m_s2"), worst
    top = channels["rdot_rad_s2"]["terms"][0]
    airspeed = {"V", "u", "v"}
    assert airspeed & set(top["vars"]) or any(
        airspeed & set(t["vars"]) for t in channels["rdot_rad_s2"]["terms"][:2]), top
    plugin = tmp_path / "tail_airspeed_error.py"
    plugin.write_text(USER_PLUGIN)
    res = add_effect(baseline, "tail_airspeed_error", ft, plugin=plugin,
                     out=tmp_path / "fixed.toml")
    assert (tmp_path / "fixed.toml").exists()
    before = analysed(baseline, ft)
    after = analysed(res.model, ft)
    rb = np.sqrt(np.mean(before.residual_band[before.mask] ** 2, 0))
    ra = np.sqrt(np.mean(after.residual_band[after.mask] ** 2, 0))
    floor = noise_floor(after)
    assert ra[5] <= 0.5 * rb[5] and ra[5] <= 1.5 * floor[5], (rb[5], ra[5], floor[5])


def test_report_opens_in_a_headless_browser_with_every_image_loaded(flights, baseline,
                                                                    tmp_path):
    ft = flights("lever_arm")
    path = tmp_path / "lever.parquet"
    write_flight_table(ft.df, path, ft.metadata)
    out = write_report(path, baseline, tmp_path / "report")
    html = (tmp_path / "report" / "index.html").read_text()
    for section in ("id=compare", "id=where", "id=candidates", "id=sparse-regression",
                    "id=error-falls"):
        assert section in html
    assert "http://" not in html and "https://" not in html and "<script" not in html
    loaded, total = images_loaded(tmp_path / "report" / "index.html")
    assert total == len(out["figures"]) and loaded == total
