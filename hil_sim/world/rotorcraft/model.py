"""The blade-element helicopter assembled from its parts: packing, trim, linearisation.

    heli = BladeElementHelicopter(load_airframe(), air_density_kg_m3=1.204, gravity_m_s2=9.80)
    tr = heli.trim(vel_ned_m_s=(0, 0, 0), yaw_rad=0.0)          # steady flight, rotor settled
    a, b = heli.linearize(tr)                                  # 12-state quasi-steady model
    x = tr.x.copy(); heli.integrate(x, t0, dt, n, tr.delta, tr.delta, heli.still_air())

Trim and linearisation hold the body ("captive", as on a whirl tower): the rotor, flybar,
inflow, drive and servos run until they settle, and the body accelerations the loads
would cause are averaged over whole revolutions (a two-bladed rotor's loads pulse at
2/rev). Trim solves, by Newton with finite-difference Jacobians, for the four commands,
roll, pitch and the governor's integral so that the averaged body accelerations vanish
and the rotor turns at the governor's set speed. Linearisation differentiates the same
averages (central differences) at the trim: a quasi-steady 12-state model
[position NED, body velocity, Euler angles, body rates] with the rotor states residualised,
what a pilot's model of the machine is.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from hil_sim.world.kinematics import euler_to_quat, quat_to_euler
from hil_sim.world.rotorcraft import (
    drive,
    dynamics,
    flybar,
    fuselage,
    main_rotor,
    servos,
    tail_rotor,
)
from hil_sim.world.rotorcraft.airframe import Airframe
from hil_sim.world.rotorcraft.dynamics import (
    AUX_ANG_ACC,
    AUX_OMEGA_DOT,
    AUX_SPECIFIC_FORCE,
    BETA,
    BODY_J,
    FLY,
    GOV,
    GYRO,
    N_AUX,
    N_ENV,
    N_STATES,
    NU0,
    OMEGA,
    PSI,
    QUAT,
    RATES,
    SERVO,
    SPEED_HELD,
    VEL,
)

DEFAULT_STEP_HZ = 2000.0
# the body-fixed grid on which the wind field is sampled (body axes, m): it spans the disc,
# the flybar, the tail rotor, the fuselage and the empennage
GRID_X = np.linspace(-0.97, 0.71, 8)
GRID_Y = np.linspace(-0.71, 0.71, 7)
GRID_Z = np.array([-0.30, 0.05])


class TrimError(RuntimeError):
    """The captive trim did not converge: what was left and where."""


@dataclass
class BladeTrim:
    """A trimmed flight condition: full state (rotor settled), commands, and how well."""

    x: np.ndarray
    delta: np.ndarray
    residual: float
    iterations: int
    info: dict = field(default_factory=dict)

    @property
    def body12(self) -> np.ndarray:
        return body_states(self.x[None])[0]


def body_states(xs: np.ndarray) -> np.ndarray:
    """(N, 12) [pos NED, body velocity, roll/pitch/yaw, body rates] from full states (N, S)."""
    euler = quat_to_euler(xs[:, QUAT:QUAT + 4])
    return np.column_stack([xs[:, 0:3], xs[:, VEL:VEL + 3], euler, xs[:, RATES:RATES + 3]])


class BladeElementHelicopter:
    """Packed parameters of one airframe and the compiled dynamics around them."""

    def __init__(self, airframe: Airframe, *, air_density_kg_m3: float, gravity_m_s2: float,
                 step_hz: float = DEFAULT_STEP_HZ) -> None:
        self.airframe = airframe
        self.rho = float(air_density_kg_m3)
        self.g = float(gravity_m_s2)
        self.dt = 1.0 / float(step_hz)
        self.mr, self.mre = main_rotor.pack(airframe)
        self.fb, self.fbe = flybar.pack(airframe)
        self.tr, self.tre = tail_rotor.pack(airframe)
        self.fus, self.fus_tab, self.emp = fuselage.pack(airframe)
        self.drv = drive.pack(airframe)
        self.srv = servos.pack(airframe)
        hub = np.asarray(airframe["main_rotor.hub_position_m"], float)
        rotor_mass = float(self.mre[:, 3].sum() + self.fbe[:, 3].sum())
        rigid = airframe["body.mass_kg"] - rotor_mass
        if rigid <= 0:
            raise ValueError(f"{airframe.path}: body.mass_kg = {airframe['body.mass_kg']} is "
                             f"below the blades' and flybar's {rotor_mass:.3f} kg")
        self.body = np.zeros(8)
        self.body[0] = rigid
        self.body[1:4] = -rotor_mass * hub / rigid  # total CG at the origin, rotor at rest
        self.body[BODY_J:BODY_J + 4] = [airframe["body.Ixx_kg_m2"], airframe["body.Iyy_kg_m2"],
                                        airframe["body.Izz_kg_m2"], airframe["body.Ixz_kg_m2"]]
        self.grid_shape = (GRID_X.size, GRID_Y.size, GRID_Z.size)
        mesh = np.meshgrid(GRID_X, GRID_Y, GRID_Z, indexing="ij")
        self.grid_nodes_body = np.stack([m.ravel() for m in mesh], axis=-1)  # (M, 3)
        self.grid_lo = np.array([GRID_X[0], GRID_Y[0], GRID_Z[0]])
        self.grid_inv = 1.0 / np.array([GRID_X[1] - GRID_X[0], GRID_Y[1] - GRID_Y[0],
                                        GRID_Z[1] - GRID_Z[0]])

    # -- geometry -------------------------------------------------------------------------

    @property
    def rotor_radius_m(self) -> float:
        return float(self.mr[main_rotor.MR_RADIUS])

    @property
    def hub_offset_body_m(self) -> np.ndarray:
        return self.mr[main_rotor.MR_HUB_X:main_rotor.MR_HUB_Z + 1].copy()

    @property
    def nominal_rotor_speed_rad_s(self) -> float:
        return float(self.drv[drive.DRV_SET])

    @property
    def mass_kg(self) -> float:
        return float(self.airframe["body.mass_kg"])

    # -- environment ----------------------------------------------------------------------

    def env(self, t0: float, t1: float) -> np.ndarray:
        e = np.zeros(N_ENV)
        e[dynamics.ENV_T0] = t0
        e[dynamics.ENV_T1] = t1
        e[dynamics.ENV_LO:dynamics.ENV_LO + 3] = self.grid_lo
        e[dynamics.ENV_INV:dynamics.ENV_INV + 3] = self.grid_inv
        e[dynamics.ENV_RHO] = self.rho
        e[dynamics.ENV_G] = self.g
        return e

    def uniform_wind(self, wind_ned_m_s=(0.0, 0.0, 0.0)) -> np.ndarray:
        """(nx, ny, nz, 3) grid snapshot of a uniform NED wind."""
        return np.broadcast_to(np.asarray(wind_ned_m_s, float),
                               self.grid_shape + (3,)).copy()

    def no_ground(self) -> np.ndarray:
        return np.zeros(self.grid_shape[:2])

    # -- integration ----------------------------------------------------------------------

    def packed(self) -> tuple:
        """The parameter arrays in dynamics.integrate's order (body .. srv)."""
        return (self.body, self.mr, self.mre, self.fb, self.fbe, self.tr, self.tre, self.fus,
                self.fus_tab, self.emp, self.drv, self.srv)

    def integrate(self, x, t0, n, delta0, delta1, env, w0, w1, g0, g1, out_x=None,
                  out_aux=None, out_start=-1, captive=0, dt=None) -> float:
        """n RK4 steps of `dt` (default `self.dt`; x updated in place); see
        dynamics.integrate."""
        if out_x is None:
            out_x = np.empty((1, N_STATES))
            out_aux = np.empty((1, N_AUX))
            out_start = -1
        return dynamics.integrate(
            x, float(t0), self.dt if dt is None else float(dt), int(n), np.asarray(delta0, float),
            np.asarray(delta1, float), *self.packed(), env, w0, w1, g0, g1, out_x, out_aux,
            int(out_start), int(captive))

    def initial_state(self, pos_ned, euler, vel_body, delta) -> np.ndarray:
        """A state at the given pose with the rotor at the set speed, servos at the
        command, inflow at the momentum value of the weight (the captive run settles it)."""
        x = np.zeros(N_STATES)
        x[0:3] = pos_ned
        x[VEL:VEL + 3] = vel_body
        x[QUAT:QUAT + 4] = euler_to_quat(np.asarray(euler, float))
        x[OMEGA] = self.nominal_rotor_speed_rad_s
        x[NU0] = math.sqrt(self.mass_kg * self.g / (2.0 * self.rho * math.pi
                                                    * self.rotor_radius_m**2))
        cmd = np.zeros(4)
        servos.servo_commands(np.asarray(delta, float), float(delta[3]), self.srv, cmd)
        x[SERVO:SERVO + 4] = cmd
        return x

    # -- captive runs, trim, linearisation -------------------------------------------------

    def revolution_steps(self, omega: float | None = None) -> int:
        w = self.nominal_rotor_speed_rad_s if omega is None else omega
        return max(1, int(round(2.0 * math.pi / w / self.dt)))

    def captive_average(self, x: np.ndarray, delta, wind_ned, ground, settle_s: float,
                        revs: int = 2) -> tuple[np.ndarray, np.ndarray]:
        """Run the rotor with the body held at x and the rotor speed held at x's: settle,
        then average over whole revolutions. Returns ((7,): the body velocity and rate
        derivatives the loads would cause, and the rotor's acceleration) and the settled
        state."""
        env = self.env(0.0, 0.0)
        w = self.uniform_wind(wind_ned)
        xs = x.copy()
        cmd = np.zeros(4)
        tail, _ = servos.tail_gyro(float(delta[3]), float(xs[RATES + 2]), float(xs[GYRO]),
                                   self.srv)
        servos.servo_commands(np.asarray(delta, float), tail, self.srv, cmd)
        xs[SERVO:SERVO + 4] = cmd
        xs[SERVO + 4:SERVO + 8] = 0.0
        # a step that divides the revolution exactly: the averages of the 1/rev and 2/rev
        # loads vanish over whole revolutions
        per_rev = self.revolution_steps(xs[OMEGA])
        dt = 2.0 * math.pi / xs[OMEGA] / per_rev
        n_settle = int(round(settle_s / dt))
        self.integrate(xs, 0.0, n_settle, delta, delta, env, w, w, ground, ground,
                       captive=SPEED_HELD, dt=dt)
        n = revs * per_rev
        ox = np.empty((n, N_STATES))
        oa = np.empty((n, N_AUX))
        self.integrate(xs, 0.0, n, delta, delta, env, w, w, ground, ground, ox, oa, 0,
                       SPEED_HELD, dt=dt)
        # body velocity derivative = specific force + g - w x v (constant while captive)
        rot_g = _gravity_body(xs, self.g)
        wv = np.cross(xs[RATES:RATES + 3], xs[VEL:VEL + 3])
        acc = oa[:, AUX_SPECIFIC_FORCE:AUX_SPECIFIC_FORCE + 3].mean(0) + rot_g - wv
        out = np.concatenate([acc, oa[:, AUX_ANG_ACC:AUX_ANG_ACC + 3].mean(0),
                              [oa[:, AUX_OMEGA_DOT].mean()]])
        return out, xs

    def trim(self, vel_ned_m_s=(0.0, 0.0, 0.0), yaw_rad: float = 0.0, wind_ned_m_s=(0.0, 0.0,
             0.0), ground=None, pos_ned_m=(0.0, 0.0, -3.0), tol: float = 2e-3,
             max_iter: int = 25) -> BladeTrim:
        """Steady flight at the given inertial velocity and heading in a uniform wind
        (module docstring). `ground`: the ground-upwash grid under the disc (None: none)."""
        ground = self.no_ground() if ground is None else ground
        vel_ned = np.asarray(vel_ned_m_s, float)
        omega_set = self.nominal_rotor_speed_rad_s
        # unknowns: col, lat, lon, ped, roll, pitch, governor integral
        z = np.array([math.radians(5.0), 0.0, 0.0, math.radians(4.0), 0.0, 0.0, 0.0])
        scale = np.array([1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0 / 300.0])
        state = None

        def build(zz, base):
            euler = np.array([zz[4], zz[5], yaw_rad])
            q = euler_to_quat(euler)
            from hil_sim.world.kinematics import quat_to_dcm
            v_body = quat_to_dcm(q).T @ vel_ned
            if base is None:
                x = self.initial_state(pos_ned_m, euler, v_body, zz[:4])
            else:
                x = base.copy()
                x[QUAT:QUAT + 4] = q
                x[VEL:VEL + 3] = v_body
            x[OMEGA] = omega_set
            x[GOV] = zz[6]
            return x

        def residual(zz, base, settle):
            out, xs = self.captive_average(build(zz, base), zz[:4], wind_ned_m_s, ground,
                                           settle)
            r = out.copy()
            r[6] = out[6] * 0.02  # rotor acceleration, rad/s^2 -> comparable to m/s^2
            return r, xs

        r, state = residual(z, None, 0.6)
        iterations = 0
        err = float(np.max(np.abs(r)))
        while err >= tol and iterations < max_iter:
            iterations += 1
            jac = np.empty((7, 7))
            for k in range(7):
                h = 1e-3 / scale[k] if k < 6 else 2e-3 / scale[k]
                zp = z.copy()
                zp[k] += h
                rp, _ = residual(zp, state, 0.25)
                zm = z.copy()
                zm[k] -= h
                rm, _ = residual(zm, state, 0.25)
                jac[:, k] = (rp - rm) / (2 * h)
            step = np.linalg.lstsq(jac, -r, rcond=None)[0]
            big = np.max(np.abs(step[:6]))
            if big > 0.1:
                step *= 0.1 / big
            z = z + step
            r, state = residual(z, state, 0.4)
            err = float(np.max(np.abs(r)))
        if err > 50 * tol:
            raise TrimError(f"blade-element trim at v = {vel_ned.tolist()} m/s did not "
                            f"converge: residual {np.round(r, 4).tolist()}")
        x = build(z, state)
        # settle once more as the free flight will start from it
        _, x = self.captive_average(x, z[:4], wind_ned_m_s, ground, 0.3)
        return BladeTrim(x=x, delta=z[:4].copy(), residual=err, iterations=iterations,
                         info={"governor_integral": float(z[6])})

    def linearize(self, trim: BladeTrim, wind_ned_m_s=(0.0, 0.0, 0.0), ground=None
                  ) -> tuple[np.ndarray, np.ndarray]:
        """Quasi-steady (A (12, 12), B (12, 4)) at a trim (module docstring)."""
        ground = self.no_ground() if ground is None else ground
        base12 = trim.body12

        def f12(b12, delta):
            x = trim.x.copy()
            x[0:3] = b12[0:3]
            x[VEL:VEL + 3] = b12[3:6]
            x[QUAT:QUAT + 4] = euler_to_quat(b12[6:9])
            x[RATES:RATES + 3] = b12[9:12]
            out, _ = self.captive_average(x, delta, wind_ned_m_s, ground, 0.25)
            return _f12_from(b12, out[:6])

        n, m = 12, 4
        a = np.zeros((n, n))
        b = np.zeros((n, m))
        for k in (3, 4, 5, 6, 7, 9, 10, 11):
            h = 0.05 if k < 6 else (0.01 if k < 9 else 0.02)
            xp = base12.copy()
            xp[k] += h
            xm = base12.copy()
            xm[k] -= h
            a[:, k] = (f12(xp, trim.delta) - f12(xm, trim.delta)) / (2 * h)
        # yaw enters only the position kinematics
        for k in (8,):
            h = 0.01
            xp = base12.copy()
            xp[k] += h
            xm = base12.copy()
            xm[k] -= h
            a[:, k] = (_f12_from(xp, np.zeros(6)) - _f12_from(xm, np.zeros(6))) / (2 * h)
            a[3:6, k] = 0.0
            a[9:12, k] = 0.0
        for k in range(m):
            h = math.radians(0.3)
            dp = trim.delta.copy()
            dp[k] += h
            dm = trim.delta.copy()
            dm[k] -= h
            b[:, k] = (f12(base12, dp) - f12(base12, dm)) / (2 * h)
        return a, b


def _gravity_body(x: np.ndarray, g: float) -> np.ndarray:
    from hil_sim.world.kinematics import quat_to_dcm
    return quat_to_dcm(x[QUAT:QUAT + 4]).T @ np.array([0.0, 0.0, g])


def _f12_from(b12: np.ndarray, acc6: np.ndarray) -> np.ndarray:
    """d/dt of [pos NED, body velocity, Euler, rates] given the body accelerations."""
    from hil_sim.world.kinematics import euler_to_dcm
    phi, theta = b12[6], b12[7]
    rot = euler_to_dcm(b12[6:9])
    p, q, r = b12[9:12]
    sp, cp = math.sin(phi), math.cos(phi)
    tt, ct = math.tan(theta), math.cos(theta)
    euler_dot = np.array([p + (q * sp + r * cp) * tt, q * cp - r * sp, (q * sp + r * cp) / ct])
    return np.concatenate([rot @ b12[3:6], acc6[:3], euler_dot, acc6[3:6]])


__all__ = ["BETA", "FLY", "PSI", "NU0", "BladeElementHelicopter", "BladeTrim", "TrimError",
           "body_states"]
