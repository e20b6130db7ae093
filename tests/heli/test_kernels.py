"""Compiled kernels: same results as the numpy paths, plugins in both styles, caching."""

import os
import subprocess
import sys
import tempfile
import threading
from pathlib import Path

import numpy as np
import pytest
from airwake.heli import codegen, load_plugin, load_spec
from airwake.heli.codegen import cache as kernel_cache
from airwake.heli.integrate import Stepper, _rk4_numpy, rk4_step, simulate
from airwake.heli.layout import Q
from airwake.heli.measurement import (
    _reconstruct_relaxation,
    _wind_array,
    flight_arrays,
    predict_measurements,
)
from airwake.heli.plugins import forget_plugin
from airwake.heli.trim import trim_hover
from numba.core.caching import NullCache

PROBES = Path(__file__).resolve().parent / "plugins" / "probe_effects.py"
ROOT = Path(__file__).resolve().parents[2]


def rows(model, n, seed=0):
    rng = np.random.default_rng(seed)
    tr = trim_hover(model)
    x = np.repeat(tr.x[None], n, 0)
    x[:, 3:6] += rng.normal(0, 2, (n, 3))
    x[:, 6:8] += rng.normal(0, 0.1, (n, 2))
    x[:, 9:12] += rng.normal(0, 0.3, (n, 3))
    x[:, 12:] += rng.normal(0, 0.01, (n, model.n_states - 12))
    u = tr.u + rng.normal(0, 0.02, (n, 4))
    w = rng.normal(0, 1, (n, 6)) * [2, 2, 1, 0.2, 0.2, 0.2]
    env = {"rotor_speed_rad_s": rng.uniform(150, 175, n), "height_agl_m": rng.uniform(1, 4, n)}
    return x, u, w, env


@pytest.fixture(scope="module")
def table52():
    return load_spec("table52")


@pytest.fixture(scope="module")
def probes():
    names = load_plugin(PROBES)
    assert names == ["test_probe_numpy", "test_probe_kernel"]
    from airwake.heli import registered_effects

    base = load_spec("table51")
    reg = registered_effects()
    return base + reg["test_probe_numpy"](), base + reg["test_probe_kernel"]()


def test_compiled_rk4_step_equals_the_numpy_rk4(table52):
    # hil_sim's truth integration must be the same numbers the numpy RK4 gives
    x, u, w, env = rows(table52, 16)
    params = np.repeat(table52.parameter_vector()[None], 16, 0)
    params[:, table52.parameter_names.index("rigid_body.Ixx_kg_m2")] *= np.linspace(0.9, 1.1, 16)
    got = rk4_step(table52, x, u, 1e-3, w, env, params)
    want = _rk4_numpy(table52, x, u, 1e-3, w, env, params)
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12)
    one = Stepper(table52, 1e-3).step(x[3], u[3], w[3])
    np.testing.assert_allclose(one, _rk4_numpy(table52, x[3:4], u[3], 1e-3, w[3], None, None)[0],
                               rtol=1e-12, atol=1e-12)


def test_stepper_single_row_path_equals_the_batch_rk4_with_its_height_and_dt(table52):
    # hil_sim's truth steps one row at a time through the fast path: same numbers as the
    # general batch step with the same per-step height, step size and default parameters
    x, u, w, env = rows(table52, 4, seed=5)
    stepper = Stepper(table52)
    for i, h in enumerate((0.8, 2.5, np.inf)):
        got = stepper.step(x[i], u[i], w[i], h, 2e-3)
        want = rk4_step(table52, x[i:i + 1], u[i], 2e-3, w[i], {"height_agl_m": h})[0]
        np.testing.assert_array_equal(got, want)
    batch = stepper.step(x, u, w, env["height_agl_m"], 1e-3)
    np.testing.assert_array_equal(
        batch, rk4_step(table52, x, u, 1e-3, w, {"height_agl_m": env["height_agl_m"]}))
    xdot, meas = stepper.rates_and_measurement(x[1], u[1], w[1], 2.0)
    want_xdot, want_meas = table52.rates_and_measurement(x[1:2], u[1], w[1],
                                                         {"height_agl_m": 2.0})
    np.testing.assert_array_equal(xdot, want_xdot[0])
    np.testing.assert_array_equal(meas, want_meas[0])
    with pytest.raises(ValueError, match="no step size"):
        stepper.step(x[0], u[0])


def test_stepper_of_a_model_with_numpy_stages_steps_through_the_numpy_rk4(probes):
    with_numpy, with_kernel = probes
    x, u, w, _ = rows(with_numpy, 2, seed=6)
    a = Stepper(with_numpy, 1e-3).step(x[0], u[0], w[0], 1.5)
    b = Stepper(with_kernel, 1e-3).step(x[0], u[0], w[0], 1.5)
    assert a.shape == (with_numpy.n_states,)
    np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12)


def test_simulate_over_sampled_arrays_equals_the_closed_loop_path(table52):
    # the whole-run compiled loop and the per-step Python loop integrate the same ODE
    tr = trim_hover(table52)
    steps, dt = 200, 1e-3
    t = np.arange(steps + 1) * dt
    u = tr.u + 0.01 * np.column_stack([np.sin(7 * t), np.sin(11 * t), np.cos(9 * t), t])
    w = np.column_stack([np.sin(3 * t), 0 * t - 0.5, 0.2 * t, 0 * t + 0.1, 0 * t, 0 * t])
    x0 = np.stack([tr.x, tr.x + 0.001])
    fast = simulate(table52, x0, steps * dt, dt, u, w, sample_every=20)
    slow = simulate(table52, x0, steps * dt, dt, lambda tt, xx: u[int(round(tt / dt))],
                    lambda tt: w[int(round(tt / dt))], sample_every=20)
    np.testing.assert_array_equal(fast.t, slow.t)
    np.testing.assert_allclose(fast.x, slow.x, rtol=1e-12, atol=1e-12)
    np.testing.assert_array_equal(fast.u, slow.u)
    np.testing.assert_array_equal(fast.w, slow.w)
    assert fast.x.shape == (11, 2, table52.n_states)


def test_numpy_and_kernel_plugins_of_the_same_effect_agree(probes):
    # a numpy plugin runs between compiled segments on the shared context: its inflow
    # change must reach the compiled main-rotor forces, its load the body dynamics
    with_numpy, with_kernel = probes
    assert not with_numpy.is_compiled and with_kernel.is_compiled
    x, u, w, env = rows(with_numpy, 12, seed=3)
    a = with_numpy.evaluate(x, u, w, env)
    b = with_kernel.evaluate(x, u, w, env)
    np.testing.assert_allclose(a.xdot, b.xdot, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(a.meas, b.meas, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(a.inflow_0, b.inflow_0, rtol=1e-12)
    np.testing.assert_allclose(a.loads["test_probe_numpy"][0], b.loads["test_probe_kernel"][0],
                               rtol=1e-12, atol=1e-15)
    plain = load_spec("table51").evaluate(x[:, :28], u, w, env)
    assert not np.allclose(plain.inflow_0, b.inflow_0)  # the probe did act
    np.testing.assert_allclose(with_numpy.derivatives(x, u, w, env),
                               with_kernel.derivatives(x, u, w, env), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(with_numpy.measure(x, u, w, env),
                               with_kernel.measure(x, u, w, env), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(rk4_step(with_numpy, x, u, 1e-3, w, env),
                               rk4_step(with_kernel, x, u, 1e-3, w, env), rtol=1e-12, atol=1e-12)


def test_per_row_parameters_reach_numpy_and_kernel_plugins_alike(probes):
    with_numpy, with_kernel = probes
    x, u, w, env = rows(with_numpy, 6, seed=4)
    params = np.repeat(with_numpy.parameter_vector()[None], 6, 0)
    params[:, -3] = np.linspace(0.01, 0.5, 6)  # tau_s per row
    a = with_numpy.derivatives(x, u, w, env, params)
    b = with_kernel.derivatives(x, u, w, env, params)
    np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12)
    d = {"test_probe_numpy.cd_m2": np.linspace(0, 0.3, 6)}
    dk = {"test_probe_kernel.cd_m2": np.linspace(0, 0.3, 6)}
    np.testing.assert_allclose(with_numpy.measure(x, u, w, env, d),
                               with_kernel.measure(x, u, w, env, dk), rtol=1e-12, atol=1e-12)


def test_compiled_hidden_pass_lands_on_the_relaxation_solution(table52):
    # both solve the same discrete equations; the compiled pass replaced the relaxation
    # for all-kernel models, the relaxation still serves models with numpy plugins
    n = 240
    t = np.arange(n) / 150.0
    tr = trim_hover(table52)
    names = ("pos_n_m", "pos_e_m", "pos_d_m", "vel_u_m_s", "vel_v_m_s", "vel_w_m_s",
             "roll_rad", "pitch_rad", "yaw_rad", "p_rad_s", "q_rad_s", "r_rad_s")
    flight = {"t_s": t + 0.0005 * np.sin(40 * t)}  # irregular sampling on purpose
    for i, c in enumerate(names):
        flight[c] = tr.x[i] + 0.05 * np.sin((1 + i) * t)
    for j, c in enumerate(("delta_col_rad", "delta_lat_rad", "delta_lon_rad", "delta_ped_rad")):
        flight[c] = tr.u[j] + 0.01 * np.sin((2 + j) * t)
    wind = np.array([0.5, -0.2, 0.1, 0.02, 0.01, -0.02])
    z, hid = predict_measurements(table52, flight, wind=wind, return_hidden=True)
    assert hid.change < 1e-8 and hid.iterations <= 12
    fa = flight_arrays(table52, flight)
    ref = _reconstruct_relaxation(table52, fa, _wind_array(wind, n), None, 30, 1e-11)
    scale = np.max(np.abs(ref.h), axis=0)
    assert np.max(np.abs(hid.h - ref.h) / scale) < 1e-7


def test_predict_measurements_runs_k_parameter_sets_in_one_pass(table52):
    n = 90
    t = np.arange(n) / 150.0
    tr = trim_hover(table52)
    flight = {"t_s": t, **{c: tr.u[j] + 0.01 * np.sin((2 + j) * t) for j, c in enumerate(
        ("delta_col_rad", "delta_lat_rad", "delta_lon_rad", "delta_ped_rad"))}}
    for i, c in enumerate(("vel_u_m_s", "vel_v_m_s", "vel_w_m_s", "roll_rad", "pitch_rad",
                           "yaw_rad", "p_rad_s", "q_rad_s", "r_rad_s")):
        flight[c] = tr.x[3 + i] + 0.03 * np.sin((1 + i) * t)
    vec = table52.parameter_vector()
    sets = np.repeat(vec[None], 3, 0)
    sets[:, table52.parameter_names.index("main_rotor.lock_number")] *= [0.9, 1.0, 1.1]
    z, hid = predict_measurements(table52, flight, params=sets, return_hidden=True)
    assert z.shape == (3, n, 6) and hid.h.shape == (3, n, 16)
    for k in range(3):
        np.testing.assert_allclose(z[k], predict_measurements(table52, flight, params=sets[k]),
                                   rtol=1e-12, atol=1e-12)


def test_context_quantities_are_views_of_the_context_array(table52):
    x, u, w, env = rows(table52, 4)
    ctx = table52.evaluate(x, u, w, env)
    assert isinstance(ctx.air_density_kg_m3, float)  # one value for all rows: a float
    ctx.inflow_0 = 0.5
    assert np.all(ctx.c[:, Q.inflow_0] == 0.5)
    assert ctx.vel_b_m_s.base is not None and np.shares_memory(ctx.vel_b_m_s, ctx.c)
    params = np.repeat(table52.parameter_vector()[None], 4, 0)
    params[:, table52.parameter_names.index("atmosphere.air_density_kg_m3")] = [1.0, 1.1, 1.2, 1.3]
    per_row = table52.evaluate(x, u, w, env, params)
    np.testing.assert_array_equal(per_row.air_density_kg_m3, [1.0, 1.1, 1.2, 1.3])
    assert sorted(per_row.loads) == ["empennage", "fuselage", "gravity", "main_rotor",
                                     "tail_rotor"]


def test_concurrent_first_calls_share_one_compiled_composition(table52):
    # pytest-xdist workers and threads may ask for the same composition at once
    # (a small composition: cheap to compile on a fresh machine)
    model = table52.without("main_rotor", "flybar", "pitt_peters_inflow", "tail_rotor")
    x, u, w, env = rows(table52, 8, seed=9)
    x = x[:, :12]
    out = [None] * 4

    def work(i):
        out[i] = model.derivatives(x, u, w, env)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(4)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    for o in out[1:]:
        np.testing.assert_array_equal(o, out[0])
    same = load_spec("table51").without("main_rotor", "flybar", "pitt_peters_inflow",
                                        "tail_rotor")
    assert model.compiled is codegen.compiled(same)


def test_generated_module_is_written_once_and_atomically(tmp_path):
    path = tmp_path / "heli_x.py"
    kernel_cache.write_once(path, "a = 1\n")
    mtime = path.stat().st_mtime_ns
    kernel_cache.write_once(path, "a = 1\n")  # same content: untouched (numba checks the stamp)
    assert path.stat().st_mtime_ns == mtime
    kernel_cache.write_once(path, "a = 2\n")  # stale or corrupt: replaced
    assert path.read_text() == "a = 2\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["heli_x.py"]  # no temp files left


def test_editing_a_kernel_or_its_helpers_changes_the_cache_stamp(tmp_path):
    # numba alone would only watch the kernel's own file and load stale machine code
    helper = tmp_path / "probe_helper.py"
    helper.write_text("from airwake.heli.kernel import kernel_function\n\n"
                      "@kernel_function\ndef gain(x):\n    return 2.0 * x\n")
    (tmp_path / "probe_kern.py").write_text(
        "from probe_helper import gain\n\n"
        "def kern(q, p, s, ds, load, scratch):\n    q[0] = gain(q[0])\n")
    sys.path.insert(0, str(tmp_path))
    try:
        from probe_kern import kern

        before = kernel_cache.fingerprint([kern])
        assert str(helper) in kernel_cache.dependency_files(kern)
        helper.write_text(helper.read_text().replace("2.0", "3.0"))
        os.utime(helper, ns=(1, 1))
        assert kernel_cache.fingerprint([kern]) != before
    finally:
        sys.path.remove(str(tmp_path))
        sys.modules.pop("probe_helper", None)
        sys.modules.pop("probe_kern", None)


def test_kernels_of_effects_defined_in_a_function_are_not_disk_cached():
    # their parameter namedtuple cannot be pickled by reference
    from airwake.heli import Effect, Parameter
    from airwake.heli.kernel import Q, kernel

    class Local(Effect):
        PARAMETERS = (Parameter("k", 1.0, "-", (0.0, 2.0), "test"),)

        @kernel
        def forces(q, p, s, ds, load, scratch):
            load[0] += p.k * q[Q.vel_b_m_s]

    assert isinstance(Local.forces._cache, NullCache)
    from airwake.heli.effects import Gravity

    assert not isinstance(Gravity.forces._cache, NullCache)


def test_a_new_process_loads_the_compiled_composition_from_the_cache(table52):
    # the second process must not compile: that is what keeps test runs and tools fast
    table52.derivatives(*rows(table52, 2)[:3])  # compiled (or loaded) here first
    code = (
        "import numpy as np\n"
        "from airwake.heli import load_spec\n"
        "m = load_spec('table52')\n"
        "m.derivatives(m.zero_state(1), np.zeros(4))\n"
        "from airwake.heli.codegen import loops\n"
        "s = loops.evaluate_rows.stats\n"
        "print(m.compiled.fns.row.cache_hits, sum(s.cache_hits.values()),"
        " sum(s.cache_misses.values()))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=ROOT, timeout=600, check=True)
    row_hits, hits, misses = map(int, out.stdout.split())
    # the composition's row and the loop that evaluates it, both loaded
    assert (row_hits, hits, misses) == (1, 1, 0), out.stderr


def test_the_effect_examples_in_the_docs_work():
    # engineers copy these; a stale example would teach a broken API
    text = (ROOT / "docs" / "effects.md").read_text()
    section = text.split("## Writing an effect", 1)[1].split("\n## ", 1)[0]
    blocks = [b.split("```", 1)[0] for b in section.split("```python\n")[1:]]
    assert len(blocks) == 2
    # a stable path: the kernel example's compiled code is cached between runs
    folder = Path(tempfile.gettempdir()) / f"airwake-doc-examples-{os.getuid()}"
    folder.mkdir(exist_ok=True)
    paths = []
    for i, code in enumerate(blocks):
        path = folder / f"doc_effect_{i}.py"
        if not path.exists() or path.read_text() != code:
            path.write_text(code)
        paths.append(path)
    try:
        (kname,), (nname,) = load_plugin(paths[0]), load_plugin(paths[1])
        from airwake.heli import registered_effects

        reg = registered_effects()
        model = load_spec("table52") + reg[kname]() + reg[nname](k=0.05)
        assert model.is_compiled is False
        tr = trim_hover(load_spec("table52"))
        x = np.repeat(tr.x[None], 2, 0)
        x[:, 4] = 3.0  # sideslip, for the boom drag
        ctx = model.evaluate(x, tr.u, env={"height_agl_m": np.array([0.5, 50.0])})
        assert np.all(np.isfinite(ctx.xdot))
        assert ctx.inflow_0[0] < ctx.inflow_0[1]  # ground effect near the ground only
        assert ctx.loads[nname][0][0, 1] < 0  # drag opposes the sideslip
        fast = load_spec("table52") + reg[kname]()
        assert fast.is_compiled
        np.testing.assert_allclose(fast.evaluate(x, tr.u, env={"height_agl_m": 0.5}).inflow_0,
                                   ctx.inflow_0[0], rtol=1e-12)
    finally:
        for path in paths:
            forget_plugin(path)
