"""The film of finite width ``B``: the 2-D Reynolds equation on the pad when the film varies along X only.

The pad is ``X in [0, l]``, ``Z in [-B/2, B/2]``, ambient pressure at all four edges. When the
link bends in its plane only, the film is ``xi(X)`` and the 2-D Reynolds equation

    d/dX(xi^3 dp/dX) + xi^3 d^2p/dZ^2 = R(X),     R = 6 mu V_r xi' + 12 mu xi_t,

separates in a sine series across the width, ``p = sum_k p_k(X) sin(k pi (Z + B/2) / B)``: with
``1 = sum_{k odd} (4 / (k pi)) sin(...)`` on the width, each odd ``k`` is the two-point problem

    (xi^3 p_k')' - (k pi / B)^2 xi^3 p_k = (4 / (k pi)) R,     p_k(0) = p_k(l) = 0,

(even terms vanish), solved here by the conservative finite-volume scheme of
:func:`~lubelink.film.reynolds.reynolds_cavitation` on the uniform pad grid, one tridiagonal
solve per term. The pressure integrated over the width is ``P = sum_k p_k 2 B / (k pi)`` [Pa m];
as ``B / l`` grows it tends to ``B`` times the 1-D film's pressure.

The short-bearing limit (``B << l``) drops the flow along the pad, ``xi^3 p_ZZ = R``:

    p = A(X) (Z^2 - B^2/4),   A = R / (2 xi^3) = (3 mu / xi^3)(V_r xi' + 2 xi_t),   P = -A B^3 / 6.

Cavitation: half-Sommerfeld clips ``p`` at ``p_cav`` (in closed form across the width for the
short film; on ``width_points`` midpoints across the width for the 2-D one); the Swift-Stieber
condition is available with the short film, where it is the obstacle problem across the width at
each X (closed form: ``p = p_cav + A (|Z| - z_c)^2`` outside the cavitated band ``|Z| < z_c``,
``z_c = B/2 - sqrt(-p_cav / A)``). For the 2-D film it needs the general solver
:func:`lubelink.film.pressure_2d`.
"""

from __future__ import annotations

import numpy as np

from .._jit import jitable, kernel
from ..params import CHOICES
from .reynolds import COS, SIN, HALF_SOMMERFELD, NO_FILM, REYNOLDS, WEDGE_SQUEEZE, grid_modal_force, pad_start
from ..beam import wavenumber

__all__ = ["ONE_D", "TWO_D", "SHORT", "width_film", "width_pressure", "centre_pressure_many", "width_sines"]

ONE_D, TWO_D, SHORT = (CHOICES["film.reynolds"].index(v) for v in ("1d", "2d", "short"))


def width_sines(modes, points):
    """``sin(k pi s_j)`` for the odd ``k = 1, 3, .., 2 modes - 1`` at the midpoints ``s_j`` of ``points`` cells of [0, 1]."""
    s = (np.arange(points) + 0.5) / points
    k = 2 * np.arange(modes) + 1
    return np.ascontiguousarray(np.sin(np.pi * np.outer(k, s)))


@jitable
def _short_line(A, B, cavitation, p_cav):
    """``(P, p_centre)`` of the short film ``p = A (Z^2 - B^2/4)`` at one X: width integral [Pa m], centre [Pa]."""
    P = -A * B * B * B / 6.0
    pc = -0.25 * A * B * B
    if cavitation == HALF_SOMMERFELD and pc < p_cav:  # clipped on |Z| < z_c where p = p_cav
        z_c = np.sqrt(0.25 * B * B + p_cav / A)
        P = 2.0 * (p_cav * z_c + A * (B * B * B / 24.0 - z_c * z_c * z_c / 3.0 - 0.25 * B * B * (0.5 * B - z_c)))
        pc = p_cav
    elif cavitation == REYNOLDS and pc < p_cav:  # Swift-Stieber across the width: p = p_cav + A (|Z| - z_c)^2
        d = np.sqrt(-p_cav / A)
        P = p_cav * B + 2.0 * A * d * d * d / 3.0
        pc = p_cav
    return P, pc


@jitable
def _clip_series(pk, B, p_cav, zsin, P, pc):
    """Half-Sommerfeld for the series: ``P``, ``pc`` from the terms ``pk`` (K, G) clipped at ``p_cav`` on the width midpoints."""
    if zsin is None:
        return
    K, G = pk.shape
    W = zsin.shape[1]
    for i in range(G):
        acc = 0.0
        for j in range(W):
            pij = 0.0
            for k in range(K):
                pij += pk[k, i] * zsin[k, j]
            acc += max(pij, p_cav)
        P[i] = B * acc / W
        centre = 0.0
        for k in range(K):
            centre += pk[k, i] if k % 2 == 0 else -pk[k, i]
        pc[i] = max(centre, p_cav)


@jitable
def width_film(grid, xi_mid, xi_t, V_r, mu, B, reynolds, modes, cavitation, p_cav, zsin, P, pc):
    """Width-integrated pressure ``P`` [Pa m] and centre-line pressure ``pc`` [Pa] at the pad grid (gauge).

    Parameters
    ----------
    grid : ndarray, shape ``(G,)``
        Uniform pad grid from 0 to ``l`` [m].
    xi_mid : ndarray, shape ``(G - 1,)``
        Film thickness at the cell midpoints [m].
    xi_t : ndarray, shape ``(G,)``
        ``d xi/dt`` at fixed link points, at the grid points [m/s].
    V_r, mu, B : float
        Collar velocity relative to the link [m/s], viscosity [Pa s], pad width [m].
    reynolds : int
        :data:`TWO_D` (sine series, ``modes`` odd terms) or :data:`SHORT`.
    cavitation : int
        Code of ``film.cavitation``; ``"reynolds"`` is honoured by the short film only.
    p_cav : float
        Gauge cavitation pressure [Pa].
    zsin : ndarray or None
        :func:`width_sines` (the 2-D film clipped by half-Sommerfeld), else None.
    P, pc : ndarray, shape ``(G,)``
        Written; zero at the pad ends, except for the short film, whose closed form ignores them.
    """
    G = grid.shape[0]
    h = grid[1] - grid[0]
    n = G - 2
    P[0] = 0.0
    P[G - 1] = 0.0
    pc[0] = 0.0
    pc[G - 1] = 0.0
    if reynolds == SHORT:  # the closed form holds up to the pad ends (it ignores them)
        for i in range(G):
            j = min(max(i, 1), G - 2)  # the ends: the film extrapolated, its slope one-sided
            xi = 0.5 * (xi_mid[j - 1] + xi_mid[j]) + (i - j) * (xi_mid[j] - xi_mid[j - 1])
            R = 6.0 * mu * V_r * (xi_mid[j] - xi_mid[j - 1]) / h + 12.0 * mu * xi_t[i]
            P[i], pc[i] = _short_line(0.5 * R / (xi * xi * xi), B, cavitation, p_cav)
        return
    a = np.empty(G - 1)  # xi^3 / h^2 at the midpoints
    for i in range(G - 1):
        a[i] = xi_mid[i] ** 3 / (h * h)
    xi3 = np.empty(n)
    R = np.empty(n)
    for i in range(n):
        xn = 0.5 * (xi_mid[i] + xi_mid[i + 1])
        xi3[i] = xn * xn * xn
        R[i] = 6.0 * mu * V_r * (xi_mid[i + 1] - xi_mid[i]) / h + 12.0 * mu * xi_t[i + 1]
    pk = np.zeros((modes, G))
    c = np.empty(n)
    for i in range(G):
        P[i] = 0.0
        pc[i] = 0.0
    for m in range(modes):
        k = 2 * m + 1
        kappa2 = (k * np.pi / B) ** 2
        ck = 4.0 / (k * np.pi)
        # -a0 p_{i-1} + (a0 + a1 + kappa^2 xi^3) p_i - a1 p_{i+1} = -c_k R_i (Thomas algorithm)
        d = a[0] + a[1] + kappa2 * xi3[0]
        c[0] = -a[1] / d
        pk[m, 1] = -ck * R[0] / d
        for i in range(1, n):
            d = a[i] + a[i + 1] + kappa2 * xi3[i] + a[i] * c[i - 1]
            c[i] = -a[i + 1] / d
            pk[m, i + 1] = (-ck * R[i] + a[i] * pk[m, i]) / d
        for i in range(n - 2, -1, -1):
            pk[m, i + 1] -= c[i] * pk[m, i + 2]
        weight = 2.0 * B / (k * np.pi)
        sign = 1.0 if m % 2 == 0 else -1.0
        for i in range(1, G - 1):
            P[i] += weight * pk[m, i]
            pc[i] += sign * pk[m, i]
    if cavitation == HALF_SOMMERFELD:
        _clip_series(pk, B, p_cav, zsin, P, pc)


@jitable
def film_on_grid(side, q, q_dot, s0, c0, f, grid_trig, xi_mid, xi_t):
    """The film ``H/2 - side u2`` at the grid's midpoints and its rate at the grid points, from ``grid_trig``."""
    N = q.shape[0]
    G = grid_trig.shape[2]
    for k in range(G - 1):
        xi_mid[k] = 0.5 * f.clearance
    for k in range(G):
        xi_t[k] = 0.0
    for n in range(N):
        a, b = side * q[n] * s0[n], side * q[n] * c0[n]
        for k in range(G - 1):  # u2(x0 + X) = sum_n q_n [sin(b x0) cos(b X) + cos(b x0) sin(b X)]
            xi_mid[k] -= a * grid_trig[COS + 2, n, k] + b * grid_trig[SIN + 2, n, k]
        if f.model == WEDGE_SQUEEZE:
            a, b = side * q_dot[n] * s0[n], side * q_dot[n] * c0[n]
            for k in range(G):
                xi_t[k] -= a * grid_trig[COS, n, k] + b * grid_trig[SIN, n, k]


@jitable
def width_side(side, q, q_dot, ws, V_r, f, B, grid_trig, zsin, F):
    """Modal forces of the finite-width film on ``side`` added to ``F`` [N]; returns its resultant along +j [N].

    ``F_n = -side int_0^l P(X) sin(beta_n (x0 + X)) dX`` by the trapezoidal rule on the pad grid;
    ``ws`` holds ``sin``, ``cos(beta_n x0)`` in its first ``2 N``
    entries. ``grid_trig`` None (the 1-D film) compiles to nothing.
    """
    if grid_trig is None:
        return 0.0
    N = q.shape[0]
    G = grid_trig.shape[2]
    grid = np.linspace(0.0, f.pad_length, G)
    h = grid[1] - grid[0]
    xi_mid = np.empty(G - 1)
    xi_t = np.empty(G)
    film_on_grid(side, q, q_dot, ws[:N], ws[N:2 * N], f, grid_trig, xi_mid, xi_t)
    P = np.empty(G)
    pc = np.empty(G)
    width_film(grid, xi_mid, xi_t, V_r, f.viscosity, B, f.reynolds, f.width_modes, f.cavitation,
               f.cavitation_pressure - f.ambient_pressure, zsin, P, pc)
    P[0] *= 0.5  # trapezoidal weights
    P[G - 1] *= 0.5
    return grid_modal_force(side, P, h, 1.0, ws, grid_trig, F)  # P is integrated across the width already


@kernel
def centre_pressure_many(X, q, q_dot, x_star, V_r, side, f, B, L, grid_trig, zsin):
    """Centre-line (``Z = 0``) gauge pressure [Pa] of the finite-width film at pad points ``X``, many states.

    ``q``, ``q_dot`` shape ``(T, N)``; ``x_star``, ``V_r`` shape ``(T,)``; ``grid_trig`` the
    :class:`~lubelink.film.force.PadTables` table of ``N`` modes. Returns shape ``(T, X.size)``.
    """
    T, N = q.shape
    out = np.zeros((T, X.shape[0]))
    if f.model == NO_FILM:
        return out
    G = grid_trig.shape[2]
    grid = np.linspace(0.0, f.pad_length, G)
    s0 = np.empty(N)
    c0 = np.empty(N)
    xi_mid = np.empty(G - 1)
    xi_t = np.empty(G)
    P = np.empty(G)
    pc = np.empty(G)
    for i in range(T):
        x0 = pad_start(x_star[i], f.pad_length, f.pad_reference)
        for m in range(N):
            s0[m] = np.sin(wavenumber(m + 1, L) * x0)
            c0[m] = np.cos(wavenumber(m + 1, L) * x0)
        film_on_grid(side, q[i], q_dot[i], s0, c0, f, grid_trig, xi_mid, xi_t)
        width_film(grid, xi_mid, xi_t, V_r[i], f.viscosity, B, f.reynolds, f.width_modes, f.cavitation,
                   f.cavitation_pressure - f.ambient_pressure, zsin, P, pc)
        out[i] = np.interp(X, grid, pc)
    return out


@kernel
def _width_kernel(grid, xi_mid, xi_t, V_r, mu, B, reynolds, modes, cavitation, p_cav, zsin):
    P = np.empty(grid.shape[0])
    pc = np.empty(grid.shape[0])
    width_film(grid, xi_mid, xi_t, V_r, mu, B, reynolds, modes, cavitation, p_cav, zsin, P, pc)
    return P, pc


def width_pressure(xi, V_r, mu, width, pad_length, *, xi_t=None, reynolds="2d", modes=8, cavitation="none",
                   p_cav=-101325.0, grid_points=201, width_points=32):
    """The finite-width film of a film ``xi(X)`` uniform across the width, on a uniform pad grid.

    What the right-hand side executes (:func:`width_film`), from Python.

    Parameters
    ----------
    xi : callable
        Film thickness [m], a vectorised function of ``X`` [m].
    V_r, mu : float
        Collar velocity relative to the link [m/s], viscosity [Pa s].
    width, pad_length : float
        ``B``, ``l`` [m].
    xi_t : callable, optional
        ``d xi / dt`` [m/s] (squeeze term).
    reynolds : {"2d", "short"}
        Sine series across the width (``modes`` odd terms) or the short-bearing closed form.
    cavitation : {"none", "half-sommerfeld", "reynolds"}
        ``"reynolds"`` with ``reynolds = "short"`` only.
    p_cav : float
        Gauge cavitation pressure [Pa].
    grid_points, width_points : int
        Pad grid; points across the width where the 2-D film is clipped (half-Sommerfeld).

    Returns
    -------
    X : ndarray, shape ``(grid_points,)``
        The grid [m].
    P : ndarray
        Pressure integrated over the width [Pa m].
    p_centre : ndarray
        Pressure on the centre line ``Z = 0`` [Pa].
    """
    if reynolds not in ("2d", "short"):
        raise ValueError(f"reynolds = {reynolds!r}: must be '2d' or 'short'")
    if cavitation not in CHOICES["film.cavitation"]:
        raise ValueError(f"cavitation = {cavitation!r}: must be 'none', 'half-sommerfeld' or 'reynolds'")
    if cavitation == "reynolds" and reynolds == "2d":
        raise ValueError("cavitation = 'reynolds' with reynolds = '2d': use lubelink.film.pressure_2d")
    grid = np.linspace(0.0, pad_length, int(grid_points))
    mid = 0.5 * (grid[1:] + grid[:-1])
    xi_mid = np.ascontiguousarray(np.broadcast_to(np.asarray(xi(mid), dtype=float), mid.shape))
    if not (np.all(np.isfinite(xi_mid)) and np.all(xi_mid > 0)):
        raise ValueError("the film thickness xi must be finite and positive on the whole pad")
    xt = np.zeros_like(grid) if xi_t is None else np.broadcast_to(np.asarray(xi_t(grid), dtype=float), grid.shape)
    cav = CHOICES["film.cavitation"].index(cavitation)
    zsin = width_sines(modes, width_points) if (reynolds == "2d" and cavitation == "half-sommerfeld") else None
    P, pc = _width_kernel(grid, xi_mid, np.ascontiguousarray(xt), float(V_r), float(mu), float(width),
                          CHOICES["film.reynolds"].index(reynolds), int(modes), cav, float(p_cav), zsin)
    return grid, P, pc
