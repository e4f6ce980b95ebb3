"""The pressure on the pad: running integral of the first integral, for any film and for many states.

:func:`pressure` for a film given as a function or samples; :func:`pad_pressure_many` (and
:func:`pad_pressure`) for the film of modal states, every cavitation option: the results'
``pressure``.
"""

from __future__ import annotations

import numpy as np

from .._jit import jitable, kernel
from ..beam import add_deflection, wavenumber, wavenumbers
from ..params import CHOICES
from .force import _film_view, _tables, gauss_legendre, integration_matrix
from .reynolds import (HALF_SOMMERFELD, NO_FILM, REYNOLDS, WEDGE_SQUEEZE, effective_film, mean_gap_slope, pad_start,
                       pressure_gradient, reynolds_cavitation, reynolds_constant)

__all__ = ["pressure_on_breaks", "pad_pressure_many", "pressure", "pad_pressure", "pressure_points", "film_thickness",
           "mode_film", "mode_film_rate"]


# --- the pressure on the pad ---------------------------------------------------------------------------
@jitable
def pressure_on_breaks(breaks, xi, xi_t, V_r, mu, w, Sm, out, Q):
    """Gauge pressure [Pa] at ``breaks`` (``p_g = 0`` at both ends) from the film at the GL nodes of each piece.

    ``xi``, ``xi_t`` shape ``(M, n)``: the film [m] and its rate [m/s] at the ``n`` Gauss-Legendre
    nodes (weights ``w`` on ``[0, 1]``) of each of the ``M`` pieces between consecutive
    ``breaks``; ``xi_t`` empty (shape ``(M, 0)``) for the wedge film. ``Sm``:
    :func:`integration_matrix` of ``n``. The pressure is the running integral of
    :func:`pressure_gradient`. Writes ``out``, shape ``(M + 1,)``; ``Q`` is scratch of shape
    ``(M, n)`` for ``int xi_t`` at the nodes (not read with the wedge film: any shape), allocated
    by the caller once for many states.
    """
    M, n = xi.shape
    squeeze = xi_t.shape[1] > 0
    if squeeze:
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
            if squeeze:
                I3 += h * w[j] * Q[k, j] * inv3
    C = reynolds_constant(I1, I2, I3, V_r, mu)
    out[0] = 0.0
    for k in range(M):
        h = breaks[k + 1] - breaks[k]
        acc = 0.0
        for j in range(n):
            acc += h * w[j] * pressure_gradient(xi[k, j], Q[k, j] if squeeze else 0.0, C, V_r, mu)
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
    s0 = np.empty(N)
    c0 = np.empty(N)
    xi = np.empty(n_pts)
    n = n_pts // M
    squeeze = f.model == WEDGE_SQUEEZE
    xi_t = np.zeros(n_pts if squeeze else 0)
    Q = np.empty((M, n) if squeeze else (1, 1))
    for i in range(T):
        x0 = pad_start(x_star[i], f.pad_length, f.pad_reference)
        for m in range(N):
            s0[m] = np.sin(wavenumber(m + 1, L) * x0)
            c0[m] = np.cos(wavenumber(m + 1, L) * x0)
        xi[:] = 0.5 * f.clearance
        add_deflection(q[i], s0, c0, sin_p, cos_p, -side, xi)
        if squeeze and f.cavitation != REYNOLDS:  # the rate of the mean gap (rough surfaces: times the contact factor)
            xi_t[:] = 0.0
            add_deflection(q_dot[i], s0, c0, sin_p, cos_p, -side, xi_t)
            for k in range(n_pts):
                xi_t[k] *= mean_gap_slope(xi[k], f.roughness)
        for k in range(n_pts):
            xi[k] = effective_film(xi[k], f.thickness_floor, f.roughness)
        if f.cavitation == REYNOLDS:
            _reynolds_sample(X, xi, q_dot[i], s0, c0, V_r[i], side, f, sin_g, cos_g, out[i])
            continue
        pressure_on_breaks(X, xi.reshape((M, n)), xi_t.reshape((M, xi_t.shape[0] // M)), V_r[i], f.viscosity,
                           w, Sm, out[i], Q)
        if f.cavitation == HALF_SOMMERFELD:
            for k in range(M + 1):
                out[i, k] = max(out[i, k], p_cav)
    return out


@jitable
def _reynolds_sample(X, xi_mid, q_dot, s0, c0, V_r, side, f, sin_g, cos_g, out):
    """One sample's pressure with the Swift-Stieber condition, on the grid of ``sin_g`` interpolated to ``X``.

    ``sin_g`` None (another cavitation option) compiles to nothing.
    """
    if sin_g is None:
        return
    G = sin_g.shape[1]
    grid = np.linspace(0.0, f.pad_length, G)
    xi_t = np.zeros(G)
    if f.model == WEDGE_SQUEEZE:
        add_deflection(q_dot, s0, c0, sin_g, cos_g, -side, xi_t)
    p = np.empty(G)
    reynolds_cavitation(grid, xi_mid, xi_t, V_r, f.viscosity, f.cavitation_pressure - f.ambient_pressure, p)
    out[:] = np.interp(X, grid, p)


@kernel
def _pressure_kernel(breaks, xi, xi_t, V_r, mu, w, Sm):
    out = np.empty(breaks.shape[0])
    pressure_on_breaks(breaks, xi, xi_t, V_r, mu, w, Sm, out, np.empty(xi.shape if xi_t.shape[1] > 0 else (1, 1)))
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
    beta = wavenumbers(q.shape[-1], rod_length)
    u2 = np.sum(q[..., None, :] * np.sin(np.asarray(x)[..., None] * beta), axis=-1)
    return 0.5 * clearance - u2


def mode_film(q, x0, clearance, rod_length):
    """The one-sided film ``xi(X) = H/2 - u2(x0 + X)`` of modal state ``q`` as a function [m]."""
    beta = wavenumbers(q.shape[-1], rod_length)
    return lambda X: 0.5 * clearance - np.sin(np.multiply.outer(x0 + np.asarray(X), beta)) @ q


def mode_film_rate(q_dot, x0, rod_length):
    """``d xi/dt = -u2_dot(x0 + X)`` at fixed link points, as a function [m/s]."""
    beta = wavenumbers(q_dot.shape[-1], rod_length)
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


def pressure_points(X, modes, rod_length, nodes=8, grid_points=0):
    """Tables for :func:`pad_pressure_many`: ``(w, Sm, sin_p, cos_p, sin_g, cos_g)`` for pad points ``X``."""
    beta = wavenumbers(modes, rod_length)
    s, w = gauss_legendre(nodes)
    if grid_points:  # Reynolds: the film at the cell midpoints, its rate at the grid points
        grid = np.linspace(0.0, X[-1], grid_points)
        pts = 0.5 * (grid[1:] + grid[:-1])
        grid_tables = tuple(np.ascontiguousarray(a) for a in _tables(beta, grid))
    else:
        pts = (X[:-1, None] + np.diff(X)[:, None] * s).ravel()
        grid_tables = (None, None)
    return (w, integration_matrix(nodes)) + tuple(np.ascontiguousarray(a) for a in _tables(beta, pts)) + grid_tables


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
