"""The 1-D Reynolds equation of the film: its first integral, its constant, and the cavitation obstacle problem.

The equations every film computation uses (see the package docstring): :func:`reynolds_constant`
and :func:`pressure_gradient` are the closed-form first integral, :func:`reynolds_cavitation`
the Swift-Stieber condition on a pad grid, :func:`grid_modal_force` the modal forces of a pressure on
that grid; :func:`pad_start` places the pad on the link.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import jitable
from ..params import CHOICES

__all__ = ["pad_start", "reynolds_constant", "pressure_gradient", "reynolds_cavitation", "effective_film",
           "effective_film_slope", "mean_gap", "mean_gap_slope",
           "mean_gap_curvature",
           "grid_modal_force"]

NO_FILM, WEDGE, WEDGE_SQUEEZE = (CHOICES["film.model"].index(v) for v in ("none", "wedge", "wedge+squeeze"))
FULL, HALF_SOMMERFELD, REYNOLDS = (CHOICES["film.cavitation"].index(v)
                                   for v in ("none", "half-sommerfeld", "reynolds"))
CENTRE = CHOICES["film.pad_reference"].index("centre")

#: Rows of the pad tables :attr:`~lubelink.film.force.PadTables.trig` (and ``sample_trig``,
#: ``grid_trig``: then ``+ 2`` for the midpoints).
SIN, COS, VERS = 0, 1, 2


@jitable
def pad_start(x_star, pad_length, pad_reference):
    """Start of the pad on the link [m] (D6): ``x_star``, or ``x_star - l/2`` when ``x_star`` is the centre.

    ``pad_reference`` is the choice's code (0 edge, 1 centre).
    """
    return x_star - 0.5 * pad_length if pad_reference == CENTRE else x_star


@jitable
def mean_gap(xi, sigma):
    """The mean gap between rough surfaces at nominal gap ``xi`` [m] (Patir & Cheng's ``h_T``).

    ``h_T = E[max(xi + delta, 0)]`` for Gaussian combined heights ``delta`` of RMS ``sigma`` [m]:
    ``xi/2 (1 + erf(H/sqrt 2)) + sigma/sqrt(2 pi) exp(-H^2/2)``, ``H = xi/sigma``. It tends to
    ``xi`` a few ``sigma`` above contact, is ``sigma/sqrt(2 pi)`` at ``xi = 0`` and stays positive
    when the asperities are pressed together (``xi < 0``). ``sigma = 0``: ``xi``.
    """
    if sigma <= 0.0:
        return xi
    H = xi / sigma
    # erfc(-z) = 1 + erf(z) without the cancellation that would leave h_T <= 0 deep in contact
    return 0.5 * xi * math.erfc(-H / math.sqrt(2.0)) + sigma * math.exp(-0.5 * H * H) / math.sqrt(2.0 * math.pi)


@jitable
def mean_gap_slope(xi, sigma):
    """``d mean_gap / d xi`` [-]: the share of the surface not in contact, ``(1 + erf(H/sqrt 2)) / 2``."""
    if sigma <= 0.0:
        return 1.0
    return 0.5 * math.erfc(-xi / (sigma * math.sqrt(2.0)))


@jitable
def mean_gap_curvature(xi, sigma):
    """``d^2 mean_gap / d xi^2`` [1/m]: the normal density of the heights at ``-xi``, ``exp(-H^2/2) / (sigma sqrt(2 pi))``."""
    if sigma <= 0.0:
        return 0.0
    H = xi / sigma
    return math.exp(-0.5 * H * H) / (sigma * math.sqrt(2.0 * math.pi))


@jitable
def effective_film(xi, floor, sigma):
    """The film thickness the Reynolds equation sees [m] at nominal gap ``xi`` [m].

    The mean gap of the rough surfaces, ``h = mean_gap(xi, sigma)`` (``film.roughness``; ``xi``
    itself for smooth ones), kept above the floor ``h_f`` (``film.thickness_floor``): ``h`` above
    ``2 h_f``, ``h_f + h^2 / (4 h_f)`` below, continuous with its slope, so the film force stays
    finite when a smooth film closes or a compliant contact penetrates (docs/breakdown.md). With
    roughness, ``h > 0.083 sigma`` while the asperities are pressed less than ``sigma`` into each
    other (``xi > -sigma``): a floor below ``0.04 sigma`` never acts there, and results stop
    depending on it. ``floor = 0``: ``h`` unchanged. The squeeze source is the rate of the mean
    gap, not of this film (:func:`mean_gap_slope` times the nominal rate; no floor in it).
    """
    h = mean_gap(xi, sigma)
    if h >= 2.0 * floor:
        return h
    if h <= 0.0:
        return floor
    return floor + h * h / (4.0 * floor)


@jitable
def effective_film_slope(xi, floor, sigma):
    """``d effective_film / d xi`` [-]."""
    h = mean_gap(xi, sigma)
    if h >= 2.0 * floor:
        return mean_gap_slope(xi, sigma)
    if h <= 0.0:
        return 0.0
    return h / (2.0 * floor) * mean_gap_slope(xi, sigma)


@jitable
def reynolds_constant(I1, I2, I3, V_r, mu):
    """Constant of the first integral, ``C = -(6 mu V_r I1 + 12 mu I3) / I2`` [Pa m^3] (paper Eq. 17, from ``p_g(l) = 0``).

    Parameters
    ----------
    I1, I2, I3 : float
        ``int_0^l xi^-2`` [1/m], ``int_0^l xi^-3`` [1/m^2], ``int_0^l Q xi^-3`` [1/s].
    V_r : float
        Collar velocity relative to the link [m/s].
    mu : float
        Viscosity [Pa s].
    """
    return -(6.0 * mu * V_r * I1 + 12.0 * mu * I3) / I2


@jitable
def pressure_gradient(xi, Q, C, V_r, mu):
    """``p_g' = (6 mu V_r xi + 12 mu Q + C) / xi^3`` [Pa/m], the first integral of the Reynolds equation.

    Parameters
    ----------
    xi : float
        Film thickness [m].
    Q : float
        ``int_0^X xi_t`` [m^2/s] (0 without the squeeze term).
    C : float
        :func:`reynolds_constant` [Pa m^3].
    V_r, mu : float
        [m/s], [Pa s].
    """
    return (6.0 * mu * V_r * xi + 12.0 * mu * Q + C) / (xi * xi * xi)


@jitable
def _solve_tridiagonal(lower, diag, upper, rhs, out):
    """Thomas algorithm: ``lower[i] x[i-1] + diag[i] x[i] + upper[i] x[i+1] = rhs[i]`` (no pivoting; M-matrices)."""
    n = diag.shape[0]
    c = np.empty(n)
    out[0] = rhs[0] / diag[0]
    c[0] = upper[0] / diag[0]
    for i in range(1, n):
        m = diag[i] - lower[i] * c[i - 1]
        c[i] = upper[i] / m
        out[i] = (rhs[i] - lower[i] * out[i - 1]) / m
    for i in range(n - 2, -1, -1):
        out[i] -= c[i] * out[i + 1]


@jitable
def reynolds_cavitation(grid, xi_mid, xi_t, V_r, mu, p_cav, out):
    """Film pressure with the Swift-Stieber (Reynolds) cavitation condition into ``out`` [Pa, gauge].

    Solves the obstacle problem ``p >= p_cav``, ``A p - f >= 0``, ``(p - p_cav)(A p - f) = 0``
    for the conservative finite-volume form of ``-(xi^3 p')' = -(6 mu V_r xi' + 12 mu xi_t)``
    with ``p = 0`` at both ends. ``A`` is a symmetric tridiagonal M-matrix, for which the
    primal-dual active-set method (Hintermueller, Ito & Kunisch 2003, SIAM J. Optim. 13)
    terminates in finitely many steps, one tridiagonal solve each. At the rupture boundary the
    discrete solution has ``p = p_cav`` with a vanishing gradient, which is Swift-Stieber.

    Parameters
    ----------
    grid : ndarray, shape ``(M + 1,)``
        Uniform pad grid from 0 to ``l`` [m].
    xi_mid : ndarray, shape ``(M,)``
        Film thickness at the cell midpoints [m].
    xi_t : ndarray, shape ``(M + 1,)``
        ``d xi/dt`` at fixed link points, at the grid points [m/s].
    V_r, mu : float
        Collar velocity relative to the link [m/s], viscosity [Pa s].
    p_cav : float
        Cavitation pressure, gauge [Pa] (``<= 0``).
    out : ndarray, shape ``(M + 1,)``
        The pressure at the grid points.
    """
    h = grid[1] - grid[0]
    n = xi_mid.shape[0] - 1
    diag = np.empty(n)
    off = np.empty(n)  # off[i] couples unknowns i and i + 1
    f = np.empty(n)
    for i in range(n):
        a0 = xi_mid[i] ** 3 / (h * h)
        a1 = xi_mid[i + 1] ** 3 / (h * h)
        diag[i] = a0 + a1
        off[i] = -a1
        f[i] = -(6.0 * mu * V_r * (xi_mid[i + 1] - xi_mid[i]) / h + 12.0 * mu * xi_t[i + 1])
    active = np.zeros(n, dtype=np.bool_)
    p = np.zeros(n)
    lower, d, upper, rhs = np.zeros(n), np.empty(n), np.zeros(n), np.empty(n)
    for _ in range(max(200, n + 1)):
        for i in range(n):
            if active[i]:
                d[i], rhs[i], lower[i], upper[i] = 1.0, p_cav, 0.0, 0.0
            else:
                d[i], rhs[i] = diag[i], f[i]
                lower[i] = off[i - 1] if i > 0 else 0.0
                upper[i] = off[i] if i < n - 1 else 0.0
        _solve_tridiagonal(lower, d, upper, rhs, p)
        changed = False
        for i in range(n):
            residual = diag[i] * p[i] - f[i]
            if i > 0:
                residual += off[i - 1] * p[i - 1]
            if i < n - 1:
                residual += off[i] * p[i + 1]
            multiplier = residual if active[i] else 0.0
            now = multiplier - diag[i] * (p[i] - p_cav) > 0.0
            if now != active[i]:
                changed = True
            active[i] = now
        if not changed:
            break
    out[0] = 0.0
    out[n + 1] = 0.0
    for i in range(n):
        out[i + 1] = max(p[i], p_cav)


@jitable
def grid_modal_force(side, p, h, scale, ws, grid_trig, F):
    """Add the modal forces [N] of a film pressure on the uniform pad grid to ``F``; return the resultant along +j [N].

    ``F_n -= side scale h sum_k p_k sin(beta_n (x0 + X_k))`` with ``sin(beta_n (x0 + X)) = sin(beta_n x0)
    cos(beta_n X) + cos(beta_n x0) sin(beta_n X)``: ``p`` the pressure [Pa] (``scale`` the pad width
    ``B`` [m]) or the pressure integrated across the width [Pa m] (``scale`` 1 [-]) at the ``G`` grid
    points, already weighted for the trapezoidal rule (zero at the pad ends, or halved there), ``h``
    [m] the grid step, ``ws`` holding ``sin``, ``cos(beta_n x0)`` in its first ``2 N`` entries,
    ``grid_trig`` the ``sin``, ``cos`` of ``beta_n X_k`` (rows :data:`SIN`, :data:`COS`).
    The resultant is ``-side scale h sum_k p_k``.
    """
    N = F.shape[0]
    G = p.shape[0]
    total = 0.0
    for k in range(G):
        total += h * p[k]
    for n in range(N):
        acc = 0.0
        for k in range(G):
            acc += p[k] * (ws[n] * grid_trig[COS, n, k] + ws[N + n] * grid_trig[SIN, n, k])
        F[n] -= side * scale * h * acc
    return -side * scale * total
