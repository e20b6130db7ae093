"""LOSA tracker geometry and triangulation (reference §3.3.1, §3.3.2.1, eq 3.3-3.4).

Tracker frame T: x right, y down, z forward (out of the tracker face), origin at the
tracker centre (docs/sensors.md, "LOSA optics"). Four modules in a cross, baseline b:
module 0 at (-b/2, 0, 0) and 1 at (+b/2, 0, 0) with arrays along +x, module 2 at
(0, -b/2, 0) and 3 at (0, +b/2, 0) with arrays along +y; all face +z. Per module: u along
the array, n = +z, w = n x u along the slots; pixel i is centred at
u = (i - 63.5) * pitch; the slot plane is h = 12 mm above the array, slots 8.0 mm apart.

Wire convention (`losa_peaks`): `peak_px = raw_px + 128 * slot` with `slot` in {-1, 0, +1}
and 0 the central slot; the firmware chooses the slot so that the unwrapped position
moves continuously. A source moving towards +u images through slots of increasing u
at decreasing pixels, so continuity puts wire slot `s` at the slot centre
u = -s * L (the simulator's `LosaGeometry` numbers its slots 0..2 from -u: index = 1 - s).

Eq 3.3 for one module, source at module coordinates (u_s, n_s), slot centre s_j, image
at u_img on the array:

    (u_img - s_j) / h = -(u_s - s_j) / (n_s - h)

i.e. the source lies on the plane through the slot line (u = s_j, n = h) and the image
line (u = u_img, n = 0), both along w. Eq 3.4 solves one pair in closed form; with four
modules we intersect the planes in least squares (normal equations of the 4 x 3 system
N x = d), which reduces to eq 3.4 for one pair plus the other pair's direction.

These constants belong to the host; the simulator's `hil_sim.sensors.losa.LosaGeometry`
extends this class with the optics it needs for its forward model.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

N_MODULES = 4
WIRE_PIXELS = 128  # the unwrapping period of `losa_peaks.peak_px`
SENSOR_FLAG_VALID = 0x01  # `losa_peaks.sensor_flags` bit 0
MIN_SENSORS = 3  # planes needed for a 3-D point (any three of the four are independent)
ADC_FULL_SCALE_COUNTS = 4095  # 12-bit ADC of the tracker (`marker_command.full_scale_counts`)


@dataclass(frozen=True)
class LosaGeometry:
    """Optical geometry of the tracker (defaults: §3.3.1, Table 3.1, TSL1401CL)."""

    baseline_m: float = 0.40
    focal_height_m: float = 0.012
    slot_spacing_m: float = 8.0e-3
    n_pixels: int = 128
    pixel_pitch_m: float = 63.5e-6

    def module_frames(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(centre, u, n, w) of each module in the tracker frame, each (4, 3)."""
        b = self.baseline_m / 2
        centre = np.array([[-b, 0, 0], [b, 0, 0], [0, -b, 0], [0, b, 0]], dtype=float)
        u = np.array([[1, 0, 0], [1, 0, 0], [0, 1, 0], [0, 1, 0]], dtype=float)
        n = np.tile([0.0, 0.0, 1.0], (N_MODULES, 1))
        return centre, u, n, np.cross(n, u)

    def pixel_to_u(self, pixel: np.ndarray) -> np.ndarray:
        return (np.asarray(pixel, dtype=float) - (self.n_pixels - 1) / 2.0) * self.pixel_pitch_m

    def slot_plane(self, module, raw_px, slot) -> tuple[np.ndarray, np.ndarray]:
        """Plane of a peak at `raw_px` (array pixel) seen through wire slot `slot` (-1/0/+1)
        of `module`: unit normal (..., 3) and offset (...), n.x = d. The plane holds the
        slot line and the image line (both along w)."""
        centre, u, n, w = self.module_frames()
        m = np.asarray(module)
        slot_u = -np.asarray(slot, dtype=float) * self.slot_spacing_m
        slot_point = centre[m] + slot_u[..., None] * u[m] + self.focal_height_m * n[m]
        image_point = centre[m] + self.pixel_to_u(raw_px)[..., None] * u[m]
        normal = np.cross(slot_point - image_point, w[m])
        normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
        return normal, np.einsum("...k,...k->...", normal, slot_point)

    def planes(self, peak_px: np.ndarray, slot: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Planes of wire peaks: unit normals (..., 4, 3) and offsets (..., 4), n.x = d.

        `peak_px` (..., 4) unwrapped wire positions, `slot` (..., 4) wire slots -1/0/+1.
        """
        slot = np.asarray(slot, dtype=float)
        raw_px = np.asarray(peak_px, dtype=float) - WIRE_PIXELS * slot
        return self.slot_plane(np.arange(N_MODULES), raw_px, slot)


DEFAULT_GEOMETRY = LosaGeometry()


def triangulate_one(peak_px, slot, valid, geometry: LosaGeometry = DEFAULT_GEOMETRY,
                    min_det_ratio: float = 1e-9) -> tuple[float, float, float] | None:
    """One frame, plain Python (the marker loop's 60 Hz path; numpy's per-call overhead
    on 3-vectors is ~100x the arithmetic). Same planes and least squares as `triangulate`:
    with d = slot point - image point = (s_u - u_img) u + h n and w = n x u,
    the plane normal is d x w = (s_u - u_img) n - h u. Returns None when fewer than
    MIN_SENSORS peaks are valid or det(N^T N) < min_det_ratio * (trace / 3)^3."""
    b = geometry.baseline_m / 2
    h = geometry.focal_height_m
    centre_px = (geometry.n_pixels - 1) / 2.0
    a = [[0.0] * 3 for _ in range(3)]
    r = [0.0, 0.0, 0.0]
    used = 0
    for m in range(N_MODULES):
        if not valid[m]:
            continue
        px = float(peak_px[m])
        if px != px:  # NaN
            continue
        s = float(slot[m])
        u_img = (px - WIRE_PIXELS * s - centre_px) * geometry.pixel_pitch_m
        s_u = -s * geometry.slot_spacing_m
        k = s_u - u_img
        norm = (k * k + h * h) ** 0.5
        # modules 0, 1: u = +x at (-+b, 0, 0); modules 2, 3: u = +y at (0, -+b, 0); n = +z
        if m < 2:
            nx, ny, nz = -h / norm, 0.0, k / norm
            cx, cy = (-b if m == 0 else b), 0.0
            px_, py_, pz_ = cx + s_u, cy, h
        else:
            nx, ny, nz = 0.0, -h / norm, k / norm
            cx, cy = 0.0, (-b if m == 2 else b)
            px_, py_, pz_ = cx, cy + s_u, h
        d = nx * px_ + ny * py_ + nz * pz_
        nv = (nx, ny, nz)
        for i in range(3):
            r[i] += nv[i] * d
            for j in range(3):
                a[i][j] += nv[i] * nv[j]
        used += 1
    if used < MIN_SENSORS:
        return None
    det = (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
           - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
           + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]))
    trace = a[0][0] + a[1][1] + a[2][2]
    if det <= min_det_ratio * (trace / 3.0) ** 3:
        return None
    # Cramer's rule
    out = []
    for col in range(3):
        m3 = [row[:] for row in a]
        for i in range(3):
            m3[i][col] = r[i]
        out.append((m3[0][0] * (m3[1][1] * m3[2][2] - m3[1][2] * m3[2][1])
                    - m3[0][1] * (m3[1][0] * m3[2][2] - m3[1][2] * m3[2][0])
                    + m3[0][2] * (m3[1][0] * m3[2][1] - m3[1][1] * m3[2][0])) / det)
    return out[0], out[1], out[2]


def triangulate(peak_px: np.ndarray, slot: np.ndarray, valid: np.ndarray,
                geometry: LosaGeometry = DEFAULT_GEOMETRY,
                max_condition: float = 1e6) -> tuple[np.ndarray, np.ndarray]:
    """Marker position in the tracker frame from wire peaks.

    `peak_px`, `slot` (..., 4) as in `losa_peaks`; `valid` (..., 4) bool (sensor flag bit 0
    and a finite position). Returns (pos (..., 3) m, ok (...,) bool): ok needs at least
    `MIN_SENSORS` valid planes and a well-conditioned intersection; pos is NaN where not ok.
    """
    peak_px = np.asarray(peak_px, dtype=float)
    valid = np.asarray(valid, dtype=bool) & np.isfinite(peak_px)
    normal, offset = geometry.planes(np.where(valid, peak_px, 0.0),
                                     np.where(valid, np.asarray(slot), 0))
    normal = np.where(valid[..., None], normal, 0.0)
    offset = np.where(valid, offset, 0.0)
    # Normal equations of N x = d over the valid planes.
    ata = np.einsum("...mi,...mj->...ij", normal, normal)
    atb = np.einsum("...mi,...m->...i", normal, offset)
    shape = peak_px.shape[:-1]
    ata, atb = ata.reshape(-1, 3, 3), atb.reshape(-1, 3)
    ok = (valid.sum(axis=-1) >= MIN_SENSORS).reshape(-1)
    pos = np.full((ok.size, 3), np.nan)
    if np.any(ok):
        a, b = ata[ok], atb[ok]
        good = np.linalg.cond(a) < max_condition
        sol = np.full(b.shape, np.nan)
        if np.any(good):
            sol[good] = np.linalg.solve(a[good], b[good][..., None])[..., 0]
        pos[ok] = sol
        ok[ok] = good
    return pos.reshape(shape + (3,)), ok.reshape(shape)


class SlotResolver:
    """Which slot each module's peak really came through (§3.3.1.5).

    The LOSA firmware unwraps each sensor's peak across its three slots from the central
    slot it assumes at start and after a loss (firmware/boards/losa/slots.h). A marker
    re-acquired off-centre (more than ~18 deg from a module's axis) is then unwrapped
    from the wrong slot, and the triangulated position is off by metres while every
    plane is self-consistent: the two modules of a pair shifted by the same slot keep
    their disparity, so nothing in one frame can tell. The tracking filter can: at a
    re-acquisition (`choose` given) every per-module slot correction that keeps the slots
    in -1..+1 is triangulated and the one the filter's prediction finds most likely is
    kept; the corrections then apply to every later frame (the firmware's own slot
    changes are relative) until the next re-acquisition re-evaluates them.

    After a long dropout the prediction has drifted (IMU dead reckoning: metres within
    seconds) and several corrections fit it about equally: the best is still taken, but
    the resolver is `ambiguous` (the second best within `ambiguity_nis` of the best).
    A wrong choice is then self-consistent while the marker stands still; motion tells:
    the wrong slots rotate the track by tens of degrees about the tracker, so a move the
    IMU measures does not match and the updates are gated until a re-acquisition from a
    short dropout decides clearly. The caller confirms a choice (`confirm()`) once the
    track has moved `confirm_move_m` with every update accepted by a settled filter
    (`PoseEkf.settled`: a wide covariance accepts a wrong choice's motion too;
    `run_pose_ekf`); until
    then the fused frames are not trustworthy (`record.marker_pose` leaves them out of
    `marker_valid`)."""

    def __init__(self, geometry: LosaGeometry = DEFAULT_GEOMETRY,
                 ambiguity_nis: float = 20.0, confirm_move_m: float = 0.3,
                 confirm_s: float = 1.0) -> None:
        self.geometry = geometry
        self.ambiguity_nis = float(ambiguity_nis)
        self.confirm_move_m = float(confirm_move_m)
        # and for this long: at flying speed 0.3 m takes 0.1 s, too short for the IMU to
        # tell a wrong choice's rotated track (a SIL still-air flight confirmed one 2 m off)
        self.confirm_s = float(confirm_s)
        self.ambiguous_at: np.ndarray | None = None  # the position of the open choice
        self.ambiguous_since: float | None = None  # when its count (re)started
        self.shift = (0, 0, 0, 0)
        self.resolved = 0  # re-acquisitions that changed the corrections
        self.ambiguous = False
        self.ambiguous_choices = 0  # re-acquisitions decided without a clear winner

    def candidates(self, peak_px, slot, valid) -> tuple[np.ndarray, np.ndarray]:
        """(corrections (K, 4) int, positions (K, 3)) of every correction combination
        giving a well-conditioned point in front of the tracker."""
        import itertools

        choices = []
        for m in range(N_MODULES):
            s = int(slot[m])
            choices.append(range(-1 - s, 2 - s) if valid[m] else (0,))
        shifts = np.array(list(itertools.product(*choices)), dtype=np.int64)
        k = shifts.shape[0]
        # another slot moves the unwrapped peak by a whole period: the same array pixel
        pos, ok = triangulate(np.asarray(peak_px, float) + WIRE_PIXELS * shifts,
                              np.asarray(slot, dtype=np.int64) + shifts,
                              np.broadcast_to(np.asarray(valid, bool), (k, N_MODULES)),
                              self.geometry)
        keep = ok & (pos[:, 2] > 0.0)
        return shifts[keep], pos[keep]

    def confirm(self, pos_ref_m, accepted: bool, t_s: float | None = None) -> None:
        """Track the open ambiguous choice: a rejected update restarts the count; a move
        of `confirm_move_m` from the choice's position over at least `confirm_s` (when
        the times `t_s` are given), every update accepted, confirms it."""
        if not self.ambiguous or self.ambiguous_at is None:
            return
        if self.ambiguous_since is None or not accepted:
            self.ambiguous_since = t_s
        if not accepted:
            self.ambiguous_at = np.array(pos_ref_m, dtype=float)
        elif (np.linalg.norm(np.asarray(pos_ref_m, float) - self.ambiguous_at)
              >= self.confirm_move_m and (t_s is None or self.ambiguous_since is None
                                          or t_s - self.ambiguous_since >= self.confirm_s)):
            self.ambiguous, self.ambiguous_at, self.ambiguous_since = False, None, None

    def position(self, peak_px, slot, valid, choose=None, lost: bool = False):
        """The frame's position (3,) with the kept corrections, or None; `choose` (a
        function of candidate positions (K, 3) -> cost (K,)) re-evaluates them first.
        `lost`: the filter has no prediction worth choosing with (`PoseEkf.lost`): the
        firmware's own slots are taken (it re-acquires from the central slot, right
        within ~18 deg of a module's axis) and the choice is ambiguous until confirmed."""
        if sum(bool(v) for v in valid) < MIN_SENSORS:
            return None  # no point, whatever the slots (the marker out of view: most frames)
        if lost:
            p = triangulate_one(peak_px, slot, valid, self.geometry)
            if p is None:
                return None
            if any(self.shift):
                self.shift = (0, 0, 0, 0)
                self.resolved += 1
            self.ambiguous = True
            self.ambiguous_choices += 1
            self.ambiguous_at = np.asarray(p, dtype=float)
            self.ambiguous_since = None
            return self.ambiguous_at.copy()
        if choose is not None:
            shifts, pos = self.candidates(peak_px, slot, valid)
            if shifts.shape[0] == 0:
                return None
            cost = np.asarray(choose(pos), dtype=float)
            best = int(np.argmin(cost))
            runner_up = np.partition(cost, 1)[1] if cost.size > 1 else np.inf
            ambiguous = bool(runner_up - cost[best] < self.ambiguity_nis)
            if ambiguous:
                self.ambiguous = True
                self.ambiguous_choices += 1
                self.ambiguous_at = np.array(pos[best], dtype=float)
                self.ambiguous_since = None
            elif self.ambiguous:
                # a clear decision on a doubtful track proves nothing by itself (the
                # prediction came from that track): the confirmation restarts from it
                self.ambiguous_at = np.array(pos[best], dtype=float)
                self.ambiguous_since = None
            new = tuple(int(v) for v in shifts[best])
            if new != self.shift:
                self.shift = new
                self.resolved += 1
            return pos[best]
        if not any(self.shift):
            p = triangulate_one(peak_px, slot, valid, self.geometry)
        else:
            p = triangulate_one([float(a) + WIRE_PIXELS * b for a, b in zip(peak_px, self.shift,
                                                                            strict=True)],
                                [int(a) + b for a, b in zip(slot, self.shift, strict=True)],
                                valid, self.geometry)
        return None if p is None else np.asarray(p, dtype=float)
