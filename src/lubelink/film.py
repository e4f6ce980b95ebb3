"""Reynolds film between the collar pad and the link (MODEL.md section 4, D4, D5).

The pad spans ``X in [0, l]`` from its start ``x0`` on the link. The film
thickness is ``xi(X) = H/2 - u2(x0 + X)`` and the gauge pressure ``p_g``
solves the 1-D Reynolds equation written in the link frame (paper Eq. 16,
plus the squeeze term the paper drops):

    (xi^3 p_g')' = 6 mu V_r xi' + 12 mu xi_t,     p_g(0) = p_g(l) = 0,

where ``V_r`` is the collar velocity relative to the link and ``xi_t`` the
time derivative of the film at a fixed point of the link. Integrating once,
``xi^3 p_g' = 6 mu V_r xi + 12 mu Q + C`` with ``Q(X) = int_0^X xi_t``, so

    p_g(X) = 6 mu V_r I1(X) + C I2(X) + 12 mu I3(X),
    C = -(6 mu V_r I1(l) + 12 mu I3(l)) / I2(l),

with ``I1 = int xi^-2``, ``I2 = int xi^-3``, ``I3 = int Q xi^-3``.

The force per unit length on the link is ``f2 = -B p_g`` (section 4: the
film pushes the link away from the collar face). Its sine transform is
computed by parts, ``F_n = -B int p_g sin(beta_n x) dX = B int p_g' W_n dX``
with ``W_n(X) = int_0^X sin(beta_n (x0 + s)) ds`` in closed form, so the
model needs only one Gauss-Legendre pass over the pad per evaluation.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

__all__ = [
    "pressure",
    "film_thickness",
    "pad_start",
    "modal_force",
    "pad_pressure",
    "mode_film",
    "resultant_force",
    "mode_film_rate",
    "pressure_on_breaks",
    "reynolds_cavitation",
    "gauss_legendre",
]


@lru_cache(maxsize=32)
def gauss_legendre(nodes):
    """Gauss-Legendre nodes and weights on ``[0, 1]``."""
    s, w = np.polynomial.legendre.leggauss(nodes)
    return 0.5 * (s + 1.0), 0.5 * w


@lru_cache(maxsize=32)
def _integration_matrix(nodes):
    """``S[i, j] = int_0^{s_i} l_j(s) ds`` for the Lagrange basis on GL nodes of [0, 1].

    Built in the Legendre basis, which stays well conditioned for many nodes
    (a monomial construction loses all digits beyond about 20 nodes).
    """
    leg = np.polynomial.legendre
    s, _ = gauss_legendre(nodes)
    z = 2.0 * s - 1.0
    V = leg.legvander(z, nodes - 1)
    V_int = np.column_stack([leg.legval(z, leg.legint(np.eye(nodes)[j], lbnd=-1.0)) for j in range(nodes)])
    return 0.5 * V_int @ np.linalg.inv(V)


def pad_start(x_star, pad_length, pad_reference="edge"):
    """Start of the pad on the link [m] (D6): ``x_star``, or ``x_star - l/2`` for ``"centre"``."""
    return x_star - 0.5 * pad_length if pad_reference == "centre" else x_star


def film_thickness(q, x, clearance, rod_length):
    """One-sided film ``xi = H/2 - u2(x)`` [m] at link positions ``x`` [m].

    ``q`` has shape ``(..., N)``, ``x`` shape ``(..., M)`` (broadcast with the
    leading axes of ``q``); returns shape ``(..., M)``.
    """
    q = np.asarray(q, dtype=float)
    beta = np.arange(1, q.shape[-1] + 1) * np.pi / rod_length
    u2 = np.sum(q[..., None, :] * np.sin(np.asarray(x)[..., None] * beta), axis=-1)
    return 0.5 * clearance - u2


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
    """Gauge pressure of the 1-D Reynolds film [Pa] (paper Eqs. 16-17, corrected).

    Solves ``(xi^3 p')' = 6 mu V_r xi' + 12 mu xi_t`` on ``[0, l]`` with
    ``p(0) = p(l) = 0`` by composite Gauss-Legendre quadrature of the
    closed-form first integral (module docstring).

    Parameters
    ----------
    X : array_like
        Increasing positions on the pad where the pressure is wanted [m].
    xi : callable or array_like
        Film thickness [m]: a vectorised function of ``X``, or its values at
        ``X`` (then ``X`` must run from 0 to ``l`` and ``xi`` is interpolated
        by a cubic spline).
    V_r : float
        Velocity of the flat surface (the collar) relative to the shaped one
        (the link), along +X [m/s].
    mu : float
        Dynamic viscosity [Pa s].
    xi_t : callable or array_like, optional
        ``d xi / dt`` at fixed points of the link [m/s] (squeeze term); same
        form as ``xi``. Omitted: the paper's wedge-only film.
    pad_length : float, optional
        ``l`` [m]; defaults to ``X[-1]``.
    cavitation : {"none", "half-sommerfeld", "reynolds"}
        ``"none"``: the full Sommerfeld solution (sub-ambient pressure
        allowed, as in the paper); ``"half-sommerfeld"``: that solution
        clipped at ``p_cav``; ``"reynolds"``: the Swift-Stieber condition
        (``p >= p_cav`` with ``p = p_cav`` and ``p' = 0`` at rupture), by
        :func:`reynolds_cavitation` on ``grid_points`` points.
    p_cav : float
        Cavitation pressure as a **gauge** pressure, ``p_cav - p_am`` [Pa].
    subintervals, nodes : int
        Composite quadrature: ``[0, l]`` is split into ``subintervals``
        pieces (and at every point of ``X``), each with ``nodes`` GL nodes.
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
    if cavitation not in ("none", "half-sommerfeld", "reynolds"):
        raise ValueError(f"cavitation = {cavitation!r}: must be 'none', 'half-sommerfeld' or 'reynolds'")
    if cavitation == "reynolds":
        grid = np.linspace(0.0, length, grid_points)
        mid = 0.5 * (grid[1:] + grid[:-1])
        xi_mid = np.asarray(xi_f(mid), dtype=float)
        if not _positive(xi_mid, xi_f(grid)):
            raise ValueError("the film thickness xi must be finite and positive on the whole pad")
        xi_t_g = np.zeros_like(grid) if xi_t_f is None else np.asarray(xi_t_f(grid), dtype=float)
        return np.interp(X, grid, reynolds_cavitation(grid, xi_mid, xi_t_g, V_r, mu, p_cav))

    breaks = np.unique(np.concatenate([np.linspace(0.0, length, subintervals + 1), np.clip(X, 0, length)]))
    s, _ = gauss_legendre(nodes)
    pts = breaks[:-1, None] + np.diff(breaks)[:, None] * s
    xi_v = np.asarray(xi_f(pts), dtype=float)
    if not _positive(xi_v, xi_f(breaks)):  # the pad ends and X are not GL nodes
        raise ValueError("the film thickness xi must be finite and positive on the whole pad")
    xi_t_v = None if xi_t_f is None else np.asarray(xi_t_f(pts), dtype=float)
    p_breaks = pressure_on_breaks(breaks, xi_v, V_r, mu, xi_t_v)
    if cavitation == "half-sommerfeld":
        p_breaks = np.maximum(p_breaks, p_cav)
    return np.interp(X, breaks, p_breaks)


def reynolds_cavitation(grid, xi_mid, xi_t, V_r, mu, p_cav, max_iter=200):
    """Film pressure with the Swift-Stieber (Reynolds) cavitation condition [Pa, gauge].

    Solves the obstacle problem ``p >= p_cav``, ``A p - f >= 0``,
    ``(p - p_cav)(A p - f) = 0`` for the conservative finite-volume form of
    ``-(xi^3 p')' = -(6 mu V_r xi' + 12 mu xi_t)`` with ``p = 0`` at both
    ends. ``A`` is a symmetric tridiagonal M-matrix, for which the
    primal-dual active-set method (Hintermueller, Ito & Kunisch 2003,
    SIAM J. Optim. 13) terminates in finitely many steps; each step is one
    banded solve. At the rupture boundary the discrete solution has
    ``p = p_cav`` with a vanishing gradient, which is Swift-Stieber.

    Parameters
    ----------
    grid : ndarray, shape ``(M + 1,)``
        Uniform pad grid from 0 to ``l`` [m].
    xi_mid : ndarray, shape ``(M,)``
        Film thickness at the cell midpoints [m].
    xi_t : ndarray, shape ``(M + 1,)``
        ``d xi/dt`` at fixed link points, at the grid points [m/s].
    V_r : float
        Collar velocity relative to the link [m/s].
    mu : float
        Viscosity [Pa s].
    p_cav : float
        Cavitation pressure, gauge [Pa] (``<= 0``).

    Returns
    -------
    ndarray, shape ``(M + 1,)``
    """
    from scipy.linalg import solve_banded

    h = grid[1] - grid[0]
    a = xi_mid**3 / h**2
    diag = a[:-1] + a[1:]
    off = -a[1:-1]
    f = -(6.0 * mu * V_r * (xi_mid[1:] - xi_mid[:-1]) / h + 12.0 * mu * xi_t[1:-1])
    n = diag.size

    def apply(p):
        out = diag * p
        out[:-1] += off * p[1:]
        out[1:] += off * p[:-1]
        return out

    active = np.zeros(n, dtype=bool)
    p = np.zeros(n)
    for _ in range(max_iter):
        ab = np.zeros((3, n))
        ab[1] = np.where(active, 1.0, diag)
        ab[0, 1:] = np.where(active[:-1], 0.0, off)
        ab[2, :-1] = np.where(active[1:], 0.0, off)
        rhs = np.where(active, p_cav, f)
        p = solve_banded((1, 1), ab, rhs)
        lam = np.where(active, apply(p) - f, 0.0)
        new_active = lam - diag * (p - p_cav) > 0.0
        if np.array_equal(new_active, active):
            break
        active = new_active
    return np.concatenate([[0.0], np.maximum(p, p_cav), [0.0]])


def pressure_on_breaks(breaks, xi_nodes, V_r, mu, xi_t_nodes=None):
    """Gauge pressure [Pa] at ``breaks`` from the film at their Gauss-Legendre nodes.

    Batched form behind :func:`pressure`: ``breaks`` has shape ``(M + 1,)``,
    ``xi_nodes`` (and ``xi_t_nodes``) shape ``(..., M, n)`` with the ``n``
    GL nodes of each piece, ``V_r`` broadcasts against the leading axes.
    Returns shape ``(..., M + 1)``.
    """
    nodes = xi_nodes.shape[-1]
    _, w = gauss_legendre(nodes)
    h = np.diff(breaks)
    wts = h[:, None] * w
    inv3 = xi_nodes**-3
    pieces = [np.sum(wts * xi_nodes**-2, axis=-1), np.sum(wts * inv3, axis=-1)]
    if xi_t_nodes is None:
        pieces.append(np.zeros_like(pieces[0]))
    else:
        piece_Q = np.sum(wts * xi_t_nodes, axis=-1)
        Q_start = np.cumsum(piece_Q, axis=-1) - piece_Q
        Q_nodes = Q_start[..., None] + h[:, None] * (xi_t_nodes @ _integration_matrix(nodes).T)
        pieces.append(np.sum(wts * Q_nodes * inv3, axis=-1))
    zero = np.zeros(pieces[0].shape[:-1] + (1,))
    I1, I2, I3 = (np.concatenate([zero, np.cumsum(v, axis=-1)], axis=-1) for v in pieces)
    V_r = np.asarray(V_r, dtype=float)[..., None]
    C = -(6.0 * mu * V_r * I1[..., -1:] + 12.0 * mu * I3[..., -1:]) / I2[..., -1:]
    return 6.0 * mu * V_r * I1 + C * I2 + 12.0 * mu * I3


def modal_force(q, q_dot, x0, V_r, *, mu, clearance, pad_length, width, rod_length,
                squeeze=False, nodes=32, cavitation="none", p_cav=-101325.0, grid_points=201):
    """Modal film forces ``F_n`` [N] and the resultant film force on the link [N].

    ``F_n = -B int_pad p_g sin(beta_n x) dx`` (MODEL.md section 2, film
    term, gauge pressure) for the one-sided film ``xi = H/2 - u2``.

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
        See :func:`pressure`. ``"none"`` integrates by parts (needs only
        ``p'``); ``"half-sommerfeld"`` integrates the pressure at the nodes
        (spectral integration matrix) and clips it; ``"reynolds"`` solves
        :func:`reynolds_cavitation` on ``grid_points`` and integrates by the
        trapezoidal rule.
    p_cav : float
        Gauge cavitation pressure [Pa].

    Returns
    -------
    F : ndarray, shape ``(N,)``
        Modal forces [N].
    total : float
        Resultant force on the link along +j [N].
    xi_min : float
        Smallest film thickness at the quadrature points [m].
    """
    q, q_dot = np.asarray(q, dtype=float), np.asarray(q_dot, dtype=float)
    beta = np.arange(1, q.shape[-1] + 1) * np.pi / rod_length
    if cavitation == "reynolds":
        grid = np.linspace(0.0, pad_length, grid_points)
        mid = 0.5 * (grid[1:] + grid[:-1])
        xi_mid = 0.5 * clearance - np.sin(np.outer(x0 + mid, beta)) @ q
        sin_g = np.sin(np.outer(x0 + grid, beta))
        xi_t = -(sin_g @ q_dot) if squeeze else np.zeros_like(grid)
        p = reynolds_cavitation(grid, xi_mid, xi_t, V_r, mu, p_cav)
        hp = (grid[1] - grid[0]) * p  # trapezoid: p vanishes at both ends
        return -width * (hp @ sin_g), -width * hp.sum(), xi_mid.min()
    s, w = gauss_legendre(nodes)
    X = pad_length * s
    wX = pad_length * w
    cos0 = np.cos(beta * x0)
    sinX = np.sin(np.outer(x0 + X, beta))  # (nodes, N)
    xi = 0.5 * clearance - sinX @ q
    inv2, inv3 = xi**-2, xi**-3
    W = (cos0 - np.cos(np.outer(x0 + X, beta))) / beta  # int_0^X sin(beta (x0 + s)) ds
    Q = -(W @ q_dot) if squeeze else np.zeros_like(X)  # int_0^X xi_t, xi_t = -u2_dot
    I1, I2, I3 = wX @ inv2, wX @ inv3, wX @ (Q * inv3)
    C = -(6.0 * mu * V_r * I1 + 12.0 * mu * I3) / I2
    if cavitation == "none":
        dp = (6.0 * mu * V_r * xi + 12.0 * mu * Q + C) * inv3  # p_g'
        return width * ((wX * dp) @ W), width * (wX @ (dp * X)), xi.min()
    S = pad_length * _integration_matrix(nodes)  # cumulative integrals at the nodes
    p = 6.0 * mu * V_r * (S @ inv2) + C * (S @ inv3) + 12.0 * mu * (S @ (Q * inv3))
    p = np.maximum(p, p_cav)
    return -width * ((wX * p) @ sinX), -width * (wX @ p), xi.min()


def resultant_force(q, q_dot, x0, V_r, *, mu, clearance, pad_length, width, rod_length, squeeze=False,
                    nodes=32):
    """Resultant force of the one-sided film on the link along +j [N], for many states at once.

    The batched form of the ``total`` of :func:`modal_force` without
    cavitation: ``-B int p_g dX = B int p_g' X dX``. ``q``, ``q_dot`` have
    shape ``(T, N)``; ``x0``, ``V_r`` shape ``(T,)``; returns shape ``(T,)``.
    """
    s, w = gauss_legendre(nodes)
    X, wX = pad_length * s, pad_length * w
    beta = np.arange(1, q.shape[-1] + 1) * np.pi / rod_length
    x = np.asarray(x0, dtype=float)[:, None] + X  # (T, nodes)
    xi = 0.5 * clearance - np.einsum("tnk,tk->tn", np.sin(x[..., None] * beta), q)
    inv3 = xi**-3
    V_r = np.asarray(V_r, dtype=float)[:, None]
    if squeeze:
        W = (np.cos(np.asarray(x0, dtype=float)[:, None, None] * beta) - np.cos(x[..., None] * beta)) / beta
        Q = -np.einsum("tnk,tk->tn", W, q_dot)
    else:
        Q = np.zeros_like(xi)
    C = -(6.0 * mu * V_r[:, 0] * (xi**-2 @ wX) + 12.0 * mu * ((Q * inv3) @ wX)) / (inv3 @ wX)
    dp = (6.0 * mu * V_r * xi + 12.0 * mu * Q + C[:, None]) * inv3
    return width * ((dp * X) @ wX)


def mode_film(q, x0, clearance, rod_length):
    """The one-sided film ``xi(X) = H/2 - u2(x0 + X)`` of modal state ``q`` as a function [m]."""
    beta = np.arange(1, q.shape[-1] + 1) * np.pi / rod_length
    return lambda X: 0.5 * clearance - np.sin(np.multiply.outer(x0 + np.asarray(X), beta)) @ q


def mode_film_rate(q_dot, x0, rod_length):
    """``d xi/dt = -u2_dot(x0 + X)`` at fixed link points, as a function [m/s]."""
    beta = np.arange(1, q_dot.shape[-1] + 1) * np.pi / rod_length
    return lambda X: -(np.sin(np.multiply.outer(x0 + np.asarray(X), beta)) @ q_dot)


def pad_pressure(X, q, q_dot, x0, V_r, *, mu, clearance, rod_length, squeeze=False, nodes=8):
    """Gauge pressure on the pad [Pa] for many modal states at once.

    Parameters
    ----------
    X : ndarray, shape ``(M + 1,)``
        Increasing pad positions from 0 to ``l`` [m].
    q, q_dot : ndarray, shape ``(T, N)``
        Modal coordinates [m] and velocities [m/s].
    x0, V_r : ndarray, shape ``(T,)``
        Pad start [m] and collar velocity [m/s].

    Returns
    -------
    ndarray, shape ``(T, M + 1)``
    """
    s, _ = gauss_legendre(nodes)
    X = np.asarray(X, dtype=float)
    pts = X[:-1, None] + np.diff(X)[:, None] * s  # (M, n)
    beta = np.arange(1, q.shape[-1] + 1) * np.pi / rod_length
    shapes = np.sin((np.asarray(x0, float)[:, None, None] + pts)[..., None] * beta)  # (T, M, n, N)
    xi = 0.5 * clearance - np.einsum("tmnk,tk->tmn", shapes, q)
    xi_t = -np.einsum("tmnk,tk->tmn", shapes, q_dot) if squeeze else None
    return pressure_on_breaks(X, xi, V_r, mu, xi_t)
