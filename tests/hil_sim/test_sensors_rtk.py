"""Simulated Piksi RTK: baseline, fix status and SBP frames (decoded with `sbp`)."""

import numpy as np
import pytest
from sbp.msg import SBP
from sbp.navigation import (
    SBP_MSG_BASELINE_NED,
    SBP_MSG_GPS_TIME,
    SBP_MSG_POS_LLH,
    SBP_MSG_VEL_NED,
)
from sbp.table import dispatch

from hil_sim.sensors.geodesy import lla_to_ned, ned_to_lla
from hil_sim.sensors.rtk import RtkConfig, RtkReceiver
from hil_sim.world import kinematics as k
from hil_sim.world.ship import Ship, ShipConfig


def split_sbp(data: bytes) -> list:
    """Decode every SBP frame (CRC checked by sbp.msg.SBP.unpack)."""
    out, i = [], 0
    while i < len(data):
        assert data[i] == 0x55
        length = data[i + 5]
        frame = data[i : i + 8 + length]
        out.append(dispatch(SBP.unpack(frame)))
        i += 8 + length
    return out


@pytest.fixture(scope="module")
def ship_flight():
    ship = Ship(ShipConfig(speed_m_s=2.0, heading_deg=30.0))
    heli = k.circle(30.0, radius_m=6.0, speed_m_s=2.0, rate_hz=200.0,
                    center_ned_m=(-10.0, 0.0, -6.0))
    base = ship.trajectory(heli.t_s).at_point([-1.0, 0.0, -1.0])
    cfg = RtkConfig(fix_schedule=((0.0, "spp"), (5.0, "float"), (12.0, "fixed")))
    rx = RtkReceiver(cfg, rng=np.random.default_rng(5))
    samples = rx.measure(heli, base)
    return heli, base, rx, samples


def test_rate_10_hz_and_gps_time_steps_100_ms(ship_flight):
    *_, samples = ship_flight
    assert np.allclose(np.diff(samples.t_s), 0.1)
    assert np.all(np.diff(samples.tow_ms) == 100)


def test_fix_schedule_transitions_and_baseline_only_in_rtk_modes(ship_flight):
    *_, samples = ship_flight
    t = samples.t_s
    assert np.all(samples.fix_mode[t < 5.0] == 1)
    assert np.all(samples.fix_mode[(t >= 5.0) & (t < 12.0)] == 3)
    assert np.all(samples.fix_mode[t >= 12.0] == 4)
    assert np.all(np.isnan(samples.baseline_ned_m[t < 5.0]))
    assert np.all(np.isfinite(samples.baseline_ned_m[t >= 5.0]))


def test_baseline_is_rover_minus_base_with_cm_noise_when_fixed(ship_flight):
    heli, base, _, samples = ship_flight
    fixed = samples.fix_mode == 4
    truth = heli.at(samples.t_s).pos_ned_m - base.at(samples.t_s).pos_ned_m
    err = samples.baseline_ned_m[fixed] - truth[fixed]
    assert np.abs(err).max() < 0.08
    assert np.sqrt(np.mean(err[:, 2] ** 2)) < 0.04


def test_noise_level_per_mode_matches_config():
    tr = k.hover(600.0, 50.0)
    base = k.hover(600.0, 50.0, pos_ned_m=(5.0, 0.0, -1.0))
    for mode, sigma in (("fixed", 0.010), ("float", 0.15)):
        rx = RtkReceiver(RtkConfig(fix_schedule=((0.0, mode),)), rng=np.random.default_rng(9))
        s = rx.measure(tr, base)
        err = s.baseline_ned_m - (tr.at(s.t_s).pos_ned_m - base.at(s.t_s).pos_ned_m)
        assert err[:, 0].std() == pytest.approx(sigma, rel=0.35)


def test_sbp_frames_decode_to_the_measured_values(ship_flight):
    *_, rx, samples = ship_flight
    stream = rx.stream(samples)
    assert len(stream) == len(samples)
    for i in (0, 80, len(samples) - 1):
        msgs = split_sbp(stream.chunk(i))
        by_type = {m.msg_type: m for m in msgs}
        assert msgs[0].msg_type == SBP_MSG_GPS_TIME
        assert by_type[SBP_MSG_GPS_TIME].tow == samples.tow_ms[i]
        llh = by_type[SBP_MSG_POS_LLH]
        assert llh.sender == rx.config.sender_id
        assert (llh.lat, llh.lon, llh.height) == pytest.approx(tuple(samples.lla[i]), abs=1e-9)
        assert llh.flags & 0x7 == samples.fix_mode[i]
        vel = by_type[SBP_MSG_VEL_NED]
        assert vel.n == round(samples.vel_ned_m_s[i, 0] * 1000)
        if samples.fix_mode[i] >= 2:
            b = by_type[SBP_MSG_BASELINE_NED]
            assert (b.n, b.e, b.d) == tuple(int(round(v * 1000)) for v in samples.baseline_ned_m[i])
            assert b.flags == samples.fix_mode[i] and b.n_sats == samples.n_sats[i]
        else:
            assert SBP_MSG_BASELINE_NED not in by_type


def test_random_dropouts_degrade_fixed_to_float():
    tr = k.hover(300.0, 20.0)
    rx = RtkReceiver(RtkConfig(dropout_rate_per_s=0.05, dropout_duration_s=4.0),
                     rng=np.random.default_rng(2))
    s = rx.measure(tr, tr)
    assert set(np.unique(s.fix_mode)) == {3, 4}
    assert 0.05 < np.mean(s.fix_mode == 3) < 0.5


def test_geodesy_round_trip_is_sub_millimetre():
    ned = np.array([[1234.5, -987.6, -12.3], [0.0, 0.0, 0.0], [-5e3, 5e3, 100.0]])
    assert np.allclose(lla_to_ned(ned_to_lla(ned)), ned, atol=1e-4)
