"""LOSA optics: peaks land where the geometry says, triangulation, saturation, exposure."""

import numpy as np
import pytest

from hil_sim.sensors.losa import MARKER_LED_DIRECTIONS, LosaConfig, LosaGeometry, LosaOptics
from hil_sim.world.kinematics import euler_to_quat, quat_to_dcm


def facing_led(quat):
    """The LED whose axis points most toward the tracker (-z in the tracker frame)."""
    axes = quat_to_dcm(quat) @ MARKER_LED_DIRECTIONS.T
    return int(np.argmin(axes[2]))


def centroid(line, half=7):
    """Sub-pixel peak: intensity-weighted mean over +-half pixels around the maximum,
    above the line's background (median: dark level + ambient light)."""
    sig = line.astype(float) - np.median(line)
    p = int(np.argmax(sig))
    idx = np.arange(max(p - half, 0), min(p + half + 1, line.size))
    w = np.clip(sig[idx], 0, None)
    return float(np.sum(w * idx) / np.sum(w))


@pytest.fixture(scope="module")
def optics():
    return LosaOptics(rng=np.random.default_rng(42))


POSES = [
    ((0.0, 0.0, 2.0), (0.0, 0.0, 0.0)),
    ((0.25, -0.15, 2.1), (0.3, -0.2, 0.5)),
    ((-0.6, 0.3, 3.5), (-0.4, 0.5, 2.0)),
    ((1.0, 0.6, 5.4), (0.1, 0.1, -1.0)),
]


@pytest.mark.parametrize("pos,euler", POSES)
def test_noiseless_peaks_land_on_the_geometric_image_subpixel(optics, pos, euler):
    # The firmware's peak finder and the host's triangulation both rely on this.
    q = euler_to_quat(np.array(euler))
    fr = optics.frames([0.0], pos, q, facing_led(q), 1.0, exposure_s=3e-3, noise=False)
    for m in range(4):
        assert np.isfinite(fr.pixel[0, m]) and fr.slot[0, m] >= 0
        est = centroid(fr.counts[0, m])
        # ADC quantisation of a weak far peak is the only error left.
        assert est == pytest.approx(fr.pixel[0, m], abs=0.05)
        # Independent inversion: the LED lies on the plane of that pixel and slot.
        normal, offset = optics.geometry.pixel_to_plane(m, fr.pixel[0, m], fr.slot[0, m])
        assert normal @ fr.led_pos_t_m[0] == pytest.approx(offset, abs=1e-9)


def test_triangulation_of_four_planes_recovers_the_led(optics):
    q = euler_to_quat(np.array([0.2, -0.3, 0.4]))
    pos = np.array([0.3, -0.2, 2.1])
    fr = optics.frames(np.arange(50) / 320, pos, q, facing_led(q), 1.0, exposure_s=3e-3)
    exact = optics.geometry.triangulate(fr.pixel[0], fr.slot[0])
    assert np.allclose(exact, fr.led_pos_t_m[0], atol=1e-9)
    est = np.array([[centroid(fr.counts[k, m]) for m in range(4)]
                    for k in range(len(fr))])
    assert np.sqrt(np.mean((est - fr.pixel) ** 2)) < 0.1  # realistic noise, sub-pixel
    xyz = optics.geometry.triangulate(est, fr.slot)
    err = np.linalg.norm(xyz.mean(axis=0) - fr.led_pos_t_m[0])
    assert err < 0.005  # mm-level at ~2 m with a 400 mm baseline, as §3.3.3 reports


def test_ray_through_pixel_and_slot_hits_a_source_in_the_central_plane():
    g = LosaGeometry()
    src = np.array([0.2 - 0.2, 0.0, 3.0]) + np.array([-0.2, 0.0, 0.0])  # module 0 x, y=0
    pix = g.image_pixels(src)[0]  # module 0
    slot = int(np.nanargmin(np.abs(pix - g.centre_pixel)))
    origin, direction = g.pixel_to_ray(0, pix[slot], slot)
    along = (src - origin) @ direction
    assert np.allclose(origin + along * direction, src, atol=1e-9)


def test_sideways_motion_moves_the_image_to_the_next_slot():
    # Three slots one sensor-length apart: when the image leaves one edge of the array
    # it re-enters from the other through the neighbouring slot (no blind spot).
    g = LosaGeometry()
    xs = np.linspace(-1.7, 1.7, 341)  # within the +-45 deg field of view at 2 m
    pts = np.stack([xs, np.zeros_like(xs), np.full_like(xs, 2.0)], axis=-1)
    pix = g.image_pixels(pts)[:, 1, :]  # module 1, (341, 3)
    on = (pix > -0.5) & (pix < 127.5)
    assert np.all(on.sum(axis=1) >= 1)  # always seen through some slot
    slots_seen = {int(np.argmax(row)) for row in on}
    assert slots_seen == {0, 1, 2}


def test_saturation_clips_the_peak_flat_and_exposure_scales_signal(optics):
    q = euler_to_quat(np.zeros(3))
    led = facing_led(q)
    cfg = optics.config
    sat_counts = round(cfg.saturation_v / cfg.adc_full_scale_v * cfg.adc_max)
    close = optics.frames([0.0], (0.0, 0.0, 0.6), q, led, 1.0, exposure_s=3e-3, noise=False)
    line = close.counts[0, 1]
    assert line.max() == sat_counts
    assert np.sum(line == sat_counts) >= 2  # flat top: the peak shape is lost
    assert close.peak_v[0, 1] > cfg.saturation_v
    # Below saturation the signal above dark is proportional to the integration time.
    far = [optics.frames([0.0], (0.0, 0.0, 3.0), q, led, 0.5, exposure_s=e, noise=False)
           for e in (1e-3, 2e-3)]
    assert far[1].peak_v[0, 1] / far[0].peak_v[0, 1] == pytest.approx(2.0, rel=1e-9)
    assert far[1].counts.max() < sat_counts


def test_signal_falls_with_distance_squared_and_drive(optics):
    q = euler_to_quat(np.zeros(3))
    led = facing_led(q)
    near = optics.frames([0.0], (0.0, 0.0, 2.0), q, led, 1.0, noise=False).peak_v[0, 1]
    far = optics.frames([0.0], (0.0, 0.0, 4.0), q, led, 1.0, noise=False).peak_v[0, 1]
    half = optics.frames([0.0], (0.0, 0.0, 2.0), q, led, 0.5, noise=False).peak_v[0, 1]
    assert near / far == pytest.approx(4.0, rel=0.05)
    assert near / half == pytest.approx(2.0, rel=1e-9)


def test_led_facing_away_leaves_only_the_dark_level(optics):
    q = euler_to_quat(np.zeros(3))
    axes = quat_to_dcm(q) @ MARKER_LED_DIRECTIONS.T
    away = int(np.argmax(axes[2]))
    fr = optics.frames([0.0], (0.0, 0.0, 2.0), q, away, 1.0, noise=False)
    assert np.all(fr.peak_v == 0.0)
    assert fr.counts.max() - fr.counts.min() <= 1


def test_dark_frame_noise_and_adc_range(optics):
    cfg = optics.config
    fr = optics.frames(np.arange(200) / 320, (0, 0, 2.0), [1, 0, 0, 0], 0, 0.0)
    volts = fr.counts.astype(float) * cfg.adc_full_scale_v / cfg.adc_max
    temporal = volts.std(axis=0).mean()
    assert temporal == pytest.approx(cfg.read_noise_v, rel=0.35)  # + ADC quantisation
    assert fr.counts.dtype == np.uint16 and fr.counts.max() <= cfg.adc_max


def test_frame_rate_default_is_about_320_hz():
    assert LosaConfig().frame_rate_hz == pytest.approx(320.0)
    with pytest.raises(ValueError, match="exposure_s"):
        LosaConfig(exposure_s=5e-3)  # longer than a 320 Hz frame


def test_line_inputs_integrate_to_the_rendered_frame(optics):
    # The native board integrates rate x exposure itself: both paths must agree.
    q = euler_to_quat(np.array([0.1, 0.2, 0.3]))
    pos = (0.2, 0.1, 2.5)
    led = facing_led(q)
    lines = optics.line_inputs([0.0], pos, q, led, 0.8, noise=False)
    fr = optics.frames([0.0], pos, q, led, 0.8, exposure_s=optics.config.exposure_s,
                       noise=False)
    integrated = np.clip(lines.rate_counts_per_us * optics.config.exposure_s * 1e6
                         + lines.dark_counts, 0, None)
    assert np.abs(np.rint(integrated) - fr.counts).max() <= 1
    assert np.array_equal(lines.pixel, fr.pixel)
    noisy = optics.line_inputs(np.zeros(200), pos, q, led, 0.8)
    assert noisy.dark_counts.std(axis=0).mean() == pytest.approx(
        optics.config.read_noise_v / optics.config.adc_full_scale_v * 4095, rel=0.2)
