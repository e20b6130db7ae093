"""LOSA optical tracker: the marker's IR LED through three slots onto four TSL1401 arrays.

Geometry (§3.3.1.1-3.3.1.3, Fig 3.3, 3.7), tracker frame T: x right, y down, z forward
(out of the tracker face toward the scene), origin at the tracker centre.
- Four modules in a cross, baseline b between the members of a pair (280 mm retracted,
  400 mm extended, default 400 mm): module 0 at (-b/2, 0, 0) and 1 at (+b/2, 0, 0) with
  arrays along +x (the x-z pair); module 2 at (0, -b/2, 0) and 3 at (0, +b/2, 0) with
  arrays along +y (the y-z pair). Every module faces +z.
- Module frame: u along the array (pixel index grows with u), n = +z toward the scene,
  w = n x u along the slots. 128 pixels at 63.5 um pitch, active 55.5 um each, pixel
  i centred at u = (i - 63.5) * pitch.
- Slot plane at height h = 12 mm (Table 3.1) above the array; three slots parallel to w
  at u = -L, 0, +L with L = 8.0 mm (the sensor length: a source images through exactly
  one slot onto the array, no blind spots); slot width d = 0.13 mm (Table 3.1; Petzval's
  d = sqrt(2 h lambda) = 0.143 mm, eq 3.1); lambda = 850 nm.
- A source at module coordinates (u_s, n_s) images through slot j (centre s_j) at
      u_img = s_j - (u_s - s_j) * h / (n_s - h)
  (similar triangles; eq 3.3 is the same relation about each module's optic centre).
  `pixel_to_plane` inverts it: a pixel + slot defines the plane containing the slot
  line and the image line, on which the source lies; `triangulate` intersects the
  four planes.

Peak shape: the slit's diffraction pattern computed exactly with Fresnel integrals for
a point source at finite distance (Fresnel number d^2/(lambda h) ~ 1.7, between the
geometric and Fraunhofer limits, so neither a box nor a sinc^2 is right), for the
oblique ray (slit foreshortened by cos(theta), distances stretched by 1/cos(theta)),
integrated exactly over each pixel's active width (a tabulated cumulative intensity).
The pattern is symmetric about u_img.

Photometry per pixel (volts at the TSL1401 output, then the ADC):
    V = dark + DSNU + (1 + PRNU) * R * 100 * T_f * (E_led * I_fresnel * cos(theta_in)
        + E_ambient) * t_int  + shot + read noise,   clipped to [0, V_sat]
with E_led = I_led * drive * cos(phi)^m / r^2 (LED radiant intensity, its angular
pattern with the 110 deg viewing angle of §3.3.1.4, inverse square), R the responsivity
(V per uJ/cm^2), 100 converting J/m^2 to uJ/cm^2, t_int the exposure (integration time).
Saturation clips at V_sat; the ADC quantises to `adc_bits`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from airwake.tracking.losa import WIRE_PIXELS
from airwake.tracking.losa import LosaGeometry as TrackerGeometry
from airwake.tracking.losa import triangulate as triangulate_wire
from scipy.special import fresnel

from hil_sim.sensors.config import check_nonnegative, check_positive, check_range
from hil_sim.world.kinematics import quat_to_dcm

N_MODULES = 4

# Active marker: four LEDs on the faces of a PCB tetrahedron (§3.3.1.4), axes = outward
# face normals in the marker frame.
MARKER_LED_DIRECTIONS = np.array(
    [[1.0, 1.0, 1.0], [1.0, -1.0, -1.0], [-1.0, 1.0, -1.0], [-1.0, -1.0, 1.0]]
) / np.sqrt(3.0)


@dataclass(frozen=True)
class LosaGeometry(TrackerGeometry):
    """Optical geometry of the tracker (defaults from §3.3.1, Table 3.1, TSL1401CL): the
    host's tracker geometry (`airwake.tracking.losa.LosaGeometry`: baseline, slot height
    and spacing, pixels — the single source of those numbers and of the inverse geometry)
    plus the optics the forward model needs."""

    slot_width_m: float = 0.13e-3
    n_slots: int = 3
    pixel_active_m: float = 55.5e-6
    wavelength_m: float = 850e-9
    cross_fov_deg: float = 60.0  # half-angle along the slots (slot length limit)

    def __post_init__(self) -> None:
        for name in ("baseline_m", "focal_height_m", "slot_width_m", "slot_spacing_m",
                     "pixel_pitch_m", "pixel_active_m", "wavelength_m"):
            check_positive(name, getattr(self, name))
        if not (isinstance(self.n_slots, int) and self.n_slots >= 1 and self.n_slots % 2 == 1):
            raise ValueError(f"n_slots = {self.n_slots!r}: must be an odd integer >= 1")
        if not (isinstance(self.n_pixels, int) and self.n_pixels >= 8):
            raise ValueError(f"n_pixels = {self.n_pixels!r}: must be an integer >= 8")
        if self.pixel_active_m > self.pixel_pitch_m:
            raise ValueError(f"pixel_active_m = {self.pixel_active_m!r}: exceeds the pitch")
        check_range("cross_fov_deg", self.cross_fov_deg, 1.0, 89.0)

    def slot_centres_m(self) -> np.ndarray:
        """(n_slots,) slot positions along u, index 0 at the most negative u."""
        half = (self.n_slots - 1) // 2
        return (np.arange(self.n_slots) - half) * self.slot_spacing_m

    @property
    def centre_pixel(self) -> float:
        return (self.n_pixels - 1) / 2.0

    def u_to_pixel(self, u_m: np.ndarray) -> np.ndarray:
        return np.asarray(u_m) / self.pixel_pitch_m + self.centre_pixel

    # -- forward geometry ----------------------------------------------------

    def to_module(self, points_t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Tracker-frame points (..., 3) -> module coordinates (u, n, w), each (..., 4)."""
        centre, u, n, w = self.module_frames()
        rel = np.asarray(points_t, dtype=float)[..., None, :] - centre
        return (np.einsum("...mk,mk->...m", rel, u), np.einsum("...mk,mk->...m", rel, n),
                np.einsum("...mk,mk->...m", rel, w))

    def image_pixels(self, points_t: np.ndarray) -> np.ndarray:
        """Continuous pixel coordinate of each slot's image, (..., 4, n_slots).

        NaN where the source is not in front of the slot plane or outside the slots'
        length (cross field of view). Values outside [-0.5, n_pixels - 0.5] are off
        the array.
        """
        us, ns, ws = self.to_module(points_t)
        h = self.focal_height_m
        s = self.slot_centres_m()
        depth = ns - h
        valid = (depth > 1e-6) & (np.abs(ws) < np.tan(np.radians(self.cross_fov_deg)) * ns)
        safe = np.where(valid, depth, 1.0)
        u_img = s - (us[..., None] - s) * h / safe[..., None]
        pix = self.u_to_pixel(u_img)
        return np.where(valid[..., None], pix, np.nan)

    # -- inverse geometry ----------------------------------------------------

    def wire_slot(self, slot_index: np.ndarray | int) -> np.ndarray:
        """Simulator slot index (0 at the most negative u) -> wire slot (-1/0/+1 at
        u = -slot * spacing, as `losa_peaks` and the host's triangulation number them)."""
        return (self.n_slots - 1) // 2 - np.asarray(slot_index)

    def pixel_to_plane(self, module: np.ndarray | int, pixel: np.ndarray | float,
                       slot: np.ndarray | int) -> tuple[np.ndarray, np.ndarray]:
        """The plane a source imaged at `pixel` through slot index `slot` of `module`
        lies on: (unit normal (..., 3), offset (...)), `normal @ x == offset`."""
        return self.slot_plane(module, pixel, self.wire_slot(slot))

    def pixel_to_ray(self, module: np.ndarray | int, pixel: np.ndarray | float,
                     slot: np.ndarray | int) -> tuple[np.ndarray, np.ndarray]:
        """Ray in the module's central plane (w = 0): (origin on the array (..., 3),
        unit direction through the slot toward the scene (..., 3))."""
        centre, u, n, _ = self.module_frames()
        m = np.asarray(module)
        slot_point = (centre[m] + self.slot_centres_m()[np.asarray(slot)][..., None] * u[m]
                      + self.focal_height_m * n[m])
        origin = centre[m] + self.pixel_to_u(pixel)[..., None] * u[m]
        d = slot_point - origin
        return origin, d / np.linalg.norm(d, axis=-1, keepdims=True)

    def triangulate(self, pixels: np.ndarray, slots: np.ndarray) -> np.ndarray:
        """Least-squares intersection of the four modules' planes (the host's
        triangulation), (..., 4) raw pixels + slot indexes -> (..., 3); NaN pixels (no
        peak) are left out, at least three planes are needed (else NaN)."""
        pixels = np.asarray(pixels, dtype=float)
        wire = self.wire_slot(np.clip(slots, 0, self.n_slots - 1))
        pos, _ = triangulate_wire(pixels + WIRE_PIXELS * wire, wire, np.isfinite(pixels),
                                  geometry=self)
        return pos


@dataclass(frozen=True)
class LosaConfig:
    """Tracker optics, LED photometry and the TSL1401 + ADC signal chain."""

    geometry: LosaGeometry = field(default_factory=LosaGeometry)
    frame_rate_hz: float = 320.0  # §3.3: ~320 Hz
    exposure_s: float = 2.0e-3  # default integration time (per-frame override)
    led_max_intensity_w_sr: float = 0.7  # high-power 850 nm LED at full current
    led_half_angle_deg: float = 55.0  # 110 deg viewing angle (50 % intensity)
    led_radius_m: float = 0.02  # LED centres from the marker centre
    filter_transmission: float = 0.9  # 850 nm IR-pass filter
    responsivity_v_per_uj_cm2: float = 19.0  # TSL1401: 25 at 640 nm, ~0.75 of it at 850 nm
    saturation_v: float = 3.0  # output swing at VDD = 3.3 V
    dark_offset_v: float = 0.05
    dark_current_v_per_s: float = 2.0
    dsnu_v: float = 0.004  # pixel-to-pixel dark offset spread (1 sigma)
    prnu: float = 0.02  # pixel-to-pixel gain spread (1 sigma)
    read_noise_v: float = 0.001
    conversion_gain_v_per_e: float = 1.0e-5  # shot noise: sigma = sqrt(V * gain)
    ambient_irradiance_w_m2: float = 0.005  # IR background through the filter
    adc_bits: int = 12
    adc_full_scale_v: float = 3.3
    window_px: int = 7  # pattern computed within +-window of each image

    def __post_init__(self) -> None:
        for name in ("frame_rate_hz", "exposure_s", "led_max_intensity_w_sr", "led_half_angle_deg",
                     "responsivity_v_per_uj_cm2", "saturation_v", "adc_full_scale_v",
                     "conversion_gain_v_per_e"):
            check_positive(name, getattr(self, name))
        for name in ("led_radius_m", "dark_offset_v", "dark_current_v_per_s", "dsnu_v", "prnu",
                     "read_noise_v", "ambient_irradiance_w_m2"):
            check_nonnegative(name, getattr(self, name))
        check_range("filter_transmission", self.filter_transmission, 0.0, 1.0)
        check_range("led_half_angle_deg", self.led_half_angle_deg, 1.0, 89.0)
        if self.exposure_s >= 1.0 / self.frame_rate_hz:
            raise ValueError(f"exposure_s = {self.exposure_s!r}: longer than a frame")
        for name in ("adc_bits", "window_px"):
            v = getattr(self, name)
            if not (isinstance(v, int) and v >= 1):
                raise ValueError(f"{name} = {v!r}: must be an integer >= 1")

    @property
    def adc_max(self) -> int:
        return (1 << self.adc_bits) - 1


@dataclass(frozen=True, eq=False)
class LosaFrames:
    """K frames. `counts` (K, 4, n_pixels) uint16 ADC lines (the TSL1401 read-out);
    `t_s` (K,) end of each integration; `exposure_s` (K,); truth: `pixel` (K, 4)
    continuous pixel coordinate of the image that lands on each array (NaN if none),
    `slot` (K, 4) its slot index (-1 if none), `peak_v` (K, 4) its noiseless peak
    signal above the dark level, `led_pos_t_m` (K, 3) the lit LED in the tracker frame."""

    t_s: np.ndarray
    exposure_s: np.ndarray
    counts: np.ndarray
    pixel: np.ndarray
    slot: np.ndarray
    peak_v: np.ndarray
    led_pos_t_m: np.ndarray

    def __len__(self) -> int:
        return self.t_s.size


@dataclass(frozen=True, eq=False)
class LosaLineInputs:
    """K lines per array for the native TSL1401 model: `rate_counts_per_us` (K, 4, 128)
    ADC counts per us of integration, `dark_counts` (K, 4, 128) (both float32, as the
    sim channel's LINE record carries them); truth as in
    `LosaFrames` (`pixel`, `slot`, `led_pos_t_m`)."""

    t_s: np.ndarray
    rate_counts_per_us: np.ndarray
    dark_counts: np.ndarray
    pixel: np.ndarray
    slot: np.ndarray
    led_pos_t_m: np.ndarray


@dataclass(frozen=True, eq=False)
class _Irradiance:
    t_s: np.ndarray
    volts_per_s: np.ndarray  # (K, 4, n) light signal rate incl. ambient, before PRNU
    pixel: np.ndarray
    slot: np.ndarray
    peak_v_per_s: np.ndarray
    led_pos_t_m: np.ndarray


_UJ_CM2_PER_J_M2 = 100.0  # 1 J/m^2 = 100 uJ/cm^2


class LosaOptics:
    """Renders TSL1401 lines for given marker poses; stateless apart from the per-pixel
    fixed-pattern noise drawn once at construction (a property of the hardware)."""

    def __init__(self, config: LosaConfig | None = None, *, rng: np.random.Generator) -> None:
        self.config = config or LosaConfig()
        self.rng = rng
        n = self.config.geometry.n_pixels
        self.pixel_gain = 1.0 + self.config.prnu * rng.standard_normal((N_MODULES, n))
        self.pixel_dark_v = self.config.dsnu_v * rng.standard_normal((N_MODULES, n))

    @property
    def geometry(self) -> LosaGeometry:
        return self.config.geometry

    def led_pose(self, marker_pos_t_m: np.ndarray, marker_quat_wxyz: np.ndarray,
                 led_index: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(position (K, 3), axis (K, 3)) of the lit LED in the tracker frame.

        `marker_quat_wxyz` (K, 4) rotates marker-frame vectors into the tracker frame.
        """
        r = quat_to_dcm(np.atleast_2d(marker_quat_wxyz))
        d = MARKER_LED_DIRECTIONS[np.asarray(led_index, dtype=int)]
        axis = np.einsum("kij,kj->ki", r, np.atleast_2d(d))
        return np.atleast_2d(marker_pos_t_m) + self.config.led_radius_m * axis, axis

    def frames(
        self,
        t_s: np.ndarray,
        marker_pos_t_m: np.ndarray,
        marker_quat_wxyz: np.ndarray,
        led_index: np.ndarray | int,
        led_drive: np.ndarray | float,
        exposure_s: np.ndarray | float | None = None,
        noise: bool = True,
    ) -> LosaFrames:
        """Render K frames. Inputs per frame: marker centre (K, 3) and attitude (K, 4) in
        the tracker frame, lit LED index 0..3 (K,), drive 0..1 (K,) (fraction of full
        current; 0 = dark frame), exposure (K,) s. `noise=False` gives the noiseless
        signal chain (no shot/read noise, no fixed-pattern noise) for geometry tests."""
        c = self.config
        lit = self._irradiance(t_s, marker_pos_t_m, marker_quat_wxyz, led_index, led_drive)
        k = lit.t_s.size
        expo = np.broadcast_to(np.asarray(c.exposure_s if exposure_s is None else exposure_s,
                                          dtype=float), (k,))
        # float32 for the (K, 4, 128) pixel arrays: 4x fewer bytes than the noise needs.
        f32 = np.float32
        light_v = lit.volts_per_s.astype(f32) * expo.astype(f32)[:, None, None]
        dark_v = (c.dark_offset_v + c.dark_current_v_per_s * expo).astype(f32)[:, None, None]
        if noise:
            light_v *= self.pixel_gain.astype(f32)
            # shot (sqrt(V * gain)) and read noise add in quadrature
            sigma = np.sqrt(np.maximum(light_v, 0) * f32(c.conversion_gain_v_per_e)
                            + f32(c.read_noise_v**2))
            volts = self.rng.standard_normal(light_v.shape, dtype=f32)
            volts *= sigma
            volts += light_v
            volts += dark_v + self.pixel_dark_v.astype(f32)
        else:
            volts = dark_v + light_v
        np.clip(volts, 0, f32(c.saturation_v), out=volts)
        volts *= f32(c.adc_max / c.adc_full_scale_v)
        counts = np.minimum(np.rint(volts), c.adc_max)
        return LosaFrames(
            t_s=lit.t_s,
            exposure_s=np.array(expo),
            counts=counts.astype(np.uint16),
            pixel=lit.pixel,
            slot=lit.slot,
            peak_v=lit.peak_v_per_s * expo[:, None],
            led_pos_t_m=lit.led_pos_t_m,
        )

    def line_inputs(
        self,
        t_s: np.ndarray,
        marker_pos_t_m: np.ndarray,
        marker_quat_wxyz: np.ndarray,
        led_index: np.ndarray | int,
        led_drive: np.ndarray | float,
        noise: bool = True,
    ) -> LosaLineInputs:
        """Per-pixel irradiance for the native board's TSL1401 model (the sim channel's
        LINE record): `rate` in ADC counts per us of integration and `dark` in counts.

        The board integrates `rate` over the exposure it chooses, adds `dark` and
        saturates, so exposure control and saturation stay the firmware's business.
        With `noise`, PRNU scales `rate`, shot noise for the nominal `exposure_s` is
        folded into `rate`, and DSNU + read noise (fresh per line) into `dark`.
        """
        c = self.config
        lit = self._irradiance(t_s, marker_pos_t_m, marker_quat_wxyz, led_index, led_drive)
        f32 = np.float32
        volts_to_counts = f32(c.adc_max / c.adc_full_scale_v)
        rate_v_s = lit.volts_per_s.astype(f32)
        expo = c.exposure_s
        dark_v = np.full(rate_v_s.shape, c.dark_offset_v + c.dark_current_v_per_s * expo,
                         dtype=f32)
        if noise:
            rate_v_s *= self.pixel_gain.astype(f32)
            # shot noise of the nominal exposure, as a rate: sqrt(rate t g) / t
            shot = np.sqrt(np.maximum(rate_v_s, 0) * f32(c.conversion_gain_v_per_e / expo))
            shot *= self.rng.standard_normal(rate_v_s.shape, dtype=f32)
            rate_v_s += shot
            read = self.rng.standard_normal(dark_v.shape, dtype=f32)
            read *= f32(c.read_noise_v)
            dark_v += self.pixel_dark_v.astype(f32) + read
        return LosaLineInputs(
            t_s=lit.t_s,
            rate_counts_per_us=rate_v_s * (f32(1e-6) * volts_to_counts),
            dark_counts=dark_v * volts_to_counts,
            pixel=lit.pixel,
            slot=lit.slot,
            led_pos_t_m=lit.led_pos_t_m,
        )

    def _irradiance(self, t_s, marker_pos_t_m, marker_quat_wxyz, led_index, led_drive
                    ) -> _Irradiance:
        """Noiseless light signal (V/s per pixel, before PRNU) and the geometric truth."""
        c = self.config
        g = c.geometry
        t = np.atleast_1d(np.asarray(t_s, dtype=float))
        k = t.size
        led_index = np.broadcast_to(np.asarray(led_index, dtype=int), (k,))
        drive = np.clip(np.broadcast_to(np.asarray(led_drive, dtype=float), (k,)), 0.0, 1.0)
        led_pos, led_axis = self.led_pose(np.broadcast_to(marker_pos_t_m, (k, 3)),
                                          np.broadcast_to(marker_quat_wxyz, (k, 4)), led_index)

        pix = g.image_pixels(led_pos)  # (K, 4, S)
        signal = np.zeros((k, N_MODULES, g.n_pixels))
        on_array = (pix > -0.5) & (pix < g.n_pixels - 0.5)
        truth_pix = np.where(on_array, pix, np.nan)
        # By design at most one slot lands on an array; at the seams keep the nearer.
        dist = np.where(on_array, np.abs(pix - g.centre_pixel), np.inf)
        best = np.argmin(dist, axis=-1)
        any_on = np.isfinite(np.min(dist, axis=-1))
        pixel_truth = np.where(any_on, np.take_along_axis(truth_pix, best[..., None], -1)[..., 0],
                               np.nan)
        slot_truth = np.where(any_on, best, -1)

        amp = self._led_signal_v_per_s(led_pos, led_axis, drive)  # (K, 4, S)
        near = np.isfinite(pix) & (pix > -0.5 - c.window_px) & (pix < g.n_pixels - 0.5
                                                                 + c.window_px)
        near &= amp > 0
        kk, mm, ss = np.nonzero(near)
        peak = np.zeros((k, N_MODULES))
        if kk.size:
            line = self._pattern(led_pos[kk], mm, ss, pix[kk, mm, ss])  # (P, W) intensities
            centre_px = np.rint(pix[kk, mm, ss]).astype(int)
            cols = centre_px[:, None] + np.arange(-c.window_px, c.window_px + 1)
            weights = line * amp[kk, mm, ss][:, None]
            inside = (cols >= 0) & (cols < g.n_pixels)
            flat = ((kk * N_MODULES + mm)[:, None] * g.n_pixels + cols)[inside]
            signal += np.bincount(flat, weights=weights[inside],
                                  minlength=k * N_MODULES * g.n_pixels).reshape(signal.shape)
            lands = any_on[kk, mm] & (ss == best[kk, mm])
            peak[kk[lands], mm[lands]] = weights[lands].max(axis=1)
        ambient = (c.responsivity_v_per_uj_cm2 * _UJ_CM2_PER_J_M2 * c.filter_transmission
                   * c.ambient_irradiance_w_m2)
        return _Irradiance(t, signal + ambient, pixel_truth, slot_truth.astype(np.int64), peak,
                           led_pos)

    def _led_signal_v_per_s(self, led_pos: np.ndarray, led_axis: np.ndarray, drive: np.ndarray
                            ) -> np.ndarray:
        """Volts per second of integration per unit Fresnel intensity, (K, 4, S)."""
        c = self.config
        g = c.geometry
        centre, u, n, _ = g.module_frames()
        slots = (centre[:, None, :] + g.slot_centres_m()[None, :, None] * u[:, None, :]
                 + g.focal_height_m * n[:, None, :])  # (4, S, 3)
        ray = slots[None] - led_pos[:, None, None, :]  # LED -> slot, (K, 4, S, 3)
        r2 = np.sum(ray * ray, axis=-1)
        r = np.sqrt(r2)
        cos_led = np.einsum("kmsi,ki->kms", ray, led_axis) / r
        m_exp = np.log(0.5) / np.log(np.cos(np.radians(c.led_half_angle_deg)))
        pattern = np.where(cos_led > 0, np.maximum(cos_led, 0.0) ** m_exp, 0.0)
        cos_in = np.einsum("kmsi,mi->kms", -ray, n) / r  # incidence on the array
        irradiance = (c.led_max_intensity_w_sr * drive[:, None, None] * pattern / r2
                      * np.maximum(cos_in, 0.0))
        return (c.responsivity_v_per_uj_cm2 * _UJ_CM2_PER_J_M2 * c.filter_transmission
                * irradiance)

    def _pattern(self, led_pos: np.ndarray, module: np.ndarray, slot: np.ndarray,
                 pix_img: np.ndarray) -> np.ndarray:
        """Pixel-averaged Fresnel slit intensity (1 = unobstructed) on the window around
        each image, (P, 2 * window + 1).

        With xi = a (x - u_img) the slit's field is
        C(b - xi) + C(b + xi) + i (S(b - xi) + S(b + xi)), a = scale z1 / n_s,
        b = scale d / 2, scale = cos(theta)^1.5 sqrt(2 n_s / (lambda z1 h)) (source at
        distance z1 from the slot plane along the ray, screen h behind it). A pixel's
        average is a difference of the tabulated cumulative intensity (exact
        integration over its active width, no quadrature points).
        """
        c = self.config
        g = c.geometry
        centre, u, n, _ = g.module_frames()
        rel = led_pos - centre[module]
        us = np.einsum("pk,pk->p", rel, u[module])
        ns = np.einsum("pk,pk->p", rel, n[module])
        h = g.focal_height_m
        s = g.slot_centres_m()[slot]
        z1 = ns - h
        cos_t = 1.0 / np.sqrt(1.0 + ((us - s) / z1) ** 2)
        scale = cos_t**1.5 * np.sqrt(2.0 * ns / (g.wavelength_m * z1 * h))
        a = scale * z1 / ns
        b = scale * g.slot_width_m / 2
        u_img = g.pixel_to_u(pix_img)
        cols = np.rint(pix_img).astype(int)[:, None] + np.arange(-c.window_px, c.window_px + 1)
        offset = g.pixel_to_u(cols) - u_img[:, None]  # pixel centre - image centre, m
        half = g.pixel_active_m / 2
        xi_lo = (offset - half) * a[:, None]
        xi_hi = (offset + half) * a[:, None]
        table = _slit_table()
        if table.covers(b):
            return (table.cumulative(xi_hi, b) - table.cumulative(xi_lo, b)) / (xi_hi - xi_lo)
        # Outside the table (unusual slot widths / extreme angles): quadrature.
        q = (np.arange(8) + 0.5) / 8
        xi = xi_lo[..., None] + (xi_hi - xi_lo)[..., None] * q
        return _slit_intensity(xi, b[:, None, None]).mean(axis=-1)


def _slit_intensity(xi: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Normalised Fresnel intensity behind a slit (1 = unobstructed), broadcast."""
    s1, c1 = fresnel(b - xi)
    s2, c2 = fresnel(b + xi)
    return 0.5 * ((c1 + c2) ** 2 + (s1 + s2) ** 2)


class _SlitTable:
    """G(xi, b) = integral of the slit intensity from -XI to xi, on a grid; bilinear."""

    XI = 12.0
    D_XI = 0.004
    B0, B1, D_B = 0.2, 1.6, 0.01

    def __init__(self) -> None:
        self.xi = np.arange(-self.XI, self.XI + self.D_XI / 2, self.D_XI)
        self.b = np.arange(self.B0, self.B1 + self.D_B / 2, self.D_B)
        f = _slit_intensity(self.xi[None, :], self.b[:, None])
        g = np.concatenate([np.zeros((self.b.size, 1)),
                            np.cumsum(0.5 * (f[:, 1:] + f[:, :-1]) * self.D_XI, axis=1)], axis=1)
        self.flat = g.ravel()
        self.n_xi = self.xi.size

    def covers(self, b: np.ndarray) -> bool:
        return bool(np.all((b >= self.B0) & (b <= self.B1 - self.D_B)))

    def cumulative(self, xi: np.ndarray, b: np.ndarray) -> np.ndarray:
        """G at (P, W) xi and per-row b (P,)."""
        fi = (np.clip(xi, -self.XI, self.XI - self.D_XI) + self.XI) / self.D_XI
        i0 = np.floor(fi)
        wi = fi - i0
        i0 = i0.astype(np.int64)
        fj = (b - self.B0) / self.D_B
        j0 = np.floor(fj)
        wj = (fj - j0)[:, None]
        row = (j0.astype(np.int64) * self.n_xi)[:, None]
        t = self.flat
        g0 = t[row + i0] * (1.0 - wi) + t[row + i0 + 1] * wi
        g1 = t[row + self.n_xi + i0] * (1.0 - wi) + t[row + self.n_xi + i0 + 1] * wi
        return g0 * (1.0 - wj) + g1 * wj


_TABLE: list[_SlitTable] = []


def _slit_table() -> _SlitTable:
    if not _TABLE:
        _TABLE.append(_SlitTable())
    return _TABLE[0]
