"""The film force's Jacobian with respect to the modal coordinates and rates (1-D film, no or half-Sommerfeld cavitation).

A stiff integrator (:mod:`lubelink.integrate.rodas`) and the periodic solver's variational
equations need ``dF_n/dq_m`` and ``dF_n/dq_dot_m`` of :func:`~lubelink.film.force.modal_film_force`.
On each film side, with the film ``h_j`` the Reynolds equation sees at the Gauss-Legendre node
``X_j`` (weight ``w_j``), ``g_j = p_g'(X_j)`` (:func:`~lubelink.film.reynolds.pressure_gradient`)
and ``C`` (:func:`~lubelink.film.reynolds.reynolds_constant`), differentiating the first integral
gives::

    dg_j/dh_j = a_j = 6 mu V_r / h_j^3 - 3 g_j / h_j,     dC/dh_k = -w_k a_k / I2,
    dg_j/dQ_j = 12 mu / h_j^3,                           dC/dQ_k = -12 mu w_k / (h_k^3 I2),

and with ``dh_j/dq_m = -side h'_j s_m(X_j)`` (``h'`` the slope of the effective film,
``s_m(X) = sin(beta_m (x0 + X))``) and ``dQ_j/dq_dot_m = -side W_m(X_j)``::

    dg_j/dq_m     = -side [e_j s_m(X_j) - c_m / h_j^3],        e_j = a_j h'_j,  c_m = sum_k w_k e_k s_m(X_k) / I2,
    dg_j/dq_dot_m = -side 12 mu / h_j^3 [W_m(X_j) - d_m],      d_m = sum_k w_k W_m(X_k) / (h_k^3 I2).

With rough surfaces the squeeze flow is that of the mean gap, ``Q_j = sum_k S_jk c_k xi_t,k``
(``S`` the integration matrix on the nodes, ``c`` the contact factor): ``W_m(X_j)`` becomes
``sum_k S_jk c_k s_m(X_k)``, and ``Q`` depends on ``q`` through ``c``, which adds
``-side 12 mu / h_j^3 [P_m(X_j) - sum_k w_k P_m(X_k) / (h_k^3 I2)]`` to ``dg_j/dq_m``, with
``P_m(X_j) = sum_k S_jk c'_k xi_t,k s_m(X_k)``.

The modal force is linear in the ``g_j``, ``F_n = side B sum_j R_nj g_j`` (no cavitation:
``R_nj = w_j W_n(X_j)``, the integral by parts), except where half-Sommerfeld clips the pressure
``p_i = sum_j S_ij g_j`` at the nodes: there ``F_n = -side B sum_i w_i s_n(X_i) max(p_i, p_cav)``,
so ``R_nj = -sum_i [p_i > p_cav] w_i s_n(X_i) S_ij``. ``side^2 = 1``: both sides add the same form.
The tests compare every entry with finite differences of the force.
"""

from __future__ import annotations

import numpy as np

from .._jit import jitable
from .force import film_nodes
from .reynolds import COS, HALF_SOMMERFELD, NO_FILM, REYNOLDS, SIN, VERS, WEDGE_SQUEEZE, mean_gap_curvature, \
    mean_gap_slope, pad_start, pressure_gradient, reynolds_constant
from .width import ONE_D
from ..beam import wavenumber

__all__ = ["has_film_jacobian", "modal_film_jacobian", "squeeze_rate"]


def has_film_jacobian(film) -> str:
    """``""`` if :func:`modal_film_jacobian` covers ``film`` (a :class:`~lubelink.params.Film`), else why not."""
    if film.model == "none":
        return ""
    if film.reynolds != "1d":
        return f"film.reynolds = {film.reynolds!r} (the analytic Jacobian covers the 1-D film)"
    if film.cavitation == "reynolds":
        return "film.cavitation = 'reynolds' (an obstacle problem; the analytic Jacobian covers 'none' and 'half-sommerfeld')"
    return ""


def squeeze_rate(film, width, modal_mass) -> float:
    """The squeeze film's linearised damping rate [1/s] at the centred link: ``sides mu B l^3 / (m (H/2)^3)``.

    A parallel film of thickness ``h`` over the pad of length ``l`` and width ``B``, closing at
    ``h_dot``, carries ``W = mu B l^3 (-h_dot) / h^3`` (p = 0 at both ends); per modal mass ``m``
    [kg] this is the rate at which it damps a mode whose shape is flat over the pad, the largest
    eigenvalue of the film's ``dF/dq_dot / m`` at rest. 0 without the squeeze term.
    """
    if film.model != "wedge+squeeze":
        return 0.0
    h = 0.5 * film.clearance
    return film.sides * film.viscosity * width * film.pad_length ** 3 / (modal_mass * h ** 3)


@jitable
def _clipped_weights(S, g, s_tab, f, pad, R):
    """``R_nj = -sum_i [p_i > p_cav] w_i s_n(X_i) S_ij`` into ``R`` (half-Sommerfeld); False if ``S`` is None."""
    if S is None:
        return False
    N, nodes = R.shape
    p_cav = f.cavitation_pressure - f.ambient_pressure
    for i in range(nodes):
        p_i = 0.0
        for j in range(nodes):
            p_i += S[i, j] * g[j]
        if p_i > p_cav:
            for n in range(N):
                u = pad.quad[1, i] * s_tab[n, i]
                for j in range(nodes):
                    R[n, j] -= u * S[i, j]
    return True


@jitable
def _mean_gap_tables(side, q, q_dot, s_tab, f, S, Wq, P):
    """Rough surfaces' squeeze flow ``Q_j = sum_k S_jk c_k xi_t,k`` (:func:`~lubelink.film.force._mean_gap_flow`):
    ``dQ_j/dq_dot_m = -side Wq[m, j]`` and ``dQ_j/dq_m = -side P[m, j]`` into ``Wq``, ``P``; False (and
    nothing written) for smooth surfaces or ``S`` None (compiled out)."""
    if S is None or f.roughness <= 0.0:
        return False
    N, nodes = s_tab.shape
    c = np.empty(nodes)
    dc = np.empty(nodes)
    for k in range(nodes):
        xi = 0.5 * f.clearance
        xi_t = 0.0
        for n in range(N):
            xi -= side * q[n] * s_tab[n, k]
            xi_t -= side * q_dot[n] * s_tab[n, k]
        c[k] = mean_gap_slope(xi, f.roughness)
        dc[k] = mean_gap_curvature(xi, f.roughness) * xi_t
    for m in range(N):
        for j in range(nodes):
            a = 0.0
            b = 0.0
            for k in range(nodes):
                a += S[j, k] * c[k] * s_tab[m, k]
                b += S[j, k] * dc[k] * s_tab[m, k]
            Wq[m, j] = a
            P[m, j] = b
    return True


@jitable
def _film_side_jacobian(side, q, q_dot, ws, L, V_r, f, B, pad, Jq, Jv):
    """Add ``dF_n/dq_m`` [N/m] to ``Jq`` and ``dF_n/dq_dot_m`` [N s/m] to ``Jv`` for the film on ``side``."""
    N = q.shape[0]
    mu = f.viscosity
    nodes = pad.quad.shape[1]
    o_xi, o_Q = 2 * N, 2 * N + nodes
    slope = np.empty(nodes)
    I1, I2, I3 = film_nodes(side, q, q_dot, ws, L, f, pad, slope)
    C = reynolds_constant(I1, I2, I3, V_r, mu)
    g = np.empty(nodes)
    e = np.empty(nodes)
    inv3 = np.empty(nodes)
    for j in range(nodes):
        h = ws[o_xi + j]
        g[j] = pressure_gradient(h, ws[o_Q + j], C, V_r, mu)
        inv3[j] = 1.0 / (h * h * h)
        e[j] = (6.0 * mu * V_r * inv3[j] - 3.0 * g[j] / h) * slope[j]
    s_tab = np.empty((N, nodes))  # s_m(X_j)
    W_tab = np.empty((N, nodes))  # W_m(X_j)
    for m in range(N):
        beta = wavenumber(m + 1, L)
        for j in range(nodes):
            s_tab[m, j] = ws[m] * pad.trig[COS, m, j] + ws[N + m] * pad.trig[SIN, m, j]
            W_tab[m, j] = (ws[N + m] * pad.trig[VERS, m, j] + ws[m] * pad.trig[SIN, m, j]) / beta
    R = np.zeros((N, nodes))
    if f.cavitation != HALF_SOMMERFELD or not _clipped_weights(pad.S, g, s_tab, f, pad, R):
        for n in range(N):
            for j in range(nodes):
                R[n, j] = pad.quad[1, j] * W_tab[n, j]
    squeeze = f.model == WEDGE_SQUEEZE
    Wq = W_tab  # dQ_j/dq_dot_m = -side Wq[m, j]; rough surfaces: also dQ_j/dq_m = -side P[m, j]
    P = np.empty((N, nodes))
    rough = False
    if squeeze:
        W_rough = np.empty((N, nodes))
        rough = _mean_gap_tables(side, q, q_dot, s_tab, f, pad.S, W_rough, P)
        if rough:
            Wq = W_rough
    c = np.zeros(N)
    d = np.zeros(N)
    dp = np.zeros(N)
    for m in range(N):
        for k in range(nodes):
            c[m] += pad.quad[1, k] * e[k] * s_tab[m, k]
            d[m] += pad.quad[1, k] * Wq[m, k] * inv3[k]
            if rough:
                dp[m] += pad.quad[1, k] * P[m, k] * inv3[k]
        c[m] /= I2
        d[m] /= I2
        dp[m] /= I2
    for n in range(N):
        for m in range(N):
            aq = 0.0
            ap = 0.0
            av = 0.0
            for j in range(nodes):
                aq += R[n, j] * (e[j] * s_tab[m, j] - c[m] * inv3[j])
                if squeeze:
                    av += R[n, j] * inv3[j] * (Wq[m, j] - d[m])
                    if rough:
                        ap += R[n, j] * inv3[j] * (P[m, j] - dp[m])
            Jq[n, m] -= B * aq
            if squeeze:
                Jv[n, m] -= 12.0 * mu * B * av
                if rough:
                    Jq[n, m] -= 12.0 * mu * B * ap


@jitable
def modal_film_jacobian(q, q_dot, x_star, V_r, f, B, pad, L, Jq, Jv):
    """Add the Jacobian of :func:`~lubelink.film.force.modal_film_force` to ``Jq`` ``(N, N)`` [N/m] and ``Jv`` [N s/m].

    ``Jq[n, m] = dF_n/dq_m``, ``Jv[n, m] = dF_n/dq_dot_m`` for the 1-D film, one or two sides,
    cavitation none or half-Sommerfeld (:func:`has_film_jacobian`); the arguments are those of
    the force.
    """
    if f.model == NO_FILM or f.reynolds != ONE_D or f.cavitation == REYNOLDS:
        return
    x0 = pad_start(x_star, f.pad_length, f.pad_reference)
    N = q.shape[0]
    ws = np.empty(2 * N + 3 * pad.quad.shape[1])
    for n in range(N):
        ws[n] = np.sin(wavenumber(n + 1, L) * x0)
        ws[N + n] = np.cos(wavenumber(n + 1, L) * x0)
    for side in (1.0, -1.0):
        if side < 0.0 and f.sides != 2:
            break
        _film_side_jacobian(side, q, q_dot, ws, L, V_r, f, B, pad, Jq, Jv)
