"""Reynolds film between the collar pad and the link (docs/model.md section 4; paper Eqs. 14-17, 20).

The pad spans ``X in [0, l]`` from its start ``x0`` on the link. The film thickness is
``xi(X) = H/2 - u2(x0 + X)`` and the gauge pressure ``p_g`` solves the 1-D Reynolds equation in
the link frame (paper Eq. 16, plus the squeeze term the paper drops):

    (xi^3 p_g')' = 6 mu V_r xi' + 12 mu xi_t,     p_g(0) = p_g(l) = 0,

``V_r`` the collar velocity relative to the link, ``xi_t`` the rate of the film at a fixed point
of the link. Integrating once (:func:`pressure_gradient`)::

    xi^3 p_g' = 6 mu V_r xi + 12 mu Q + C,    Q(X) = int_0^X xi_t,

and ``p_g(l) = 0`` fixes the constant (:func:`reynolds_constant`)::

    C = -(6 mu V_r I1 + 12 mu I3) / I2,   I1 = int_0^l xi^-2,  I2 = int_0^l xi^-3,  I3 = int_0^l Q xi^-3.

The force per unit length on the link is ``f2 = -B p_g`` (the film pushes the link away from the
collar face). Its sine transform is taken by parts, ``F_n = -B int p_g sin(beta_n x) dX =
B int p_g' W_n dX`` with ``W_n(X) = int_0^X sin(beta_n (x0 + s)) ds`` in closed form, so one
Gauss-Legendre pass over the pad gives the modal forces (:func:`modal_film_force`); the pressure
itself is the running integral of ``p_g'`` (half-Sommerfeld cavitation, the pressure output).
The Swift-Stieber (Reynolds) cavitation condition is an obstacle problem solved on a pad grid
(:func:`reynolds_cavitation`).
"""

from __future__ import annotations

from functools import lru_cache
from typing import NamedTuple

import numpy as np

from ._jit import jitable, kernel
from .beam import add_deflection
from .params import CHOICES, Film, kernel_view

__all__ = [
    "PadTables",
    "pad_tables",
    "gauss_legendre",
    "integration_matrix",
    "pad_start",
    "reynolds_constant",
    "pressure_gradient",
    "reynolds_cavitation",
    "modal_film_force",
    "pressure",
    "modal_force",
    "pad_pressure",
    "resultant_force",
    "film_thickness",
    "mode_film",
    "mode_film_rate",
]

NO_FILM, WEDGE, WEDGE_SQUEEZE = (CHOICES["film.model"].index(v) for v in ("none", "wedge", "wedge+squeeze"))
FULL, HALF_SOMMERFELD, REYNOLDS = (CHOICES["film.cavitation"].index(v)
                                   for v in ("none", "half-sommerfeld", "reynolds"))
CENTRE = CHOICES["film.pad_reference"].index("centre")


class PadTables(NamedTuple):
    """What depends on the pad geometry only, tabulated once per model (``N`` modes).

    ``quad`` (2, nodes): the Gauss-Legendre nodes ``X_j`` [m] and weights [m] on ``[0, l]``;
    ``trig`` (3, N, nodes): ``sin``, ``cos`` and ``1 - cos`` of ``beta_n X_j`` (rows
    :data:`SIN`, :data:`COS`, :data:`VERS`), so that ``sin(beta_n (x0 + X_j))`` needs ``sin``,
    ``cos(beta_n x0)`` only; ``S`` [m]: the spectral integration matrix on the nodes
    (half-Sommerfeld; else empty); ``grid_trig`` (4, N, G): ``sin``, ``cos`` at the points of the
    uniform Reynolds-cavitation grid and at its ``G - 1`` cell midpoints (else empty);
    ``sample_trig`` (2, N, K): ``sin``, ``cos`` at the uniform samples of the thinnest-film
    search. Few arrays, because every array of the parameters costs a reference count at each
    call of the right-hand side.
    """

    quad: np.ndarray
    trig: np.ndarray
    S: np.ndarray
    grid_trig: np.ndarray
    sample_trig: np.ndarray


#: Rows of :attr:`PadTables.trig` (and ``sample_trig``, ``grid_trig``: then ``+ 2`` for the midpoints).
SIN, COS, VERS = 0, 1, 2


@lru_cache(maxsize=32)
def gauss_legendre(nodes):
    """Gauss-Legendre nodes and weights on ``[0, 1]``."""
    s, w = np.polynomial.legendre.leggauss(nodes)
    return 0.5 * (s + 1.0), 0.5 * w


@lru_cache(maxsize=32)
def integration_matrix(nodes):
    """``S[i, j] = int_0^{s_i} l_j(s) ds`` for the Lagrange basis on the GL nodes of ``[0, 1]``.

    Built in the Legendre basis, which stays well conditioned for many nodes (a monomial
    construction loses all digits beyond about 20 nodes).
    """
    leg = np.polynomial.legendre
    s, _ = gauss_legendre(nodes)
    z = 2.0 * s - 1.0
    V = leg.legvander(z, nodes - 1)
    V_int = np.column_stack([leg.legval(z, leg.legint(np.eye(nodes)[j], lbnd=-1.0)) for j in range(nodes)])
    return np.ascontiguousarray(0.5 * V_int @ np.linalg.inv(V))


def _tables(beta, X):
    bX = np.outer(beta, X)
    return np.sin(bX), np.cos(bX)


def pad_tables(modes, rod_length, film: Film) -> PadTables:
    """The :class:`PadTables` of ``modes`` sine modes on a link of length ``rod_length`` [m]."""
    beta = np.arange(1, modes + 1) * np.pi / rod_length
    l = film.pad_length
    s, w = gauss_legendre(film.quadrature_nodes)
    X = l * s
    sin_bX, cos_bX = _tables(beta, X)
    vers_bX = 2.0 * np.sin(0.5 * np.outer(beta, X)) ** 2  # 1 - cos without cancellation
    S = l * integration_matrix(film.quadrature_nodes) if film.cavitation == "half-sommerfeld" else np.zeros((0, 0))
    if film.cavitation == "reynolds":
        grid = np.linspace(0.0, l, film.grid_points)
        mid = np.append(0.5 * (grid[1:] + grid[:-1]), l)  # the last column is not used
        grid_trig = np.stack(_tables(beta, grid) + _tables(beta, mid))
    else:
        grid_trig = np.zeros((4, modes, 0))
    samples = np.linspace(0.0, l, 16 + 4 * modes)
    return PadTables(*(np.ascontiguousarray(a, dtype=float) for a in
                       (np.stack([X, l * w]), np.stack([sin_bX, cos_bX, vers_bX]), S, grid_trig,
                        np.stack(_tables(beta, samples)))))


# --- the equations -------------------------------------------------------------------------------
@jitable
def pad_start(x_star, pad_length, pad_reference):
    """Start of the pad on the link [m] (D6): ``x_star``, or ``x_star - l/2`` when ``x_star`` is the centre.

    ``pad_reference`` is the choice's code (0 edge, 1 centre).
    """
    return x_star - 0.5 * pad_length if pad_reference == CENTRE else x_star


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


# --- the modal film force --------------------------------------------------------------------------
@jitable
def _film_side(side, q, q_dot, ws, L, V_r, f, B, pad, F):
    """Add the modal forces of the film on ``side`` to ``F`` [N]; return its resultant along +j [N].

    ``side = 1``: the film ``H/2 - u2`` (the paper's); ``-1``: ``H/2 + u2``, which is the first
    one for the mirrored state ``-q`` with its force mirrored back. ``ws``: scratch holding
    ``sin``, ``cos(beta_n x0)`` in its first ``2 N`` entries, then room for the film, ``Q`` and
    ``w p'`` at the nodes. (The tables and the scratch are indexed, not sliced: a view of an
    array costs two atomic reference-count updates in compiled code, which here would cost more
    than the arithmetic.)
    """
    N = q.shape[0]
    mu = f.viscosity
    if f.cavitation == REYNOLDS:  # the obstacle problem on the pad grid, integrated by the trapezoidal rule
        G = pad.grid_trig.shape[2]
        grid = np.linspace(0.0, f.pad_length, G)
        h = grid[1] - grid[0]
        xi_mid = np.full(G - 1, 0.5 * f.clearance)
        xi_t = np.zeros(G)
        for n in range(N):
            a, b = side * q[n] * ws[n], side * q[n] * ws[N + n]
            for k in range(G - 1):  # u2(x0 + X) = sum_n q_n [sin(b x0) cos(b X) + cos(b x0) sin(b X)]
                xi_mid[k] -= a * pad.grid_trig[COS + 2, n, k] + b * pad.grid_trig[SIN + 2, n, k]
            if f.model == WEDGE_SQUEEZE:
                a, b = side * q_dot[n] * ws[n], side * q_dot[n] * ws[N + n]
                for k in range(G):
                    xi_t[k] -= a * pad.grid_trig[COS, n, k] + b * pad.grid_trig[SIN, n, k]
        p = np.empty(G)
        reynolds_cavitation(grid, xi_mid, xi_t, V_r, mu, f.cavitation_pressure - f.ambient_pressure, p)
        total = 0.0
        for k in range(G):
            total += h * p[k]
        for n in range(N):
            acc = 0.0
            for k in range(G):
                acc += p[k] * (ws[n] * pad.grid_trig[COS, n, k] + ws[N + n] * pad.grid_trig[SIN, n, k])
            F[n] -= side * B * h * acc
        return -side * B * total

    nodes = pad.quad.shape[1]
    o_xi, o_Q, o_wdp = 2 * N, 2 * N + nodes, 2 * N + 2 * nodes
    squeeze = f.model == WEDGE_SQUEEZE
    for j in range(nodes):
        ws[o_xi + j] = 0.5 * f.clearance
        ws[o_Q + j] = 0.0
    for n in range(N):
        a, b = side * q[n] * ws[n], side * q[n] * ws[N + n]
        for j in range(nodes):  # xi = H/2 - side u2(x0 + X_j)
            ws[o_xi + j] -= a * pad.trig[COS, n, j] + b * pad.trig[SIN, n, j]
        if squeeze:  # Q = -side sum_n q_dot_n W_n(X), W_n = [c0 (1 - cos bX) + s0 sin bX] / b
            beta = (n + 1) * np.pi / L
            a, b = side * q_dot[n] * ws[N + n] / beta, side * q_dot[n] * ws[n] / beta
            for j in range(nodes):
                ws[o_Q + j] -= a * pad.trig[VERS, n, j] + b * pad.trig[SIN, n, j]
    I1 = 0.0
    I2 = 0.0
    I3 = 0.0
    for j in range(nodes):
        xi = ws[o_xi + j]
        w_inv3 = pad.quad[1, j] / (xi * xi * xi)
        I1 += w_inv3 * xi
        I2 += w_inv3
        I3 += w_inv3 * ws[o_Q + j]
    C = reynolds_constant(I1, I2, I3, V_r, mu)
    for j in range(nodes):
        ws[o_wdp + j] = pad.quad[1, j] * pressure_gradient(ws[o_xi + j], ws[o_Q + j], C, V_r, mu)
    if f.cavitation == FULL:  # by parts: F_n = B int p' W_n, resultant B int p' X
        total = 0.0
        for j in range(nodes):
            total += ws[o_wdp + j] * pad.quad[0, j]
        for n in range(N):
            av = 0.0
            bs = 0.0
            for j in range(nodes):
                av += ws[o_wdp + j] * pad.trig[VERS, n, j]
                bs += ws[o_wdp + j] * pad.trig[SIN, n, j]
            F[n] += side * B * (ws[N + n] * av + ws[n] * bs) / ((n + 1) * np.pi / L)
        return side * B * total
    # half-Sommerfeld: the pressure at the nodes is the running integral of p', clipped; w p_g into o_Q
    p_cav = f.cavitation_pressure - f.ambient_pressure
    total = 0.0
    for i in range(nodes):
        p_i = 0.0
        for j in range(nodes):
            p_i += pad.S[i, j] * ws[o_wdp + j] / pad.quad[1, j]
        ws[o_Q + i] = pad.quad[1, i] * max(p_i, p_cav)
        total += ws[o_Q + i]
    for n in range(N):
        acc = 0.0
        for j in range(nodes):
            acc += ws[o_Q + j] * (ws[n] * pad.trig[COS, n, j] + ws[N + n] * pad.trig[SIN, n, j])
        F[n] -= side * B * acc
    return -side * B * total


@jitable
def modal_film_force(q, q_dot, x_star, V_r, f, B, pad, L, F):
    """Modal film forces added to ``F`` [N]; returns the resultant film force on the link along +j [N].

    ``F_n = -B int_pad p_g sin(beta_n x) dx`` (docs/model.md sections 2 and 4; the corrected
    paper Eq. 20, gauge pressure) for every film of ``f`` (a :func:`lubelink.params.kernel_view`
    of :class:`~lubelink.params.Film`): wedge or wedge and squeeze, one or two sides, cavitation
    none, half-Sommerfeld or Reynolds.

    Parameters
    ----------
    q, q_dot : ndarray, shape ``(N,)``
        Modal coordinates [m] and velocities [m/s].
    x_star : float
        Collar position on the link [m].
    V_r : float
        Collar velocity relative to the link [m/s].
    f : FilmView
        Film parameters.
    B : float
        Pad (link) width [m].
    pad : PadTables
        Tables of the pad geometry.
    L : float
        Link length [m] (the wavenumbers are ``beta_n = n pi / L``).
    F : ndarray, shape ``(N,)``
        Accumulates the modal forces.
    """
    if f.model == NO_FILM:
        return 0.0
    x0 = pad_start(x_star, f.pad_length, f.pad_reference)
    N = q.shape[0]
    ws = np.empty(2 * N + 3 * pad.quad.shape[1])
    for n in range(N):
        ws[n] = np.sin((n + 1) * np.pi / L * x0)
        ws[N + n] = np.cos((n + 1) * np.pi / L * x0)
    total = _film_side(1.0, q, q_dot, ws, L, V_r, f, B, pad, F)
    if f.sides == 2:
        total += _film_side(-1.0, q, q_dot, ws, L, V_r, f, B, pad, F)
    return total


@kernel
def film_force_many(q, q_dot, x_star, V_r, f, B, pad, L):
    """:func:`modal_film_force`'s resultant [N] for many states: ``q``, ``q_dot`` shape ``(T, N)``, ``x_star``, ``V_r`` shape ``(T,)``."""
    T, N = q.shape
    out = np.empty(T)
    F = np.empty(N)
    for i in range(T):
        out[i] = modal_film_force(q[i], q_dot[i], x_star[i], V_r[i], f, B, pad, L, F)
    return out


# --- the pressure on the pad ---------------------------------------------------------------------------
@jitable
def pressure_on_breaks(breaks, xi, xi_t, V_r, mu, w, Sm, out):
    """Gauge pressure [Pa] at ``breaks`` (``p_g = 0`` at both ends) from the film at the GL nodes of each piece.

    ``xi``, ``xi_t`` shape ``(M, n)``: the film [m] and its rate [m/s] at the ``n`` Gauss-Legendre
    nodes (weights ``w`` on ``[0, 1]``) of each of the ``M`` pieces between consecutive
    ``breaks``; ``xi_t`` empty (shape ``(M, 0)``) for the wedge film. ``Sm``:
    :func:`integration_matrix` of ``n``. The pressure is the running integral of
    :func:`pressure_gradient`. Writes ``out``, shape ``(M + 1,)``.
    """
    M, n = xi.shape
    Q = np.zeros((M, n))
    if xi_t.shape[1] > 0:
        Q_start = 0.0
        for k in range(M):
            h = breaks[k + 1] - breaks[k]
            for i in range(n):
                acc = 0.0
                for j in range(n):
                    acc += Sm[i, j] * xi_t[k, j]
                Q[k, i] = Q_start + h * acc
            for j in range(n):
                Q_start += h * w[j] * xi_t[k, j]
    I1 = 0.0
    I2 = 0.0
    I3 = 0.0
    for k in range(M):
        h = breaks[k + 1] - breaks[k]
        for j in range(n):
            inv3 = 1.0 / (xi[k, j] * xi[k, j] * xi[k, j])
            I1 += h * w[j] * xi[k, j] * inv3
            I2 += h * w[j] * inv3
            I3 += h * w[j] * Q[k, j] * inv3
    C = reynolds_constant(I1, I2, I3, V_r, mu)
    out[0] = 0.0
    for k in range(M):
        h = breaks[k + 1] - breaks[k]
        acc = 0.0
        for j in range(n):
            acc += h * w[j] * pressure_gradient(xi[k, j], Q[k, j], C, V_r, mu)
        out[k + 1] = out[k] + acc
    out[M] = 0.0  # the boundary condition; the running integral ends at 0 up to rounding


@kernel
def pad_pressure_many(X, q, q_dot, x_star, V_r, side, f, L, w, Sm, sin_p, cos_p, sin_g, cos_g):
    """Gauge pressure [Pa] at pad points ``X`` (from 0 to ``l``) for many states, on film ``side``.

    ``q``, ``q_dot`` shape ``(T, N)``; ``x_star``, ``V_r`` shape ``(T,)``. ``sin_p``, ``cos_p``:
    tables of ``beta_n = n pi / L`` times the points where the film is needed, shape ``(N, M n)``: the
    ``n`` Gauss-Legendre nodes (weights ``w``, integration matrix ``Sm``) of each of the ``M``
    pieces between consecutive ``X`` (cavitation none, half-Sommerfeld: :func:`pressure_on_breaks`,
    then clipped), or the midpoints of the uniform ``f.grid_points`` grid (Reynolds, with
    ``sin_g``, ``cos_g`` at the grid points: :func:`reynolds_cavitation`, interpolated to ``X``).
    Returns shape ``(T, X.size)``.
    """
    T, N = q.shape
    M = X.shape[0] - 1
    out = np.zeros((T, M + 1))
    if f.model == NO_FILM:
        return out
    p_cav = f.cavitation_pressure - f.ambient_pressure
    n_pts = sin_p.shape[1]
    grid = np.linspace(0.0, f.pad_length, sin_g.shape[1])
    for i in range(T):
        x0 = pad_start(x_star[i], f.pad_length, f.pad_reference)
        s0 = np.sin(np.arange(1, N + 1) * np.pi / L * x0)
        c0 = np.cos(np.arange(1, N + 1) * np.pi / L * x0)
        xi = np.full(n_pts, 0.5 * f.clearance)
        add_deflection(q[i], s0, c0, sin_p, cos_p, -side, xi)
        if f.cavitation == REYNOLDS:
            xi_t = np.zeros(grid.shape[0])
            if f.model == WEDGE_SQUEEZE:
                add_deflection(q_dot[i], s0, c0, sin_g, cos_g, -side, xi_t)
            p = np.empty(grid.shape[0])
            reynolds_cavitation(grid, xi, xi_t, V_r[i], f.viscosity, p_cav, p)
            out[i] = np.interp(X, grid, p)
            continue
        n = n_pts // M
        xi_t = np.zeros(n_pts if f.model == WEDGE_SQUEEZE else 0)
        if f.model == WEDGE_SQUEEZE:
            add_deflection(q_dot[i], s0, c0, sin_p, cos_p, -side, xi_t)
        pressure_on_breaks(X, xi.reshape((M, n)), xi_t.reshape((M, xi_t.shape[0] // M)), V_r[i], f.viscosity,
                           w, Sm, out[i])
        if f.cavitation == HALF_SOMMERFELD:
            for k in range(M + 1):
                out[i, k] = max(out[i, k], p_cav)
    return out


@kernel
def _modal_force_kernel(q, q_dot, x_star, V_r, f, B, pad, L):
    F = np.zeros(q.shape[0])
    total = modal_film_force(q, q_dot, x_star, V_r, f, B, pad, L, F)
    return F, total


@kernel
def _pressure_kernel(breaks, xi, xi_t, V_r, mu, w, Sm):
    out = np.empty(breaks.shape[0])
    pressure_on_breaks(breaks, xi, xi_t, V_r, mu, w, Sm, out)
    return out


@kernel
def _reynolds_kernel(grid, xi_mid, xi_t, V_r, mu, p_cav):
    out = np.empty(grid.shape[0])
    reynolds_cavitation(grid, xi_mid, xi_t, V_r, mu, p_cav, out)
    return out


# --- the public, vectorised API ----------------------------------------------------------------------
def film_thickness(q, x, clearance, rod_length):
    """One-sided film ``xi = H/2 - u2(x)`` [m] at link positions ``x`` [m].

    ``q`` has shape ``(..., N)``, ``x`` shape ``(..., M)`` (broadcast with the leading axes of
    ``q``); returns shape ``(..., M)``.
    """
    q = np.asarray(q, dtype=float)
    beta = np.arange(1, q.shape[-1] + 1) * np.pi / rod_length
    u2 = np.sum(q[..., None, :] * np.sin(np.asarray(x)[..., None] * beta), axis=-1)
    return 0.5 * clearance - u2


def mode_film(q, x0, clearance, rod_length):
    """The one-sided film ``xi(X) = H/2 - u2(x0 + X)`` of modal state ``q`` as a function [m]."""
    beta = np.arange(1, q.shape[-1] + 1) * np.pi / rod_length
    return lambda X: 0.5 * clearance - np.sin(np.multiply.outer(x0 + np.asarray(X), beta)) @ q


def mode_film_rate(q_dot, x0, rod_length):
    """``d xi/dt = -u2_dot(x0 + X)`` at fixed link points, as a function [m/s]."""
    beta = np.arange(1, q_dot.shape[-1] + 1) * np.pi / rod_length
    return lambda X: -(np.sin(np.multiply.outer(x0 + np.asarray(X), beta)) @ q_dot)


def _as_function(values, X, name):
    if callable(values):
        return values
    from scipy.interpolate import CubicSpline

    values = np.asarray(values, dtype=float)
    if values.shape != X.shape:
        raise ValueError(f"{name} must be a callable or an array shaped like X {X.shape}, got {values.shape}")
    return CubicSpline(X, values)


def _positive(*films):
    return all(np.all(np.isfinite(f)) and np.all(np.asarray(f) > 0) for f in films)


def pressure(X, xi, V_r, mu, *, xi_t=None, pad_length=None, cavitation="none", p_cav=-101325.0,
             subintervals=32, nodes=8, grid_points=401):
    """Gauge pressure of the 1-D Reynolds film [Pa] (paper Eqs. 16-17, corrected), for any film.

    Solves ``(xi^3 p')' = 6 mu V_r xi' + 12 mu xi_t`` on ``[0, l]`` with ``p(0) = p(l) = 0`` by
    composite Gauss-Legendre quadrature of the closed-form first integral
    (:func:`pressure_on_breaks`, the function the results use too).

    Parameters
    ----------
    X : array_like
        Increasing positions on the pad where the pressure is wanted [m].
    xi : callable or array_like
        Film thickness [m]: a vectorised function of ``X``, or its values at ``X`` (then ``X``
        must run from 0 to ``l`` and ``xi`` is interpolated by a cubic spline).
    V_r : float
        Velocity of the flat surface (the collar) relative to the shaped one (the link), along
        +X [m/s].
    mu : float
        Dynamic viscosity [Pa s].
    xi_t : callable or array_like, optional
        ``d xi / dt`` at fixed points of the link [m/s] (squeeze term); same form as ``xi``.
        Omitted: the paper's wedge-only film.
    pad_length : float, optional
        ``l`` [m]; defaults to ``X[-1]``.
    cavitation : {"none", "half-sommerfeld", "reynolds"}
        ``"none"``: the full Sommerfeld solution (sub-ambient pressure allowed, as in the paper);
        ``"half-sommerfeld"``: that solution clipped at ``p_cav``; ``"reynolds"``: the
        Swift-Stieber condition (``p >= p_cav`` with ``p = p_cav`` and ``p' = 0`` at rupture), by
        :func:`reynolds_cavitation` on ``grid_points`` points.
    p_cav : float
        Cavitation pressure as a **gauge** pressure, ``p_cav - p_am`` [Pa].
    subintervals, nodes : int
        Composite quadrature: ``[0, l]`` is split into ``subintervals`` pieces (and at every
        point of ``X``), each with ``nodes`` GL nodes.
    grid_points : int
        Grid of the ``"reynolds"`` solver.

    Returns
    -------
    ndarray
        Gauge pressure ``P - p_am`` at ``X`` [Pa].

    Examples
    --------
    Plane inclined slider, converging in the direction of motion:

    >>> import numpy as np
    >>> X = np.linspace(0, 0.05, 5)
    >>> p = pressure(X, lambda X: 2e-4 - 1e-4 * X / 0.05, V_r=1.0, mu=0.1)
    >>> bool(p[2] > 0)
    True
    """
    X = np.asarray(X, dtype=float)
    if X.ndim != 1 or X.size < 1 or np.any(np.diff(X) < 0):
        raise ValueError("X must be a non-empty increasing 1-D array of pad positions")
    length = float(X[-1]) if pad_length is None else float(pad_length)
    if not length > 0 or X[0] < 0 or X[-1] > length * (1 + 1e-12):
        raise ValueError(f"X must lie in [0, pad_length = {length}]")
    sampled = not callable(xi) or (xi_t is not None and not callable(xi_t))
    if sampled and (X[0] != 0.0 or X[-1] < length * (1 - 1e-12)):
        raise ValueError(f"xi or xi_t given as values at X needs X to run from 0 to pad_length = {length}")
    xi_f = _as_function(xi, X, "xi")
    xi_t_f = None if xi_t is None else _as_function(xi_t, X, "xi_t")
    if cavitation not in CHOICES["film.cavitation"]:
        raise ValueError(f"cavitation = {cavitation!r}: must be 'none', 'half-sommerfeld' or 'reynolds'")
    if cavitation == "reynolds":
        grid = np.linspace(0.0, length, grid_points)
        mid = 0.5 * (grid[1:] + grid[:-1])
        xi_mid = np.asarray(xi_f(mid), dtype=float)
        if not _positive(xi_mid, xi_f(grid)):
            raise ValueError("the film thickness xi must be finite and positive on the whole pad")
        xi_t_g = np.zeros_like(grid) if xi_t_f is None else np.asarray(xi_t_f(grid), dtype=float)
        p = _reynolds_kernel(grid, np.ascontiguousarray(xi_mid), xi_t_g, float(V_r), float(mu), float(p_cav))
        return np.interp(X, grid, p)
    breaks = np.unique(np.concatenate([np.linspace(0.0, length, subintervals + 1), np.clip(X, 0, length)]))
    s, w = gauss_legendre(nodes)
    pts = breaks[:-1, None] + np.diff(breaks)[:, None] * s
    xi_v = np.ascontiguousarray(np.asarray(xi_f(pts), dtype=float).reshape(pts.shape))
    if not _positive(xi_v, xi_f(breaks)):  # the pad ends and X are not GL nodes
        raise ValueError("the film thickness xi must be finite and positive on the whole pad")
    xi_t_v = (np.zeros((pts.shape[0], 0)) if xi_t_f is None
              else np.ascontiguousarray(np.asarray(xi_t_f(pts), dtype=float).reshape(pts.shape)))
    p_breaks = _pressure_kernel(breaks, xi_v, xi_t_v, float(V_r), float(mu), w, integration_matrix(nodes))
    if cavitation == "half-sommerfeld":
        p_breaks = np.maximum(p_breaks, p_cav)
    return np.interp(X, breaks, p_breaks)


def _film_view(mu, clearance, pad_length, squeeze, nodes, cavitation, p_cav, grid_points, sides=1):
    film = Film(model="wedge+squeeze" if squeeze else "wedge", viscosity=mu, clearance=clearance,
                pad_length=pad_length, quadrature_nodes=nodes, sides=sides, cavitation=cavitation,
                cavitation_pressure=p_cav, ambient_pressure=0.0, grid_points=grid_points)
    return film, kernel_view(film)


def modal_force(q, q_dot, x0, V_r, *, mu, clearance, pad_length, width, rod_length, squeeze=False, nodes=32,
                cavitation="none", p_cav=-101325.0, grid_points=201):
    """Modal film forces ``F_n`` [N], the resultant film force [N] and the thinnest film [m] of one state.

    :func:`modal_film_force` (what the right-hand side executes) for the one-sided film
    ``xi = H/2 - u2`` on the pad ``[x0, x0 + l]``.

    Parameters
    ----------
    q, q_dot : ndarray, shape ``(N,)``
        Modal coordinates [m] and velocities [m/s].
    x0 : float
        Pad start on the link [m].
    V_r : float
        Collar velocity relative to the link [m/s].
    mu, clearance, pad_length, width, rod_length : float
        ``mu`` [Pa s], ``H`` [m], ``l`` [m], ``B`` [m], ``L`` [m].
    squeeze : bool
        Include the ``12 mu xi_t`` term.
    nodes : int
        Gauss-Legendre nodes on the pad.
    cavitation : {"none", "half-sommerfeld", "reynolds"}
        See :func:`pressure`.
    p_cav : float
        Gauge cavitation pressure [Pa].
    grid_points : int
        Grid of the ``"reynolds"`` solver.

    Returns
    -------
    F : ndarray, shape ``(N,)``
    total : float
    xi_min : float
        Smallest film thickness at the quadrature nodes [m].
    """
    q = np.ascontiguousarray(q, dtype=float)
    q_dot = np.ascontiguousarray(q_dot, dtype=float)
    film, view = _film_view(mu, clearance, pad_length, squeeze, nodes, cavitation, p_cav, grid_points)
    pad = pad_tables(q.shape[0], rod_length, film)
    beta = np.arange(1, q.shape[0] + 1) * np.pi / rod_length
    F, total = _modal_force_kernel(q, q_dot, float(x0), float(V_r), view, float(width), pad, float(rod_length))
    xi_min = float(np.min(0.5 * clearance - np.sin(np.outer(x0 + pad.quad[0], beta)) @ q))
    return F, total, xi_min


def resultant_force(q, q_dot, x0, V_r, *, mu, clearance, pad_length, width, rod_length, squeeze=False, nodes=32,
                    cavitation="none", p_cav=-101325.0, grid_points=201, sides=1):
    """Resultant force of the film on the link along +j [N], for many states at once.

    ``q``, ``q_dot`` have shape ``(T, N)``; ``x0``, ``V_r`` shape ``(T,)``; returns shape ``(T,)``.
    """
    q = np.ascontiguousarray(q, dtype=float)
    film, view = _film_view(mu, clearance, pad_length, squeeze, nodes, cavitation, p_cav, grid_points, sides)
    pad = pad_tables(q.shape[1], rod_length, film)
    return film_force_many(q, np.ascontiguousarray(q_dot, dtype=float), np.ascontiguousarray(x0, dtype=float),
                           np.ascontiguousarray(V_r, dtype=float), view, float(width), pad, float(rod_length))


def pressure_points(X, modes, rod_length, nodes=8, grid_points=0):
    """Tables for :func:`pad_pressure_many`: ``(w, Sm, sin_p, cos_p, sin_g, cos_g)`` for pad points ``X``."""
    beta = np.arange(1, modes + 1) * np.pi / rod_length
    s, w = gauss_legendre(nodes)
    if grid_points:
        grid = np.linspace(0.0, X[-1], grid_points)
        pts = 0.5 * (grid[1:] + grid[:-1])
    else:
        grid = np.zeros(0)
        pts = (X[:-1, None] + np.diff(X)[:, None] * s).ravel()
    tables = _tables(beta, pts) + _tables(beta, grid)
    return (w, integration_matrix(nodes)) + tuple(np.ascontiguousarray(a) for a in tables)


def pad_pressure(X, q, q_dot, x0, V_r, *, mu, clearance, rod_length, squeeze=False, nodes=8,
                 cavitation="none", p_cav=-101325.0, grid_points=201, side=1):
    """Gauge pressure on the pad [Pa] for many modal states at once (:func:`pad_pressure_many`).

    Parameters
    ----------
    X : ndarray, shape ``(M + 1,)``
        Increasing pad positions from 0 to ``l`` [m].
    q, q_dot : ndarray, shape ``(T, N)``
        Modal coordinates [m] and velocities [m/s].
    x0, V_r : ndarray, shape ``(T,)``
        Pad start [m] and collar velocity [m/s].
    side : {1, -1}
        The film at ``H/2 - u2`` (1) or at ``H/2 + u2`` (-1).

    Returns
    -------
    ndarray, shape ``(T, M + 1)``
    """
    X = np.ascontiguousarray(X, dtype=float)
    q = np.ascontiguousarray(np.atleast_2d(q), dtype=float)
    film, view = _film_view(mu, clearance, float(X[-1]), squeeze, 8, cavitation, p_cav, grid_points)
    tables = pressure_points(X, q.shape[1], rod_length, nodes, grid_points if cavitation == "reynolds" else 0)
    return pad_pressure_many(X, q, np.ascontiguousarray(np.atleast_2d(q_dot), dtype=float),
                             np.ascontiguousarray(np.atleast_1d(x0), dtype=float),
                             np.ascontiguousarray(np.atleast_1d(V_r), dtype=float), float(side), view,
                             float(rod_length), *tables)
