"""A hand-carried anemometer survey of a wind field (reference §3.4, Fig 3.13).

    table, metadata = survey_table(SurveyConfig(), seed=2)     # one row per sample

The reference pushed a pole on casters carrying a Young 81000 anemometer with the LOSA
marker on it through the two-fan hall: discrete stations on serpentine lines at several
heights, at least 20 s at each, 100 Hz. Here the carrier (the marker) visits the
stations of a regular lattice in serpentine order, dwelling `dwell_s` at each while the
pole sways (a few cm, a few degrees, the heading wandering through tens of degrees), and
moving between stations on minimum-jerk segments. The anemometer sits at
`lever_arm_m` from the marker (marker axes, z down) with its axes the marker's, and is
sampled by the simulator's own sensor model (`hil_sim.sensors.anemometer`: the relative
air velocity in its own frame) on the truth wind field — nothing of the host's map model.

The wind field is built exactly as `run_scenario` builds it (the "wind" child of the
seed's SeedSequence, the scenario's `[wind]` table), so `hil_sim.world.truth_field`
rebuilds it from the metadata for scoring; the sensor noise uses the
"reserved_anemometer" child.

Columns: `t_s`; `anemo_u/v/w_m_s` (sensor frame), `anemo_temp_c`, `anemo_valid`; the
carrier's truth pose with the simulator's truth names: `truth_pos_n/e/d_m`,
`truth_vel_u/v/w_m_s` (body), `truth_roll/pitch/yaw_rad`, `truth_p/q/r_rad_s`; and the
truth wind at the sensor, `truth_anemo_wind_n/e/d_m_s`. Metadata: `frame` "ned",
`source` "sim", `scenario`, `seed`, `scenario_config` (its wind), `anemometer_lever_arm_m`,
`survey` (the settings) and `sensors`.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np

from hil_sim.sensors.anemometer import Anemometer, AnemometerConfig
from hil_sim.sensors.config import check_finite, check_positive, config_to_dict
from hil_sim.world.kinematics import Trajectory, euler_rates_to_body_rates, euler_to_quat

Vec3 = tuple[float, float, float]


@dataclass(frozen=True)
class SurveyConfig:
    """Stations: the lattice x in `x_range_m` step `step_m[0]`, y likewise, at `heights_d_m`
    (NED down); `dwell_s` at each; `speed_m_s` between them. Sway amplitudes are 1-sigma-
    like peak values of sums of slow sines."""

    x_range_m: tuple[float, float] = (0.5, 6.5)
    y_range_m: tuple[float, float] = (-0.9, 0.9)
    heights_d_m: tuple[float, ...] = (-1.25, -1.75, -2.25, -2.75)
    step_m: tuple[float, float] = (0.5, 0.3)
    dwell_s: float = 20.0
    speed_m_s: float = 0.4
    rate_hz: float = 200.0
    sway_m: float = 0.03
    tilt_rad: float = 0.06
    heading_swing_rad: float = 0.6
    heading_rad: float = 0.0  # the carrier's mean heading (marker axes; x = north at 0)
    lever_arm_m: Vec3 = (0.05, 0.0, -0.30)
    # the marker on the pole: marker axes -> carrier (anemometer) axes; the carrier's
    # axes are the anemometer's, upright (z down), x along the pole's heading
    marker_mount_quat_wxyz: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        check_finite("x_range_m", self.x_range_m)
        check_finite("y_range_m", self.y_range_m)
        check_finite("heights_d_m", self.heights_d_m)
        check_positive("dwell_s", self.dwell_s)
        check_positive("speed_m_s", self.speed_m_s)
        check_positive("rate_hz", self.rate_hz)
        check_finite("lever_arm_m", self.lever_arm_m)
        check_finite("heading_rad", self.heading_rad)
        check_finite("marker_mount_quat_wxyz", self.marker_mount_quat_wxyz)
        if abs(float(np.linalg.norm(self.marker_mount_quat_wxyz)) - 1.0) > 1e-6:
            raise ValueError(f"marker_mount_quat_wxyz = {self.marker_mount_quat_wxyz!r}: "
                             "not a unit quaternion")
        for name, v in (("step_m", self.step_m[0]), ("step_m", self.step_m[1])):
            check_positive(name, v)

    def stations(self) -> np.ndarray:
        """(S, 3) NED station positions in serpentine order (x fastest, then y, then z)."""
        xs = np.arange(self.x_range_m[0], self.x_range_m[1] + 1e-9, self.step_m[0])
        ys = np.arange(self.y_range_m[0], self.y_range_m[1] + 1e-9, self.step_m[1])
        out = []
        flip = False
        for z in self.heights_d_m:
            for y in ys:
                row = xs[::-1] if flip else xs
                out.extend((x, y, z) for x in row)
                flip = not flip
            ys = ys[::-1]
        return np.asarray(out, dtype=float)


def survey_duration_s(cfg: SurveyConfig) -> float:
    """The whole survey's length (s)."""
    t = carrier_trajectory(cfg).t_s
    return float(t[-1] - t[0])


def _min_jerk(tau: np.ndarray) -> np.ndarray:
    return tau**3 * (10.0 - 15.0 * tau + 6.0 * tau * tau)


def carrier_trajectory(cfg: SurveyConfig) -> Trajectory:
    """The marker's truth kinematics: stations, transits, sway (module docstring)."""
    st = cfg.stations()
    pieces_t, pieces_p = [], []
    t0 = 0.0
    dt = 1.0 / cfg.rate_hz
    for k, p in enumerate(st):
        n = int(round(cfg.dwell_s * cfg.rate_hz))
        pieces_t.append(t0 + dt * np.arange(n))
        pieces_p.append(np.broadcast_to(p, (n, 3)))
        t0 += n * dt
        if k + 1 < len(st):
            d = st[k + 1] - p
            dur = max(1.875 * np.linalg.norm(d) / cfg.speed_m_s, 1.0)
            n = int(round(dur * cfg.rate_hz))
            tau = np.arange(n) / n
            pieces_t.append(t0 + dt * np.arange(n))
            pieces_p.append(p + np.outer(_min_jerk(tau), d))
            t0 += n * dt
    t = np.concatenate(pieces_t)
    pos = np.concatenate(pieces_p).copy()

    def sines(amp, periods, phases):
        return amp * sum(np.sin(2 * np.pi * t / per + ph) for per, ph in
                         zip(periods, phases, strict=True)) / len(periods)

    pos[:, 0] += sines(cfg.sway_m, (2.7, 7.1), (0.3, 1.1))
    pos[:, 1] += sines(cfg.sway_m, (3.3, 5.9), (2.0, 0.4))
    pos[:, 2] += sines(0.3 * cfg.sway_m, (1.9, 4.3), (0.7, 2.2))
    euler = np.column_stack([sines(cfg.tilt_rad, (1.4, 3.7), (0.0, 1.3)),
                             sines(cfg.tilt_rad, (1.1, 4.1), (0.9, 2.5)),
                             cfg.heading_rad
                             + sines(cfg.heading_swing_rad, (37.0, 5.3), (0.0, 0.8))])
    vel = np.gradient(pos, t, axis=0)
    rates = euler_rates_to_body_rates(euler, np.gradient(euler, t, axis=0))
    return Trajectory.from_states(t, pos, vel, euler_to_quat(euler), rates)


class SurveyWorld:
    """The survey as a flown world, for the table and for the SIL boards
    (`airwake sim run --survey`): `truth` the carrier's (marker's) kinematics, `samples`
    the anemometer's, `streams()` its serial output ("marker/anemometer", the ASCII lines
    the marker board reads), `flight_table()` the survey table (`survey_table`), and the
    scenario whose wind field it samples."""

    def __init__(self, cfg: SurveyConfig | None = None, *, seed: int = 2,
                 scenario="fans_indoor", duration_s: float | None = None,
                 anemometer: AnemometerConfig | None = None) -> None:
        from hil_sim.world.run import RNG_STREAMS
        from hil_sim.world.scenario import load_scenario
        from hil_sim.world.wind import build_wind_field

        self.config = cfg or SurveyConfig()
        self.scenario = load_scenario(scenario) if isinstance(scenario, str) else scenario
        self.seed = int(seed)
        children = np.random.SeedSequence(self.seed).spawn(len(RNG_STREAMS))
        rngs = {name: np.random.default_rng(c) for name, c in zip(RNG_STREAMS, children,
                                                                  strict=True)}
        self.field = build_wind_field(self.scenario.wind, rng=rngs["wind"], ship=None)
        carrier = carrier_trajectory(self.config)
        if duration_s is not None:
            carrier = carrier.window(0.0, float(duration_s))
        self.truth = carrier
        self.duration_s = float(carrier.t_s[-1])
        sensor = carrier.at_point(np.asarray(self.config.lever_arm_m, float))
        self.device = Anemometer(anemometer, rng=rngs["reserved_anemometer"])
        self.samples = self.device.measure(sensor, self.field)
        self._streams: dict | None = None

    def streams(self) -> dict:
        if self._streams is None:
            self._streams = {"marker/anemometer": self.device.ascii_stream(self.samples)}
        return self._streams

    def build_config(self):
        """The builder settings (the site's NED origin; there is no helicopter)."""
        from airwake.record.flight_builder import FlightBuildConfig

        return FlightBuildConfig(
            ned_origin_lla=tuple(self.scenario.sensors.vn200.origin_lla))

    def table(self):
        """(DataFrame, metadata): the survey table (module docstring). The truth pose is
        the marker's (the reference point a tracker follows), so the metadata give the
        lever arm in marker axes and the anemometer's axes relative to the marker's."""
        import pandas as pd

        from hil_sim.world.kinematics import quat_to_dcm

        s, cfg, sc = self.samples, self.config, self.scenario
        mount = np.asarray(cfg.marker_mount_quat_wxyz, float)
        c = self.truth.at_point(np.zeros(3), mount).at(s.t_s)
        r_marker = quat_to_dcm(mount).T @ np.asarray(cfg.lever_arm_m, float)
        cols = {"t_s": s.t_s,
                "anemo_u_m_s": s.wind_sensor_m_s[:, 0], "anemo_v_m_s": s.wind_sensor_m_s[:, 1],
                "anemo_w_m_s": s.wind_sensor_m_s[:, 2], "anemo_temp_c": s.sonic_temperature_c,
                "anemo_valid": np.ones(len(s))}
        for j, n in enumerate(("n", "e", "d")):
            cols[f"truth_pos_{n}_m"] = c.pos_ned_m[:, j]
        for j, n in enumerate(("u", "v", "w")):
            cols[f"truth_vel_{n}_m_s"] = c.vel_body_m_s[:, j]
        for j, n in enumerate(("roll", "pitch", "yaw")):
            cols[f"truth_{n}_rad"] = c.euler_rad[:, j]
        for j, n in enumerate(("p", "q", "r")):
            cols[f"truth_{n}_rad_s"] = c.rates_body_rad_s[:, j]
        for j, n in enumerate(("n", "e", "d")):
            cols[f"truth_anemo_wind_{n}_m_s"] = s.wind_ned_m_s[:, j]
        meta = {"frame": "ned", "source": "sim", "scenario": f"{sc.name}_anemometer_survey",
                "seed": self.seed, "scenario_config": {"wind": dict(sc.describe()["wind"])},
                "anemometer_lever_arm_m": [float(v) for v in r_marker],
                "anemometer_mount_quat_wxyz": [float(mount[0]), *(-float(v)
                                                                  for v in mount[1:])],
                "survey": {k: (list(v) if isinstance(v, tuple) else v)
                           for k, v in config_to_dict(cfg).items()},
                "sensors": {"anemometer": config_to_dict(self.device.config)}}
        return pd.DataFrame(cols), meta

    def flight_table(self):
        """The table as the SIL run's truth table wants it (`.df`, `.metadata`)."""
        df, meta = self.table()
        return SimpleNamespace(df=df, metadata=meta)


def survey_table(cfg: SurveyConfig | None = None, *, seed: int = 2,
                 scenario: str = "fans_indoor", duration_s: float | None = None,
                 anemometer: AnemometerConfig | None = None):
    """(DataFrame, metadata) of the survey (module docstring). `duration_s` cuts the
    survey short (tests)."""
    return SurveyWorld(cfg, seed=seed, scenario=scenario, duration_s=duration_s,
                       anemometer=anemometer).table()
