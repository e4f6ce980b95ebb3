"""The modal film force on the link: pad tables and the Gauss-Legendre pass of the first integral.

:func:`modal_film_force` is what the right-hand side executes, for every film option;
:func:`film_force_many` its resultant for many samples (the results' ``film_force``);
:func:`modal_force` and :func:`resultant_force` the same for a film given by its parameters.
"""

from __future__ import annotations

from functools import lru_cache
from typing import NamedTuple

import numpy as np

from .._jit import jitable, kernel, stack_empty
from ..params import Film
from ..views import kernel_view
from .reynolds import (CENTRE, COS, FULL, HALF_SOMMERFELD, NO_FILM, REYNOLDS, SIN, VERS, WEDGE,  # noqa: F401
                       WEDGE_SQUEEZE, effective_film, effective_film_slope, grid_modal_force, mean_gap_slope, pad_start,
                       pressure_gradient, reynolds_cavitation, reynolds_constant)
from .width import ONE_D, width_side, width_terms
from ..beam import wavenumber, wavenumbers

__all__ = ["PadTables", "pad_tables", "gauss_legendre", "integration_matrix", "modal_film_force", "film_force_many",
           "modal_force", "resultant_force", "SIN", "COS", "VERS"]


#: Entries of the film's scratch (``2 N + 3 nodes``, :func:`_film_side`) kept on the stack of the
#: compiled right-hand side (:func:`lubelink._jit.stack_empty`): up to 32 modes at 64 nodes; a larger
#: film allocates its scratch at each evaluation.
STACK_SCRATCH = 256


class PadTables(NamedTuple):
    """What depends on the pad geometry only, tabulated once per model (``N`` modes).

    ``quad`` (2, nodes): the Gauss-Legendre nodes ``X_j`` [m] and weights [m] on ``[0, l]``;
    ``trig`` (3, N, nodes): ``sin``, ``cos`` and ``1 - cos`` of ``beta_n X_j`` (rows
    :data:`SIN`, :data:`COS`, :data:`VERS`), so that ``sin(beta_n (x0 + X_j))`` needs ``sin``,
    ``cos(beta_n x0)`` only; ``sample_trig`` (2, N, K): ``sin``, ``cos`` at the uniform samples of
    the thinnest-film search. The tables of one cavitation option are None for the others:
    ``S`` [m], the spectral integration matrix on the nodes (half-Sommerfeld, and the squeeze flow of
    rough surfaces); ``grid_trig``
    (4, N, G), ``sin``, ``cos`` at the points of the uniform grid and at its ``G - 1`` cell
    midpoints (Reynolds). A None table has another type in compiled code, so the kernels are
    compiled for the options a configuration uses only. ``grid_trig`` serves the finite-width
    films too (``film.reynolds`` "2d", "short"), and ``width`` (3 + W, J) the terms of the 2-D film
    across the width (:func:`~lubelink.film.width.width_terms`; with the ``W`` points where
    half-Sommerfeld clips it). Few arrays, because every array of the parameters costs a
    reference count at each call of the right-hand side.
    """

    quad: np.ndarray
    trig: np.ndarray
    sample_trig: np.ndarray
    S: np.ndarray | None
    grid_trig: np.ndarray | None
    width: np.ndarray | None = None


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


@lru_cache(maxsize=64)
def pad_tables(modes, rod_length, film: Film) -> PadTables:
    """The :class:`PadTables` of ``modes`` sine modes on a link of length ``rod_length`` [m] (cached: read only)."""
    beta = wavenumbers(modes, rod_length)
    l = film.pad_length
    s, w = gauss_legendre(film.quadrature_nodes)
    X = l * s
    sin_bX, cos_bX = _tables(beta, X)
    vers_bX = 2.0 * np.sin(0.5 * np.outer(beta, X)) ** 2  # 1 - cos without cancellation
    S = grid_trig = width = None
    if film.reynolds != "1d":
        if film.reynolds == "2d":
            width = width_terms(film.width_modes, film.width_series,
                                film.width_points if film.cavitation == "half-sommerfeld" else 0)
    elif film.cavitation == "half-sommerfeld" or (film.roughness > 0.0 and film.model == "wedge+squeeze"):
        S = _c(l * integration_matrix(film.quadrature_nodes))
    if film.cavitation == "reynolds" or film.reynolds != "1d":
        grid = np.linspace(0.0, l, film.grid_points)
        mid = np.append(0.5 * (grid[1:] + grid[:-1]), l)  # the last column is not used
        grid_trig = _c(np.stack(_tables(beta, grid) + _tables(beta, mid)))
    samples = np.linspace(0.0, l, 16 + 4 * modes)
    return PadTables(_c(np.stack([X, l * w])), _c(np.stack([sin_bX, cos_bX, vers_bX])),
                     _c(np.stack(_tables(beta, samples))), S, grid_trig, width)


def _c(a):
    return np.ascontiguousarray(a, dtype=np.float64)

# --- the modal film force --------------------------------------------------------------------------
@jitable
def _reynolds_side(side, q, q_dot, ws, V_r, f, B, grid_trig, F):
    """The film on ``side`` with the Swift-Stieber condition: the obstacle problem on the pad grid.

    Integrated by the trapezoidal rule (``p = 0`` at the pad ends); ``grid_trig`` None (another
    cavitation option) compiles to nothing.
    """
    if grid_trig is None:
        return 0.0
    N = q.shape[0]
    G = grid_trig.shape[2]
    grid = np.linspace(0.0, f.pad_length, G)
    h = grid[1] - grid[0]
    xi_mid = np.full(G - 1, 0.5 * f.clearance)
    xi_t = np.zeros(G)
    for n in range(N):
        a, b = side * q[n] * ws[n], side * q[n] * ws[N + n]
        for k in range(G - 1):  # u2(x0 + X) = sum_n q_n [sin(b x0) cos(b X) + cos(b x0) sin(b X)]
            xi_mid[k] -= a * grid_trig[COS + 2, n, k] + b * grid_trig[SIN + 2, n, k]
        if f.model == WEDGE_SQUEEZE:
            a, b = side * q_dot[n] * ws[n], side * q_dot[n] * ws[N + n]
            for k in range(G):
                xi_t[k] -= a * grid_trig[COS, n, k] + b * grid_trig[SIN, n, k]
    for k in range(G - 1):
        xi_mid[k] = effective_film(xi_mid[k], f.thickness_floor, f.roughness)
    p = np.empty(G)
    reynolds_cavitation(grid, xi_mid, xi_t, V_r, f.viscosity, f.cavitation_pressure - f.ambient_pressure, p)
    return grid_modal_force(side, p, h, B, ws, grid_trig, F)  # p = 0 at the pad ends: the trapezoidal rule


@jitable
def _half_sommerfeld_side(side, ws, nodes, f, B, pad, S, F):
    """The film on ``side`` clipped at the cavitation pressure: the pressure at the nodes is the running
    integral of ``p'`` (``w p'`` at ``ws[2 N + 2 nodes:]``), by the spectral integration matrix ``S``.

    ``S`` None (another cavitation option) compiles to nothing.
    """
    if S is None:
        return 0.0
    N = F.shape[0]
    o_wp, o_wdp = 2 * N + nodes, 2 * N + 2 * nodes
    p_cav = f.cavitation_pressure - f.ambient_pressure
    total = 0.0
    for i in range(nodes):
        p_i = 0.0
        for j in range(nodes):
            p_i += S[i, j] * ws[o_wdp + j] / pad.quad[1, j]
        ws[o_wp + i] = pad.quad[1, i] * max(p_i, p_cav)
        total += ws[o_wp + i]
    for n in range(N):
        acc = 0.0
        for j in range(nodes):
            acc += ws[o_wp + j] * (ws[n] * pad.trig[COS, n, j] + ws[N + n] * pad.trig[SIN, n, j])
        F[n] -= side * B * acc
    return -side * B * total


@jitable
def _keep_slope(slope, j, xi, floor, sigma):
    """``slope[j] = d effective_film / d xi`` at ``xi`` (``slope`` None: compiles to nothing)."""
    if slope is None:
        return
    slope[j] = effective_film_slope(xi, floor, sigma)


@jitable
def _mean_gap_flow(side, q_dot, ws, f, pad, S):
    """Rough surfaces: the squeeze flow ``Q(X_j) = int_0^X_j dh_T/dt`` of the mean gap ``h_T`` into
    ``ws`` (:func:`film_nodes`' layout, the nominal film at its nodes), ``dh_T/dt = c xi_t`` with the
    contact factor ``c = mean_gap_slope(xi)``, integrated by ``S``; nothing for smooth surfaces, the
    wedge film, or ``S`` None (compiled out).
    """
    if S is None or f.roughness <= 0.0 or f.model != WEDGE_SQUEEZE:
        return
    N = q_dot.shape[0]
    nodes = S.shape[0]
    o_xi, o_Q, o_rate = 2 * N, 2 * N + nodes, 2 * N + 2 * nodes
    for k in range(nodes):
        xi_t = 0.0
        for n in range(N):
            xi_t -= side * q_dot[n] * (ws[n] * pad.trig[COS, n, k] + ws[N + n] * pad.trig[SIN, n, k])
        ws[o_rate + k] = mean_gap_slope(ws[o_xi + k], f.roughness) * xi_t
    for j in range(nodes):
        acc = 0.0
        for k in range(nodes):
            acc += S[j, k] * ws[o_rate + k]
        ws[o_Q + j] = acc


@jitable
def film_nodes(side, q, q_dot, ws, L, f, pad, slope):
    """The film on ``side`` at the pad's nodes, and its integrals ``(I1, I2, I3)`` (:func:`reynolds_constant`).

    Writes the film the Reynolds equation sees, ``effective_film(H/2 - side u2(x0 + X_j))`` [m],
    at ``ws[2 N:2 N + nodes]`` and ``Q(X_j)`` [m^2/s] (0 without the squeeze term; rough surfaces:
    :func:`_mean_gap_flow`) after it;
    ``ws`` holds ``sin``, ``cos(beta_n x0)`` in its first ``2 N`` entries. ``slope`` (an array of
    ``nodes``, or None: compiled out) receives ``d effective_film / d xi`` at each node.
    """
    N = q.shape[0]
    nodes = pad.quad.shape[1]
    o_xi, o_Q = 2 * N, 2 * N + nodes
    squeeze = f.model == WEDGE_SQUEEZE
    for j in range(nodes):
        ws[o_xi + j] = 0.5 * f.clearance
        ws[o_Q + j] = 0.0
    for n in range(N):
        a, b = side * q[n] * ws[n], side * q[n] * ws[N + n]
        for j in range(nodes):  # xi = H/2 - side u2(x0 + X_j)
            ws[o_xi + j] -= a * pad.trig[COS, n, j] + b * pad.trig[SIN, n, j]
        if squeeze:  # Q = -side sum_n q_dot_n W_n(X), W_n = [c0 (1 - cos bX) + s0 sin bX] / b
            beta = wavenumber(n + 1, L)
            a, b = side * q_dot[n] * ws[N + n] / beta, side * q_dot[n] * ws[n] / beta
            for j in range(nodes):
                ws[o_Q + j] -= a * pad.trig[VERS, n, j] + b * pad.trig[SIN, n, j]
    _mean_gap_flow(side, q_dot, ws, f, pad, pad.S)
    I1 = 0.0
    I2 = 0.0
    I3 = 0.0
    for j in range(nodes):
        _keep_slope(slope, j, ws[o_xi + j], f.thickness_floor, f.roughness)
        xi = effective_film(ws[o_xi + j], f.thickness_floor, f.roughness)
        ws[o_xi + j] = xi
        w_inv3 = pad.quad[1, j] / (xi * xi * xi)
        I1 += w_inv3 * xi
        I2 += w_inv3
        I3 += w_inv3 * ws[o_Q + j]
    return I1, I2, I3


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
    nodes = pad.quad.shape[1]
    o_xi, o_Q, o_wdp = 2 * N, 2 * N + nodes, 2 * N + 2 * nodes
    I1, I2, I3 = film_nodes(side, q, q_dot, ws, L, f, pad, None)
    C = reynolds_constant(I1, I2, I3, V_r, mu)
    for j in range(nodes):
        ws[o_wdp + j] = pad.quad[1, j] * pressure_gradient(ws[o_xi + j], ws[o_Q + j], C, V_r, mu)
    if f.cavitation == HALF_SOMMERFELD:
        return _half_sommerfeld_side(side, ws, nodes, f, B, pad, pad.S, F)
    # no cavitation: by parts, F_n = B int p' W_n and the resultant B int p' X
    total = 0.0
    for j in range(nodes):
        total += ws[o_wdp + j] * pad.quad[0, j]
    for n in range(N):
        av = 0.0
        bs = 0.0
        for j in range(nodes):
            av += ws[o_wdp + j] * pad.trig[VERS, n, j]
            bs += ws[o_wdp + j] * pad.trig[SIN, n, j]
        F[n] += side * B * (ws[N + n] * av + ws[n] * bs) / wavenumber(n + 1, L)
    return side * B * total


@jitable(inline=True)
def modal_film_force(q, q_dot, x_star, V_r, f, B, pad, L, F):
    """Modal film forces added to ``F`` [N]; returns the resultant film force on the link along +j [N].

    ``F_n = -B int_pad p_g sin(beta_n x) dx`` (docs/model.md sections 2 and 4; the corrected
    paper Eq. 20, gauge pressure) for every film of ``f`` (a :func:`lubelink.views.kernel_view`
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
    need = 2 * N + 3 * pad.quad.shape[1]
    ws = stack_empty(STACK_SCRATCH) if need <= STACK_SCRATCH else np.empty(need)
    for n in range(N):
        ws[n] = np.sin(wavenumber(n + 1, L) * x0)
        ws[N + n] = np.cos(wavenumber(n + 1, L) * x0)
    total = 0.0
    for side in (1.0, -1.0):
        if side < 0.0 and f.sides != 2:
            break
        if f.reynolds != ONE_D:
            total += width_side(side, q, q_dot, ws, V_r, f, B, pad.grid_trig, pad.width, F)
        elif f.cavitation == REYNOLDS:
            total += _reynolds_side(side, q, q_dot, ws, V_r, f, B, pad.grid_trig, F)
        else:
            total += _film_side(side, q, q_dot, ws, L, V_r, f, B, pad, F)
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


def _modal_force_kernel(q, q_dot, x_star, V_r, f, B, pad, L):
    F = np.zeros(q.shape[0])
    total = modal_film_force(q, q_dot, x_star, V_r, f, B, pad, L, F)
    return F, total


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
    beta = wavenumbers(q.shape[0], rod_length)
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
