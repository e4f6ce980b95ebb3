"""Continuation of periodic responses: folds and Floquet crossings on maps with known answers, and
lubelink's response curves against shooting and long transients.
"""

import math

import numpy as np
import pytest

import lubelink
from lubelink.cli import main
from lubelink.config import resolve
from lubelink.steady import continuation, find_periodic
from lubelink.steady.arclength import continue_branch
from lubelink.steady.shooting import MapValue


# ----------------------------------------------------------------------------- maps with known branches
def family_of(P, dP, exact_jacobian):
    def family(lam):
        def fmap(y, jacobian=False):
            return MapValue(P(y, lam), dP(y, lam) if (jacobian and exact_jacobian) else None)

        return fmap

    return family


def ones(y, value):
    return np.ones_like(y)


@pytest.mark.parametrize("exact_jacobian", [True, False])
def test_fold_of_a_quadratic_branch(exact_jacobian):
    # fixed points y^2 = 1 - lam: a fold at lam = 1; multiplier 1 - y, stable for y > 0
    family = family_of(lambda y, lam: y - 0.5 * (y**2 + lam - 1), lambda y, lam: np.array([[1 - y[0]]]),
                       exact_jacobian)
    branch = continue_branch(family, np.array([0.9]), 0.0, 2.0, ones, ds=0.05, ds_max=0.1)
    assert branch.status == "stopped" and "turned back past the start" in branch.message
    lam = np.array([p.parameter for p in branch.points])
    y = np.array([p.y[0] for p in branch.points])
    np.testing.assert_allclose(y**2, 1 - lam, atol=1e-8)
    assert y[0] > 0 > y[-1]
    assert all(p.stable == (p.y[0] > 1e-6) for p in branch.points if abs(p.y[0]) > 1e-3)
    kinds = [b.kind for b in branch.bifurcations]
    assert kinds == ["fold"]
    assert branch.bifurcations[0].parameter == pytest.approx(1.0, abs=1e-3)


def test_period_doubling_and_neimark_sacker_crossings():
    # y = 0 for every lam; multiplier -lam (flip at lam = 1)
    flip = family_of(lambda y, lam: -lam * y + y**3, lambda y, lam: np.array([[-lam + 3 * y[0] ** 2]]), True)
    branch = continue_branch(flip, np.array([0.01]), 0.5, 1.5, ones)
    assert branch.status == "complete" and branch.points[-1].parameter == 1.5
    (b,) = branch.bifurcations
    assert b.kind == "period doubling (-1)" and b.parameter == pytest.approx(1.0, abs=1e-6)
    # a rotation by 1 rad scaled by lam: a complex pair leaves the circle at lam = 1
    c, s = math.cos(1.0), math.sin(1.0)
    R = np.array([[c, -s], [s, c]])
    torus = family_of(lambda y, lam: lam * R @ y, lambda y, lam: lam * R, True)
    branch = continue_branch(torus, np.array([0.0, 0.0]), 0.8, 1.3, ones)
    (b,) = branch.bifurcations
    assert b.kind == "Neimark-Sacker (complex pair)" and b.parameter == pytest.approx(1.0, abs=1e-6)
    assert abs(np.angle(b.multiplier)) == pytest.approx(1.0, abs=1e-6)


def test_a_multiplier_within_its_accuracy_of_the_circle_is_neither_stable_nor_a_crossing():
    """Issue 36: the stability test and the crossings use each multiplier's accuracy estimate as margin.

    A rotation by 1 rad scaled by ``lam`` whose map gives, as its check, a Jacobian off by ``e``: the
    multipliers' estimates are then about ``e``, the orbits within ``e`` of ``lam = 1`` are undecided,
    and the crossing is reported once, located within ``e``. A pair that wobbles by ``e / 2`` about
    the circle (its moduli ``1 +- e/2`` alternately) is never stable and never a crossing; with a
    margin of rounding it would cross at every point."""
    c, s = math.cos(1.0), math.sin(1.0)
    R = np.array([[c, -s], [s, c]])
    e = 1e-4

    def family(modulus):
        def at(lam):
            def fmap(y, jacobian=False):
                J = modulus(lam) * R
                check = J @ (np.eye(2) + e * np.array([[1.0, 0.3], [0.0, 1.0]])) if jacobian == "checked" else None
                return MapValue(J @ y, J if jacobian else None, {}, check)

            return fmap

        return at

    branch = continue_branch(family(lambda lam: lam), np.zeros(2), 0.8, 1.3, ones)
    (b,) = branch.bifurcations
    assert b.kind == "Neimark-Sacker (complex pair)" and b.parameter == pytest.approx(1.0, abs=2 * e)
    for p in branch.points:
        assert np.all(p.errors > 0.5 * e) and np.all(p.errors < 2 * e)
        undecided = abs(p.parameter - 1.0) <= p.errors[0]
        assert p.stable == (p.parameter < 1.0 and not undecided)
    wobble = family(lambda lam: 1.0 + 0.5 * e * math.cos(200.0 * lam))
    branch = continue_branch(wobble, np.zeros(2), 0.0, 1.0, ones)
    assert branch.status == "complete" and len(branch.points) > 20
    assert branch.bifurcations == [] and not any(p.stable for p in branch.points)
    moduli = [abs(p.multipliers[0]) for p in branch.points]
    assert min(moduli) < 1.0 - 1e-5 and max(moduli) > 1.0 + 1e-5  # both sides of the circle, beyond rounding


def test_undamped_dry_branch_has_no_bifurcation_and_no_stable_orbit():
    """Issue 36: ``paper-dry`` without damping from 5 rad/s reported six Neimark-Sacker bifurcations by 5.2
    rad/s, called orbits stable and stopped with a "fold" at 5.293 rad/s (finite differences of fixed
    step 1e-5 on a map integrated at rtol 1e-10: moduli 8e-6 off). The link is linear and undamped:
    ``tr J = 0`` so ``det M = 1`` (Liouville), and its one mode's pair is complex conjugate on the
    circle, ``|mu| = 1`` exactly, except in a parametric resonance tongue, none of which is wide
    enough to be met here. Between 5 and 5.35 rad/s the pair passes +1 twice (``omega_1 / 29 =
    5.1105``, ``omega_1 / 28 = 5.2930``: resonances of the 29th and 28th harmonics, poles of the
    response) and -1 once (``2 omega_1 / 57 = 5.2002``) without leaving the circle. The moduli's
    errors must stay within their estimates; no orbit is stable; nothing is a bifurcation but a
    resonance, at ``omega_1 / k``; and the branch goes on past the poles (the 29th harmonic's is too
    narrow to be met at all)."""
    w1 = 148.20524632103607
    for jacobian in ("auto", "finite-difference"):
        ds = continuation("paper-dry", {"beam.damping_ratio": 0.0}, start=5.0, stop=5.35, jacobian=jacobian)
        assert ds.attrs["status"] == "complete", ds.attrs["message"]
        assert not ds.stable.values.any()
        for kind, lam in zip(ds.bifurcation_type.values, ds.bifurcation_parameter.values):
            assert kind == 4, ds.attrs["bifurcations"]  # resonance (+1 on the circle)
            assert lam == pytest.approx(w1 / round(w1 / lam), abs=1e-4)
        error = np.abs(ds.floquet_modulus.values - 1.0)
        assert np.all(error <= ds.floquet_error.values), (jacobian, np.max(error / ds.floquet_error.values))
        assert np.max(ds.floquet_error.values) < (1e-6 if jacobian == "finite-difference" else 1e-7)
        # the argument of the pair is omega_1 T mod 2 pi (less a few 1e-4 rad: the centrifugal -omega(t)^2
        # lowers the frequency a little): it passes 0 and pi in this stretch
        expected = np.angle(np.exp(2j * np.pi * w1 / ds.parameter.values))
        np.testing.assert_allclose(np.abs(ds.floquet_argument.values[:, 0]), np.abs(expected), atol=1e-3)
        assert np.any(np.abs(expected) < 0.1) and np.any(np.abs(expected) > np.pi - 0.1)


# ----------------------------------------------------------------------------- lubelink's response curves
def test_continuation_passes_a_resonance_and_comes_back_to_the_same_branch():
    settings = {"beam.damping_ratio": 0.02}
    w1 = 148.20524632103607  # omega_1 of the paper's rod (docs/model.md §10.1); omega_1/3 = 49.40 rad/s
    up = continuation("paper-dry", settings, start=46.0, stop=53.0)
    down = continuation("paper-dry", settings, start=53.0, stop=46.0, y0=np.r_[up.q0.values[-1], up.q_dot0.values[-1]])
    for ds in (up, down):
        assert ds.attrs["status"] == "complete" and ds.bifurcation.size == 0 and ds.stable.all()
        # the resonance is resolved: the peak deflection rises fastest within its half-width
        # (zeta omega_1 / 3 ~ 1 rad/s) of omega_1/3, and many orbits lie there
        x, y = ds.parameter.values, ds.peak_u2_mid.values
        order = np.argsort(x)
        slope = np.diff(y[order]) / np.diff(x[order])
        assert abs(x[order][np.argmax(slope)] - w1 / 3) < 1.0
        assert np.sum(np.abs(x - w1 / 3) < 1.0) >= 8
    # the same branch both ways: end points, and every orbit of the way back against the way up
    np.testing.assert_allclose(down.q0.values[-1], up.q0.values[0], rtol=1e-7)
    np.testing.assert_allclose(down.q_dot0.values[-1], up.q_dot0.values[0], rtol=1e-7)
    xu, order = up.parameter.values, np.argsort(up.parameter.values)
    interpolated = np.interp(down.parameter.values, xu[order], up.peak_u2_mid.values[order])
    np.testing.assert_allclose(down.peak_u2_mid.values, interpolated, rtol=5e-3)  # linear interpolation
    for i in (len(down.point) // 3, 2 * len(down.point) // 3):  # and exactly against shooting there
        orbit = find_periodic(resolve("paper-dry", {**settings, "mechanism.crank_speed": float(down.parameter[i])}))
        np.testing.assert_allclose(orbit.y0, np.r_[down.q0.values[i], down.q_dot0.values[i]], rtol=1e-7,
                                   atol=1e-12)


def test_response_curve_agrees_with_long_transients_and_its_instability_is_real():
    # the paper's wedge film with 1 % damping: stable up to ~37.6 rad/s, then a multiplier leaves
    # through -1 (period doubling) and the link settles on a response of two crank turns
    settings = {"beam.damping_ratio": 0.01}
    ds = continuation("paper", settings, start=36.0, stop=38.0)
    assert ds.attrs["status"] == "complete"
    assert ds.bifurcation.size == 1 and int(ds.bifurcation_type[0]) == 2  # period doubling (-1)
    assert 37.2 < float(ds.bifurcation_parameter[0]) < 37.9
    assert ds.stable.values[0] == 1 and ds.stable.values[-1] == 0
    for i, stable in ((0, True), (-1, False)):
        speed = float(ds.parameter[i])
        T = 2 * math.pi / speed
        run = lubelink.simulate("paper", {**settings, "mechanism.crank_speed": speed, "solver.t_end": 60 * T,
                                          "solver.output_step": T / 10, "solver.rtol": 1e-10,
                                          "solver.atol": 1e-13})
        late = np.c_[run.q.values[-21::10, 0], run.q_dot.values[-21::10, 0]]  # at 58 T, 59 T, 60 T
        orbit = np.r_[ds.q0.values[i], ds.q_dot0.values[i]]
        if stable:  # exp(-zeta omega_1 58 T) ~ 1e-6 of the start-up vibration: well within 0.1 um
            np.testing.assert_allclose(late, np.tile(orbit, (3, 1)), rtol=0, atol=1e-7)
        else:  # not the unstable orbit: a period-2 response, which shooting over two turns finds
            assert np.max(np.abs(late[1] - late[0])) > 1e-5
            np.testing.assert_allclose(late[2], late[0], rtol=0, atol=1e-7)
            two = find_periodic(resolve("paper", {**settings, "mechanism.crank_speed": speed}), periods=2,
                                y0=late[0])
            assert two.stable
            np.testing.assert_allclose(two.y0, late[2], rtol=0, atol=1e-7)


def test_cli_continue_writes_the_branch_and_its_figure(tmp_path, capsys):
    out, png = tmp_path / "b.nc", tmp_path / "b.png"
    code = main(["continue", "--scenario", "paper-dry", "--set", "beam.damping_ratio=0.05", "--from", "30",
                 "--to", "31", "-o", str(out), "--figure", str(png)])
    assert code == 0 and png.stat().st_size > 10_000
    assert "complete" in capsys.readouterr().out
    import xarray as xr

    ds = xr.load_dataset(out)
    assert ds.parameter.values[0] == 30 and ds.parameter.values[-1] == 31
    assert ds.parameter.attrs["units"] == "rad s-1" and ds.stable.all()
    assert main(["plot-branch", str(out), "-o", str(tmp_path / "c.png")]) == 0
    assert main(["continue", "--scenario", "paper-dry", "--to", "31", "-o", str(out)]) == 2  # exists
    assert main(["continue", "--scenario", "paper-dry", "--parameter", "beam.modez", "--to", "2",
                 "-o", str(tmp_path / "d.nc")]) == 2
    assert "did you mean 'beam.modes'" in capsys.readouterr().err


@pytest.mark.parametrize("args, needle", [
    (["periodic", "--tol", "inf"], "--tol inf: must be a number in (0, 0.001]"),
    (["periodic", "--tol", "nan"], "--tol nan: must be a number in (0, 0.001]"),
    (["periodic", "--tol", "0"], "--tol 0.0: must be a number in (0, 0.001]"),
    (["periodic", "--tol", "-1"], "--tol -1.0: must be a number in (0, 0.001]"),
    (["periodic", "--warmup", "-2"], "--warmup -2: must be >= 0"),
    (["periodic", "--periods", "0"], "--periods 0: must be >= 1"),
    (["continue", "--to", "31", "--max-points", "0"], "--max-points 0: must be >= 2"),
    (["continue", "--to", "31", "--max-points", "-5"], "--max-points -5: must be >= 2"),
    (["continue", "--to", "31", "--warmup", "-2"], "--warmup -2: must be >= 0"),
    (["continue", "--to", "31", "--max-step", "inf"], "--max-step inf: must be a finite number > 0"),
    (["continue", "--to", "nan"], "--to nan: must be a finite number"),
    (["continue", "--to", "31", "--from", "inf"], "--from inf: must be a finite number"),
    (["continue", "--to", "31.41592653589793"], "the end of the branch (31.4159) must differ from its start"),
])
def test_numeric_options_out_of_range_are_one_line_and_status_2_before_any_work(args, needle, tmp_path, capsys):
    """Issue 37 item 2: ``periodic --tol inf`` used to exit 0 with an orbit of residual 0.50, ``--tol 0`` exit 1,
    ``--max-points 0`` write a one-point branch, ``--warmup -2`` pass, ``--to`` at the start fail after
    computing the first orbit. Each is now refused up front, naming the option, its value and the range."""
    import time

    out = tmp_path / "x.nc"
    began = time.perf_counter()
    assert main([args[0], "--scenario", "paper-dry", *args[1:], "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert needle in err and "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    assert not out.exists() and time.perf_counter() - began < 5.0  # nothing computed (a period takes seconds)


def test_outputs_are_checked_before_any_work(tmp_path, capsys):
    """Issue 37 items 3 and 4: ``continue -o b.txt`` worked 149 s and then refused the name; ``plot-branch -o
    x.txt``, an existing folder or FIFO given ``--overwrite``, a read-only folder and ``continue --figure
    f.txt`` ended in tracebacks. Each is refused before anything is computed, in one line, status 2."""
    import os
    import stat
    import time

    folder = tmp_path / "taken.png"
    folder.mkdir()
    fifo = tmp_path / "pipe.png"
    os.mkfifo(fifo)
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(stat.S_IRUSR | stat.S_IXUSR)
    cases = [
        (["continue", "--scenario", "paper-dry", "--to", "31", "-o", str(tmp_path / "b.txt")], "name the file *.nc"),
        (["periodic", "--scenario", "paper-dry", "-o", str(tmp_path / "o.txt")], "name the file *.nc"),
        (["continue", "--scenario", "paper-dry", "--to", "31", "-o", str(tmp_path / "b.nc"), "--figure",
          str(tmp_path / "f.txt")], "--figure"),
        (["plot-branch", "missing.nc", "-o", str(tmp_path / "x.txt")], "a figure is written as"),
        (["plot-branch", "missing.nc", "-o", str(folder), "--overwrite"], "only a regular file is ever replaced"),
        (["plot-branch", "missing.nc", "-o", str(fifo), "--overwrite"], "only a regular file is ever replaced"),
    ]
    if os.geteuid() != 0:  # (permission bits do not bind root)
        cases.append((["plot-branch", "missing.nc", "-o", str(locked / "x.png")], "locked"))
    for args, needle in cases:
        began = time.perf_counter()
        assert main(args) == 2, args
        err = capsys.readouterr().err
        assert needle in err and "Traceback" not in err and len(err.strip().splitlines()) == 1, (args, err)
        assert time.perf_counter() - began < 5.0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["locked", "pipe.png", "taken.png"]
