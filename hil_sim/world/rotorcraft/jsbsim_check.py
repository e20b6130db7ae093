"""A second opinion from an established engine: the airframe as a JSBSim FGRotor model.

    python -m hil_sim.world.rotorcraft.jsbsim_check            # markdown table, 0..8 m/s
    rows = compare(speeds_m_s=(0.0, 4.0, 8.0))                 # [ComparisonRow, ...]

`write_jsbsim_model` generates a JSBSim aircraft (XML) from the airframe file, nothing
hand-copied: JSBSim's FGRotor (T. Kreitler, after Shaugnessy, Deaux & Yenni 1979, NASA
TP-1285, and Talbot et al. 1982, NASA TM-84281) is a closed-form rotor: uniform
momentum inflow with a first-order lag, thrust, coning and first-harmonic flapping from
the integrated blade-element equations with one air velocity at the hub, hub moment from
an equivalent hinge offset, a fixed profile-drag polar. What the generator feeds it:

    radius, chord, blade count, twist        main_rotor.* / tail_rotor.*
    lift-curve slope                         least-squares slope of the NACA 0012 table
                                             (airfoil.py) over 0..6 deg, the table our
                                             blades fly on
    tip-loss factor B                        Prandtl's approximation B = 1 - sqrt(2 C_T) / N
                                             (Johnson, Helicopter Theory, 1980, eq. 4.8 ff.)
                                             at the hover C_T of the weight (main) or of
                                             the hover anti-torque thrust (tail)
    flapping moment I_b, mass moment S_b     sum m r^2 and sum m r of one blade's elements
                                             (main_rotor.pack), so the Lock number is ours
    hinge offset e                           the teetering hub's spring K: a teetering
                                             rotor's mean hub moment is K/2 per rad of disc
                                             tilt; FGRotor's is e N Omega^2 S_b / 2, so
                                             e = K / (N Omega^2 S_b)
    hub and tail-rotor positions, shaft      main_rotor.hub_position_m (shaft along body z),
                                             tail_rotor.hub_position_m (shaft along body y)
    rotor speed                              drive.governor_speed_rpm held exactly (an ideal
                                             governor, `ExternalRPM`), the tail geared by
                                             tail_rotor.gear_ratio; the motor is JSBSim's
                                             brushless DC motor with our kV, resistance,
                                             no-load current and pack voltage
    mass, inertia                            body.* plus the blades and flybar averaged over
                                             a revolution
    fuselage, stabiliser, fin                the drag areas of our fuselage tables (pod:
                                             frontal C_D0 w h and crossflow C_dc x plan/side
                                             area at the reference point; boom: crossflow at
                                             its centroid) in the form of Gavrilets, Mettler
                                             & Feron 2001: each part, and the stabiliser,
                                             in the disc's induced velocity while the wake
                                             column (leaving at FGRotor's downwash angle)
                                             covers it; lift slopes by Helmbold's equation

Two things FGRotor cannot take: the Bell-Hiller flybar (its blade pitch is the control)
and the sense of rotation in its flapping: FGRotor's flapping and side-force equations
are those of a counter-clockwise rotor whatever `sense` says (sense only flips the
torque). A clockwise airframe is therefore modelled as its mirror image (y -> -y,
rotation reversed) and the lateral results mirrored back
(docs/truth-world.md, "Second opinion: JSBSim").

The trim: JSBSim's own FGTrim pairs udot with the throttle and wdot with alpha, which a
helicopter's throttle (the rotor speed is governed) and a hovering alpha cannot trim;
`JSBSimHelicopter.trim` therefore solves the six body accelerations for collective,
lateral, longitudinal, pedal, roll and pitch by Newton's method, each evaluation running
JSBSim's models with the integration suspended until FGRotor's lagged inflow has settled.

Our side (`ours`): `BladeElementHelicopter.trim`, with the blade pitch measured at the
blades (collective and the first harmonic of the cyclic, swashplate, rigging and flybar
together), which is what FGRotor's controls are.
"""

from __future__ import annotations

import math
import tempfile
from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import escape

import numpy as np

from hil_sim.world.rotorcraft import airfoil, flybar, main_rotor
from hil_sim.world.rotorcraft.airframe import Airframe, load_airframe

MODEL_NAME = "airwake_blade_element"
FT = 0.3048              # m
IN = 0.0254              # m
SLUG = 14.59390294       # kg
LBF = 4.4482216152605    # N
SLUG_FT2 = SLUG * FT**2  # kg m^2
RANKINE = 5.0 / 9.0      # K
DEFAULT_SPEEDS_M_S = (0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0)
DEFAULT_DENSITY = 1.204  # kg/m^3, 20 C at sea-level pressure (the project's still-air value)
LIFT_SLOPE_FIT_DEG = (0.0, 6.0)
INFLOW_SETTLE_RUNS = 400  # JSBSim frames with integration suspended per evaluation


class JSBSimCheckError(RuntimeError):
    """The JSBSim model could not be built or trimmed: what and where."""


# -- parameters derived from the airframe ----------------------------------------------------

def lift_curve_slope_per_rad() -> float:
    """Least-squares slope through the origin of the NACA 0012 table (airfoil.py) over
    LIFT_SLOPE_FIT_DEG: the attached-flow slope our blades fly on."""
    a, cl, _ = airfoil.load_table()
    sel = (a >= LIFT_SLOPE_FIT_DEG[0]) & (a <= LIFT_SLOPE_FIT_DEG[1])
    x = np.radians(a[sel])
    return float(np.dot(x, cl[sel]) / np.dot(x, x))


def helmbold_slope(area_m2: float, span_m: float) -> float:
    """Finite-wing lift slope per rad (Helmbold 1942)."""
    aspect = span_m**2 / area_m2
    return 2.0 * math.pi * aspect / (2.0 + math.sqrt(aspect**2 + 4.0))


def prandtl_tip_loss_factor(c_t: float, n_blades: int) -> float:
    """B = 1 - sqrt(2 C_T) / N (Prandtl's tip loss in its classical closed form)."""
    return 1.0 - math.sqrt(2.0 * max(c_t, 0.0)) / n_blades


def fgrotor_hover_torque(thrust_n, rho, radius, chord, n_blades, omega, slope, tip_loss):
    """FGRotor's own hover torque (N m) at a thrust: momentum induced torque plus its
    profile term (calc_torque), used only to size the tail rotor's tip loss."""
    area = math.pi * radius**2
    vtip = omega * radius
    sigma = n_blades * chord / (math.pi * radius)
    c_t = thrust_n / (rho * area * vtip**2)
    nu = math.sqrt(c_t / 2.0) / tip_loss
    delta = 0.009 + 0.3 * (6.0 * c_t / (slope * sigma)) ** 2
    profile = rho * n_blades * chord * delta * vtip**2 * radius**2 / 8.0
    return profile + thrust_n * nu * radius


@dataclass(frozen=True)
class RotorSpec:
    """One FGRotor, SI units."""

    name: str
    radius_m: float
    chord_m: float
    n_blades: int
    twist_rad: float
    lift_slope: float
    tip_loss: float
    flap_inertia_kg_m2: float
    mass_moment_kg_m: float
    polar_inertia_kg_m2: float
    hinge_offset_m: float
    rpm: float
    gear_ratio: float
    inflow_lag_s: float
    location_body_m: tuple
    sense: int
    tail: bool
    thrust_y: float = 0.0       # tail rotor: side its thrust points to (+1 right, -1 left)

    @property
    def lock_number_at(self) -> float:
        """Lock number per unit density (gamma / rho)."""
        return self.lift_slope * self.chord_m * self.radius_m**4 / self.flap_inertia_kg_m2


@dataclass(frozen=True)
class JSBSimAirframe:
    """Everything the XML is written from (SI, body axes FRD about the CG)."""

    mass_kg: float
    inertia_kg_m2: tuple        # Ixx, Iyy, Izz, Ixz
    main: RotorSpec
    tail: RotorSpec
    motor: dict
    fuselage: dict
    stabilizer: dict
    fin: dict
    mirrored: bool


def derive(airframe: Airframe, *, rho: float, g: float, mirror: bool | None = None
           ) -> JSBSimAirframe:
    """The FGRotor airframe from ours (module docstring). `mirror`: model the mirror image
    (default: when our main rotor turns clockwise, which FGRotor's flapping cannot)."""
    m = airframe.part("main_rotor")
    t = airframe.part("tail_rotor")
    d = airframe.part("drive")
    if mirror is None:
        mirror = m["rotation"] == "clockwise"
    ys = -1.0 if mirror else 1.0
    slope = lift_curve_slope_per_rad()
    mass = airframe["body.mass_kg"]
    omega = d["governor_speed_rpm"] * 2.0 * math.pi / 60.0

    # main rotor: one blade's element table (blade 0 carries the imbalance: take the mean)
    _, elements = main_rotor.pack(airframe)
    r, mel = elements[:, 1], elements[:, 3]
    i_b = float(np.sum(mel * r**2)) / 2.0
    s_b = float(np.sum(mel * r)) / 2.0
    _, fb_el = flybar.pack(airframe)
    i_fb = float(np.sum(fb_el[:, 3] * fb_el[:, 1] ** 2))
    area = math.pi * m["radius_m"] ** 2
    vtip = omega * m["radius_m"]
    c_t = mass * g / (rho * area * vtip**2)
    b_main = prandtl_tip_loss_factor(c_t, 2)
    gamma_per_rho = slope * m["chord_m"] * m["radius_m"] ** 4 / i_b
    hinge = m["hub_spring_nm_rad"] / (2.0 * omega**2 * s_b)
    # FGRotor: sense +1 = counter-clockwise seen from above; the mirror reverses it
    ccw = (m["rotation"] == "counterclockwise") != mirror
    hub = np.asarray(m["hub_position_m"], float)
    main = RotorSpec(
        name="main_rotor", radius_m=m["radius_m"], chord_m=m["chord_m"], n_blades=2,
        twist_rad=math.radians(m["twist_deg"]), lift_slope=slope, tip_loss=b_main,
        flap_inertia_kg_m2=i_b, mass_moment_kg_m=s_b,
        polar_inertia_kg_m2=2.0 * i_b + i_fb + d["shaft_inertia_kg_m2"],
        hinge_offset_m=hinge, rpm=d["governor_speed_rpm"], gear_ratio=d["gear_ratio"],
        inflow_lag_s=16.0 / (gamma_per_rho * rho * omega),
        location_body_m=(hub[0], ys * hub[1], hub[2]), sense=1 if ccw else -1, tail=False)

    # tail rotor: blades' flap inertia from the stated polar inertia (two blades), a
    # uniform blade's mass moment 3 I_b / (2 R); no hinge offset (rigid-ish, no moment)
    t_omega = omega * t["gear_ratio"]
    t_hub = np.asarray(t["hub_position_m"], float)
    arm = math.hypot(t_hub[0], t_hub[1])
    q_hover = fgrotor_hover_torque(mass * g, rho, m["radius_m"], m["chord_m"], 2, omega,
                                   slope, b_main)
    t_area = math.pi * t["radius_m"] ** 2
    c_tt = (q_hover / arm) / (rho * t_area * (t_omega * t["radius_m"]) ** 2)
    i_bt = t["polar_inertia_kg_m2"] / 2.0
    gamma_t = slope * t["chord_m"] * t["radius_m"] ** 4 / i_bt
    # our tail thrust (positive pitch) pushes the tail to the side that yaws the nose
    # against the main rotor's torque; in FGRotor, sense +1 spins the rotor about its
    # thrust axis. Tail rotor spin vector: +y for top_blade_aft (right-handed about y).
    thrust_y = -1.0 if m["rotation"] == "clockwise" else 1.0  # ours: to the left for CW
    spin_y = 1.0 if t["rotation"] == "top_blade_aft" else -1.0
    if mirror:  # y -> -y: a polar vector's y flips, an axial vector's y does not
        thrust_y = -thrust_y
    tail = RotorSpec(
        name="tail_rotor", radius_m=t["radius_m"], chord_m=t["chord_m"], n_blades=2,
        twist_rad=0.0, lift_slope=slope, tip_loss=prandtl_tip_loss_factor(c_tt, 2),
        flap_inertia_kg_m2=i_bt, mass_moment_kg_m=1.5 * i_bt / t["radius_m"],
        polar_inertia_kg_m2=t["polar_inertia_kg_m2"], hinge_offset_m=0.0,
        rpm=d["governor_speed_rpm"] * t["gear_ratio"],
        gear_ratio=d["gear_ratio"] / t["gear_ratio"],
        inflow_lag_s=16.0 / (gamma_t * rho * t_omega),
        location_body_m=(t_hub[0], ys * t_hub[1], t_hub[2]),
        sense=1 if spin_y * thrust_y > 0 else -1, tail=True, thrust_y=thrust_y)

    # mass and inertia: the rigid body plus the blades and flybar averaged over azimuth
    rot_m = np.concatenate([mel, fb_el[:, 3]])
    rot_r = np.concatenate([r, fb_el[:, 1]])
    h2 = float(hub[2] ** 2)
    ixx = airframe["body.Ixx_kg_m2"] + float(np.sum(rot_m * (rot_r**2 / 2.0 + h2)))
    iyy = airframe["body.Iyy_kg_m2"] + float(np.sum(rot_m * (rot_r**2 / 2.0 + h2)))
    izz = airframe["body.Izz_kg_m2"] + float(np.sum(rot_m * rot_r**2))
    ixz = airframe["body.Ixz_kg_m2"]  # unchanged by y -> -y

    f = airframe.part("fuselage")
    ref = np.asarray(f["reference_point_m"], float)
    c_dc = f["crossflow_drag_coefficient"]
    boom_area = f["boom_length_m"] * f["boom_diameter_m"]
    # the boom's centroid, as fuselage.slender_body_coefficients places it
    boom_x = -0.5 * f["length_m"] + ref[0] - 0.5 * f["boom_length_m"]
    fuselage = {  # drag areas C S (m^2) along body x, y, z and where they act
        "pod": {"point_m": (ref[0], ys * ref[1], ref[2]),
                "S_m2": (f["frontal_drag_coefficient"] * f["width_m"] * f["height_m"],
                         c_dc * f["length_m"] * f["height_m"],
                         c_dc * f["length_m"] * f["width_m"])},
        "boom": {"point_m": (boom_x, ys * ref[1], ref[2]),
                 "S_m2": (0.0, c_dc * boom_area, c_dc * boom_area)},
    }
    hs = airframe.part("horizontal_stabilizer")
    vf = airframe.part("vertical_fin")
    hs_pos = np.asarray(hs["position_m"], float)
    vf_pos = np.asarray(vf["position_m"], float)
    stabilizer = {"point_m": (hs_pos[0], ys * hs_pos[1], hs_pos[2]), "area_m2": hs["area_m2"],
                  "slope": helmbold_slope(hs["area_m2"], hs["span_m"]) if hs["area_m2"] > 0
                  else 0.0, "incidence_rad": math.radians(hs["incidence_deg"])}
    fin = {"point_m": (vf_pos[0], ys * vf_pos[1], vf_pos[2]), "area_m2": vf["area_m2"],
           "slope": helmbold_slope(vf["area_m2"], vf["span_m"]) if vf["area_m2"] > 0 else 0.0}
    motor = {"kv": d["motor_kv_rpm_per_v"], "resistance_ohm": d["motor_resistance_ohm"],
             "no_load_current_a": d["no_load_current_a"],
             "max_volts": d["battery_cells"] * d["cell_voltage_v"]}
    return JSBSimAirframe(mass_kg=mass, inertia_kg_m2=(ixx, iyy, izz, ixz), main=main,
                          tail=tail, motor=motor, fuselage=fuselage, stabilizer=stabilizer,
                          fin=fin, mirrored=mirror)


# -- XML ------------------------------------------------------------------------------------

def _structural_in(p_body_m) -> tuple[float, float, float]:
    """Body FRD (m, about the CG) -> JSBSim structural frame (x aft, y right, z up; in)."""
    return (-p_body_m[0] / IN, p_body_m[1] / IN, -p_body_m[2] / IN)


def _loc(tag_name: str | None, p_body_m) -> str:
    x, y, z = _structural_in(p_body_m)
    name = f' name="{tag_name}"' if tag_name else ""
    return (f'<location{name} unit="IN"> <x> {x:.6f} </x> <y> {y:.6f} </y> '
            f'<z> {z:.6f} </z> </location>')


def rotor_xml(spec: RotorSpec) -> str:
    lines = [
        '<?xml version="1.0"?>',
        '<!-- generated by hil_sim/world/rotorcraft/jsbsim_check.py from the airframe file -->',
        f'<rotor name="{spec.name}">',
        f'  <diameter unit="FT"> {2.0 * spec.radius_m / FT:.8f} </diameter>',
        f'  <numblades> {spec.n_blades} </numblades>',
        f'  <gearratio> {spec.gear_ratio:.8f} </gearratio>',
        f'  <nominalrpm> {spec.rpm:.6f} </nominalrpm>',
        f'  <chord unit="FT"> {spec.chord_m / FT:.8f} </chord>',
        f'  <liftcurveslope> {spec.lift_slope:.6f} </liftcurveslope>',
        f'  <twist unit="RAD"> {spec.twist_rad:.8f} </twist>',
        f'  <hingeoffset unit="FT"> {spec.hinge_offset_m / FT:.8f} </hingeoffset>',
        f'  <flappingmoment unit="SLUG*FT2"> {spec.flap_inertia_kg_m2 / SLUG_FT2:.10g} '
        '</flappingmoment>',
        f'  <massmoment> {spec.mass_moment_kg_m / (SLUG * FT):.10g} </massmoment>',
        f'  <polarmoment unit="SLUG*FT2"> {spec.polar_inertia_kg_m2 / SLUG_FT2:.10g} '
        '</polarmoment>',
        f'  <inflowlag> {spec.inflow_lag_s:.6f} </inflowlag>',
        f'  <tiplossfactor> {spec.tip_loss:.6f} </tiplossfactor>',
    ]
    if spec.tail:
        lines += ['  <ExternalRPM> 0 </ExternalRPM>', '  <controlmap> TAIL </controlmap>']
    else:
        lines += ['  <ExternalRPM> -1 </ExternalRPM>']
    lines.append('</rotor>')
    return "\n".join(lines) + "\n"


def motor_xml(motor: dict) -> str:
    return ('<?xml version="1.0"?>\n'
            '<!-- generated by hil_sim/world/rotorcraft/jsbsim_check.py (drive.*) -->\n'
            '<brushless_dc_motor name="drive_motor">\n'
            f'  <velocityconstant> {motor["kv"]:.6f} </velocityconstant>\n'
            f'  <coilresistance> {motor["resistance_ohm"]:.6f} </coilresistance>\n'
            f'  <noloadcurrent> {motor["no_load_current_a"]:.6f} </noloadcurrent>\n'
            f'  <maxvolts> {motor["max_volts"]:.6f} </maxvolts>\n'
            '</brushless_dc_motor>\n')


def _p(name):
    return f"<p> {name} </p>"


def _v(x):
    return f"<v> {x:.10g} </v>"


def _prod(*terms):
    return "<product> " + " ".join(terms) + " </product>"


def _sum(*terms):
    return "<sum> " + " ".join(terms) + " </sum>"


def _fn(name, body, description=""):
    desc = f"<description> {escape(description)} </description> " if description else ""
    return f'    <function name="{name}"> {desc}{body} </function>'


def _moment_terms(point_body_m, force_props):
    """{axis: [function body, ...]} of r x F (ft lbf) for a force given as body-axis
    property names (lbf or None) acting at point_body_m."""
    x, y, z = (c / FT for c in point_body_m)
    fx, fy, fz = force_props
    out = {"ROLL": [], "PITCH": [], "YAW": []}

    def add(axis, coef, prop):
        if prop is not None and abs(coef) > 1e-12:
            out[axis].append(_prod(_v(coef), _p(prop)))
    add("ROLL", y, fz)      # L = y Fz - z Fy
    add("ROLL", -z, fy)
    add("PITCH", z, fx)     # M = z Fx - x Fz
    add("PITCH", -x, fz)
    add("YAW", x, fy)       # N = x Fy - y Fx
    add("YAW", -y, fx)
    return out


def aerodynamics_xml(a: JSBSimAirframe) -> str:
    """Fuselage drag areas, stabiliser and fin after Gavrilets, Mettler & Feron 2001, in
    body axes about the CG (AERORP = CG)."""
    rho = _p("atmosphere/rho-slugs_ft3")
    u, v, w = (_p(f"velocities/{c}-aero-fps") for c in "uvw")
    p_, q_, r_ = (f"velocities/{c}-aero-rad_sec" for c in "pqr")
    vi = _p("propulsion/engine[0]/vi-fps")
    ft2 = 1.0 / FT**2
    hs, fin = a.stabilizer, a.fin
    hub = a.main.location_body_m
    radius_ft = a.main.radius_m / FT
    f = []

    def in_wake(name, point_m):
        """1 where the main rotor's wake column covers the point (it leaves the disc at
        FGRotor's downwash angle theta_dw, positive forward; a 10 % R soft edge)."""
        xs = (point_m[0] - hub[0]) / FT
        dz = max(point_m[2] - hub[2], 0.0) / FT
        f.append(_fn(f"aero/{name}/wake-offset-ft", "<difference> " + _v(xs) + " " + _prod(
            _v(dz), "<tan> " + _p("propulsion/engine[0]/theta-downwash-rad") + " </tan>")
            + " </difference>", f"{name}: distance from the wake column's axis"))
        edge = 0.1 * radius_ft
        f.append(_fn(f"aero/{name}/in-wake", f"<table> <independentVar> aero/{name}/"
                     "wake-offset-ft </independentVar> <tableData>\n"
                     f"      {-radius_ft - edge:.6f} 0\n      {-radius_ft + edge:.6f} 1\n"
                     f"      {radius_ft - edge:.6f} 1\n      {radius_ft + edge:.6f} 0\n"
                     "    </tableData> </table>"))
        return _p(f"aero/{name}/in-wake")

    # fuselage pod and boom: X = -rho/2 S_x u V, Y = -rho/2 S_y v V,
    # Z = -rho/2 S_z (w - K v_i) V, V = |(u, v, w - K v_i)|, K = 1 in the wake column
    body_forces = {"X": [], "Y": [], "Z": []}
    moments = {"ROLL": [], "PITCH": [], "YAW": []}
    for name, part in a.fuselage.items():
        k = in_wake(name, part["point_m"])
        f.append(_fn(f"aero/{name}/w-rel-fps", _sum(w, _prod(_v(-1.0), k, vi)),
                     f"{name}: vertical speed relative to the main rotor's induced flow"))
        wrel = _p(f"aero/{name}/w-rel-fps")
        f.append(_fn(f"aero/{name}/speed-fps", "<pow> " + _sum(_prod(u, u), _prod(v, v),
                                                              _prod(wrel, wrel))
                     + " <v> 0.5 </v> </pow>"))
        props = []
        for axis, comp, area in zip("xyz", (u, v, wrel), part["S_m2"], strict=True):
            if area <= 0.0:
                props.append(None)
                continue
            prop = f"aero/{name}/F{axis}-lbs"
            f.append(_fn(prop, _prod(_v(-0.5 * area * ft2), rho, comp,
                                     _p(f"aero/{name}/speed-fps")),
                         f"{name}: drag area {area:.5f} m2 along body {axis}"))
            body_forces[axis.upper()].append(prop)
            props.append(prop)
        for axis, terms in _moment_terms(part["point_m"], props).items():
            moments[axis] += terms
    k_ht = in_wake("ht", hs["point_m"])
    xh_ft = hs["point_m"][0] / FT
    f.append(_fn("aero/ht/w-fps", _sum(w, _prod(_v(-xh_ft), _p(q_)), _prod(
        _v(-1.0), k_ht, vi)),
        "normal velocity at the stabiliser: w - q x_ht - K v_i"))
    uabs = f"<abs> {u} </abs>"
    wht = _p("aero/ht/w-fps")
    f.append(_fn("aero/ht/Fz-lbs", _prod(_v(-0.5 * hs["area_m2"] * ft2), rho, _sum(
        _prod(_v(hs["slope"]), uabs, wht),
        _prod(_v(hs["slope"] * hs["incidence_rad"]), uabs, u),
        _prod(f"<abs> {wht} </abs>", wht))),
        "stabiliser: -rho/2 S (a |u| w_ht + a i u|u| + |w_ht| w_ht)"))
    xf_ft, zf_ft = fin["point_m"][0] / FT, fin["point_m"][2] / FT
    f.append(_fn("aero/vt/v-fps", _sum(v, _prod(_v(xf_ft), _p(r_)), _prod(_v(-zf_ft),
                                                                          _p(p_))),
                 "lateral velocity at the fin: v + r x_vt - p z_vt"))
    vvt = _p("aero/vt/v-fps")
    f.append(_fn("aero/vt/Fy-lbs", _prod(_v(-0.5 * fin["area_m2"] * ft2), rho, _sum(
        _prod(_v(fin["slope"]), uabs, vvt), _prod(f"<abs> {vvt} </abs>", vvt))),
        "fin: -rho/2 S (a |u| v_vt + |v_vt| v_vt)"))

    body_forces["Y"].append("aero/vt/Fy-lbs")
    body_forces["Z"].append("aero/ht/Fz-lbs")
    for point, props in ((hs["point_m"], (None, None, "aero/ht/Fz-lbs")),
                         (fin["point_m"], (None, "aero/vt/Fy-lbs", None))):
        for axis, terms in _moment_terms(point, props).items():
            moments[axis] += terms
    axes = []
    for axis, props in body_forces.items():
        axes.append(f'    <axis name="{axis}"> <function name="aero/force/{axis}-total"> '
                    + _sum(*[_p(pp) for pp in props], _v(0.0)) + " </function> </axis>")
    for axis, terms in moments.items():
        axes.append(f'    <axis name="{axis}"> <function name="aero/moment/{axis}-total"> '
                    + _sum(*terms, _v(0.0)) + " </function> </axis>")
    return "  <aerodynamics>\n" + "\n".join(f) + "\n" + "\n".join(axes) + "\n  </aerodynamics>\n"


def aircraft_xml(a: JSBSimAirframe) -> str:
    ixx, iyy, izz, ixz = (i / SLUG_FT2 for i in a.inertia_kg_m2)
    origin = (0.0, 0.0, 0.0)

    def thruster(spec: RotorSpec, orient: tuple[float, float, float]) -> str:
        return (f'    <engine file="drive_motor">\n'
                f'      <thruster file="{spec.name}">\n'
                f'        {_loc(None, spec.location_body_m)}\n'
                f'        <orient unit="DEG"> <roll> {orient[0]} </roll> <pitch> {orient[1]} '
                f'</pitch> <yaw> {orient[2]} </yaw> </orient>\n'
                f'        <sense> {spec.sense} </sense>\n'
                '      </thruster>\n    </engine>\n')

    tail_yaw = 90.0 if a.tail.thrust_y > 0 else -90.0
    mirror_note = " (its mirror image: FGRotor flaps counter-clockwise)" if a.mirrored else ""
    disc_ft2 = math.pi * (a.main.radius_m / FT) ** 2
    return (
        '<?xml version="1.0"?>\n'
        f'<fdm_config name="{MODEL_NAME}" version="2.0" release="ALPHA">\n'
        '  <fileheader>\n'
        '    <author> generated by hil_sim/world/rotorcraft/jsbsim_check.py </author>\n'
        '    <description> The blade-element truth airframe as a JSBSim FGRotor helicopter'
        f'{mirror_note}. </description>\n'
        '  </fileheader>\n'
        '  <metrics>\n'
        f'    <wingarea unit="FT2"> {disc_ft2:.6f} </wingarea>\n'
        f'    <wingspan unit="FT"> {2 * a.main.radius_m / FT:.6f} </wingspan>\n'
        f'    <chord unit="FT"> {a.main.chord_m / FT:.6f} </chord>\n'
        f'    {_loc("AERORP", origin)}\n    {_loc("EYEPOINT", origin)}\n'
        f'    {_loc("VRP", origin)}\n'
        '  </metrics>\n'
        '  <mass_balance>\n'
        f'    <ixx unit="SLUG*FT2"> {ixx:.10g} </ixx> <iyy unit="SLUG*FT2"> {iyy:.10g} </iyy>\n'
        f'    <izz unit="SLUG*FT2"> {izz:.10g} </izz> <ixz unit="SLUG*FT2"> {ixz:.10g} </ixz>\n'
        f'    <emptywt unit="LBS"> {a.mass_kg / SLUG * 32.174049:.10g} </emptywt>\n'
        f'    {_loc("CG", origin)}\n'
        '  </mass_balance>\n'
        '  <ground_reactions/>\n'
        '  <propulsion>\n'
        + thruster(a.main, (0.0, 90.0, 0.0)) + thruster(a.tail, (0.0, 0.0, tail_yaw)) +
        '  </propulsion>\n'
        '  <flight_control name="none"/>\n'
        + aerodynamics_xml(a) +
        '</fdm_config>\n')


def write_jsbsim_model(airframe: Airframe, root: str | Path, *, rho: float, g: float,
                       mirror: bool | None = None) -> JSBSimAirframe:
    """Write root/aircraft/MODEL_NAME/{MODEL_NAME.xml, Engines/*.xml}; returns what was
    written (SI)."""
    spec = derive(airframe, rho=rho, g=g, mirror=mirror)
    folder = Path(root) / "aircraft" / MODEL_NAME
    (folder / "Engines").mkdir(parents=True, exist_ok=True)
    (folder / f"{MODEL_NAME}.xml").write_text(aircraft_xml(spec))
    (folder / "Engines" / "main_rotor.xml").write_text(rotor_xml(spec.main))
    (folder / "Engines" / "tail_rotor.xml").write_text(rotor_xml(spec.tail))
    (folder / "Engines" / "drive_motor.xml").write_text(motor_xml(spec.motor))
    return spec


# -- running JSBSim -------------------------------------------------------------------------

@dataclass
class Trim:
    """A trimmed level flight: blade pitch (rad; collective, lateral = tilts the disc right,
    longitudinal = tilts it forward), attitude (rad), main-rotor power (W) and thrust (N)."""

    speed_m_s: float
    collective: float
    lateral: float
    longitudinal: float
    pedal: float
    roll: float
    pitch: float
    power_w: float
    thrust_n: float
    residual: float
    iterations: int


ACCELERATIONS = ("accelerations/udot-ft_sec2", "accelerations/vdot-ft_sec2",
                 "accelerations/wdot-ft_sec2", "accelerations/pdot-rad_sec2",
                 "accelerations/qdot-rad_sec2", "accelerations/rdot-rad_sec2")


class JSBSimHelicopter:
    """The generated model loaded in JSBSim, at a fixed altitude, heading north, in an
    atmosphere whose density is set to `air_density_kg_m3` (module docstring)."""

    ALTITUDE_FT = 300.0

    def __init__(self, airframe: Airframe | None = None, *, air_density_kg_m3: float =
                 DEFAULT_DENSITY, gravity_m_s2: float = 9.80, mirror: bool | None = None,
                 root: str | Path | None = None) -> None:
        import jsbsim  # dev extra: imported here so the package does not need it

        self.airframe = airframe if airframe is not None else load_airframe()
        self._tmp = None
        if root is None:
            self._tmp = tempfile.TemporaryDirectory(prefix="airwake-jsbsim-")
            root = self._tmp.name
        self.root = Path(root)
        self.spec = write_jsbsim_model(self.airframe, self.root, rho=air_density_kg_m3,
                                       g=gravity_m_s2, mirror=mirror)
        jsbsim.FGJSBBase().debug_lvl = 0
        self.fdm = jsbsim.FGFDMExec(str(self.root))
        self.fdm.set_debug_level(0)
        try:
            self.fdm.load_model(MODEL_NAME)
        except Exception as exc:  # JSBSim raises its own exception types
            raise JSBSimCheckError(f"{self.root}/aircraft/{MODEL_NAME}: JSBSim could not load "
                                   f"the generated model ({exc})") from None
        self.fdm["ic/terrain-elevation-ft"] = 0.0
        self.fdm["ic/h-sl-ft"] = self.ALTITUDE_FT
        self.fdm["ic/lat-geod-deg"] = 45.0
        self.fdm["ic/long-gc-deg"] = 0.0
        self.omega = self.spec.main.rpm * 2.0 * math.pi / 60.0
        self.fdm["propulsion/engine[0]/x-rpm-dict"] = self.spec.main.rpm * self.spec.main.gear_ratio
        self._set_density(air_density_kg_m3)
        self.air_density_kg_m3 = self.fdm["atmosphere/rho-slugs_ft3"] * SLUG / FT**3
        self.gravity_m_s2 = self._effective_gravity()

    def _set_density(self, rho: float) -> None:
        """Offset the standard atmosphere's temperature until the density is `rho` (at
        constant pressure rho ~ 1 / T)."""
        for _ in range(10):
            self._evaluate(np.zeros(6), 0.0, runs=1)
            now = self.fdm["atmosphere/rho-slugs_ft3"] * SLUG / FT**3
            if abs(now / rho - 1.0) < 1e-7:
                return
            t_r = self.fdm["atmosphere/T-R"]
            self.fdm["atmosphere/delta-T"] = self.fdm["atmosphere/delta-T"] + t_r * (
                now / rho - 1.0)
        raise JSBSimCheckError(f"could not set JSBSim's air density to {rho} kg/m3 "
                               f"(reached {now:.6f})")

    def _effective_gravity(self) -> float:
        """|body acceleration - aerodynamic and propulsive force / mass| at rest: gravity
        with the Earth's rotation as JSBSim has it, for our model to use the same."""
        self._evaluate(np.zeros(6), 0.0, runs=2)
        acc = np.array([self.fdm[k] for k in ACCELERATIONS[:3]]) * FT
        force = np.array([self.fdm[f"forces/fb{c}-total-lbs"] for c in "xyz"]) * LBF
        return float(np.linalg.norm(acc - force / self.spec.mass_kg))

    def _evaluate(self, z: np.ndarray, speed_m_s: float, runs: int = INFLOW_SETTLE_RUNS
                  ) -> np.ndarray:
        """Body accelerations (m/s^2, rad/s^2) in level flight north at `speed_m_s` with
        z = [collective, lateral, longitudinal, pedal, roll, pitch] of the JSBSim model,
        after `runs` frames with the integration suspended (FGRotor's inflow settles)."""
        f = self.fdm
        f["ic/phi-rad"] = z[4]
        f["ic/theta-rad"] = z[5]
        f["ic/psi-true-rad"] = 0.0
        f["ic/vn-fps"] = speed_m_s / FT
        f["ic/ve-fps"] = 0.0
        f["ic/vd-fps"] = 0.0
        f["ic/p-rad_sec"] = 0.0
        f["ic/q-rad_sec"] = 0.0
        f["ic/r-rad_sec"] = 0.0
        controls = ("propulsion/engine[0]/collective-ctrl-rad",
                    "propulsion/engine[0]/lateral-ctrl-rad",
                    "propulsion/engine[0]/longitudinal-ctrl-rad",
                    "propulsion/engine[1]/antitorque-ctrl-rad")
        for name, value in zip(controls, z[:4], strict=True):
            f[name] = value
        f.run_ic()
        f.suspend_integration()
        for _ in range(runs):
            f.run()
        f.resume_integration()
        acc = np.array([f[k] for k in ACCELERATIONS])
        acc[:3] *= FT
        return acc

    def trim(self, speed_m_s: float, tol: float = 1e-7, max_iter: int = 30) -> Trim:
        """Level flight north at `speed_m_s`: Newton on the six body accelerations in the
        four controls and roll and pitch (module docstring). Results are for our airframe
        (mirrored back when the model is the mirror image)."""
        z = np.array([0.07, 0.0, 0.0, 0.08, 0.0, 0.0])
        r = self._evaluate(z, speed_m_s)
        err = float(np.max(np.abs(r)))
        it = 0
        while err >= tol and it < max_iter:
            it += 1
            jac = np.empty((6, 6))
            h = 1e-5
            for k in range(6):
                zp = z.copy()
                zp[k] += h
                zm = z.copy()
                zm[k] -= h
                jac[:, k] = (self._evaluate(zp, speed_m_s) - self._evaluate(zm, speed_m_s)) / (
                    2 * h)
            step = np.linalg.solve(jac, -r)
            big = np.max(np.abs(step))
            if big > 0.05:
                step *= 0.05 / big
            z = z + step
            r = self._evaluate(z, speed_m_s)
            err = float(np.max(np.abs(r)))
        if err > 1e3 * tol:
            raise JSBSimCheckError(f"JSBSim trim at {speed_m_s} m/s did not converge: "
                                   f"accelerations {np.round(r, 5).tolist()}")
        f = self.fdm
        power = f["propulsion/engine[0]/torque-lbsft"] * FT * LBF * self.omega
        thrust = f["propulsion/engine[0]/thrust-lbs"] * LBF
        side = -1.0 if self.spec.mirrored else 1.0
        return Trim(speed_m_s=speed_m_s, collective=float(z[0]), lateral=side * float(z[1]),
                    longitudinal=float(z[2]), pedal=float(z[3]), roll=side * float(z[4]),
                    pitch=float(z[5]), power_w=float(power), thrust_n=float(thrust),
                    residual=err, iterations=it)

    def close(self) -> None:
        if self._tmp is not None:
            self._tmp.cleanup()
            self._tmp = None


# -- our model, measured the same way --------------------------------------------------------

def blade_pitch_harmonics(heli, states: np.ndarray, aux: np.ndarray) -> tuple[float, float,
                                                                             float]:
    """(collective, lateral, longitudinal) blade pitch (rad) over whole revolutions of our
    rotor: the collective the blades see (swashplate + the mean of the blades' pitch
    offsets at 0.75 R) and the first harmonic of blade 0's cyclic (swashplate through the
    Bell mixer, with the rigging's phase, plus the flybar through the Hiller arm), written
    in the swashplate's convention theta = s lat cos(psi) - lon sin(psi) (main_rotor.py)."""
    from hil_sim.world.rotorcraft import dynamics as D

    mr, mre = heli.mr, heli.mre
    s = mr[main_rotor.MR_SENSE]
    psi = states[:, D.PSI]
    h0, slat, slon = (aux[:, D.AUX_PITCH + i] for i in range(3))
    a = psi + mr[main_rotor.MR_PHASE]
    cyclic = (mr[main_rotor.MR_BELL] * (s * slat * np.cos(a) - slon * np.sin(a))
              + mr[main_rotor.MR_HILLER] * states[:, D.FLY])
    basis = np.column_stack([np.cos(psi), np.sin(psi), np.ones_like(psi)])
    (c1, s1, _), *_ = np.linalg.lstsq(basis, cyclic, rcond=None)
    radius = mr[main_rotor.MR_RADIUS]
    offsets = [mre[mre[:, 0] == sign] for sign in (1.0, -1.0)]
    at_075 = [rows[int(np.argmin(np.abs(rows[:, 1] - 0.75 * radius))), 4] for rows in offsets]
    return float(h0.mean() + np.mean(at_075)), float(s * c1), float(-s1)


def ours_trim(heli, speed_m_s: float, revolutions: int = 4) -> Trim:
    """Our blade-element helicopter trimmed in level flight north at `speed_m_s`, measured
    over `revolutions` whole revolutions of the settled rotor."""
    from hil_sim.world.rotorcraft import dynamics as D

    tr = heli.trim(vel_ned_m_s=(speed_m_s, 0.0, 0.0))
    x = tr.x.copy()
    env = heli.env(0.0, 0.0)
    w = heli.uniform_wind()
    g = heli.no_ground()
    n = heli.revolution_steps() * revolutions
    ox = np.empty((n, D.N_STATES))
    oa = np.empty((n, D.N_AUX))
    heli.integrate(x, 0.0, n, tr.delta, tr.delta, env, w, w, g, g, ox, oa, 0, D.SPEED_HELD)
    col, lat, lon = blade_pitch_harmonics(heli, ox, oa)
    roll, pitch = tr.body12[6], tr.body12[7]
    return Trim(speed_m_s=speed_m_s, collective=col, lateral=lat, longitudinal=lon,
                pedal=float(tr.delta[3]), roll=float(roll), pitch=float(pitch),
                power_w=float(oa[:, D.AUX_POWER].mean()),
                thrust_n=float(oa[:, D.AUX_THRUST].mean()), residual=float(tr.residual),
                iterations=int(tr.iterations))


# -- the comparison ---------------------------------------------------------------------------

@dataclass
class ComparisonRow:
    speed_m_s: float
    ours: Trim
    jsbsim: Trim


def compare(speeds_m_s=DEFAULT_SPEEDS_M_S, airframe: Airframe | None = None,
            air_density_kg_m3: float = DEFAULT_DENSITY) -> list[ComparisonRow]:
    """Both helicopters trimmed at each speed, in the same air and gravity (JSBSim's,
    with the density set to `air_density_kg_m3`)."""
    from hil_sim.world.rotorcraft.model import BladeElementHelicopter

    airframe = airframe if airframe is not None else load_airframe()
    jsb = JSBSimHelicopter(airframe, air_density_kg_m3=air_density_kg_m3)
    try:
        heli = BladeElementHelicopter(airframe, air_density_kg_m3=jsb.air_density_kg_m3,
                                      gravity_m_s2=jsb.gravity_m_s2)
        return [ComparisonRow(float(v), ours_trim(heli, float(v)), jsb.trim(float(v)))
                for v in speeds_m_s]
    finally:
        jsb.close()


def markdown_table(rows: list[ComparisonRow]) -> str:
    """One line per speed, each cell 'ours / JSBSim' (angles in deg)."""
    head = ("| V (m/s) | collective | lateral cyclic | longitudinal cyclic | pitch | roll "
            "| main-rotor power (W) | thrust (N) |\n|---|---|---|---|---|---|---|---|")
    lines = [head]
    def deg(row, name):
        return (f"{math.degrees(getattr(row.ours, name)):.2f} / "
                f"{math.degrees(getattr(row.jsbsim, name)):.2f}")

    for row in rows:
        o, j = row.ours, row.jsbsim
        lines.append(f"| {row.speed_m_s:g} | {deg(row, 'collective')} | "
                     f"{deg(row, 'lateral')} | {deg(row, 'longitudinal')} | "
                     f"{deg(row, 'pitch')} | {deg(row, 'roll')} | "
                     f"{o.power_w:.0f} / {j.power_w:.0f} | {o.thrust_n:.1f} / {j.thrust_n:.1f} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    import argparse

    parser = argparse.ArgumentParser(
        prog="python -m hil_sim.world.rotorcraft.jsbsim_check",
        description="Trim the blade-element truth and its JSBSim FGRotor twin from hover "
                    "to 8 m/s and print both side by side (markdown).")
    parser.add_argument("--speeds", type=float, nargs="+", default=list(DEFAULT_SPEEDS_M_S),
                        help="level-flight speeds, m/s (default: %(default)s)")
    parser.add_argument("--density", type=float, default=DEFAULT_DENSITY,
                        help="air density, kg/m3 (default: %(default)s)")
    args = parser.parse_args(argv)
    rows = compare(args.speeds, air_density_kg_m3=args.density)
    print("Each cell: ours (blade-element truth) / JSBSim FGRotor. Blade pitch in deg at "
          "the blades; lateral + tilts the disc right, longitudinal + forward; pitch and "
          "roll attitude in deg.\n")
    print(markdown_table(rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
