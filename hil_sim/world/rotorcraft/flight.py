"""One flight of the blade-element helicopter through a wind field, flown by a pilot.

    flown = fly(scenario, duration_s, rngs, field, ship, frame, knots, reference, progress)

The loop (what `hil_sim.world.run.run_scenario` calls for `[helicopter] model =
"blade_element"`):

- the field is sampled on the body-fixed grid around the aircraft (`model.GRID_*`:
  disc, flybar, tail rotor, fuselage, empennage) at `wind_rate_hz` (>= 200 Hz), and each
  element interpolates it where it is (trilinear in space, linear in time between
  snapshots). Snapshots are sampled `LOOKAHEAD_S` ahead in one batched field call, the
  grid's future poses predicted from the state at the batch start (constant velocity
  and rates; within ~1 cm over 0.1 s, well below the fields' 0.15-0.25 m turbulence
  grids). The ground/deck upwash of the image sources (inflow.ground_upwash) is
  computed for the same snapshots from whatever surface is under each part of the disc;
- the pilot decides on the RC frame grid (knots) from the state at the knot; between
  knots the command is the pilot's first-order hold, passed to the compiled integrator
  linear over each stretch between events (a snapshot or a knot);
- the integrator (dynamics.integrate) runs at the airframe's fixed step (2 kHz by
  default; `scenario.rate_hz` if higher) and records every step.

Returns the recorded states, the auxiliary outputs, the commands, and the truth columns
this truth adds (`truth_main_rotor_thrust_n`, `truth_main_rotor_power_w`,
`truth_inflow_m_s`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from hil_sim.world.kinematics import (
    euler_to_dcm,
    euler_to_quat,
    quat_from_rotvec,
    quat_multiply,
    quat_to_dcm,
)
from hil_sim.world.rotorcraft import dynamics
from hil_sim.world.rotorcraft.airframe import load_airframe
from hil_sim.world.rotorcraft.atmosphere import air_density_kg_m3, normal_gravity_m_s2
from hil_sim.world.rotorcraft.dynamics import (
    AUX_ANG_ACC,
    AUX_NU0,
    AUX_PITCH,
    AUX_POWER,
    AUX_SPECIFIC_FORCE,
    AUX_TAIL_PITCH,
    AUX_THRUST,
    ENV_T0,
    ENV_T1,
    FREE,
    N_AUX,
    N_STATES,
    OMEGA,
    PSI,
    QUAT,
    RATES,
    VEL,
)
from hil_sim.world.rotorcraft.inflow import disc_sources, ground_upwash
from hil_sim.world.rotorcraft.model import BladeElementHelicopter, body_states

LOOKAHEAD_S = 0.1
MIN_WIND_RATE_HZ = 200.0
SCORING_RATE_HZ = 100.0  # the eq 5.3 scoring columns (not the forcing)
DIVERGED_RATE_RAD_S = 15.0


@dataclass
class BladeElementTruth:
    """The blade-element truth of one flight: the helicopter and where it came from."""

    heli: BladeElementHelicopter
    airframe_path: str
    overrides: dict = field(default_factory=dict)

    @property
    def rotor_radius_m(self) -> float:
        return self.heli.rotor_radius_m

    @property
    def nominal_rotor_speed_rad_s(self) -> float:
        return self.heli.nominal_rotor_speed_rad_s

    @property
    def hub_offset_body_m(self) -> np.ndarray:
        return self.heli.hub_offset_body_m

    @property
    def imu_position_m(self) -> np.ndarray:
        return np.asarray(self.heli.airframe["imu.position_m"], float)

    @property
    def spec(self) -> str:
        return f"blade_element:{self.airframe_path}"


@dataclass
class Flown:
    """What the loop recorded (N steps at the integrator's rate)."""

    t_s: np.ndarray
    states: np.ndarray          # (N, N_STATES)
    body12: np.ndarray          # (N, 12) pos, body velocity, Euler, rates
    aux: np.ndarray             # (N, N_AUX)
    commands_rad: np.ndarray    # (N, 4) the radio's commands
    applied_rad: np.ndarray     # (N, 4) collective, lateral and longitudinal swashplate, tail
    wind_body: np.ndarray       # (N, 6) eq 5.3 fit at the hub (scoring only)
    heights_m: np.ndarray       # (N,) hub above what is below
    pilot: object
    trim: object
    truth: BladeElementTruth
    extra_truth: dict
    timing: dict = field(default_factory=dict)  # wall s: "trim", "field", "integrate"


def build_truth(scenario) -> BladeElementTruth:
    """The blade-element helicopter of a scenario (airframe, site atmosphere, gravity)."""
    hc = scenario.helicopter
    airframe = load_airframe(hc.airframe, hc.overrides)
    rho = air_density_kg_m3(scenario.site.temperature_c, scenario.site.pressure_hpa)
    g = normal_gravity_m_s2(scenario.sensors.vn200.origin_lla[0],
                            scenario.sensors.vn200.origin_lla[2])
    heli = BladeElementHelicopter(airframe, air_density_kg_m3=rho, gravity_m_s2=g,
                                  step_hz=max(2000.0, scenario.rate_hz))
    return BladeElementTruth(heli=heli, airframe_path=airframe.path,
                             overrides=dict(hc.overrides))


class GridSampler:
    """Snapshots of the wind field and the ground upwash on the body-fixed grid."""

    def __init__(self, heli: BladeElementHelicopter, field_, surface, rate_hz: float) -> None:
        self.heli = heli
        self.field = field_
        self.surface = surface  # (t, points NED (K, 3)) -> height above what is below (K,)
        self.dt = 1.0 / rate_hz
        self.n = max(2, int(round(LOOKAHEAD_S * rate_hz)) + 1)
        self.nodes = heli.grid_nodes_body
        nx, ny, _ = heli.grid_shape
        hub = heli.hub_offset_body_m
        self.plane_nodes = np.column_stack([
            heli.grid_nodes_body[:, 0].reshape(heli.grid_shape)[:, :, 0].ravel(),
            heli.grid_nodes_body[:, 1].reshape(heli.grid_shape)[:, :, 0].ravel(),
            np.full(nx * ny, hub[2])])
        src, self.source_area = disc_sources(heli.rotor_radius_m)
        self.sources = np.column_stack([src[:, 0] + hub[0], src[:, 1] + hub[1],
                                        np.full(len(src), hub[2])])
        self.k0 = None
        self.wind = None
        self.ground = None

    def snapshots(self, k: int, x: np.ndarray, t_now: float):
        """(wind k, wind k+1, ground k, ground k+1) for snapshot index k (time k dt)."""
        if self.k0 is None or not (self.k0 <= k and k + 1 < self.k0 + self.n):
            self._refill(k, x, t_now)
        j = k - self.k0
        return self.wind[j], self.wind[j + 1], self.ground[j], self.ground[j + 1]

    def _refill(self, k: int, x: np.ndarray, t_now: float) -> None:
        heli = self.heli
        times = (k + np.arange(self.n)) * self.dt
        lead = times - t_now
        q0 = x[QUAT:QUAT + 4]
        rot0 = quat_to_dcm(q0)
        vel_ned = rot0 @ x[VEL:VEL + 3]
        quats = quat_multiply(np.broadcast_to(q0, (self.n, 4)),
                              quat_from_rotvec(np.outer(lead, x[RATES:RATES + 3])))
        rots = quat_to_dcm(quats)  # (n, 3, 3)
        origin = x[0:3] + np.outer(lead, vel_ned)  # (n, 3)
        pts = origin[:, None, :] + np.einsum("nij,mj->nmi", rots, self.nodes)
        m = self.nodes.shape[0]
        w = self.field.velocity_ned(np.repeat(times, m), pts.reshape(-1, 3))
        self.wind = np.ascontiguousarray(w.reshape((self.n,) + heli.grid_shape + (3,)))
        src = origin[:, None, :] + np.einsum("nij,mj->nmi", rots, self.sources)
        heights = self.surface(np.repeat(times, src.shape[1]), src.reshape(-1, 3)).reshape(
            self.n, -1)
        plane = origin[:, None, :] + np.einsum("nij,mj->nmi", rots, self.plane_nodes)
        ground = np.empty((self.n,) + heli.grid_shape[:2])
        for i in range(self.n):
            ground[i] = ground_upwash(plane[i], src[i], heights[i], self.source_area).reshape(
                heli.grid_shape[:2])
        self.ground = ground
        self.k0 = k


def surface_function(ship):
    """(t (K,), points NED (K, 3)) -> height above the ground / deck / roof / sea (K,)."""
    if ship is None:
        return lambda t, p: np.maximum(-p[:, 2], 1e-3)
    return lambda t, p: np.maximum(ship.height_above_surface(t, p), 1e-3)


def fly(scenario, duration_s: float, rngs: dict, field_, ship, frame, knots: np.ndarray,
        reference, reference_vel_ned: np.ndarray, progress=None, make_pilot=None,
        truth=None) -> Flown:
    """Fly the scenario (module docstring). `frame`: run.PlanFrame; `knots`: the pilot's
    decision times, `reference` the flight plan on them and `reference_vel_ned` (K, 3) its
    velocity in NED; `make_pilot(a, b, trim12, trim) -> pilot` builds the pilot from the
    quasi-steady linear model at the initial trim; `truth`: the scenario's built
    (`build_truth`), when the caller has it already."""
    import time

    from hil_sim.world.run import SimulationError

    clock = time.perf_counter
    t_begin = clock()
    truth = build_truth(scenario) if truth is None else truth
    heli = truth.heli
    dt = heli.dt
    surface = surface_function(ship)
    wind_rate = max(MIN_WIND_RATE_HZ, scenario.wind_rate_hz)
    sampler = GridSampler(heli, field_, surface, wind_rate)
    steps_per_snapshot = max(1, int(round(1.0 / (wind_rate * dt))))
    sampler.dt = steps_per_snapshot * dt  # snapshots on the step grid

    # -- initial trim ------------------------------------------------------------------------
    pc = scenario.pilot
    yaw0 = frame.heading_rad + (math.radians(pc.yaw_deg) if pc.yaw_deg is not None else 0.0)
    p0, v0 = frame.to_ned(0.0, np.asarray(pc.start_m, float)[None], np.zeros((1, 3)))
    p0, v0 = p0[0], v0[0]
    level = euler_to_dcm(np.array([0.0, 0.0, yaw0]))
    hub0 = p0 + level @ heli.hub_offset_body_m
    wind0 = field_.mean_velocity_ned(0.0, hub0)
    x_probe = heli.initial_state(p0, [0.0, 0.0, yaw0], level.T @ v0, np.zeros(4))
    sampler_trim = GridSampler(heli, field_, surface, wind_rate)
    _, _, ground0, _ = sampler_trim.snapshots(0, x_probe, 0.0)
    trim = heli.trim(vel_ned_m_s=v0, yaw_rad=yaw0, wind_ned_m_s=wind0, ground=ground0,
                     pos_ned_m=p0)
    a, b = heli.linearize(trim, wind_ned_m_s=wind0, ground=ground0)
    trim12 = trim.body12
    pilot = make_pilot(a, b, trim12, trim)
    t_trimmed = clock()
    field_s = 0.0

    # -- integrate ------------------------------------------------------------------------------
    n = int(round(duration_s / dt))
    xs = np.empty((n + 1, N_STATES))
    aux = np.empty((n + 1, N_AUX))
    x = trim.x.copy()
    x[0:3] = p0
    knot_steps = np.ceil(np.asarray(knots) / dt - 1e-6).astype(np.int64)
    env = heli.env(0.0, 0.0)
    parts = heli.packed()
    n_knots = knots.size
    knot = 0
    i = 0
    report_every = int(round(1.0 / dt))
    next_report = report_every
    while True:
        # pilot decisions due at this step
        if knot < n_knots - 1 and knot_steps[knot] <= i:
            b12 = body_states(x[None])[0]
            rot = euler_to_dcm(b12[6:9])
            while knot < n_knots - 1 and knot_steps[knot] <= i:
                p_frame = frame.from_ned(knots[knot], b12[0:3][None])[0]
                v_ref_body = rot.T @ reference_vel_ned[knot]
                pilot.update(knot, b12, p_frame, v_ref_body, b12[8] - frame.heading_rad)
                knot += 1
        if i >= n:
            break
        gk = i // steps_per_snapshot
        nxt = min((gk + 1) * steps_per_snapshot, n)
        if knot < n_knots - 1:
            nxt = min(nxt, max(int(knot_steps[knot]), i + 1))
        t = i * dt
        t_next = nxt * dt
        t_field = clock()
        w0, w1, g0, g1 = sampler.snapshots(gk, x, t)
        field_s += clock() - t_field
        env[ENV_T0] = gk * sampler.dt
        env[ENV_T1] = (gk + 1) * sampler.dt
        dynamics.integrate(x, t, dt, nxt - i, pilot.command(t), pilot.command(t_next), *parts,
                           env, w0, w1, g0, g1, xs, aux, i, FREE)
        i = nxt
        if i >= next_report or i >= n:
            next_report += report_every
            w_body = x[RATES:RATES + 3]
            if not np.all(np.isfinite(x)) or np.max(np.abs(w_body)) > DIVERGED_RATE_RAD_S:
                b12 = body_states(x[None])[0]
                raise SimulationError(
                    f"scenario {scenario.name!r}: the blade-element helicopter left the "
                    f"envelope at t = {t_next:.2f} s (rates {np.round(w_body, 2).tolist()} "
                    f"rad/s, attitude {np.round(np.degrees(b12[6:9]), 1).tolist()} deg)")
            if progress is not None:
                progress.update(t_next)
    # the last row: the final state and its outputs
    env = heli.env(0.0, 0.0)
    w_last, _, g_last, _ = sampler.snapshots(n // steps_per_snapshot, x, n * dt)
    last = np.empty((1, N_STATES))
    last_aux = np.empty((1, N_AUX))
    heli.integrate(x.copy(), n * dt, 1, pilot.command(n * dt), pilot.command(n * dt), env,
                   w_last, w_last, g_last, g_last, last, last_aux, 0)
    xs[n] = last[0]
    aux[n] = last_aux[0]
    if progress is not None:
        progress.finish()
    t_flown = clock()

    ts = np.arange(n + 1) * dt
    body12 = body_states(xs)
    cmds = np.column_stack([np.interp(ts, pilot.knots_t[:pilot.filled + 1],
                                      pilot.knots_u[:pilot.filled + 1, j]) for j in range(4)])
    applied = np.column_stack([aux[:, AUX_PITCH:AUX_PITCH + 3], aux[:, AUX_TAIL_PITCH]])
    hub_off = heli.hub_offset_body_m
    rots = quat_to_dcm(xs[:, QUAT:QUAT + 4])
    hubs = xs[:, 0:3] + rots @ hub_off
    heights = surface(ts, hubs)
    # eq 5.3 local wind at the hub: the scoring definition (never the forcing)
    k = max(1, int(round(1.0 / (SCORING_RATE_HZ * dt))))
    sel = np.arange(0, n + 1, k)
    if sel[-1] != n:
        sel = np.append(sel, n)
    fit = field_.local_wind(ts[sel], hubs[sel], xs[sel, QUAT:QUAT + 4])
    wind_body = np.column_stack([np.interp(ts, ts[sel], fit[:, j]) for j in range(6)])
    extra = {"truth_main_rotor_thrust_n": aux[:, AUX_THRUST],
             "truth_main_rotor_power_w": aux[:, AUX_POWER],
             "truth_inflow_m_s": aux[:, AUX_NU0]}
    timing = {"trim": t_trimmed - t_begin, "field": field_s,
              "integrate": t_flown - t_trimmed - field_s, "scoring": clock() - t_flown}
    return Flown(t_s=ts, states=xs, body12=body12, aux=aux, commands_rad=cmds,
                 applied_rad=applied, wind_body=wind_body, heights_m=heights, pilot=pilot,
                 trim=trim, truth=truth, extra_truth=extra, timing=timing)


def measurement_at_cg(flown: Flown) -> tuple[np.ndarray, np.ndarray]:
    """(specific force (N, 3), angular acceleration (N, 3)) at the body origin, from the
    multibody solution at every step (rotor vibration included)."""
    return (flown.aux[:, AUX_SPECIFIC_FORCE:AUX_SPECIFIC_FORCE + 3],
            flown.aux[:, AUX_ANG_ACC:AUX_ANG_ACC + 3])


__all__ = ["BladeElementTruth", "Flown", "GridSampler", "build_truth", "fly",
           "measurement_at_cg", "OMEGA", "PSI", "euler_to_quat"]
