"""The simulation loop: a scenario -> truth trajectory, sensor samples, streams, flight table.

    result = run_scenario(load_scenario("still_air_calibration"), seed=3, duration_s=20)
    result.truth                 # Trajectory of the CG at the integration rate (truth)
    result.imu_truth             # the IMU point's Trajectory (lever arm applied)
    result.samples["vn200"]      # measured values per device (hil_sim.sensors samples)
    result.streams()             # the bytes / edges each device emits (for the SIL boards)
    built = result.flight_table()   # BuiltFlight: the shared builder + truth_* columns
    write_flight_table(built.df, "flight.parquet", built.metadata)

Integration: fixed-step classical RK4 at `scenario.rate_hz` (>= 1 kHz) of the truth
`HeliModel` (host effects + hidden effects). Per step: the pilot's command (first-order
hold between RC frames, delayed by the servo-lag scenario's pure delay) and the eq 5.3
local wind at the hub (`HeldLocalWind`, refreshed at `wind_rate_hz`, zero-order hold)
are held over the step; the height above ground/deck goes to the model's environment
(on a ship with the deck-edge ground effect: the disk-averaged ground-plane height).
The first RK4 stage is a full `evaluate`, whose measurement (specific force at the CG,
angular accelerations) is the truth the IMU senses. Sensor-side hidden effects: the
lever arm (`Trajectory.at_point`), the accelerometers' vibration rectification (added to
the IMU point's specific force) and the pilot-input stream's time skew (the RC receiver
records the command of t + offset).

Random numbers: one `SeedSequence(seed)` spawns a fixed child per consumer (wind,
pilot, each device), so a seed gives the same flight and switching a device on or off
does not change the others' noise.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field

import numpy as np
from airwake.errors import AirwakeError
from airwake.heli import Stepper
from airwake.heli.trim import linearize

from hil_sim.sensors.rc import RcReceiver, TailServoPwm
from hil_sim.sensors.rotor import RotorTachometer
from hil_sim.sensors.rtk import RtkReceiver
from hil_sim.sensors.streams import sample_times
from hil_sim.sensors.vn200 import Vn200
from hil_sim.world.hidden import HEIGHT_EFFECTS, ElectricDriveGovernor, SecondOrderServo
from hil_sim.world.hidden.ground_effect import DISK_POINTS, deck_height_equivalent
from hil_sim.world.hidden.sensor_side import skewed_commands, with_rectification
from hil_sim.world.kinematics import (
    Trajectory,
    euler_to_dcm,
    euler_to_quat,
)
from hil_sim.world.pilot import Pilot, build_reference, cg_script
from hil_sim.world.scenario import Scenario, vibration_for
from hil_sim.world.ship import Ship
from hil_sim.world.truth import BODY, TruthModel, build_truth_model

# Fixed child index of each random consumer (never reorder: seeds would change flights).
RNG_STREAMS = ("wind", "pilot", "vn200", "rc", "tail_servo", "rotor", "rtk", "base_vn200",
               "reserved_losa", "reserved_marker", "reserved_anemometer", "streams")
DIVERGED_RATE_RAD_S = 15.0  # a body rate above this means the flight is lost


class SimulationError(AirwakeError):
    """The flight cannot be simulated (diverged, bad duration): what and when."""


# ---------------------------------------------------------------------------
# Frames of the flight plan
# ---------------------------------------------------------------------------


class PlanFrame:
    """The script's frame: "ned", or the ship's heading frame riding on the ship."""

    def __init__(self, kind: str, ship: Ship | None) -> None:
        self.kind = kind
        self.ship = ship
        heading = math.radians(ship.config.heading_deg) if ship is not None else 0.0
        self.heading_rad = heading if kind == "ship" else 0.0
        c, s = math.cos(self.heading_rad), math.sin(self.heading_rad)
        self.rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])  # frame -> NED

    def origin(self, t: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
        """(position (N,3), velocity (N,3)) of the frame origin in NED."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        if self.kind == "ned":
            return np.zeros((t.size, 3)), np.zeros((t.size, 3))
        return self.ship.origin_ned_m(t), self.ship.translational_velocity_ned(t)

    def to_ned(self, t, p_frame, v_frame) -> tuple[np.ndarray, np.ndarray]:
        o, vo = self.origin(t)
        return o + p_frame @ self.rot.T, vo + v_frame @ self.rot.T

    def from_ned(self, t: float, p_ned: np.ndarray) -> np.ndarray:
        o, _ = self.origin(t)
        return (p_ned - o[0]) @ self.rot


# ---------------------------------------------------------------------------
# Result
# ---------------------------------------------------------------------------


@dataclass
class SimResult:
    """Everything one simulated flight produced (see module docstring).

    Arrays at the integration rate (N samples): `states` (N, S) full truth model state
    (`state_names`), `commands_rad` (N, 4) pilot commands [col, lat, lon, ped] as the RC
    records them, `applied_rad` (N, 4) blade pitch the rotor gets (after servo lag),
    `wind_body` (N, 6) the eq 5.3 hub wind that drove the dynamics.
    `samples`: device name -> measured samples ("vn200", "rc", "tail_servo", "rotor",
    and "rtk", "base_vn200" where the site has them). `devices`: the sensor objects.
    `timing`: wall seconds of "integration", "sensors" (and "table" after flight_table()).
    """

    scenario: Scenario
    seed: int
    duration_s: float
    truth_model: TruthModel
    truth: Trajectory
    imu_truth: Trajectory
    imu_position_m: np.ndarray
    states: np.ndarray
    state_names: list
    commands_rad: np.ndarray
    applied_rad: np.ndarray
    wind_body: np.ndarray
    samples: dict
    devices: dict
    ship: Ship | None
    base_truth: Trajectory | None
    pilot_info: dict
    body12: np.ndarray | None = None  # (N, 12) pos, body velocity, Euler, rates of the CG
    tail_servo_command_rad: np.ndarray | None = None  # (N,) the gyro's output, if any
    extra_truth: dict = field(default_factory=dict)  # more truth_* columns at the steps
    timing: dict = field(default_factory=dict)
    _streams: dict | None = None

    @property
    def body_states(self) -> np.ndarray:
        """(N, 12) [pos NED, body velocity, roll/pitch/yaw, body rates] of the CG."""
        if self.body12 is not None:
            return self.body12
        b = self.truth_model.model.state_slice(BODY).start
        return self.states[:, b:b + 12]

    @property
    def realtime_factor(self) -> float:
        """Simulated seconds per wall second (integration + sensors + table if built)."""
        wall = sum(self.timing.values())
        return self.duration_s / wall if wall > 0 else math.inf

    def message_tables(self) -> dict:
        """Per-message tables ("<board>/<message>" -> MessageTable) from the measured
        values, as the recorder would export them (the flight-table builder's input)."""
        return message_tables(self)

    def flight_table(self):
        """`BuiltFlight` (df, metadata): the shared builder + truth_* columns."""
        t0 = time.perf_counter()
        built = build_sim_flight_table(self)
        self.timing["table"] = time.perf_counter() - t0
        built.metadata.setdefault("sim", {})["realtime_factor"] = self.realtime_factor
        return built

    def streams(self) -> dict:
        """Device name -> ByteStream / EdgeStream (what each device emits, timed)."""
        if self._streams is None:
            out = {}
            s = self.samples
            d = self.devices
            out["rover/vn200"] = d["vn200"].stream(s["vn200"])
            out["base/rc"] = d["rc"].stream(s["rc"])
            out["rover/tail_servo"] = d["tail_servo"].stream(s["tail_servo"])
            out["rover/rotor"] = d["rotor"].stream(s["rotor"])
            if "rtk" in s:
                out["rover/rtk"] = d["rtk"].stream(s["rtk"])
            if "base_vn200" in s:
                out["base/vn200"] = d["base_vn200"].stream(s["base_vn200"])
            self._streams = out
        return self._streams


# ---------------------------------------------------------------------------
# The loop
# ---------------------------------------------------------------------------


class TruthStepper(Stepper):
    """The heli `Stepper` of the truth model (fixed-step classical RK4, inputs, wind and
    height held over the step; the caller passes the inputs at the step's midpoint), plus
    the rotor speed the truth flies at:

        x_next = stepper.step(x, u, w, h, dt)
        xdot, meas, omega = stepper.evaluate(x, u, w, h)

    x (S,), u (4,), w (6,) eq 5.3 hub wind, h the hub height above ground/deck (m).
    `meas` (6,) is the model's measurement (specific force at the CG, angular
    accelerations) and `omega` the rotor speed it used, at (x, u). The truth model is
    all compiled kernels (the host's effects and the hidden ones), so a step is one
    compiled call; a scenario spec with a numpy plugin steps through numpy RK4 in heli."""

    def evaluate(self, x, u, w, h):
        xdot, meas = self.rates_and_measurement(x, u, w, h)
        return xdot, meas, rotor_speed_of(self.model, x[None])[0]


def rotor_speed_of(model, xs: np.ndarray) -> np.ndarray:
    """(N,) rotor speed the truth model flies at states xs (N, S): the governor's state
    when the droop effect is on, else the main rotor's nominal speed (no measured speed
    is fed to the truth)."""
    if ElectricDriveGovernor.name in model:
        return xs[:, model.state_slice(ElectricDriveGovernor.name).start].copy()
    if "main_rotor" not in model:
        return np.zeros(xs.shape[0])
    nominal = model["main_rotor"].parameters()["nominal_speed_rad_s"]
    return np.full(xs.shape[0], float(nominal))


def batch_measurement(model, xs, us, ws, hs, chunk: int = 20000) -> np.ndarray:
    """The model's measurement (N, 6) at every recorded step, in batched calls."""
    out = np.empty((xs.shape[0], 6))
    for a in range(0, xs.shape[0], chunk):
        sl = slice(a, a + chunk)
        out[sl] = model.measure(xs[sl], us[sl], ws[sl], {"height_agl_m": hs[sl]})
    return out


WIND_LOOKAHEAD_S = 0.1


class WindLookahead:
    """The eq 5.3 hub wind for the step loop, zero-order held on the update grid
    k / rate_hz (as `HeldLocalWind`), with the field sampled for `WIND_LOOKAHEAD_S` of
    updates in one batched `local_wind` call: the hub poses of the coming updates are
    predicted from the state at the batch start (constant NED velocity, constant body
    rates). Over 0.1 s that is within ~1 cm and ~0.2 deg of the flown pose, far below the
    fields' 0.15-0.25 m turbulence grids, and 5-10x cheaper than one call per update
    (local_wind is compiled: ~0.07 ms per hub on the ship and fan fields)."""

    def __init__(self, field, rate_hz: float, hub_off_m: np.ndarray, body_start: int) -> None:
        self.field = field
        self.dt = 1.0 / rate_hz
        self.n = max(1, int(round(WIND_LOOKAHEAD_S * rate_hz)))
        self.hub = np.asarray(hub_off_m, dtype=float)
        self.b = body_start
        self._k0 = None  # first update index of the current batch
        self._values = np.zeros((self.n, 6))
        self._k = None
        self._w = np.zeros(6)

    def __call__(self, t: float, x: np.ndarray) -> np.ndarray:
        k = int(math.floor(t / self.dt + 1e-9))
        if k == self._k:
            return self._w
        if self._k0 is None or not (self._k0 <= k < self._k0 + self.n):
            self._refill(k, t, x)
        self._k = k
        self._w = self._values[k - self._k0]
        return self._w

    def _refill(self, k: int, t: float, x: np.ndarray) -> None:
        from hil_sim.world.kinematics import quat_from_rotvec, quat_multiply, rotate

        b = self.b
        times = (k + np.arange(self.n)) * self.dt
        times[0] = t
        lead = times - t
        q0 = euler_to_quat(x[b + 6:b + 9])
        vel_ned = euler_to_dcm(x[b + 6:b + 9]) @ x[b + 3:b + 6]
        quats = quat_multiply(np.broadcast_to(q0, (self.n, 4)),
                              quat_from_rotvec(np.outer(lead, x[b + 9:b + 12])))
        hubs = x[b:b + 3] + np.outer(lead, vel_ned) + rotate(quats, self.hub)
        self._values = self.field.local_wind(times, hubs, quats)
        self._k0 = k


def _height_function(scenario: Scenario, ship: Ship | None, radius_m: float):
    """(t, hub NED (3,), body->NED rotation (3, 3)) -> (hub height above the ground / deck /
    hangar roof / sea, the ground-plane height the rotor's hidden ground effects see).
    They differ only on a ship with the ground effect's `deck_edge`: there the second is
    Hayden's equivalent height of the disk-averaged reduction, each part of the disk over
    whatever is under it (`hidden.ground_effect.deck_height_equivalent`)."""
    if ship is None:
        def flat(t, hub, rot):
            return -float(hub[2]), -float(hub[2])
        return flat
    ge = scenario.hidden.enabled().get("ground_effect")
    if ge is None or not ge.deck_edge:
        def surface(t, hub, rot):
            h = float(ship.height_above_surface(t, hub[None])[0])
            return h, h
        return surface
    disk = np.column_stack([DISK_POINTS * radius_m, np.zeros(len(DISK_POINTS))])

    def deck(t, hub, rot):
        hs = ship.height_above_surface(t, hub + disk @ rot.T)  # DISK_POINTS[0]: the hub
        return float(hs[0]), deck_height_equivalent(hs, radius_m, ge)
    return deck


def hub_offset_body_m(scenario: Scenario) -> np.ndarray:
    """(3,) the scenario's truth airframe's main-rotor hub from its CG, body axes (z down):
    where a `point = "hub"` script's positions are (`pilot.cg_script`)."""
    if scenario.helicopter.model == "blade_element":
        from hil_sim.world.rotorcraft.flight import build_truth

        return np.asarray(build_truth(scenario).heli.hub_offset_body_m, dtype=float)
    truth = build_truth_model(scenario.helicopter.spec, scenario.helicopter.overrides,
                              scenario.hidden)
    return np.asarray(truth.hub_offset_body_m, dtype=float)


def run_scenario(scenario: Scenario, seed: int | None = None, duration_s: float | None = None,
                 *, progress=None, rate_hz: float | None = None,
                 sensors: bool = True) -> SimResult:
    """Fly `scenario` (its seed/duration unless given) and sample every sensor.

    `rate_hz` overrides the integration rate (tests of the integrator only); `sensors=
    False` skips the devices (truth only). `progress`: an `airwake.progress.Progress`-like
    object (update(done_s), finish()) or None."""
    from hil_sim.world.wind import build_wind_field

    seed = scenario.seed if seed is None else int(seed)
    duration = scenario.duration_s if duration_s is None else float(duration_s)
    if not duration > 0:
        raise SimulationError(f"duration_s = {duration!r}: must be > 0")
    rate = scenario.rate_hz if rate_hz is None else float(rate_hz)
    dt = 1.0 / rate
    children = np.random.SeedSequence(seed).spawn(len(RNG_STREAMS))
    rngs = {name: np.random.default_rng(c) for name, c in zip(RNG_STREAMS, children,
                                                              strict=True)}
    t_start = time.perf_counter()
    if scenario.helicopter.model == "blade_element":
        return _run_blade_element(scenario, seed, duration, rngs, t_start, progress, sensors)

    truth = build_truth_model(scenario.helicopter.spec, scenario.helicopter.overrides,
                              scenario.hidden)
    model = truth.model
    ship = Ship(scenario.ship) if scenario.ship is not None else None
    field_ = build_wind_field(scenario.wind, rng=rngs["wind"], ship=ship)
    frame = PlanFrame(scenario.pilot.frame, ship)
    height_of = _height_function(scenario, ship, truth.rotor_radius_m)
    hub_off = truth.hub_offset_body_m
    body = model.state_slice(BODY)
    b = body.start

    # -- initial trim at the start point ----------------------------------------------
    pc = cg_script(scenario.pilot, hub_off)
    yaw0_frame = math.radians(pc.yaw_deg) if pc.yaw_deg is not None else 0.0
    yaw0 = frame.heading_rad + yaw0_frame
    p0_ned, v0_ned = frame.to_ned(0.0, np.asarray(pc.start_m, float)[None], np.zeros((1, 3)))
    p0_ned, v0_ned = p0_ned[0], v0_ned[0]
    level = euler_to_dcm(np.array([0.0, 0.0, yaw0]))
    v0_body = level.T @ v0_ned
    hub0 = p0_ned + level @ hub_off
    w0 = field_.local_wind(0.0, hub0, euler_to_quat(np.array([0.0, 0.0, yaw0])),
                           unsteady=False, turbulence=False)
    h0 = height_of(0.0, hub0, level)[1]
    tr = truth.trim(v0_body, yaw_rad=yaw0, wind=w0, height_agl_m=h0)
    x = tr.x.copy()
    x[b:b + 3] = p0_ned
    x[b + 8] = yaw0

    # -- pilot --------------------------------------------------------------------------
    rc_timing = scenario.sensors.rc.timing
    knots = sample_times(0.0, duration + 1.0 / rc_timing.frame_rate_hz,
                         rc_timing.frame_rate_hz, rc_timing.phase_s)
    ref = build_reference(pc, knots, rngs["pilot"])
    x_lin = tr.x.copy()
    x_lin[b:b + 3] = 0.0
    x_lin[b + 8] = 0.0
    lin_trim = type(tr)(x_lin, tr.u, tr.residual, tr.iterations)
    env0 = {"height_agl_m": np.array([h0])}
    a_lin, b_lin = linearize(truth.linear_model(), lin_trim.x, lin_trim.u, w0, env0)
    pilot = make_pilot(scenario, a_lin, b_lin, lin_trim, ref, body, rngs["pilot"])
    pilot.trim = type(tr)(tr.x.copy(), tr.u, tr.residual, tr.iterations)
    ref_pos_ned, ref_vel_ned = frame.to_ned(knots, ref.pos_m, ref.vel_m_s)
    lag = scenario.hidden.enabled().get("servo_lag")
    delay = lag.delay_s if lag is not None else 0.0
    servo = SecondOrderServo.name
    lag_slice = model.state_slice(servo) if servo in model else None

    # -- integrate --------------------------------------------------------------------
    steps = int(round(duration * rate))
    n = steps + 1
    s_dim = model.n_states
    xs = np.empty((n, s_dim))
    cmds = np.empty((n, 4))
    used = np.empty((n, 4))
    winds = np.empty((n, 6))
    heights = np.empty(n)
    ground_heights = np.empty(n)  # what the model's ground effects saw (= heights but on
    # a ship with the deck-edge ground effect)
    knot = 0
    n_knots = knots.size
    stepper = TruthStepper(model)
    report_every = max(1, int(rate))
    hub_x, hub_y, hub_z = (float(v) for v in hub_off)
    w = np.zeros(6)
    static_wind = scenario.wind.get("type") == "still_air"
    wind = WindLookahead(field_, scenario.wind_rate_hz, hub_off, b)
    need_height = any(n in model for n in HEIGHT_EFFECTS)
    for i in range(n):
        t = i * dt
        if knot < n_knots - 1 and knots[knot] <= t + 1e-9:
            rot = euler_to_dcm(x[b + 6:b + 9])
            while knot < n_knots - 1 and knots[knot] <= t + 1e-9:
                p_frame = frame.from_ned(knots[knot], x[b:b + 3][None])[0]
                v_ref_body = rot.T @ ref_vel_ned[knot]
                pilot.update(knot, x, p_frame, v_ref_body, x[b + 8] - frame.heading_rad)
                knot += 1
        u = pilot.command(t - delay) if delay else pilot.command(t)
        # hub = CG + R(attitude) r_hub; only its height is needed every step
        sr, cr = math.sin(x[b + 6]), math.cos(x[b + 6])
        sp, cp = math.sin(x[b + 7]), math.cos(x[b + 7])
        hub_d = x[b + 2] - sp * hub_x + cp * sr * hub_y + cp * cr * hub_z
        if not static_wind:
            w = wind(t, x)
        if ship is None:
            h = h_ground = -hub_d
        elif need_height:
            rot = euler_to_dcm(x[b + 6:b + 9])
            h, h_ground = height_of(t, x[b:b + 3] + rot @ hub_off, rot)
        else:
            h = h_ground = np.inf  # nothing in the model reads it; recorded exactly below
        xs[i] = x
        cmds[i] = u if not delay else pilot.command(t)
        used[i] = u
        winds[i] = w
        heights[i] = h
        ground_heights[i] = h_ground
        if i == steps:
            break
        # the command at the step's midpoint: held over the step, it is exact to first order
        # for the pilot's first-order hold (held at the step's start, the blades would
        # lag the recorded commands by dt/2, which the analysis reads as a servo lag)
        x = stepper.step(x, pilot.command(t + 0.5 * dt - delay), w, h_ground, dt)
        if i % 100 == 0:
            if not np.all(np.isfinite(x)) or np.max(np.abs(x[b + 9:b + 12])) > \
                    DIVERGED_RATE_RAD_S or abs(x[b + 7]) > 1.3:
                raise SimulationError(
                    f"scenario {scenario.name!r}: the helicopter left the envelope at "
                    f"t = {t:.2f} s (rates {np.round(x[b + 9:b + 12], 2).tolist()} rad/s, "
                    f"attitude {np.round(np.degrees(x[b + 6:b + 9]), 1).tolist()} deg)")
            if progress is not None and i % report_every == 0:
                progress.update(t)
    meas = batch_measurement(model, xs, used, winds, ground_heights)
    omega = rotor_speed_of(model, xs)
    t_integrated = time.perf_counter()
    ts = np.arange(n) * dt
    if ship is not None and not need_height:
        hubs = xs[:, b:b + 3] + np.einsum("nij,j->ni", euler_to_dcm(xs[:, b + 6:b + 9]),
                                          hub_off)
        heights = ship.height_above_surface(ts, hubs)
    applied = (SecondOrderServo.positions(xs[:, lag_slice]) if lag_slice is not None
               else cmds)

    # -- truth trajectory -----------------------------------------------------------------
    euler = xs[:, b + 6:b + 9]
    quat = euler_to_quat(euler)
    rots = euler_to_dcm(euler)
    vel_ned = np.einsum("nij,nj->ni", rots, xs[:, b + 3:b + 6])
    ship_traj = ship.trajectory(ts) if ship is not None else None
    traj = Trajectory.from_states(
        ts, xs[:, b:b + 3], vel_ned, quat, xs[:, b + 9:b + 12],
        ang_acc_body_rad_s2=meas[:, 3:6], specific_force_body_m_s2=meas[:, 0:3],
        rotor_speed_rad_s=omega, blade_pitch_rad=cmds, height_agl_m=heights, ship=ship_traj)
    lever = scenario.hidden.enabled().get("lever_arm")
    r_imu = np.asarray(lever.position_m if lever is not None else (0.0, 0.0, 0.0), float)
    imu_traj = traj.at_point(r_imu)
    rectification = scenario.hidden.enabled().get("vibration_rectification")
    if rectification is not None:
        imu_traj = with_rectification(imu_traj, rectification, truth.nominal_rotor_speed_rad_s)

    result = SimResult(
        scenario=scenario, seed=seed, duration_s=duration, truth_model=truth, truth=traj,
        imu_truth=imu_traj, imu_position_m=r_imu, states=xs, state_names=list(
            model.state_names), commands_rad=cmds, applied_rad=applied, wind_body=winds,
        samples={}, devices={}, ship=ship, base_truth=None,
        pilot_info={"trim_u_rad": tr.u.tolist(), "trim_roll_rad": float(tr.x[b + 6]),
                    "trim_pitch_rad": float(tr.x[b + 7]),
                    "closed_loop_spectral_radius": pilot.closed_loop_radius,
                    "saturated_frames": pilot.saturated,
                    "wind_description": field_.describe(),
                    "reference_pos_ned_m": ref_pos_ned, "reference_t_s": knots})
    result.timing["integration"] = t_integrated - t_start
    if progress is not None:
        progress.finish()
    if sensors:
        _measure(result, rngs)
        result.timing["sensors"] = time.perf_counter() - t_integrated
    return result


# hidden effects the blade-element truth takes on top of its own physics: the sensor-side
# ones (its rotor, inflow, ground effect, drive and servos are already physical)
BLADE_ELEMENT_HIDDEN = ("lever_arm", "input_time_skew", "vibration_rectification")


def make_pilot(scenario: Scenario, a: np.ndarray, b: np.ndarray, lin_trim, ref,
               body_slice: slice, rng: np.random.Generator):
    """The scenario's pilot on the truth's linear model (a, b) at `lin_trim` (x, u)."""
    if scenario.helicopter.pilot == "crossover":
        from hil_sim.world.crossover_pilot import CrossoverPilot

        return CrossoverPilot(a, b, lin_trim, ref, scenario.pilot.crossover,
                              body_slice=body_slice, rng=rng)
    return Pilot(a, b, lin_trim, ref, scenario.pilot.gains, body_slice=body_slice)


def _run_blade_element(scenario: Scenario, seed: int, duration: float, rngs: dict,
                       t_start: float, progress, sensors: bool) -> SimResult:
    """run_scenario for `[helicopter] model = "blade_element"` (hil_sim.world.rotorcraft)."""
    from types import SimpleNamespace

    from hil_sim.sensors.isolator import IsolatorConfig, isolate
    from hil_sim.world.rotorcraft.flight import build_truth, fly, measurement_at_cg
    from hil_sim.world.wind import build_wind_field

    unsupported = [k for k in scenario.hidden.enabled() if k not in BLADE_ELEMENT_HIDDEN]
    if unsupported:
        raise SimulationError(
            f"scenario {scenario.name!r}: hidden effect(s) {', '.join(unsupported)} are not "
            "added to the blade-element truth: it has that physics of its own (ground and "
            "deck effect, servos, rotor-speed governor, dynamic inflow); only "
            f"{', '.join(BLADE_ELEMENT_HIDDEN)} apply")
    ship = Ship(scenario.ship) if scenario.ship is not None else None
    field_ = build_wind_field(scenario.wind, rng=rngs["wind"], ship=ship)
    frame = PlanFrame(scenario.pilot.frame, ship)
    # the pilot flies the CG: a script for the hub is moved by the airframe's hub offset
    flown_scenario, built = scenario, None
    if scenario.pilot.point != "cg":
        built = build_truth(scenario)
        flown_scenario = dataclasses.replace(scenario, pilot=cg_script(
            scenario.pilot, built.heli.hub_offset_body_m))
    pc = flown_scenario.pilot
    rc_timing = scenario.sensors.rc.timing
    knots = sample_times(0.0, duration + 1.0 / rc_timing.frame_rate_hz,
                         rc_timing.frame_rate_hz, rc_timing.phase_s)
    ref = build_reference(pc, knots, rngs["pilot"])
    ref_pos_ned, ref_vel_ned = frame.to_ned(knots, ref.pos_m, ref.vel_m_s)
    lag = scenario.hidden.enabled().get("input_time_skew")
    del lag  # applied to the RC record below

    def pilot_factory(a, b, trim12, trim):
        lin = trim12.copy()
        lin[0:3] = 0.0
        lin[8] = 0.0
        lin_trim = SimpleNamespace(x=lin, u=trim.delta.copy())
        pilot = make_pilot(scenario, a, b, lin_trim, ref, slice(0, 12), rngs["pilot"])
        pilot.trim = SimpleNamespace(x=trim12.copy(), u=trim.delta.copy())
        return pilot

    flown = fly(flown_scenario, duration, rngs, field_, ship, frame, knots, ref, ref_vel_ned,
                progress=progress, make_pilot=pilot_factory, truth=built)
    t_integrated = time.perf_counter()
    truth = flown.truth
    ts = flown.t_s
    xs = flown.states
    b12 = flown.body12
    quat = xs[:, 6:10]
    rots = euler_to_dcm(b12[:, 6:9])
    vel_ned = np.einsum("nij,nj->ni", rots, b12[:, 3:6])
    sf, aa = measurement_at_cg(flown)
    from hil_sim.world.rotorcraft.dynamics import AUX_TAIL_COMMAND, OMEGA, PSI

    traj = Trajectory.from_states(
        ts, b12[:, 0:3], vel_ned, quat, b12[:, 9:12], ang_acc_body_rad_s2=aa,
        specific_force_body_m_s2=sf, rotor_speed_rad_s=xs[:, OMEGA],
        rotor_azimuth_rad=xs[:, PSI], blade_pitch_rad=flown.commands_rad,
        height_agl_m=flown.heights_m, ship=ship.trajectory(ts) if ship is not None else None)
    af = truth.heli.airframe
    r_imu = truth.imu_position_m
    lever = scenario.hidden.enabled().get("lever_arm")
    if lever is not None:
        r_imu = r_imu + np.asarray(lever.position_m, float)
    imu_traj = isolate(traj.at_point(r_imu), IsolatorConfig(
        af["imu.isolator_natural_hz"], af["imu.isolator_damping"]))
    rectification = scenario.hidden.enabled().get("vibration_rectification")
    if rectification is not None:
        imu_traj = with_rectification(imu_traj, rectification, truth.nominal_rotor_speed_rad_s)
    trim = flown.trim
    result = SimResult(
        scenario=scenario, seed=seed, duration_s=duration, truth_model=truth, truth=traj,
        imu_truth=imu_traj, imu_position_m=r_imu, states=xs, state_names=list(STATE_NAMES),
        commands_rad=flown.commands_rad, applied_rad=flown.applied_rad,
        wind_body=flown.wind_body, samples={}, devices={}, ship=ship, base_truth=None,
        pilot_info={"trim_u_rad": trim.delta.tolist(),
                    "trim_roll_rad": float(trim.body12[6]),
                    "trim_pitch_rad": float(trim.body12[7]),
                    "closed_loop_spectral_radius": getattr(flown.pilot, "closed_loop_radius",
                                                           float("nan")),
                    "saturated_frames": flown.pilot.saturated,
                    "wind_description": field_.describe(),
                    "reference_pos_ned_m": ref_pos_ned, "reference_t_s": knots},
        body12=b12, extra_truth=flown.extra_truth,
        tail_servo_command_rad=flown.aux[:, AUX_TAIL_COMMAND])
    result.timing["integration"] = t_integrated - t_start
    result.pilot_info["blade_element_timing_s"] = dict(flown.timing)
    if sensors:
        _measure(result, rngs)
        result.timing["sensors"] = time.perf_counter() - t_integrated
    return result


STATE_NAMES = ("pos_n_m", "pos_e_m", "pos_d_m", "vel_u_m_s", "vel_v_m_s", "vel_w_m_s",
               "quat_w", "quat_x", "quat_y", "quat_z", "p_rad_s", "q_rad_s", "r_rad_s",
               "rotor_azimuth_rad", "rotor_speed_rad_s", "teeter_rad", "teeter_rate_rad_s",
               "flybar_teeter_rad", "flybar_teeter_rate_rad_s", "inflow_nu0_m_s",
               "inflow_nux_m_s", "inflow_nuy_m_s", "tail_inflow_m_s", "governor_integral",
               "servo1_rad", "servo2_rad", "servo3_rad", "tail_servo_rad",
               "servo1_rate_rad_s", "servo2_rate_rad_s", "servo3_rate_rad_s",
               "tail_servo_rate_rad_s", "gyro_hold_integral_rad")


def _measure(result: SimResult, rngs: dict) -> None:
    """Every device's measured values from the truth (fills samples and devices)."""
    import dataclasses

    sc = result.scenario
    cfg = sc.sensors
    vn_cfg = dataclasses.replace(cfg.vn200, imu=dataclasses.replace(
        cfg.vn200.imu, vibration=vibration_for(cfg)))
    if sc.helicopter.model == "blade_element":
        vn_cfg = blade_element_vn200(cfg.vn200, rngs["vn200"])
    d = result.devices
    s = result.samples
    d["vn200"] = Vn200(vn_cfg, rng=rngs["vn200"])
    s["vn200"] = d["vn200"].measure(result.imu_truth)
    d["rc"] = RcReceiver(cfg.rc, rng=rngs["rc"])
    skew = sc.hidden.enabled().get("input_time_skew")
    s["rc"] = d["rc"].measure(result.truth, commands_rad=None if skew is None else
                              skewed_commands(result.truth.t_s, result.commands_rad,
                                              skew.offset_s))
    d["tail_servo"] = TailServoPwm(cfg.tail_servo, rng=rngs["tail_servo"])
    servo_traj = result.truth
    if result.tail_servo_command_rad is not None:  # a yaw gyro drives the tail servo
        pitch = result.truth.blade_pitch_rad.copy()
        pitch[:, 3] = result.tail_servo_command_rad
        servo_traj = dataclasses.replace(result.truth, blade_pitch_rad=pitch)
    s["tail_servo"] = d["tail_servo"].measure(servo_traj)
    d["rotor"] = RotorTachometer(cfg.rotor, rng=rngs["rotor"])
    s["rotor"] = d["rotor"].measure(result.truth)
    ts = result.truth.t_s
    if sc.rtk_enabled:
        rover_ant = result.truth.at_point(np.asarray(cfg.rover_antenna_m, float))
        if result.ship is not None:
            base = result.truth.ship.at_point(np.asarray(cfg.base_antenna_m, float))
        else:
            p = np.asarray(cfg.base_antenna_m, float)
            base = Trajectory.from_states(
                ts, np.broadcast_to(p, (ts.size, 3)), np.zeros((ts.size, 3)),
                np.broadcast_to([1.0, 0.0, 0.0, 0.0], (ts.size, 4)), np.zeros((ts.size, 3)),
                ang_acc_body_rad_s2=np.zeros((ts.size, 3)),
                specific_force_body_m_s2=np.broadcast_to([0.0, 0.0, -9.798], (ts.size, 3)))
        result.base_truth = base
        d["rtk"] = RtkReceiver(cfg.rtk, rng=rngs["rtk"])
        s["rtk"] = d["rtk"].measure(rover_ant, base)
    if result.ship is not None:
        d["base_vn200"] = Vn200(cfg.base_vn200, rng=rngs["base_vn200"])
        s["base_vn200"] = d["base_vn200"].measure(
            result.truth.ship.at_point(np.asarray(cfg.base_ins_m, float)))


# VN-200 data sheet (VectorNav, VN-200 Rugged GNSS/INS, rev. 2.x): IMU rate 800 Hz; gyro
# in-run bias stability < 10 deg/h, accelerometer < 0.04 mg. The turn-on residual biases of
# the compensated outputs (what the INS's online bias estimate leaves) are drawn per flight
# at class values: gyro 0.01 deg/s, accelerometer 1 mg, 1 sigma per axis.
VN200_IMU_RATE_HZ = 800.0
VN200_GYRO_TURN_ON_RAD_S = math.radians(0.01)
VN200_ACCEL_TURN_ON_M_S2 = 1e-3 * 9.81
VN200_SOLUTION_DELAY_S = 0.0025  # two IMU samples of filter latency (class value)


def blade_element_vn200(config, rng: np.random.Generator):
    """The rover VN-200 on the blade-element truth: vibration comes from the dynamics (the
    sinusoidal model is off), the IMU samples at its own rate and averages to the output,
    turn-on biases drawn per flight, the INS solution a little late."""
    imu = dataclasses.replace(
        config.imu, vibration=dataclasses.replace(
            config.imu.vibration, accel_1p_m_s2=(0.0,) * 3, accel_2p_m_s2=(0.0,) * 3,
            gyro_1p_rad_s=(0.0,) * 3, gyro_2p_rad_s=(0.0,) * 3),
        gyro_bias_rad_s=tuple((np.asarray(config.imu.gyro_bias_rad_s) + rng.normal(
            0.0, VN200_GYRO_TURN_ON_RAD_S, 3)).tolist()),
        accel_bias_m_s2=tuple((np.asarray(config.imu.accel_bias_m_s2) + rng.normal(
            0.0, VN200_ACCEL_TURN_ON_M_S2, 3)).tolist()))
    return dataclasses.replace(
        config, imu=imu,
        imu_sample_rate_hz=config.imu_sample_rate_hz or VN200_IMU_RATE_HZ,
        solution_delay_s=config.solution_delay_s or VN200_SOLUTION_DELAY_S)


# ---------------------------------------------------------------------------
# Message tables and the flight table
# ---------------------------------------------------------------------------

TRUTH_STATE_COLUMNS = ("pos_n_m", "pos_e_m", "pos_d_m", "vel_u_m_s", "vel_v_m_s", "vel_w_m_s",
                       "roll_rad", "pitch_rad", "yaw_rad", "p_rad_s", "q_rad_s", "r_rad_s")
TRUTH_MEAS_COLUMNS = ("acc_x_m_s2", "acc_y_m_s2", "acc_z_m_s2", "pdot_rad_s2", "qdot_rad_s2",
                      "rdot_rad_s2")
INPUT_COLUMNS = ("delta_col_rad", "delta_lat_rad", "delta_lon_rad", "delta_ped_rad")


def message_tables(result: SimResult) -> dict:
    """"<board>/<message>" -> MessageTable filled from the devices' measured values, with
    each message's host time = the instant the device sampled (no link latency: the SIL
    path adds the real transport and board clocks)."""
    from airwake.record.flight_builder import message_table

    s = result.samples
    out = {}
    vn = s["vn200"]
    out["rover/ins"] = _ins_table(vn)
    rc = s["rc"]
    out["base/pilot_inputs"] = message_table(
        "pilot_inputs", rc.t_s, pwm_us=np.round(rc.width_us).astype(np.uint16),
        valid_mask=0x1F)
    rot = s["rotor"]
    if len(rot) >= 2:
        interval = np.diff(rot.t_s)
        out["rover/rotor_speed"] = message_table(
            "rotor_speed", rot.t_s[1:], rotor_speed_rad_s=rot.rotor_speed_rad_s,
            pulse_interval_us=np.round(interval * 1e6).astype(np.uint32),
            pulse_count=np.arange(2, len(rot) + 1, dtype=np.uint32))
    ts = s["tail_servo"]
    out["rover/tail_servo"] = message_table(
        "tail_servo", ts.t_s, pulse_width_us=np.round(ts.width_us[:, 0]).astype(np.uint16),
        valid=1)
    if "rtk" in s:
        r = s["rtk"]
        base = np.nan_to_num(r.baseline_ned_m, nan=0.0)
        out["rover/rtk_baseline"] = message_table(
            "rtk_baseline", r.t_s, gps_tow_ms=r.tow_ms.astype(np.uint32),
            baseline_ned_mm=np.round(base * 1000.0).astype(np.int32),
            h_accuracy_mm=np.round(r.h_accuracy_m * 1000).astype(np.uint16),
            v_accuracy_mm=np.round(r.v_accuracy_m * 1000).astype(np.uint16),
            num_sats=r.n_sats.astype(np.uint8), fix_mode=r.fix_mode.astype(np.uint8))
        # the receiver's Doppler velocity (SBP MSG_VEL_NED, flags 1 = measured Doppler)
        # with the accuracy its stream reports (RtkModel.stream)
        vel_sigma = np.asarray(result.devices["rtk"].config.velocity_sigma_m_s, float)
        out["rover/rtk_vel"] = message_table(
            "rtk_vel", r.t_s, gps_tow_ms=r.tow_ms.astype(np.uint32),
            vel_ned_mm_s=np.round(r.vel_ned_m_s * 1000.0).astype(np.int32),
            h_accuracy_mm_s=np.uint16(round(float(np.hypot(*vel_sigma[:2])) * 1000.0)),
            v_accuracy_mm_s=np.uint16(round(float(vel_sigma[2]) * 1000.0)),
            num_sats=r.n_sats.astype(np.uint8), fix_mode=1)
    if "base_vn200" in s:
        out["base/ins"] = _ins_table(s["base_vn200"])
    return out


def _ins_table(vn):
    from airwake.record.flight_builder import message_table

    return message_table(
        "ins", vn.t_s, time_startup_ns=vn.time_startup_ns, ypr_deg=vn.ypr_deg,
        angular_rate_frd_rad_s=vn.rates_body_rad_s, lat_deg=vn.lla[:, 0], lon_deg=vn.lla[:, 1],
        alt_m=vn.lla[:, 2], vel_ned_m_s=vn.vel_ned_m_s, accel_frd_m_s2=vn.accel_body_m_s2,
        ins_status=vn.ins_status)


def build_config(result: SimResult):
    """The builder settings this flight's set-up implies (origin, antenna, base height)."""
    from airwake.record.flight_builder import FlightBuildConfig
    from airwake.record.rigging import PwmRigging

    sc = result.scenario
    cfg = sc.sensors
    hub = result.truth_model.hub_offset_body_m
    rover_to_hub = hub - np.asarray(cfg.rover_antenna_m, float)
    base_h = cfg.base_antenna_height_m
    if base_h is None:
        base_h = -float(cfg.base_antenna_m[2])
    m = cfg.rc.mapping
    rigging = PwmRigging(center_us=m.center_us, gain_rad_per_us=m.gain_rad_per_us,
                         offset_rad=m.offset_rad)
    ship_xy = (tuple(float(v) for v in cfg.base_antenna_m[:2])
               if result.ship is not None else None)
    return FlightBuildConfig(ned_origin_lla=tuple(cfg.vn200.origin_lla),
                             base_antenna_height_above_deck_m=base_h,
                             base_antenna_ship_xy_m=ship_xy,
                             rover_antenna_to_hub_frd_m=tuple(rover_to_hub.tolist()),
                             rigging=rigging)


def truth_columns(result: SimResult, t_s: np.ndarray) -> dict:
    """truth_* columns at times t_s (interpolated from the integration-rate truth):
    noise-free states of the CG, the noise-free IMU channels at the IMU point (hidden
    effects included, vibration and sensor errors excluded), rotor speed, hub height,
    the eq 5.3 wind and the blade pitch the rotor got."""
    from hil_sim.world.wind import LOCAL_WIND_COLUMNS

    tr = result.truth.at(t_s)
    imu = result.imu_truth.at(t_s)
    t_all = result.truth.t_s

    def interp(a):
        return np.stack([np.interp(t_s, t_all, a[:, j]) for j in range(a.shape[1])], -1)

    cols = {}
    body = interp(result.body_states)
    for j, name in enumerate(TRUTH_STATE_COLUMNS):
        cols[f"truth_{name}"] = body[:, j]
    cols["truth_yaw_rad"] = np.pi - np.mod(np.pi - body[:, 8], 2 * np.pi)
    meas = np.column_stack([imu.specific_force_body_m_s2, imu.ang_acc_body_rad_s2])
    for j, name in enumerate(TRUTH_MEAS_COLUMNS):
        cols[f"truth_{name}"] = meas[:, j]
    cols["truth_rotor_speed_rad_s"] = tr.rotor_speed_rad_s
    cols["truth_height_agl_m"] = tr.height_agl_m
    wind = interp(result.wind_body)
    for j, name in enumerate(LOCAL_WIND_COLUMNS):
        cols[name] = wind[:, j]
    applied = interp(result.applied_rad)
    for j, name in enumerate(INPUT_COLUMNS):
        cols[f"truth_{name}"] = applied[:, j]
    for name, values in result.extra_truth.items():
        cols[name] = np.interp(t_s, t_all, values)
    return cols


def build_sim_flight_table(result: SimResult):
    """The flight table through the shared builder (`airwake.record.flight_builder`)
    plus the truth_* columns and the simulation metadata."""
    from airwake.record.flight_builder import build_flight_table

    from hil_sim.sensors.config import config_to_dict

    built = build_flight_table(message_tables(result), build_config(result))
    df = built.df
    cols = truth_columns(result, df["t_s"].to_numpy())
    for k, v in cols.items():
        df[k] = v
    sc = result.scenario
    meta = built.metadata
    meta.update({
        "source": "sim",
        "scenario": sc.name,
        "seed": result.seed,
        "scenario_config": sc.describe(),
        "sim": {"rate_hz": sc.rate_hz, "wind_rate_hz": sc.wind_rate_hz,
                "duration_s": result.duration_s, "site": sc.site.type,
                "truth_spec": sc.helicopter.spec if sc.helicopter.model == "effects"
                else result.truth_model.spec, "truth_model": sc.helicopter.model,
                "pilot_model": sc.helicopter.pilot,
                "imu_position_m": result.imu_position_m.tolist(),
                "pilot": {k: v for k, v in result.pilot_info.items()
                          if not isinstance(v, np.ndarray)},
                "timing_s": dict(result.timing)},
        "sensors": {name: config_to_dict(dev.config) for name, dev in result.devices.items()},
    })
    return built
