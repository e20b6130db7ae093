"""Issue 11's acceptance tests on hil_sim flights with hidden (truth-only) effects, which the
truth world implements from formulations other than the catalogue's (hil_sim/world/hidden/,
docs/scenarios.md):

- for every hidden-effect scenario, `diagnose` ranks the matching catalogue effect first
  (and significant); `add_effect` of it cuts every affected channel's RMS by >= 60 % and
  makes no channel more than 10 % worse;
- where the catalogue's simpler formula cannot represent the truth's physics, the
  channel is listed in KNOWN_GAPS with the cut the catalogue does reach (asserted, so a
  better catalogue effect shows up here);
- after the catalogue's ground effect, the "where" breakdown of what remains points at
  the regime it misses, and a user plugin written here closes most of it;
- two hidden effects at once: both in the top 3, adding both cuts every affected channel
  by at least half;
- clean still-air data with a calibrated model (C's calibrator): no false alarm.

A channel is "affected" when the baseline's RMS there exceeds 2.5x the flight's noise
floor (`flights.noise_floor`: output noise and measured-state noise, from the truth
columns): the error cannot fall below the floor, so a cut is only measurable with room
above it. Flights are the compact scenarios of tests/discrepancy/scenarios (fixed seeds
the tests were not tuned on).
"""

from __future__ import annotations

import numpy as np
import pytest
from airwake.discrepancy import where
from airwake.discrepancy.add import add_effect
from airwake.discrepancy.diagnose import diagnose
from airwake.heli.context import MEAS_CHANNELS

from .flights import analysed, noise_floor

# scenario -> the catalogue effect that models its hidden effect
HIDDEN = {
    "ground_effect": "ground_effect",        # Hayden 1976 fit, wake-footprint fade
    "servo_lag": "servo_lag",                # delay + deadband + 2nd order + slew limit
    "rotor_droop": "rotor_droop",            # electric drive + saturating PI governor
    "dynamic_inflow": "dynamic_inflow",      # three-state Pitt-Peters
    "recirculation": "wake_recirculation",   # ground vortex + image
    "lever_arm": "imu_lever_arm",
    "vibration_rectification": "accel_bias",
    "input_time_skew": "servo_lag",          # a lag is the catalogue's closest to a skew
}
AFFECTED = 2.5  # x noise floor
MIN_CUT = 0.6
MAX_WORSE = 1.1
# (scenario, channel) -> (cut the catalogue effect reaches at least, why not MIN_CUT)
KNOWN_GAPS = {
    ("dynamic_inflow", "pdot_rad_s2"): (
        -0.1, "the catalogue lags the mean inflow only; the truth's Pitt-Peters harmonics "
              "(lambda_c, lambda_s, ~10 ms) change the rotor's roll/pitch response"),
    ("dynamic_inflow", "qdot_rad_s2"): (
        -0.1, "as pdot: no inflow-harmonic dynamics in the catalogue"),
    ("recirculation", "pdot_rad_s2"): (
        0.45, "the catalogue's upstream gradient is a fixed share of the mean rise; the "
              "ground vortex's gradient changes with the vortex's place (airspeed)"),
    ("recirculation", "qdot_rad_s2"): (
        0.45, "as pdot: the vortex-position dependent inflow gradient"),
}


def rms(an) -> np.ndarray:
    return np.sqrt(np.mean(an.residual_band[an.mask] ** 2, 0))


@pytest.mark.parametrize("scenario", sorted(HIDDEN))
def test_diagnose_ranks_the_matching_effect_first_and_adding_it_cuts_the_error(
        scenario, flights, baseline):
    ft = flights(scenario)
    before_an = analysed(baseline, ft)
    d = diagnose(baseline, ft, sindy=False, refine_top=3, analysis=before_an)
    expected = HIDDEN[scenario]
    assert d.top(1) == [expected], f"{scenario}: ranked {d.top(3)}"
    assert d.result(expected).significant
    after = rms(analysed(add_effect(baseline, expected, ft, analysis=before_an).model, ft))
    before = rms(before_an)
    floor = noise_floor(before_an)
    affected = before > AFFECTED * floor
    assert affected.any(), f"{scenario}: no residual above {AFFECTED}x the floor"
    for (name, channel), _ in KNOWN_GAPS.items():
        if name == scenario:  # a gap entry for a channel the flight does not affect is stale
            assert affected[MEAS_CHANNELS.index(channel)], (scenario, channel)
    for j, c in enumerate(MEAS_CHANNELS):
        cut = 1.0 - after[j] / before[j]
        where_ = f"{scenario} {c}: {before[j]:.4g} -> {after[j]:.4g} (floor {floor[j]:.4g})"
        assert after[j] <= MAX_WORSE * before[j], where_
        if affected[j]:
            need = KNOWN_GAPS.get((scenario, c), (MIN_CUT, ""))[0]
            assert cut >= need, where_


USER_GROUND_EFFECT = '''
import numpy as np
from airwake.heli import Effect, Parameter, register_effect


@register_effect("ground_effect_user")
class GroundEffectUser(Effect):
    """A user's ground effect: lambda_0 <- lambda_0 / (1 + b (R/z)^2 exp(-(V z/(V_f R))^2)),
    an image-like (R/z)^2 law that fades in forward flight with how far aft the skewed
    wake lands, V z (V the in-plane air speed at the hub, z the hub height, >= R/2)."""

    PARAMETERS = (Parameter("b", 0.0, "-", (-0.5, 2.0), "fitted"),
                  Parameter("fade_speed_m_s", 3.0, "m/s", (0.3, 20.0), "fitted"))
    REQUIRES = ("main_rotor", "pitt_peters_inflow")

    def inflow(self, ctx, p):
        radius = np.asarray(ctx.tip_speed_m_s) / np.asarray(ctx.rotor_speed_rad_s)
        z = np.maximum(np.nan_to_num(np.asarray(ctx.height_agl_m, float), posinf=1e9),
                       0.5 * radius)
        v = np.hypot(*np.asarray(ctx.hub_air_velocity_m_s)[:, :2].T)
        fade = np.exp(-(v * z / (p.fade_speed_m_s * radius)) ** 2)
        ctx.inflow_0 = ctx.inflow_0 / (1.0 + p.b * (radius / z) ** 2 * fade)
'''


def test_after_the_ground_effect_the_rest_shows_at_speed_and_a_user_plugin_closes_it(
        flights, baseline, tmp_path):
    # the catalogue's image model fades with the wake skew as 1/(1 + (mu/lambda)^2); the
    # truth's ground effect leaves with the wake's footprint, faster near the ground:
    # what remains after adding it is a thrust over-prediction in the low passes
    ft = flights("ground_effect")
    with_ge = add_effect(baseline, "ground_effect", ft).model
    an = analysed(with_ge, ft)
    report = where.summary(where.breakdown(an, tests=False))
    speed = report["regimes"]["airspeed_m_s"]["bins"]
    worst = max(speed, key=lambda b: abs(b["mean"]["acc_z_m_s2"]))
    assert worst is speed[-1] and worst["lo"] > 1.0, worst  # the fastest bin
    assert worst["mean"]["acc_z_m_s2"] > 3 * noise_floor(an)[2]  # less thrust than modelled
    plugin = tmp_path / "ground_effect_user.py"
    plugin.write_text(USER_GROUND_EFFECT)
    res = add_effect(with_ge, "ground_effect_user", ft, plugin=plugin,
                     retune=["ground_effect.strength"])
    after = analysed(res.model, ft)
    # "what remains": the excess of the residual's variance over the floor's
    excess_before = rms(an)[2] ** 2 - noise_floor(an)[2] ** 2
    excess_after = rms(after)[2] ** 2 - noise_floor(after)[2] ** 2
    assert excess_after < 0.5 * excess_before, (excess_before, excess_after)
    # the other channels: no more than 10 % worse, or still within 1.5x their floor (the
    # refitted thrust moves pdot a little, ~1.0x -> 1.2x its floor)
    ok = (rms(after) <= MAX_WORSE * rms(an)) | (rms(after) <= 1.5 * noise_floor(after))
    assert ok.all(), (rms(an), rms(after), noise_floor(after))


def test_two_hidden_effects_are_both_in_the_top_three_and_adding_both_cuts_the_error(
        flights, baseline):
    ft = flights("two_effects")
    before_an = analysed(baseline, ft)
    d = diagnose(baseline, ft, sindy=False, refine_top=4, analysis=before_an)
    assert {"servo_lag", "imu_lever_arm"} <= set(d.top(3)), d.top(3)
    model = baseline
    for name in ("servo_lag", "imu_lever_arm"):
        model = add_effect(model, name, ft).model
    before, after = rms(before_an), rms(analysed(model, ft))
    affected = before > AFFECTED * noise_floor(before_an)
    assert affected.any()
    assert np.all(after <= MAX_WORSE * before)
    # at least half: the servos' second-order dynamics and delay, which the catalogue's
    # first-order lag cannot represent, keep ~1/3 of their residual (servo_lag scenario)
    assert np.all(after[affected] <= 0.5 * before[affected])


def test_clean_still_air_flight_with_a_calibrated_model_raises_no_false_alarm(
        flights, calibrated):
    d = diagnose(calibrated, flights("calibration"), sindy=False)
    assert d.significant() == [], [(r.name, r.decision) for r in d.ranked if r.significant]
