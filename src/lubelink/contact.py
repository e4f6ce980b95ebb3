"""Film breakdown and impact at the collar (MODEL.md section 5, D8).

The gap is the smallest film thickness on the pad; the film breaks down when
it reaches ``xi_min``. The impact then follows Newton's law (paper Eq. 21)
with an impulse at the contact point ``x_c`` on a collar that does not move
transversally relative to the rigid link.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "thinnest_film",
    "approach_velocity",
    "restitution_jump",
    "impact_energy_loss",
    "lankarani_nikravesh",
]


def _u2_and_derivatives(q, x, beta):
    bx = np.multiply.outer(x, beta)
    s, c = np.sin(bx), np.cos(bx)
    return s @ q, (c * beta) @ q, -((s * beta**2) @ q)


def thinnest_film(q, x0, pad_length, clearance, rod_length, samples=None):
    """Smallest one-sided film ``H/2 - u2`` over the pad and where it is.

    The deflection is sampled on the pad and the best sample polished by
    Newton iterations on ``u2' = 0`` (or kept at a pad edge), so the result
    is a continuous function of the state, as an event function must be.

    Parameters
    ----------
    q : ndarray, shape ``(N,)``
        Modal coordinates [m].
    x0 : float
        Pad start on the link [m].
    pad_length, clearance, rod_length : float
        ``l``, ``H``, ``L`` [m].
    samples : int, optional
        Sample points on the pad; default ``16 + 4 N``.

    Returns
    -------
    xi_min : float
        Smallest film thickness [m].
    x_c : float
        Where it occurs on the link [m].
    at_edge : bool
        Whether ``x_c`` is a pad edge (it then moves with the collar).
    """
    N = q.shape[-1]
    beta = np.arange(1, N + 1) * np.pi / rod_length
    n_s = samples or 16 + 4 * N
    xs = np.linspace(x0, x0 + pad_length, n_s)
    u = np.sin(np.outer(xs, beta)) @ q
    i = int(np.argmax(u))
    if i == 0 or i == n_s - 1:
        d1 = _u2_and_derivatives(q, np.array([xs[i]]), beta)[1][0]
        inward = d1 < 0 if i == 0 else d1 > 0
        if inward:
            return 0.5 * clearance - u[i], xs[i], True
    x = xs[i]
    lo, hi = xs[max(i - 1, 0)], xs[min(i + 1, n_s - 1)]
    for _ in range(8):
        _, d1, d2 = _u2_and_derivatives(q, np.array([x]), beta)
        if d2[0] >= 0:
            break
        x_new = min(max(x - d1[0] / d2[0], lo), hi)
        if abs(x_new - x) < 1e-15 * max(1.0, abs(x)):
            x = x_new
            break
        x = x_new
    u_x = np.sin(beta * x) @ q
    if u_x < u[i]:
        x, u_x = xs[i], u[i]
    edge = x <= x0 or x >= x0 + pad_length
    return 0.5 * clearance - u_x, x, bool(edge)


def approach_velocity(q, q_dot, x_c, V_c, rod_length):
    """Normal velocity at which the link closes the gap at ``x_c`` [m/s].

    ``v_c = u2_dot(x_c) + u2'(x_c) V_c`` where ``V_c`` is the velocity of the
    contact point along the link: the collar velocity ``V_r`` when ``x_c`` is
    a pad edge (the collar corner slides over the sloped link), 0 at an
    interior extremum (where ``u2' = 0`` anyway). Positive closes the gap.
    """
    beta = np.arange(1, q.shape[-1] + 1) * np.pi / rod_length
    return float(np.sin(beta * x_c) @ q_dot + (beta * np.cos(beta * x_c)) @ q * V_c)


def restitution_jump(q_dot, x_c, v_minus, restitution, rod_length):
    """Modal velocities after an impact at ``x_c`` [m/s] (MODEL.md section 5).

    ``Delta q_dot_n = -(1 + e) v_c^- s_n / sum_m s_m^2`` with
    ``s_n = sin(beta_n x_c)``; the displacements do not jump.

    Parameters
    ----------
    q_dot : ndarray, shape ``(N,)``
        Modal velocities before the impact [m/s].
    x_c : float
        Contact point on the link [m].
    v_minus : float
        Approach velocity before the impact, positive closing [m/s].
    restitution : float
        ``e`` [-].
    """
    s = np.sin(np.arange(1, q_dot.shape[-1] + 1) * np.pi / rod_length * x_c)
    return q_dot - (1.0 + restitution) * v_minus * s / (s @ s)


def impact_energy_loss(v_minus, x_c, restitution, modes, mass, rod_length):
    """Energy lost in one impact [J]: ``(1 - e^2)/2 * m / sum s_m^2 * (v_c^-)^2``.

    ``mass`` is the modal mass ``rho A L / 2`` [kg].
    """
    s = np.sin(np.arange(1, modes + 1) * np.pi / rod_length * x_c)
    return 0.5 * (1.0 - restitution**2) * mass / (s @ s) * v_minus**2


def lankarani_nikravesh(delta, delta_dot, v_minus, stiffness, exponent, restitution):
    """Compliant contact force [N] (Lankarani & Nikravesh 1990, J. Mech. Des. 112).

    ``F = K delta^n (1 + 3 (1 - e^2)/4 * delta_dot / v_minus)``, clipped at 0
    (no adhesion).

    Parameters
    ----------
    delta : float
        Penetration [m] (> 0 in contact).
    delta_dot : float
        Penetration rate [m/s].
    v_minus : float
        Approach velocity when the contact began [m/s]; the damping term is
        dropped for a grazing contact (``v_minus <= 0``).
    stiffness : float
        ``K`` [N/m^n].
    exponent : float
        ``n`` [-].
    restitution : float
        ``e`` [-].
    """
    if delta <= 0.0:
        return 0.0
    damping = 0.75 * (1.0 - restitution**2) * delta_dot / v_minus if v_minus > 0.0 else 0.0
    return max(stiffness * delta**exponent * (1.0 + damping), 0.0)
