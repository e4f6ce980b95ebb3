"""Pinned-pinned Euler-Bernoulli link in sine modes (docs/model.md sections 1-2).

``u2(x, t) = sum_n q_n(t) sin(beta_n x)``, ``beta_n = n pi / L``. Every function here is pure and
vectorised over modes (last axis) and, where it makes sense, over leading time axes. The
``@jitable`` ones are also what the compiled right-hand side executes, one mode at a time.
"""

from __future__ import annotations

import numpy as np

from ._jit import ENABLED, jitable, kernel

__all__ = [
    "wavenumber",
    "deflection_at",
    "wavenumbers",
    "natural_frequencies",
    "modal_mass",
    "rigid_load",
    "rigid_forcing",
    "point_load",
    "project_point_load",
    "project_distributed_load",
    "modal_acceleration",
    "add_deflection",
    "deflection",
    "slope",
    "curvature",
    "modal_energy",
    "linear_domain",
]


@jitable
def wavenumber(n, rod_length):
    """The wavenumber of mode ``n`` (from 1), ``beta_n = n pi / L`` [1/m]: the one place it is written."""
    return n * np.pi / rod_length


@jitable
def deflection_at(q, x, rod_length):
    """``u2(x) = sum_n q_n sin(beta_n x)`` [m] at one point ``x`` [m] of the link (``q`` [m], shape ``(N,)``)."""
    u = 0.0
    for n in range(q.shape[0]):
        u += q[n] * np.sin(wavenumber(n + 1, rod_length) * x)
    return u


@jitable
def wavenumbers(modes, rod_length):
    """Modal wavenumbers ``beta_n = n pi / L`` [1/m] for ``n = 1..modes``."""
    return np.arange(1, modes + 1) * np.pi / rod_length


def natural_frequencies(modes, rod_length, youngs_modulus, second_moment, density, area):
    """Natural circular frequencies ``omega_n = beta_n^2 sqrt(EI/(rho A))`` [rad/s].

    Parameters
    ----------
    modes : int
        Number of modes ``N`` [-].
    rod_length : float
        ``L`` [m].
    youngs_modulus : float
        ``E`` [Pa].
    second_moment : float
        ``I_z`` [m^4].
    density : float
        ``rho`` [kg/m^3].
    area : float
        ``A`` [m^2].
    """
    beta = wavenumbers(modes, rod_length)
    return beta**2 * np.sqrt(youngs_modulus * second_moment / (density * area))


def modal_mass(density, area, rod_length):
    """Mass of every sine mode, ``rho A L / 2`` [kg]."""
    return 0.5 * density * area * rod_length


@jitable
def rigid_load(A_O2, alpha, n, rod_length):
    """Modal load of the rigid-motion inertia per unit modal mass, mode ``n`` [m/s^2] (paper Eq. 18, corrected).

    The sine transform of ``-rho A (A_O2 + alpha x)`` divided by the modal mass ``rho A L / 2``
    (docs/model.md section 2): ``-2/(L beta_n) {A_O2 [1 + (-1)^(n+1)] + alpha L (-1)^(n+1)}``.
    Elementwise over arrays.

    Parameters
    ----------
    A_O2 : float or ndarray
        True transverse acceleration of O [m/s^2].
    alpha : float or ndarray
        Angular acceleration of the link [rad/s^2].
    n : int or ndarray of int
        Mode number, from 1 [-].
    rod_length : float
        ``L`` [m].
    """
    beta = wavenumber(n, rod_length)
    sign = 1.0 - 2.0 * ((n + 1) % 2)  # (-1)^(n+1)
    return -2.0 / (rod_length * beta) * (A_O2 * (1.0 + sign) + alpha * rod_length * sign)


def rigid_forcing(A_O2, alpha, modes, rod_length):
    """:func:`rigid_load` of modes ``1..modes`` [m/s^2], shape ``(..., modes)`` for ``A_O2``, ``alpha`` of shape ``(...)``."""
    n = np.arange(1, modes + 1)
    A_O2 = np.asarray(A_O2, dtype=float)[..., None]
    alpha = np.asarray(alpha, dtype=float)[..., None]
    return rigid_load(A_O2, alpha, n, rod_length)


@jitable
def point_load(force, position, beta):
    """Sine transform of a point force, ``F sin(beta_n x_F)`` [N] (a load inside the span; elementwise).

    Parameters
    ----------
    force : float
        Force along +j [N].
    position : float
        Where it acts, from O [m].
    beta : float or ndarray
        Wavenumber(s) ``beta_n`` [1/m].
    """
    return force * np.sin(beta * position)


def project_point_load(force, position, modes, rod_length):
    """:func:`point_load` on modes ``1..modes`` [N], shape ``(..., modes)``.

    Parameters
    ----------
    force : float or ndarray
        Force along +j [N].
    position : float or ndarray
        Where it acts, from O [m].
    """
    beta = wavenumbers(modes, rod_length)
    force = np.asarray(force, dtype=float)[..., None]
    position = np.asarray(position, dtype=float)[..., None]
    return point_load(force, position, beta)


def project_distributed_load(load, start, stop, modes, rod_length, nodes=64):
    """Sine transform ``int f(x) sin(beta_n x) dx`` of a load on ``[start, stop]`` [N].

    Parameters
    ----------
    load : callable
        Force per unit length along +j [N/m], vectorised in ``x`` [m].
    start, stop : float
        Loaded interval [m].
    nodes : int
        Gauss-Legendre nodes.
    """
    s, w = np.polynomial.legendre.leggauss(nodes)
    half = 0.5 * (stop - start)
    x = start + half * (s + 1.0)
    beta = wavenumbers(modes, rod_length)
    return half * np.sum((w * load(x))[:, None] * np.sin(np.outer(x, beta)), axis=0)


@jitable
def modal_acceleration(q, q_dot, omega_n, damping_ratio, omega, forcing):
    """Modal accelerations of the corrected modal ODE [m/s^2] (paper Eq. 18 corrected, docs/model.md section 2).

    ``q_ddot = -(omega_n^2 - omega^2) q - 2 zeta omega_n q_dot + forcing``,
    where ``forcing`` already holds the rigid-motion load and the external
    modal forces divided by the modal mass.
    """
    return -(omega_n**2 - omega**2) * q - 2.0 * damping_ratio * omega_n * q_dot + forcing


@jitable
def add_deflection(q, s0, c0, sin_t, cos_t, scale, out):
    """``out[k] += scale * u2(x0 + X_k)``, ``u2 = sum_n q_n [sin(b_n x0) cos(b_n X_k) + cos(b_n x0) sin(b_n X_k)]``.

    ``s0``, ``c0``: ``sin``, ``cos(beta_n x0)``; ``sin_t``, ``cos_t``: tables of ``beta_n X_k``,
    shape ``(N, K)``. With ``q`` the modal velocities it gives ``u2_dot``.
    """
    for n in range(q.shape[0]):
        a = scale * q[n] * s0[n]
        b = scale * q[n] * c0[n]
        for k in range(out.shape[0]):
            out[k] += a * cos_t[n, k] + b * sin_t[n, k]


def _mode_shapes(x, modes, rod_length):
    beta = wavenumbers(modes, rod_length)
    return beta, np.multiply.outer(np.asarray(x, dtype=float), beta)


def deflection(q, x, rod_length):
    """Transverse deflection ``u2(x) = sum q_n sin(beta_n x)`` [m].

    Parameters
    ----------
    q : ndarray, shape ``(..., N)``
        Modal coordinates [m].
    x : ndarray, shape ``(M,)``
        Positions along the link [m].

    Returns
    -------
    ndarray, shape ``(..., M)``
    """
    q = np.asarray(q, dtype=float)
    _, bx = _mode_shapes(x, q.shape[-1], rod_length)
    shapes = np.sin(bx).T
    if ENABLED and q.ndim == 2:
        return modal_sum(np.ascontiguousarray(q), np.ascontiguousarray(shapes))
    return q @ shapes


@kernel
def modal_sum(q, shapes):
    """``q @ shapes`` for ``q`` shape ``(T, N)``, ``shapes`` ``(N, M)``, by loops.

    The same product as NumPy's ``@``, without BLAS: for the few modes here a threaded BLAS
    spends more on its threads than on the arithmetic (8 ms instead of 0.3 for 2001 samples of
    7 modes at 101 points on a busy 2-core machine). Each row of the result takes the modes two
    at a time (one pass over the row per pair): 2001 x 101 from 5 modes in 0.25 ms against 0.41
    ms one mode at a time (``benchmarks/README.md``).
    """
    T, N = q.shape
    M = shapes.shape[1]
    if N == 0:
        return np.zeros((T, M))
    out = np.empty((T, M))
    for i in range(T):
        row = out[i]
        a = q[i, 0]
        for k in range(M):
            row[k] = a * shapes[0, k]
        n = 1
        while n + 1 < N:
            a, b = q[i, n], q[i, n + 1]
            for k in range(M):
                row[k] += a * shapes[n, k] + b * shapes[n + 1, k]
            n += 2
        if n < N:
            a = q[i, n]
            for k in range(M):
                row[k] += a * shapes[n, k]
    return out


def slope(q, x, rod_length):
    """``du2/dx`` [-] at ``x``; shapes as :func:`deflection`."""
    q = np.asarray(q, dtype=float)
    beta, bx = _mode_shapes(x, q.shape[-1], rod_length)
    return q @ (beta * np.cos(bx)).T


def curvature(q, x, rod_length):
    """``d2u2/dx2`` [1/m] at ``x``; shapes as :func:`deflection`."""
    q = np.asarray(q, dtype=float)
    beta, bx = _mode_shapes(x, q.shape[-1], rod_length)
    shapes = -(beta**2 * np.sin(bx)).T
    if ENABLED and q.ndim == 2:
        return modal_sum(np.ascontiguousarray(q), np.ascontiguousarray(shapes))
    return q @ shapes


@jitable
def modal_energy(q, q_dot, omega_n, mass):
    """Elastic plus kinetic energy of the modes in the link frame [J] (the energy budget's, :mod:`lubelink.energy`).

    ``m/2 sum (q_dot_n^2 + omega_n^2 q_n^2)`` with ``m = rho A L / 2``; over the last axis.
    """
    return 0.5 * mass * np.sum(np.asarray(q_dot) ** 2 + (omega_n * np.asarray(q)) ** 2, axis=-1)


def linear_domain(q, rod_length, points):
    """How far states are into the linear theory's domain: ``(max |u2|/L, max |u2'|, stretching strain)`` [-].

    ``q`` [m] of shape ``(N,)`` or ``(T, N)``; the result has shape ``(3,)`` or ``(T, 3)``.
    ``u2`` and ``u2'`` are taken at ``points`` uniform points of ``[0, L]``; the stretching
    strain is the mean axial strain ``1/(2L) int u2'^2 dx = sum_n beta_n^2 q_n^2 / 4`` that a link
    of fixed length would have, which the linear (small-deflection) theory neglects.
    """
    q = np.asarray(q, dtype=float)
    beta = wavenumbers(q.shape[-1], rod_length)
    x = np.linspace(0.0, rod_length, points)
    u = q @ np.sin(np.outer(beta, x))
    slope = (q * beta) @ np.cos(np.outer(beta, x))
    return np.stack([np.abs(u).max(axis=-1) / rod_length, np.abs(slope).max(axis=-1),
                     0.25 * np.sum((beta * q) ** 2, axis=-1)], axis=-1)
