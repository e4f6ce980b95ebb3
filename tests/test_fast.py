"""The compiled fast path: kernels, integrators, and whole runs against independent references.

* the Numba kernels against the NumPy reference functions on random states, with tolerances
  scaled by the size of the terms each sum adds up (both codes round differently, and the film
  force is a cancelling sum);
* the compiled integrators against exact solutions, SciPy's DOP853 and the Python
  Bulirsch-Stoer (same algorithms, so the same steps up to rounding);
* whole runs of the fast path against the reference path: samples within the solver tolerance,
  event times within the tolerance of the event location, fallback for what is not compiled.

No timing here: speed is measured in ``benchmarks/bench.py``. The first run compiles (cached on
disk by Numba; about half a minute of CPU cold).
"""

import subprocess
import sys

import numpy as np
import pytest

pytest.importorskip("numba")

import numba  # noqa: E402

from lubelink import _kernels as K  # noqa: E402
from lubelink import contact, film, kinematics  # noqa: E402
from lubelink.config import resolve  # noqa: E402
from lubelink.integrate import fast  # noqa: E402
from lubelink.integrate.bulirsch_stoer import BulirschStoer  # noqa: E402
from lubelink.kinematics import PrescribedMotion, SliderCrank  # noqa: E402
from lubelink.model import ContactPhase, build_model  # noqa: E402
from lubelink.simulate import reference_segment_integrator, run, segment_integrator  # noqa: E402

EPS = np.finfo(float).eps

#: Configurations exercising every compiled branch (film models, sides, cavitation, pad reference,
#: collar mass, gravity).
KERNEL_CASES = {
    "wedge": {},
    "squeeze-two-sided": {"film.model": "wedge+squeeze", "film.sides": 2},
    "half-sommerfeld": {"film.model": "wedge+squeeze", "film.cavitation": "half-sommerfeld",
                        "film.cavitation_pressure": 9e4},
    "centre-mass-gravity": {"film.pad_reference": "centre", "collar.mass": 0.3,
                            "mechanism.gravity": [0.0, -9.81]},
    "dry": {"film.model": "none"},
}

#: Dry joint with a 5 mm clearance: the link first reaches the collar at about t = 0.24 s.
IMPACT = {"film.model": "none", "film.clearance": 5e-3, "contact.law": "restitution",
          "solver.t_end": 0.3, "solver.output_step": 1e-3}


def model_of(overrides, modes):
    return build_model(resolve("paper", {**overrides, "beam.modes": modes}))


def random_states(model, count, rng, amplitude=1.5e-3):
    """States with modal amplitudes falling like the static response, ``1/n^2``, and times in 0-2 s."""
    N = model.modes
    amp = amplitude / np.arange(1, N + 1) ** 2
    for _ in range(count):
        q = rng.uniform(-1, 1, N) * amp
        q_dot = rng.uniform(-1, 1, N) * amp * model.omega_n[0]
        yield rng.uniform(0.0, 2.0), np.concatenate([q, q_dot])


def contact_xi(model, t, q_side):
    """Thinnest film of one side (``q_side = side * q``) by the reference functions [m]."""
    fm = model.config.film
    x0 = film.pad_start(float(model.motion(t).x_star), fm.pad_length, fm.pad_reference)
    return contact.thinnest_film(q_side, x0, fm.pad_length, fm.clearance, model.config.mechanism.rod_length)[0]


def film_term_scale(model, t, y):
    """Per-mode and resultant sums of the magnitudes of the terms of the modal film force [N].

    Both codes evaluate the same quadrature sums in different orders and forms, so their
    difference is bounded by a small multiple of eps times these scales (the wedge force is a
    small difference of large terms: its relative error is much larger than eps).
    """
    cfg = model.config
    fm, N, L = cfg.film, model.modes, cfg.mechanism.rod_length
    kin = model.motion(t)
    x0 = film.pad_start(float(kin.x_star), fm.pad_length, fm.pad_reference)
    V = abs(float(kin.V_r))
    beta = np.arange(1, N + 1) * np.pi / L
    s, w = film.gauss_legendre(fm.quadrature_nodes)
    X, wX = fm.pad_length * s, fm.pad_length * w
    sinX = np.abs(np.sin(np.outer(x0 + X, beta)))
    W = np.abs((np.cos(beta * x0) - np.cos(np.outer(x0 + X, beta))) / beta) + 2.0 / beta
    mu, B = fm.viscosity, cfg.beam.width
    F_scale, total_scale = np.zeros(N), 0.0
    for side in model.sides:
        xi = 0.5 * fm.clearance - np.sin(np.outer(x0 + X, beta)) @ (side * y[:N])
        Q = np.abs(W) @ np.abs(y[N:]) if fm.model == "wedge+squeeze" else np.zeros_like(X)
        inv2, inv3 = xi**-2, xi**-3
        C = (6 * mu * V * (wX @ inv2) + 12 * mu * (wX @ (Q * inv3))) / (wX @ inv3)
        if fm.cavitation == "none":
            dp = (6 * mu * V * xi + 12 * mu * Q + C) * inv3
            F_scale += B * (wX * dp) @ W
            total_scale += B * wX @ (dp * X)
        else:
            S = np.abs(fm.pad_length * film._integration_matrix(fm.quadrature_nodes))
            p = 6 * mu * V * (S @ inv2) + C * (S @ inv3) + 12 * mu * (S @ (Q * inv3)) + abs(fm.cavitation_pressure)
            F_scale += B * (wX * p) @ sinX
            total_scale += B * wX @ p
    return F_scale, total_scale


# ----------------------------------------------------------------------------------------------
# kernels against the NumPy reference
def test_slider_crank_kernel_matches_reference():
    m = resolve("paper").mechanism
    for t in np.linspace(0.0, 0.4, 37):
        ref = kinematics.slider_crank(t, m.crank_length, m.rod_length, m.crank_speed, m.guide_distance)
        got = K.slider_crank(t, m.crank_length, m.rod_length, m.crank_speed, m.guide_distance)
        names = ("A_O2", "omega", "alpha", "x_star", "V_r", "Y_ddot", "cos_theta")
        for name, value in zip(names, got):
            # the same closed forms, evaluated in the same order: rounding only
            assert value == pytest.approx(float(ref[name]), rel=1e-14, abs=1e-14 * abs(m.crank_speed) ** 2), name


@pytest.mark.parametrize("case", sorted(KERNEL_CASES))
@pytest.mark.parametrize("modes", [1, 5, 15])
def test_film_and_rhs_kernels_match_reference(case, modes):
    model = model_of(KERNEL_CASES[case], modes)
    p = K.pack(model)
    rng = np.random.default_rng(modes)
    for t, y in random_states(model, 12, rng):
        F_ref, total_ref = model.film_loads(t, y)
        F, total = K.film_loads(t, y, p)
        if model.config.film.enabled:
            F_scale, total_scale = film_term_scale(model, t, y)
            np.testing.assert_array_less(np.abs(F - F_ref), 64 * EPS * F_scale + 1e-300)
            assert abs(total - total_ref) <= 64 * EPS * total_scale
        else:
            assert not np.any(F) and total == 0.0
        ref = model.rhs(t, y)
        out = np.empty_like(y)
        K.rhs(t, y, out, p)
        np.testing.assert_array_equal(out[:modes], ref[:modes])
        # q_ddot: the stiffness, rigid-body and film terms; the film part carries the error above
        kin = model.motion(t)
        L, beta = model.config.mechanism.rod_length, np.arange(1, modes + 1) * np.pi
        rigid = 2.0 / (L * beta) * (2 * abs(float(kin.A_O2)) + 10.0 + abs(float(kin.alpha)) * L)
        scale = (np.abs(model.omega_n**2 * y[:modes]) + rigid
                 + (F_scale / model.modal_mass if model.config.film.enabled else 0.0))
        np.testing.assert_array_less(np.abs(out[modes:] - ref[modes:]), 64 * EPS * scale)


@pytest.mark.parametrize("sides", [1, 2])
@pytest.mark.parametrize("modes", [1, 3, 8])
def test_thinnest_film_and_gap_kernels_match_reference(sides, modes):
    model = model_of({"film.sides": sides, "film.pad_reference": "centre" if modes == 3 else "edge"}, modes)
    p = K.pack(model)
    H = model.config.film.clearance
    rng = np.random.default_rng(10 * sides + modes)
    for t, y in random_states(model, 40, rng, amplitude=2.9e-3):
        xi_ref, x_ref, edge_ref, side_ref = model.thinnest_film(t, y)
        xi, x_c, edge, side = K.thinnest_film(t, y, p)
        # H/2 - u2: the deflection sums carry a few eps of H; the point is a Newton root of u2' = 0
        assert xi == pytest.approx(xi_ref, abs=16 * EPS * H)
        assert x_c == pytest.approx(x_ref, abs=1e-12)
        assert (edge, side) == (edge_ref, side_ref)
        gap = model.gap(t, y)
        assert K.gap(t, y, p) == pytest.approx(gap, abs=16 * EPS * H)
        assert K.event(t, y, K.set_segment(p, None, -1)) == K.gap(t, y, p)
        assert K.event(t, y, K.set_segment(p, None, 1)) == -K.gap(t, y, p)


@pytest.mark.parametrize("side", [1, -1])
@pytest.mark.parametrize("modes", [1, 5])
def test_contact_force_kernel_matches_reference(side, modes):
    model = model_of({"film.clearance": 3.2e-3, "film.sides": 2, "contact.law": "compliant"}, modes)
    ct, H = model.config.contact, model.config.film.clearance
    rng = np.random.default_rng(modes)
    touching = 0
    for t, y in random_states(model, 60, rng, amplitude=side * 3e-3):
        phase = ContactPhase(side=side, v_minus=0.2)
        p = K.pack(model, phase=phase)
        F_ref, force_ref = model.contact_force(t, y, phase)
        F, force = K.contact_force(t, y, p)
        xi = contact_xi(model, t, side * y[:modes])
        delta = ct.min_film - xi
        touching += delta > 0
        # the force is stiff in the penetration, itself H/2 - u2 minus min_film: propagate the few
        # eps of H of the deflection sums
        sensitivity = ct.stiffness * ct.exponent * max(delta, 0.0) ** (ct.exponent - 1) * 3.0
        tol = 1e-13 * force_ref + sensitivity * 16 * EPS * H
        assert force == pytest.approx(force_ref, abs=tol)
        np.testing.assert_allclose(F, F_ref, rtol=0, atol=tol)
        out, ref = np.empty_like(y), model.rhs(t, y, phase)
        K.rhs(t, y, out, p)
        film_tol = 64 * EPS * film_term_scale(model, t, y)[0]
        np.testing.assert_allclose(out[modes:], ref[modes:], rtol=1e-13,
                                   atol=np.max((tol + film_tol) / model.modal_mass))
    assert touching > 5  # the states do reach the collar


def test_film_force_many_is_film_loads_per_sample():
    model = model_of({"film.sides": 2}, 3)
    p = K.pack(model)
    rng = np.random.default_rng(3)
    ts, ys = zip(*random_states(model, 25, rng))
    ts, ys = np.array(ts), np.array(ys)
    batch = K.film_force_many(ts, ys, p)
    for t, y, value in zip(ts, ys, batch):
        total_scale = film_term_scale(model, t, y)[1]
        assert abs(value - model.film_loads(t, y)[1]) <= 64 * EPS * total_scale


@pytest.mark.parametrize("overrides", [{"film.model": "wedge+squeeze", "film.sides": 2},
                                       {"film.cavitation": "half-sommerfeld", "film.cavitation_pressure": 9e4}])
def test_pad_pressure_many_is_the_results_pressure(overrides):
    model = model_of(overrides, 3)
    fm, L = model.config.film, model.config.mechanism.rod_length
    rng = np.random.default_rng(4)
    ts, ys = (np.array(v) for v in zip(*random_states(model, 30, rng)))
    N = model.modes
    kin = model.motion(ts)
    x0 = film.pad_start(np.asarray(kin.x_star), fm.pad_length, fm.pad_reference)
    X = np.linspace(0.0, fm.pad_length, 21)
    for side in model.sides:
        ref = film.pad_pressure(X, side * ys[:, :N], side * ys[:, N:], x0, kin.V_r, mu=fm.viscosity,
                                clearance=fm.clearance, rod_length=L, squeeze=fm.model == "wedge+squeeze")
        if fm.cavitation == "half-sommerfeld":
            ref = np.maximum(ref, fm.cavitation_pressure - fm.ambient_pressure)
        got = K.pad_pressure_many(model, ts, ys, X, side)
        # cumulative quadratures of positive terms (xi^-2, xi^-3) and of the squeeze flux: a few
        # eps of the pressure scale
        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12 * np.max(np.abs(ref)))


# ----------------------------------------------------------------------------------------------
# the compiled integrators on problems with exact solutions
@numba.njit(cache=True)
def oscillator(t, y, out, p):
    """``y'' = -w^2 y`` as a first-order system; ``p = [w]``."""
    out[0] = y[1]
    out[1] = -p[0] ** 2 * y[0]


@numba.njit(cache=True)
def below(t, y, p):
    """Event: ``y[0] - p[1]`` (falls to zero where the oscillator passes ``p[1]``)."""
    return y[0] - p[1]


def exact(t, w):
    return np.array([np.cos(w * t), -w * np.sin(w * t)])


@pytest.mark.parametrize("method", fast.COMPILED_METHODS)
def test_compiled_error_tracks_the_tolerance(method):
    """Global error on 10 periods of the oscillator, scaled by rtol, stays within a band."""
    w = 2 * np.pi
    ratios = []
    for rtol in 10.0 ** -np.arange(4, 13, 2):
        seg = fast.solve(oscillator, (0.0, 10.0), [1.0, 0.0], [w], method=method, rtol=rtol, atol=rtol * 1e-3,
                         t_eval=np.linspace(0.5, 10.0, 20))
        assert seg.status == "finished" and seg.t_final == 10.0
        err = max(np.max(np.abs(y - exact(t, w)) / np.array([1.0, w])) for t, y in zip(seg.t, seg.y))
        ratios.append(err / rtol)
    # proportionality: the error follows the tolerance within two decades over eight
    # (global error ~ tolerance x number of steps x error growth, which varies with the order)
    assert max(ratios) < 300 and max(ratios) / min(ratios) < 100, ratios


def test_compiled_bs_takes_the_steps_of_the_python_bs():
    w = 3.0
    for rtol in (1e-4, 1e-8):
        seg = fast.solve(oscillator, (0.0, 10.0), [1.0, 0.0], [w], rtol=rtol, atol=rtol * 1e-3)
        py = BulirschStoer(lambda t, y: np.array([y[1], -w**2 * y[0]]), 0.0, np.array([1.0, 0.0]), 10.0,
                           rtol=rtol, atol=rtol * 1e-3)
        steps = 0
        while py.status == "running":
            py.step()
            steps += 1
        # the same algorithm and tables: the same steps, values equal up to rounding
        assert (seg.nfev, seg.nsteps) == (py.nfev, steps)
        np.testing.assert_allclose(seg.y_final, py.y, rtol=0, atol=1e-12 * w)


def test_compiled_dop853_takes_the_steps_of_scipy():
    from scipy.integrate import DOP853

    w = 3.0
    for rtol in (1e-5, 1e-10):
        seg = fast.solve(oscillator, (0.0, 10.0), [1.0, 0.0], [w], method="DOP853", rtol=rtol, atol=rtol * 1e-3)
        sp = DOP853(lambda t, y: np.array([y[1], -w**2 * y[0]]), 0.0, np.array([1.0, 0.0]), 10.0,
                    rtol=rtol, atol=rtol * 1e-3)
        steps = 0
        while sp.status == "running":
            sp.step()
            steps += 1
        assert (seg.nfev, seg.nsteps) == (sp.nfev, steps)
        np.testing.assert_allclose(seg.y_final, sp.y, rtol=0, atol=1e-12 * w)


@pytest.mark.parametrize("method", fast.COMPILED_METHODS)
def test_dense_output_and_events(method):
    w = 2 * np.pi
    # first downward crossing of y = 0.5: cos(w t) = 0.5 at t = 1/6
    seg = fast.solve(oscillator, (0.0, 3.0), [1.0, 0.0], [w, 0.5], method=method, rtol=1e-10, atol=1e-13,
                     t_eval=np.linspace(0.01, 3.0, 300), event=below)
    assert seg.status == "event"
    assert seg.t_final == pytest.approx(1 / 6, abs=1e-10)
    assert seg.y_final[0] == pytest.approx(0.5, abs=1e-10)
    assert seg.t[-1] <= seg.t_final < seg.t[-1] + 0.01
    for t, y in zip(seg.t, seg.y):  # the dense output between the steps
        np.testing.assert_allclose(y, exact(t, w), atol=1e-8 * w)


@pytest.mark.parametrize("method", fast.COMPILED_METHODS)
def test_a_dip_inside_one_long_step_is_found(method):
    """The event dips below zero between two step ends (y near -1 for a moment): sub-sampling finds it."""
    w = 1.0
    args = dict(method=method, rtol=1e-8, atol=1e-11)
    # y[0] = cos t reaches -1 at t = pi; the event y[0] + 0.9999 is negative only on a 0.028 s window
    missed = fast.solve(oscillator, (0.0, 4.0), [1.0, 0.0], [w, -0.9999], event=below, **args)
    found = fast.solve(oscillator, (0.0, 4.0), [1.0, 0.0], [w, -0.9999], event=below, event_resolution=0.005,
                       **args)
    assert 4.0 / missed.nsteps > 0.2  # the steps are much longer than the window
    assert missed.status == "finished"
    assert found.status == "event"
    # where y = -0.9999 the slope is 0.014: the dense output's error of ~rtol is ~1e-7 s in time
    assert found.t_final == pytest.approx(np.pi - np.arccos(0.9999), abs=1e-6)


def test_progress_and_deadline():
    seen = []
    seg = fast.solve(oscillator, (0.0, 50.0), [1.0, 0.0], [20.0], rtol=1e-10, atol=1e-13, progress=seen.append)
    # about every 1 % of the interval (0.5 here; the steps are about 0.1 long)
    assert seg.status == "finished" and len(seen) >= 50
    assert np.all(np.diff(seen) >= 0) and np.max(np.diff(seen)) < 1.0 and seen[-1] == 50.0
    late = fast.solve(oscillator, (0.0, 50.0), [1.0, 0.0], [1.0], rtol=1e-10, atol=1e-13, deadline=0.0)
    assert late.status == "timeout" and "wall-time budget" in late.message
    assert 0.0 < late.t_final < 50.0 and np.all(np.isfinite(late.y_final))


# ----------------------------------------------------------------------------------------------
# whole runs: the fast path against the reference path
def runs(scenario, overrides, methods=fast.COMPILED_METHODS):
    """The reference DOP853 run and the fast runs of ``methods``, on one configuration."""
    ref = run(resolve(scenario, {**overrides, "solver.backend": "numpy"}))
    fast_runs = {m: run(resolve(scenario, {**overrides, "solver.method": m, "solver.backend": "numba"}))
                 for m in methods}
    return ref, fast_runs


@pytest.mark.parametrize("scenario, modes, t_end", [("paper", 1, 0.5), ("paper", 5, 0.08),
                                                     ("paper-dry", 1, 0.5), ("paper-dry", 5, 0.08)])
def test_fast_runs_match_the_reference(scenario, modes, t_end):
    rtol = 1e-10
    ref, fast_runs = runs(scenario, {"beam.modes": modes, "solver.t_end": t_end, "solver.rtol": rtol,
                                     "solver.atol": 1e-14})
    # the solvers control an RMS norm over the state: scale the errors of the q and q_dot blocks
    # by the amplitude of each block
    N = modes
    scale = np.repeat([np.max(np.abs(ref.y[:, :N])), np.max(np.abs(ref.y[:, N:]))], N)
    for method, r in fast_runs.items():
        assert r.status == "complete" and np.array_equal(r.t, ref.t)
        # each run is within a few tolerances of the exact solution over these few periods, so
        # of the other
        assert np.all(np.abs(r.y - ref.y) <= 200 * rtol * scale), method
    dop = fast_runs["DOP853"]
    assert dop.nfev == pytest.approx(ref.nfev, rel=0.02)  # the same DOP853 steps up to rounding


def test_event_times_agree_across_methods_and_paths():
    ref, fast_runs = runs("paper", IMPACT)
    t_ref = [i[0] for i in ref.impacts]
    assert len(t_ref) >= 1
    for method, r in fast_runs.items():
        assert [round(i[4]) for i in r.impacts] == [round(i[4]) for i in ref.impacts]
        # located by root finding to ~1e-15 s on dense outputs that agree to the solver tolerance
        np.testing.assert_allclose([i[0] for i in r.impacts], t_ref, rtol=0, atol=1e-7, err_msg=method)
        np.testing.assert_allclose([i[2] for i in r.impacts], [i[2] for i in ref.impacts], rtol=1e-5,
                                   err_msg=method)


def test_paper_impact_first_impact_agrees():
    """DOP853 only: this first contact is a graze (the film dips 36 nm below min_film for 30 us),
    which sub-sampling at event_resolution catches or not depending on where the steps fall; the
    compiled DOP853 takes SciPy's steps, so it samples where the reference does."""
    ref, fast_runs = runs("paper-impact", {"solver.t_end": 1.3}, methods=("DOP853",))
    assert ref.impacts
    assert fast_runs["DOP853"].impacts[0][0] == pytest.approx(ref.impacts[0][0], abs=1e-9)


def test_compliant_contact_matches_the_reference():
    over = {**IMPACT, "contact.law": "compliant", "solver.t_end": 0.26}
    ref, fast_runs = runs("paper", over)
    assert ref.impacts and np.isfinite(ref.impacts[0][3])  # a contact that began and ended
    for method, r in fast_runs.items():
        assert len(r.impacts) == len(ref.impacts)
        for a, b in zip(r.impacts, ref.impacts):
            assert a[0] == pytest.approx(b[0], abs=1e-7) and a[3] == pytest.approx(b[3], rel=1e-4)
        np.testing.assert_allclose(r.y, ref.y, rtol=0, atol=1e-6 * np.max(np.abs(ref.y)), err_msg=method)


@pytest.mark.parametrize("method", ["RK45", "Radau"])
def test_scipy_methods_run_on_the_compiled_rhs(method):
    over = {"solver.method": method, "solver.t_end": 0.05, "solver.rtol": 1e-8}
    model = build_model(resolve("paper", over))
    segment = fast.make_segment_integrator(model)
    assert segment is not None
    args = dict(phase=None, event_sign=-1, event_resolution=1e-3, deadline=None, progress=None)
    t_eval = np.arange(1, 51) * 1e-3
    got = segment(0.0, model.initial_state(), 0.05, t_eval, **args)
    want = reference_segment_integrator(model)(0.0, model.initial_state(), 0.05, t_eval, **args)
    assert got.status == want.status == "finished"
    # the same SciPy stepping on right-hand sides equal to rounding: the same steps
    assert np.all(np.abs(got.y - want.y) <= 1e-9 * np.max(np.abs(want.y), axis=0))
    assert got.nfev == pytest.approx(want.nfev, rel=0.05)


# ----------------------------------------------------------------------------------------------
# what is not compiled, and the cache
def test_unsupported_configurations_take_the_reference_path():
    reynolds = build_model(resolve("paper", {"film.cavitation": "reynolds", "film.cavitation_pressure": 9e4}))
    assert fast.make_segment_integrator(reynolds) is None
    sc = SliderCrank(resolve("paper").mechanism)
    user = PrescribedMotion(A_O2=lambda t: sc(t).A_O2, omega=lambda t: sc(t).omega, alpha=lambda t: sc(t).alpha,
                            x_star=lambda t: sc(t).x_star, V_r=lambda t: sc(t).V_r)
    assert fast.make_segment_integrator(build_model(resolve("paper"), motion=user)) is None
    # the orchestrator falls back under "auto" and refuses under "numba"
    assert segment_integrator(reynolds).__qualname__.startswith("reference_segment_integrator")
    strict = build_model(resolve("paper", {"film.cavitation": "reynolds", "film.cavitation_pressure": 9e4,
                                           "solver.backend": "numba"}))
    with pytest.raises(ValueError, match="not supported"):
        segment_integrator(strict)
    with pytest.raises(ValueError, match="compiled integrators"):
        fast.solve(oscillator, (0.0, 1.0), [1.0, 0.0], [1.0], method="RK45")


def test_a_second_process_loads_the_compiled_code_from_the_cache():
    fast.compile_all()  # this process has compiled (or loaded) everything, and written the cache
    code = ("from lubelink.integrate import fast; from lubelink import _kernels as K; fast.compile_all(); "
            "print(sum(d.stats.cache_hits.total() for d in (fast._advance, K.rhs, K.event)), "
            "sum(d.stats.cache_misses.total() for d in (fast._advance, K.rhs, K.event)))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    hits, misses = (int(v) for v in out.stdout.split())
    assert (hits, misses) == (3, 0)
