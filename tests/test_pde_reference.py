"""The modal solution against an independent finite-difference solution of the PDE.

docs/model.md §11, "How each piece is checked": an independent
solution of the beam PDE against the modal solution, converging as the mesh
is refined. ``tests/reference/fd_beam.py`` integrates

    EI u'''' + rho A u_tt - rho A omega^2 u = -rho A (A_O2 + alpha x)

by the method of lines (5-point u'''' with ghost nodes for the pinned ends),
with no lubelink code. The forcing is the paper's slider-crank, written here
from docs/model.md §3's formulas with the math module (and cross-checked
against lubelink.link.kinematics). The modal solution is ``lubelink.simulate``'s
"paper-dry" scenario with 5 modes.

Runtime: ~10-20 s (three FD meshes plus one simulation), hence ``slow``; it
is not deselected by default.
"""

from __future__ import annotations

import importlib.util
import math
import pathlib
import sys

import numpy as np
import pytest

import lubelink
from lubelink.link.kinematics import slider_crank

pytestmark = pytest.mark.slow


def _load_reference():
    # by path, so the test does not depend on how pytest sets sys.path
    path = pathlib.Path(__file__).parent / "reference" / "fd_beam.py"
    spec = importlib.util.spec_from_file_location("lubelink_tests_reference_fd_beam", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


fd_beam = _load_reference()

# Section 6 rod and mechanism, written out (not from lubelink.params)
E, RHO, B, HH, L = 207e9, 7650.0, 0.01, 0.01, 1.0
EI, RHO_A = E * B * HH**3 / 12.0, RHO * B * HH
OA, W0, A_GUIDE = 0.07, 10.0 * math.pi, 0.4
LAM = OA / L

T_END, DT = 0.25, 1e-3  # the first 0.25 s holds the 2.6 mm peak (t = 0.244 s)
MESHES = (10, 20, 40)
MODES = 5


def paper_motion(t):
    """docs/model.md §3: A_O2 = -OA w0^2 sin(phi + theta), omega, alpha (paper Section 6)."""
    phi = W0 * t
    s, c = math.sin(phi), math.cos(phi)
    r = math.sqrt(1.0 - (LAM * s) ** 2)
    theta = math.asin(LAM * s)
    A_O2 = -OA * W0**2 * math.sin(phi + theta)
    omega = -LAM * W0 * c / r
    alpha = LAM * W0**2 * s / r - LAM**3 * W0**2 * c * c * s / r**3
    return A_O2, omega, alpha


@pytest.fixture(scope="module")
def solutions():
    t_eval = np.arange(0.0, T_END + DT / 2, DT)
    ds = lubelink.simulate("paper-dry", set={"beam.modes": MODES, "solver.t_end": T_END,
                                             "solver.output_step": DT, "solver.rtol": 1e-10,
                                             "solver.atol": 1e-14, "output.x_points": 11})
    assert ds.attrs["status"] == "complete"
    np.testing.assert_allclose(ds.time.values, t_eval, rtol=0, atol=1e-12)
    fd = {n: fd_beam.solve_fd(n, EI=EI, rho_A=RHO_A, L=L, motion=paper_motion, t_eval=t_eval)
          for n in MESHES}
    return ds, fd


def test_forcing_matches_lubelink_kinematics():
    """The hand-written forcing is the motion lubelink integrates (to round-off)."""
    for t in (0.0, 0.0123, 0.07, 0.131, 0.2):
        k = slider_crank(t, OA, L, W0, A_GUIDE)
        np.testing.assert_allclose(paper_motion(t), [k["A_O2"], k["omega"], k["alpha"]], rtol=1e-13, atol=1e-13)


def test_fd_operator_is_pinned_fourth_derivative():
    """Reference self-check: with the ghost nodes the FD operator has the sine modes of a
    pinned-pinned beam as eigenvectors and the eigenvalues (4/h^2 sin^2(beta_n h/2))^2,
    which tend to beta_n^4 as O(h^2)."""
    n_el = 16
    h = L / n_el
    D = fd_beam.fourth_difference(n_el, h)
    x = np.linspace(0.0, L, n_el + 1)[1:-1]
    for n in range(1, n_el):
        beta = n * np.pi / L
        mode = np.sin(beta * x)
        lam = (4.0 / h**2 * np.sin(beta * h / 2) ** 2) ** 2
        np.testing.assert_allclose(D @ mode, lam * mode, rtol=0, atol=1e-9 * lam)
    assert (4.0 / h**2 * np.sin(np.pi * h / 2) ** 2) ** 2 == pytest.approx(np.pi**4, rel=(np.pi * h) ** 2 / 6 * 1.01)


def test_fd_converges_to_modal_solution_at_second_order(solutions):
    """Midspan deflection: max error over 0-0.25 s against the 5-mode solution,
    for 10, 20, 40 elements; the log-log slope must be 2 (within [1.6, 2.4]).

    Error budget at 40 elements: the FD mode-1 frequency is low by
    (beta_1 h)^2/12 = 5e-4, i.e. a phase drift of 5e-4 * 148 rad/s * 0.25 s
    = 0.019 rad on the ~0.5 mm free vibration: ~1e-5 m (observed 9e-6 m).
    The 5-mode truncation (next symmetric mode: 1/7^5 of the static part,
    ~1e-7 m) and the solver tolerances (~1e-11 m) are far below it. So the
    finest error must be below 2e-5 m, < 1 % of the 2.6 mm peak.
    """
    ds, fd = solutions
    u_modal = ds.u2_mid.values
    peak = np.abs(u_modal).max()
    assert peak == pytest.approx(2.6e-3, abs=0.05e-3)  # docs/model.md §2: "a peak of about 2.6 mm"
    errors = np.array([np.abs(fd[n].at(0.5 * L) - u_modal).max() for n in MESHES])
    h = L / np.array(MESHES)
    slope = np.polyfit(np.log(h), np.log(errors), 1)[0]
    assert 1.6 <= slope <= 2.4, (errors, slope)
    # each halving of h divides the error by ~4 (not just on average)
    assert np.all((errors[:-1] / errors[1:] > 3.0) & (errors[:-1] / errors[1:] < 5.3)), errors
    assert errors[-1] < 2e-5
    assert errors[-1] < 0.01 * peak


def test_fd_richardson_extrapolation_approaches_modal_solution(solutions):
    """If the FD error is C h^2 + o(h^2) about the modal solution, the Richardson value
    (4 u_{h/2} - u_h)/3 must be much closer to it than u_{h/2}: it removes the h^2
    term and leaves O(h^4) plus the modal truncation (~1e-7 m). Required: 7x
    closer at 20 -> 40 elements (observed ~12x)."""
    ds, fd = solutions
    u_modal = ds.u2_mid.values
    u20, u40 = fd[20].at(0.5 * L), fd[40].at(0.5 * L)
    extrapolated = (4.0 * u40 - u20) / 3.0
    err40 = np.abs(u40 - u_modal).max()
    err_ex = np.abs(extrapolated - u_modal).max()
    assert err_ex < err40 / 7.0, (err_ex, err40)


def test_fd_whole_deflection_field_converges(solutions):
    """u2(x, t) at x = 0.1 .. 0.9 m (nodes of every mesh): the max error over x and t
    also falls as h^2 (antisymmetric modes, driven by alpha, included)."""
    ds, fd = solutions
    x = ds.x.values
    inner = (x > 0.05) & (x < L - 0.05)
    u_modal = ds.u2.values[:, inner]
    errors = []
    for n in MESHES:
        u_fd = np.stack([fd[n].at(xi) for xi in x[inner]], axis=1)
        errors.append(np.abs(u_fd - u_modal).max())
    errors = np.array(errors)
    slope = np.polyfit(np.log(L / np.array(MESHES)), np.log(errors), 1)[0]
    assert 1.6 <= slope <= 2.4, (errors, slope)
    assert errors[-1] < 0.01 * np.abs(u_modal).max()
