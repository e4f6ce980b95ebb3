"""Asperity contact beside the film: the Greenwood-Tripp pressure (mixed lubrication, docs/breakdown.md).

Two rough surfaces with combined RMS roughness ``sigma`` whose summits (density ``eta``, radius
``beta``) are Gaussian in height touch where the mean gap ``h`` is a few ``sigma``; the nominal
pressure they carry is (Greenwood & Tripp 1970, Proc. IMechE 185)::

    p_a(h) = K E' F_{5/2}(h / sigma),    K = 16 sqrt(2) pi / 15 (eta beta sigma)^2 sqrt(sigma / beta),
    F_{5/2}(lam) = 1/sqrt(2 pi) int_lam^inf (s - lam)^{5/2} exp(-s^2 / 2) ds.

It shares the load with the film (:mod:`lubelink.film.force`): the link feels both on the pad.
``F_{5/2}`` is computed here by quadrature (:func:`f52`); the tests compare it with its closed
form through the parabolic cylinder function, ``Gamma(7/2) exp(-lam^2/4) D_{-7/2}(lam) / sqrt(2 pi)``.
"""

from __future__ import annotations

import numpy as np

from .._jit import jitable, kernel
from .reynolds import pad_start
from ..beam import deflection_at, wavenumber

__all__ = ["f52", "greenwood_tripp_integral", "asperity_factor", "asperity_pressure", "asperity_stiffness",
           "modal_asperity_force", "modal_asperity_jacobian", "asperity_force_many"]

#: Simpson intervals of :func:`f52` (relative error below 1e-9 for every ``lam < 10``, see the tests).
F52_INTERVALS = 256


@jitable
def greenwood_tripp_integral(lam, k):
    """``F_k(lam) = 1/sqrt(2 pi) int_lam^inf (s - lam)^k exp(-s^2 / 2) ds`` [-] for ``k = 5/2`` (else ``3/2``).

    With ``s - lam = w^2`` it is ``2/sqrt(2 pi) int w^(2 k + 1) exp(-(w^2 + lam)^2 / 2) dw``, a smooth
    integrand: composite Simpson over ``-10 < s < s_max``, ``s_max = max(10, sqrt(lam^2 + 70))``. Beyond
    ``s_max`` the integrand is below ``e^-50`` and, where ``lam`` is large and the integral itself
    small (``~ Gamma(k + 1) phi(lam) lam^-(k + 1)``), below ``1e-12`` of it. 0 for ``lam >= 10``.
    """
    if lam >= 10.0:
        return 0.0
    lo = np.sqrt(max(0.0, -lam - 10.0))
    hi = np.sqrt(max(10.0, np.sqrt(lam * lam + 70.0)) - lam)
    n = F52_INTERVALS
    h = (hi - lo) / n
    total = 0.0
    for j in range(n + 1):
        w = lo + j * h
        a = w * w + lam
        g = (w**6 if k == 2.5 else w**4) * np.exp(-0.5 * a * a)
        c = 1.0 if (j == 0 or j == n) else (4.0 if j % 2 == 1 else 2.0)
        total += c * g
    return 2.0 / np.sqrt(2.0 * np.pi) * total * h / 3.0


@jitable
def f52(lam):
    """The Greenwood-Tripp integral ``F_{5/2}(lam)`` [-] of the standardised separation ``lam = h / sigma``
    (:func:`greenwood_tripp_integral`); its derivative is ``-5/2 F_{3/2}(lam)``."""
    return greenwood_tripp_integral(lam, 2.5)


@jitable
def asperity_factor(summit_product, summit_ratio):
    """``K = 16 sqrt(2) pi / 15 (eta beta sigma)^2 sqrt(sigma / beta)`` [-]."""
    return 16.0 * np.sqrt(2.0) * np.pi / 15.0 * summit_product**2 * np.sqrt(summit_ratio)


@jitable
def asperity_pressure(h, sigma, K, modulus):
    """Nominal asperity contact pressure ``K E' F_{5/2}(h / sigma)`` [Pa] at mean gap ``h`` [m] (0 if ``sigma = 0``)."""
    if sigma <= 0.0:
        return 0.0
    return K * modulus * f52(h / sigma)


@jitable
def asperity_stiffness(h, sigma, K, modulus):
    """``d p_a / d h`` [Pa/m] of :func:`asperity_pressure`: ``-5/2 K E' F_{3/2}(h / sigma) / sigma`` (0 if ``sigma = 0``)."""
    if sigma <= 0.0:
        return 0.0
    return -2.5 * K * modulus * greenwood_tripp_integral(h / sigma, 1.5) / sigma


@jitable
def modal_asperity_jacobian(q, x_star, f, B, pad, L, Jq):
    """Add ``dF_n/dq_m`` [N/m] of :func:`modal_asperity_force` to ``Jq`` ``(N, N)``.

    ``dF_n/dq_m = B sum_side sum_j w_j p_a'(xi_j) s_n(x_j) s_m(x_j)`` (``d xi / d q_m = -side s_m``).
    """
    if f.roughness <= 0.0:
        return
    N = q.shape[0]
    K = asperity_factor(f.summit_product, f.summit_ratio)
    x0 = pad_start(x_star, f.pad_length, f.pad_reference)
    nodes = pad.quad.shape[1]
    s = np.empty(N)
    for side in (1.0, -1.0):
        if side < 0.0 and f.sides != 2:
            break
        for j in range(nodes):
            x = x0 + pad.quad[0, j]
            u = 0.0
            for n in range(N):
                s[n] = np.sin(wavenumber(n + 1, L) * x)
                u += q[n] * s[n]
            k = asperity_stiffness(0.5 * f.clearance - side * u, f.roughness, K, f.contact_modulus)
            if k == 0.0:
                continue
            a = B * pad.quad[1, j] * k
            for n in range(N):
                for m in range(N):
                    Jq[n, m] += a * s[n] * s[m]


@jitable
def modal_asperity_force(q, x_star, f, B, pad, L, F):
    """Add the asperity contact's modal forces to ``F`` [N]; return its resultant along +j [N].

    ``F_n = -side B int p_a(xi) sin(beta_n x) dX`` on each film ``xi = H/2 - side u2`` of the
    pad, by the film's Gauss-Legendre nodes (``pad.quad``); nothing when ``film.roughness = 0``.
    """
    if f.roughness <= 0.0:
        return 0.0
    N = q.shape[0]
    K = asperity_factor(f.summit_product, f.summit_ratio)
    x0 = pad_start(x_star, f.pad_length, f.pad_reference)
    nodes = pad.quad.shape[1]
    total = 0.0
    for side in (1.0, -1.0):
        if side < 0.0 and f.sides != 2:
            break
        for j in range(nodes):
            x = x0 + pad.quad[0, j]
            p = asperity_pressure(0.5 * f.clearance - side * deflection_at(q, x, L), f.roughness, K, f.contact_modulus)
            if p == 0.0:
                continue
            load = side * B * pad.quad[1, j] * p
            total -= load
            for n in range(N):
                F[n] -= load * np.sin(wavenumber(n + 1, L) * x)
    return total


@kernel
def asperity_force_many(q, x_star, f, B, pad, L):
    """:func:`modal_asperity_force`'s resultant [N] for many states: ``q`` ``(T, N)``, ``x_star`` ``(T,)``."""
    out = np.empty(q.shape[0])
    F = np.empty(q.shape[1])
    for i in range(q.shape[0]):
        out[i] = modal_asperity_force(q[i], x_star[i], f, B, pad, L, F)
    return out
