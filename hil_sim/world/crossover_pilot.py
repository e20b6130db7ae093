"""A human-like pilot: McRuer's crossover model in nested loops, flying from the deck.

Sources: McRuer & Jex 1967, "A review of quasi-linear pilot models" (IEEE Trans. HFE-8):
around the crossover frequency w_c a human adapts to the controlled element Y_c so that
the open loop is Y_p Y_c ~ w_c e^(-tau_e s) / s, with the pilot

    Y_p(s) = K_p (T_L s + 1) e^(-tau s) / (T_N s + 1)

(gain K_p, lead T_L to cancel the plant's lag, reaction delay tau ~ 0.1-0.3 s,
neuromuscular lag T_N ~ 0.1 s); McRuer & Krendel 1974 (AGARDograph 188) for the
parameter ranges (w_c 2-5 rad/s on rate-like elements, lower on acceleration-like ones)
and the remnant; Levison, Baron & Kleinman 1969 for the remnant as observation noise
scaled to what is seen; Hess 1997 (structural model) and Padfield 2007 ch. 7 for
multi-loop helicopter tasks: inner attitude loops, outer position loops at roughly a
quarter of their crossover.

What the pilot sees is what a person on the deck sees: the helicopter's position, its
motion, its attitude and heading relative to the ship frame (not the air, not the
inflow, not the rotor) — perceived `reaction_delay_s` late, with Gauss-Markov
observation noise (the remnant). Loops, each a crossover-model element on the truth's
quasi-steady linear model at the initial trim (the "learned" helicopter):

    roll / pitch:  lat/lon cyclic from the attitude error, lead on the attitude rate,
                   T_L = 1 / (-L_p) (the rate lag the flybar rotor gives), K from w_c;
    yaw:           pedal from the heading error, lead on the yaw rate;
    heave:         collective from the height error, lead on the climb rate;
    position:      the wanted bank / pitch from the horizontal position error with lead
                   on the velocity error (T_L = 2 / w_c for the acceleration-like
                   element), plus the flight plan's acceleration as a feed-forward
                   (a pilot knows where the script goes next);
    trim:          a slow integral on each loop (a person re-trims over seconds) and the
                   collective-to-pedal cross-feed of the learned model.

Commands pass the neuromuscular lag and are held on the RC frame grid with a first-order
hold between decisions, exactly like the full-state pilot (`pilot.Pilot`): same
`update(k, x, ...)` / `command(t)` interface.
"""

from __future__ import annotations

import math

import numpy as np

from hil_sim.world.pilot import (
    COMMAND_MAX,
    COMMAND_MIN,
    CrossoverConfig,
    HeldCommands,
    Reference,
    wrap_pi,
)


class _Remnant:
    """Gauss-Markov observation noise per perceived quantity (unit variance, scaled)."""

    def __init__(self, n: int, dt: float, tau: float, rng: np.random.Generator) -> None:
        self.a = math.exp(-dt / tau)
        self.b = math.sqrt(1.0 - self.a**2)
        self.rng = rng
        self.state = rng.standard_normal(n)

    def step(self) -> np.ndarray:
        self.state = self.a * self.state + self.b * self.rng.standard_normal(self.state.size)
        return self.state


class CrossoverPilot(HeldCommands):
    """The human-like pilot for one flight (module docstring).

    `a`, `b`: the truth's linear model at `trim` (trim.x, trim.u), body states at
    `body_slice` ([pos, body velocity, Euler, rates]); `reference`: the flight plan."""

    def __init__(self, a: np.ndarray, b: np.ndarray, trim, reference: Reference,
                 config: CrossoverConfig, *, body_slice: slice,
                 rng: np.random.Generator) -> None:
        self.trim = trim
        self.ref = reference
        self.config = config
        self.body = body_slice
        self.dt = float(np.median(np.diff(reference.t_s))) if reference.t_s.size > 1 else 0.02
        c = config
        b0 = body_slice.start
        row = {"u": b0 + 3, "v": b0 + 4, "w": b0 + 5, "p": b0 + 9, "q": b0 + 10, "r": b0 + 11}
        lp = a[row["p"], row["p"]]
        mq = a[row["q"], row["q"]]
        nr = a[row["r"], row["r"]]
        zw = a[row["w"], row["w"]]
        l_lat = b[row["p"], 1]
        m_lon = b[row["q"], 2]
        n_ped = b[row["r"], 3]
        z_col = b[row["w"], 0]
        for name, gain in (("L_lat", l_lat), ("M_lon", m_lon), ("N_ped", n_ped),
                           ("Z_col", z_col)):
            if not np.isfinite(gain) or abs(gain) < 1e-6:
                raise ValueError(f"crossover pilot: the helicopter's {name} = {gain!r} "
                                 "gives no control authority to adapt to")

        def lead(damping):
            # cancel the rate lag 1 / (s - damping); a person leads at most max_lead_s
            return float(np.clip(1.0 / max(-damping, 1e-3), 0.1, c.max_lead_s))

        self.t_roll = lead(lp)
        self.t_pitch = lead(mq)
        self.t_yaw = lead(nr)
        self.t_heave = lead(zw)
        # crossover: K (control derivative) T_L = w_c
        self.k_roll = c.attitude_crossover_rad_s / (l_lat * self.t_roll)
        self.k_pitch = c.attitude_crossover_rad_s / (m_lon * self.t_pitch)
        self.k_yaw = c.yaw_crossover_rad_s / (n_ped * self.t_yaw)
        self.k_heave = c.heave_crossover_rad_s / (z_col * self.t_heave)
        # outer loop: x'' = g theta-like element (K/s^2): lead T_L = 2 / w_c, K g T_L = w_c
        self.t_pos = 2.0 / c.position_crossover_rad_s
        self.k_pos = c.position_crossover_rad_s / (9.8 * self.t_pos)
        self.cross_feed = -b[row["r"], 0] / n_ped  # pedal per collective, learned
        self.delay_knots = max(0, int(round(c.reaction_delay_s / self.dt)))
        self.nm = self.dt / (c.neuromuscular_lag_s + self.dt)
        self.remnant = _Remnant(12, self.dt, c.remnant_tau_s, rng)
        self.noise_scale = np.array(
            [c.position_noise_m] * 3 + [c.velocity_noise_m_s] * 3
            + [math.radians(c.attitude_noise_deg)] * 2 + [math.radians(c.heading_noise_deg)]
            + [math.radians(c.rate_noise_deg_s)] * 3)
        self.percepts: list[np.ndarray] = []
        self.integral = np.zeros(4)
        self.output = np.asarray(trim.u, float).copy()
        self._start_hold(reference, trim.u, self.dt)
        k = reference.t_s.size
        self.closed_loop_radius = float("nan")
        # the flight plan's acceleration (feed-forward), in the plan frame
        self.ref_acc = np.gradient(reference.vel_m_s, reference.t_s, axis=0) if k > 1 else \
            np.zeros((k, 3))

    def update(self, k: int, x: np.ndarray, pos_frame_m: np.ndarray,
               vel_frame_body_m_s: np.ndarray, yaw_frame_rad: float) -> np.ndarray:
        """At knot k decide the command for knot k+1 (same contract as pilot.Pilot)."""
        ref = self.ref
        b = self.body.start
        c = self.config
        psi_r = ref.yaw_rad[k]
        cr, sr = math.cos(psi_r), math.sin(psi_r)
        to_heading = np.array([[cr, sr, 0.0], [-sr, cr, 0.0], [0.0, 0.0, 1.0]])
        # what is seen now: position error in the reference-heading frame, velocity error
        # (body axes, the aircraft's own frame as seen), attitude, heading error, rates
        e_pos = to_heading @ (ref.pos_m[k] - pos_frame_m)
        e_vel = vel_frame_body_m_s - x[b + 3:b + 6]
        seen = np.concatenate([e_pos, e_vel, x[b + 6:b + 8],
                               [wrap_pi(psi_r - yaw_frame_rad)], x[b + 9:b + 12]])
        seen = seen + self.noise_scale * self.remnant.step()
        self.percepts.append(seen)
        # ... and acted on a reaction time later
        p = self.percepts[max(0, len(self.percepts) - 1 - self.delay_knots)]
        e_pos, e_vel = p[0:3], p[3:6]
        roll, pitch, e_yaw = p[6], p[7], p[8]
        rp, rq, rr = p[9], p[10], p[11]
        trim_u = self.trim.u
        x0 = self.trim.x
        acc_ff = to_heading @ self.ref_acc[min(k + self.delay_knots, ref.t_s.size - 1)]
        # outer loops: wanted pitch and bank from the position error (+ plan acceleration)
        g = 9.8
        ax = self.k_pos * g * (e_pos[0] + self.t_pos * e_vel[0]) + acc_ff[0]
        ay = self.k_pos * g * (e_pos[1] + self.t_pos * e_vel[1]) + acc_ff[1]
        lim = math.radians(c.max_bank_deg)
        pitch_cmd = x0[b + 7] + float(np.clip(-ax / g, -lim, lim))
        roll_cmd = x0[b + 6] + float(np.clip(ay / g, -lim, lim))
        e = np.array([
            -(e_pos[2] + self.t_heave * e_vel[2]),               # heave (down positive)
            roll_cmd - roll - self.t_roll * rp,                   # roll
            pitch_cmd - pitch - self.t_pitch * rq,                # pitch
            e_yaw - self.t_yaw * rr])                             # heading
        gains = np.array([-self.k_heave, self.k_roll, self.k_pitch, self.k_yaw])
        self.integral += self.dt / c.trim_time_s * gains * e
        self.integral = np.clip(self.integral, COMMAND_MIN - trim_u, COMMAND_MAX - trim_u)
        raw = trim_u + gains * e + self.integral
        raw[3] += self.cross_feed * (raw[0] - trim_u[0])
        raw += ref.excitation_rad[min(k + 1, ref.t_s.size - 1)]
        self.output = self.output + self.nm * (raw - self.output)
        return self._decide(k, self.output)
