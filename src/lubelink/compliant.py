"""The compliant contact law: the Lankarani-Nikravesh force at the thinnest-film point, and its Jacobian.

Under ``contact.law = "compliant"`` a contact phase presses the link into the collar face below
``contact.min_film``; the force acts at the thinnest-film point (:func:`lubelink.contact.thinnest_film_sides`)
against the side's normal (docs/model.md section 5.4). :func:`compliant_jacobian` is what the stiff
method (:mod:`lubelink.integrate.rodas`) needs of it (docs/model.md section 7.5).
"""

from __future__ import annotations

import numpy as np

from ._jit import jitable
from .beam import wavenumber
from .contact import approach_velocity, thinnest_film_sides

__all__ = ["lankarani_nikravesh", "compliant_force", "compliant_jacobian"]


@jitable
def lankarani_nikravesh(delta, delta_dot, v_minus, stiffness, exponent, restitution):
    """Compliant contact force [N] (Lankarani & Nikravesh 1990, J. Mech. Des. 112).

    ``F = K delta^n (1 + 3 (1 - e^2)/4 * delta_dot / v_minus)``, never adhesive (``F >= 0``).

    Parameters
    ----------
    delta : float
        Penetration [m] (> 0 in contact).
    delta_dot : float
        Penetration rate [m/s].
    v_minus : float
        Approach velocity when the contact began [m/s]; the damping term is dropped for a
        grazing contact (``v_minus <= 0``).
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


@jitable
def compliant_force(q, q_dot, x0, V_r, f, c, pad, rod_length, side, v_minus, F):
    """Add the compliant contact's modal force on ``side`` to ``F`` [N]; return its magnitude [N].

    The Lankarani-Nikravesh force of the penetration below ``min_film`` acts at the thinnest-film
    point against the side's normal.
    """
    xi, x_c, at_edge, _ = thinnest_film_sides(q, x0, f, pad, rod_length, side)
    delta = c.min_film - xi
    if delta <= 0.0:
        return 0.0
    delta_dot = side * approach_velocity(q, q_dot, x_c, V_r if at_edge else 0.0, rod_length)
    force = lankarani_nikravesh(delta, delta_dot, v_minus, c.stiffness, c.exponent, c.restitution)
    for n in range(q.shape[0]):
        F[n] -= side * force * np.sin(wavenumber(n + 1, rod_length) * x_c)
    return force


@jitable
def compliant_jacobian(q, q_dot, x0, V_r, f, c, pad, rod_length, side, v_minus, Jq, Jv):
    """Add the Jacobian of :func:`compliant_force`'s modal forces to ``Jq`` [N/m] and ``Jv`` [N s/m].

    The force acts at the thinnest-film point ``x_c``, held fixed: at an interior minimum the film's
    slope is zero there, so moving ``x_c`` changes the penetration only to second order (at a pad
    edge ``x_c`` is fixed anyway). With ``s_m = sin(beta_m x_c)``, ``d delta / d q_m = side s_m``,
    ``d delta_dot / d q_dot_m = side s_m``, ``d delta_dot / d q_m = side V_c beta_m cos(beta_m x_c)``
    and ``F_n = -side F s_n``::

        dF_n/dq_m     = -s_n (F_delta s_m + F_delta_dot V_c beta_m cos(beta_m x_c)),
        dF_n/dq_dot_m = -s_n F_delta_dot s_m,

    ``F_delta``, ``F_delta_dot`` the derivatives of :func:`lankarani_nikravesh` (0 where it is clipped).
    """
    xi, x_c, at_edge, _ = thinnest_film_sides(q, x0, f, pad, rod_length, side)
    delta = c.min_film - xi
    if delta <= 0.0:
        return
    V_c = V_r if at_edge else 0.0
    delta_dot = side * approach_velocity(q, q_dot, x_c, V_c, rod_length)
    if lankarani_nikravesh(delta, delta_dot, v_minus, c.stiffness, c.exponent, c.restitution) <= 0.0:
        return
    k = 0.75 * (1.0 - c.restitution**2) / v_minus if v_minus > 0.0 else 0.0
    F_delta = c.exponent * c.stiffness * delta ** (c.exponent - 1.0) * (1.0 + k * delta_dot)
    F_rate = c.stiffness * delta**c.exponent * k
    N = q.shape[0]
    for n in range(N):
        s_n = np.sin(wavenumber(n + 1, rod_length) * x_c)
        for m in range(N):
            b = wavenumber(m + 1, rod_length)
            s_m = np.sin(b * x_c)
            Jq[n, m] -= s_n * (F_delta * s_m + F_rate * V_c * b * np.cos(b * x_c))
            Jv[n, m] -= s_n * F_rate * s_m
