"""What a calibration flight identifies: the default free set (subset selection), the
envelope of air velocities it flew, the wind components that makes trustworthy, and the
[calibration] table the spec carries to the wind estimator."""

import json

import numpy as np
import pytest
from airwake.calibrate import calibrate
from airwake.calibrate.envelope import envelope_fraction, flight_envelope, wind_trust
from airwake.calibrate.residuals import FlightData
from airwake.cli import main
from airwake.heli import load_spec, spec_calibration

MODEL = load_spec("table52")


def _data(vel, rates):
    n = len(vel)
    t = np.arange(n) / 150.0
    x = np.zeros((n, MODEL.n_states))
    for j, s in enumerate(("vel_u_m_s", "vel_v_m_s", "vel_w_m_s")):
        x[:, MODEL.state_index(s)] = vel[:, j]
    for j, s in enumerate(("p_rad_s", "q_rad_s", "r_rad_s")):
        x[:, MODEL.state_index(s)] = rates[:, j]
    return FlightData(t, x, np.zeros((n, 4)), {}, np.zeros((n, 6)), [slice(0, n)],
                      1 / 150.0, np.ones(6))


def test_a_hover_flight_trusts_no_mean_flow_component_and_legs_make_them_trusted():
    n = 3000
    rng = np.random.default_rng(1)
    hover = _data(0.05 * rng.standard_normal((n, 3)), 0.3 * rng.standard_normal((n, 3)))
    trust = wind_trust(flight_envelope(hover, MODEL))
    assert not any(trust[c]["trusted"] for c in ("vx", "vy", "vz"))
    assert "not exercised" in trust["vx"]["why"]
    assert all(trust[c]["trusted"] for c in ("wx", "wy", "wz"))
    legs = np.column_stack([3.0 * np.sin(np.linspace(0, 6 * np.pi, n)),
                            2.0 * np.cos(np.linspace(0, 4 * np.pi, n)), np.zeros(n)])
    env = flight_envelope(_data(legs, np.zeros((n, 3))), MODEL)
    trust = wind_trust(env)
    assert trust["vx"]["trusted"] and trust["vy"]["trusted"] and not trust["vz"]["trusted"]
    lo, hi = env["air_velocity_body_m_s"]["x"]
    assert lo == pytest.approx(-3.0, abs=0.05) and hi == pytest.approx(3.0, abs=0.05)
    # an estimate's air velocity inside / outside that range
    inside = envelope_fraction(env, np.array([[2.0, 0.0, 0.0], [6.0, 0.0, 0.0]]))
    assert inside[0] == pytest.approx(0.5) and inside[1] == pytest.approx(1.0)


def test_default_free_set_holds_what_a_hover_flight_cannot_separate(still_air_flight):
    # a0 and delta_0 enter the loads only as delta_0 / a0: one of them is held, and named
    res = calibrate(still_air_flight, "table52", max_nfev=3, max_windows=8, cutoff_hz=None)
    held = [h.split(":")[0] for h in res.info["held"]]
    assert {"main_rotor.lift_slope_per_rad", "main_rotor.drag_delta0"} & set(held), held
    assert not set(held) & set(res.names)
    assert all("held at" in h and "not identified by this flight" in h
               for h in res.info["held"])


def test_the_spec_carries_the_calibration_table_and_still_loads(short_flight_file, tmp_path,
                                                                capsys):
    out = tmp_path / "fitted.toml"
    assert main(["calibrate", str(short_flight_file), "--out", str(out), "--params",
                 "rigid_body.I*", "--max-nfev", "3", "--window-s", "1", "--warmup-s",
                 "0.5"]) == 0
    text = capsys.readouterr().out
    assert "wind components this model can be trusted for" in text
    cal = spec_calibration(out)
    assert cal["method"] == "lsq" and cal["front_end"]["cutoff_hz"] == 6.0
    assert set(cal["trusted"]) == {"vx", "vy", "vz", "wx", "wy", "wz"}
    assert set(cal["envelope"]["air_velocity_body_m_s"]) == {"x", "y", "z"}
    assert cal["free_parameters"] == ["rigid_body.Ixx_kg_m2", "rigid_body.Iyy_kg_m2",
                                      "rigid_body.Izz_kg_m2", "rigid_body.Ixz_kg_m2"]
    load_spec(out)  # the model ignores the table
    assert spec_calibration("table52") is None


def test_raw_calibration_is_still_available(short_flight_file, tmp_path, capsys):
    out = tmp_path / "raw.toml"
    assert main(["calibrate", str(short_flight_file), "--out", str(out), "--cutoff-hz", "0",
                 "--params", "rigid_body.Ixx_kg_m2", "--max-nfev", "2", "--window-s", "1",
                 "--warmup-s", "0.5", "--json"]) == 0
    rep = json.loads(capsys.readouterr().out)
    assert rep["front_end"] is None and "front_end" not in spec_calibration(out)


def test_a_cutoff_above_the_rotor_harmonics_is_refused(short_flight_file, tmp_path, capsys):
    out = tmp_path / "x.toml"
    assert main(["calibrate", str(short_flight_file), "--out", str(out), "--cutoff-hz", "20",
                 "--params", "rigid_body.Ixx_kg_m2"]) == 2
    err = capsys.readouterr().err
    assert "--cutoff-hz 20" in err and "1/rev" in err and not out.exists()
