"""The 2-D Reynolds equation on the pad for any film ``xi(X, Z)``: sparse finite volumes, cavitation as an LCP.

    d/dX(xi^3 dp/dX) + d/dZ(xi^3 dp/dZ) = 6 mu V_r dxi/dX + 12 mu dxi/dt

on ``X in [0, l]``, ``Z in [-B/2, B/2]``, gauge pressure ``p = 0`` (ambient) at all four edges.
In flux form, with the volume flow per unit width ``q = -xi^3 grad p / (12 mu) + (V_r xi / 2) e_X``
[m^2/s], it reads ``div q = -xi_t``: the discretisation is the node-centred finite-volume one of
this conservation law (a control volume around every interior node, the film at a face the mean
of its two nodes), second order on smooth films, and conservative, so the flow through the pad
boundary balances the squeeze of the film. The matrix is a symmetric M-matrix; it is factorised
by SciPy's sparse LU.

Cavitation: ``"half-sommerfeld"`` clips the full solution at ``p_cav``; ``"reynolds"``
(Swift-Stieber) is the linear complementarity problem ``p >= p_cav``, ``w = A p - b >= 0``,
``(p - p_cav) w = 0``, solved by the primal-dual active-set method (finite termination for
M-matrices; Hintermueller, Ito & Kunisch 2003), one sparse solve per iteration.

The right-hand side of the model does not use this module: when the film varies along ``X``
only it runs the sine series of :mod:`lubelink.film.width`; this one is the general solver, and
the second method the series is checked against.
"""

from __future__ import annotations

import numpy as np

from ..params import CHOICES

__all__ = ["pressure_2d", "reynolds_2d_system"]


def _grid(values, name):
    a = np.asarray(values, dtype=float)
    if a.ndim != 1 or a.size < 3 or not np.all(np.isfinite(a)) or np.any(np.diff(a) <= 0):
        raise ValueError(f"{name} must be a strictly increasing 1-D array of at least 3 finite values [m]")
    return a


def _field(values, X, Z, name):
    """``values`` (a callable of ``(X[:, None], Z[None, :])`` or an array) as shape ``(X.size, Z.size)``."""
    if callable(values):
        values = values(X[:, None], Z[None, :])
    try:
        return np.array(np.broadcast_to(np.asarray(values, dtype=float), (X.size, Z.size)))
    except ValueError:
        raise ValueError(f"{name} must broadcast to (X.size, Z.size) = {(X.size, Z.size)}, got shape "
                         f"{np.shape(values)}") from None


def reynolds_2d_system(X, Z, xi, V_r, mu, xi_t=None):
    """The finite-volume system ``A p = b`` of the interior nodes (see the module docstring).

    Parameters
    ----------
    X, Z : array_like
        Node grids along the pad (``0`` to ``l``) and across it (``-B/2`` to ``B/2``) [m].
    xi : callable or array_like
        Film thickness [m], broadcastable to ``(X.size, Z.size)``, or a function of
        ``(X[:, None], Z[None, :])``.
    V_r, mu : float
        Collar velocity relative to the link, along +X [m/s]; viscosity [Pa s].
    xi_t : callable or array_like, optional
        ``d xi / dt`` [m/s], same forms as ``xi``.

    Returns
    -------
    A : scipy.sparse.csc_matrix, shape ``(n, n)``, ``n = (X.size - 2) (Z.size - 2)``
        ``-div(xi^3 grad)`` integrated over the control volumes [m^3] (row-major, Z fastest).
    b : ndarray, shape ``(n,)``
        ``-(6 mu V_r dxi/dX + 12 mu xi_t)`` integrated over them [Pa m^3].
    """
    import scipy.sparse as sp

    X, Z = _grid(X, "X"), _grid(Z, "Z")
    xi = _field(xi, X, Z, "xi")
    if not (np.all(np.isfinite(xi)) and np.all(xi > 0)):
        raise ValueError("the film thickness xi must be finite and positive on the whole pad")
    xt = np.zeros_like(xi) if xi_t is None else _field(xi_t, X, Z, "xi_t")
    nx, nz = X.size - 2, Z.size - 2
    dX, dZ = np.diff(X), np.diff(Z)
    wX = 0.5 * (dX[:-1] + dX[1:])  # control-volume sizes of the interior nodes
    wZ = 0.5 * (dZ[:-1] + dZ[1:])
    xe = 0.5 * (xi[1:, 1:-1] + xi[:-1, 1:-1])  # faces between X nodes, interior Z: (nx + 1, nz)
    xz = 0.5 * (xi[1:-1, 1:] + xi[1:-1, :-1])  # faces between Z nodes, interior X: (nx, nz + 1)
    gX = xe ** 3 * wZ[None, :] / dX[:, None]  # conductances [m^3]
    gZ = xz ** 3 * wX[:, None] / dZ[None, :]
    idx = np.arange(nx * nz).reshape(nx, nz)
    diag = gX[:-1] + gX[1:] + gZ[:, :-1] + gZ[:, 1:]
    rows = [idx.ravel()]
    cols = [idx.ravel()]
    vals = [diag.ravel()]
    for a, b_, g in ((idx[:-1], idx[1:], gX[1:-1]), (idx[:, :-1], idx[:, 1:], gZ[:, 1:-1])):
        rows += [a.ravel(), b_.ravel()]
        cols += [b_.ravel(), a.ravel()]
        vals += [-g.ravel(), -g.ravel()]
    A = sp.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(nx * nz,) * 2)
    b = -(6.0 * mu * V_r * (xe[1:] - xe[:-1]) * wZ[None, :] + 12.0 * mu * xt[1:-1, 1:-1] * np.outer(wX, wZ))
    return A, b.ravel()


def pressure_2d(X, Z, xi, V_r, mu, xi_t=None, *, cavitation="none", p_cav=-101325.0, max_iterations=None):
    """Gauge pressure of the 2-D Reynolds film [Pa] at the nodes ``(X, Z)``, ambient at all four edges.

    Parameters
    ----------
    X, Z : array_like
        Increasing node grids along the pad (from 0 to ``l``) and across it (from ``-B/2`` to
        ``B/2``) [m]; the first and last of each are the pad edges.
    xi : callable or array_like
        Film thickness [m], broadcastable to ``(X.size, Z.size)`` (e.g. shape ``(X.size, 1)`` for
        a film uniform across the width), or a vectorised function of ``(X[:, None], Z[None, :])``.
    V_r : float
        Velocity of the flat collar relative to the shaped link, along +X [m/s].
    mu : float
        Viscosity [Pa s].
    xi_t : callable or array_like, optional
        ``d xi / dt`` at fixed link points [m/s] (squeeze term); same forms as ``xi``.
    cavitation : {"none", "half-sommerfeld", "reynolds"}
        Full solution; clipped at ``p_cav``; or the Swift-Stieber condition (LCP).
    p_cav : float
        Cavitation pressure, gauge [Pa] (``<= 0``).
    max_iterations : int, optional
        Active-set iterations of ``"reynolds"`` (default: the number of unknowns).

    Returns
    -------
    ndarray, shape ``(X.size, Z.size)``
        Zero on the edges.
    """
    from scipy.sparse.linalg import splu

    if cavitation not in CHOICES["film.cavitation"]:
        raise ValueError(f"cavitation = {cavitation!r}: must be 'none', 'half-sommerfeld' or 'reynolds'")
    if not (np.isfinite(p_cav) and p_cav <= 0.0):
        raise ValueError(f"p_cav = {p_cav}: the gauge cavitation pressure must be finite and <= 0 [Pa]")
    A, b = reynolds_2d_system(X, Z, xi, V_r, mu, xi_t)
    X, Z = np.asarray(X, dtype=float), np.asarray(Z, dtype=float)
    p = splu(A).solve(b)
    if cavitation == "half-sommerfeld":
        p = np.maximum(p, p_cav)
    elif cavitation == "reynolds":
        p = _active_set(A, b, p_cav, p, max_iterations or A.shape[0] + 1)
    out = np.zeros((X.size, Z.size))
    out[1:-1, 1:-1] = p.reshape(X.size - 2, Z.size - 2)
    return out


def _active_set(A, b, p_cav, p, iterations):
    """The LCP ``p >= p_cav, A p - b >= 0, (p - p_cav)(A p - b) = 0`` by the primal-dual active-set method."""
    from scipy.sparse.linalg import splu

    c = A.diagonal()
    active = p < p_cav
    p = np.where(active, p_cav, p)
    for _ in range(iterations):
        free = ~active
        q = np.full_like(p, p_cav)
        if free.any():
            rhs = b[free] - A[free][:, active] @ q[active]
            q[free] = splu(A[free][:, free].tocsc()).solve(rhs)
        multiplier = np.where(active, A @ q - b, 0.0)
        now = multiplier - c * (q - p_cav) > 0.0
        p = q
        if np.array_equal(now, active):
            return p
        active = now
    raise RuntimeError(f"the Swift-Stieber active-set iteration did not settle in {iterations} iterations")
