"""The compliant contact law: the Lankarani-Nikravesh force at the thinnest film or over the pad face.

Under ``contact.law = "compliant"`` a contact phase presses the link into the collar face below
``contact.min_film`` (docs/model.md section 5.4). With ``contact.extent = "point"`` the force acts
at the thinnest-film point (:func:`lubelink.contact.thinnest_film_sides`) against the side's
normal; :func:`compliant_jacobian` is what the stiff method (:mod:`lubelink.integrate.rodas`) needs
of it (docs/model.md section 7.5). With ``"pad"`` a pressure acts wherever the film on the pad is
below ``min_film``: an elastic foundation of the collar face (:func:`face_contact_force`).
"""

from __future__ import annotations

import numpy as np

from ._jit import jitable
from .beam import add_deflection, deflection_at, wavenumber
from .contact import COMPLIANT_PAD, approach_velocity, thinnest_film_side, thinnest_film_sides

__all__ = ["lankarani_nikravesh", "compliant_force", "face_contact_force", "compliant_jacobian"]


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
def compliant_force(q, q_dot, x0, V_r, f, c, pad, rod_length, side, v_minus, width, F):
    """Add the compliant contact's modal force on ``side`` to ``F`` [N]; return its magnitude [N].

    ``contact.extent = "point"``: the Lankarani-Nikravesh force of the penetration below ``min_film``
    acts at the thinnest-film point against the side's normal. ``"pad"``: :func:`face_contact_force`
    on a face of ``width`` [m].
    """
    if c.law == COMPLIANT_PAD:
        return face_contact_force(q, q_dot, x0, f, c, pad, rod_length, side, v_minus, width, F)
    xi, x_c, at_edge, _ = thinnest_film_sides(q, x0, f, pad, rod_length, side)
    delta = c.min_film - xi
    if delta <= 0.0:
        return 0.0
    delta_dot = side * approach_velocity(q, q_dot, x_c, V_r if at_edge else 0.0, rod_length)
    force = lankarani_nikravesh(delta, delta_dot, v_minus, c.stiffness, c.exponent, c.restitution)
    for n in range(q.shape[0]):
        F[n] -= side * force * np.sin(wavenumber(n + 1, rod_length) * x_c)
    return force


#: Gauss-Legendre nodes and weights on ``[-1, 1]`` of :func:`face_contact_force`'s pieces (exact to degree 5).
_GAUSS_X = np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)])
_GAUSS_W = np.array([5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0])


@jitable
def _face_depth(q, x, side, film_min, rod_length):
    """The face's penetration ``min_film - xi(x)`` [m] at ``x`` (``film_min``: ``min_film - H/2``)."""
    return film_min + side * deflection_at(q, x, rod_length)


@jitable
def _face_root(q, a, b, d_a, d_b, side, film_min, rod_length):
    """Where the penetration changes sign between ``a`` and ``b`` [m] (``d_a``, ``d_b`` of opposite signs):
    secant steps kept inside the bracket."""
    for _ in range(6):
        x = a + (b - a) * d_a / (d_a - d_b)
        d = _face_depth(q, x, side, film_min, rod_length)
        if d == 0.0 or abs(b - a) < 1e-12:
            return x
        if (d > 0.0) == (d_a > 0.0):
            a, d_a = x, d
        else:
            b, d_b = x, d
    return a + (b - a) * d_a / (d_a - d_b)


@jitable
def face_contact_force(q, q_dot, x0, f, c, pad, rod_length, side, v_minus, width, F):
    """Add the modal force of the collar face pressed over the pad to ``F`` [N]; return the resultant [N].

    Wherever the film ``xi(x) = H/2 - side u2(x)`` on the pad ``[x0, x0 + l]`` is below ``min_film``
    the face, an elastic foundation of stiffness ``k_f`` [Pa/m] (``contact.face_stiffness``), presses
    the link with the load per unit length

        w(x) = B k_f delta (1 + 3 (1 - e^2)/4 * delta_dot / v^-),   delta = min_film - xi(x),

    :func:`lankarani_nikravesh` with exponent 1 and stiffness ``B k_f`` [N/m^2], ``delta_dot`` the
    link's own normal velocity ``side u2_dot(x)`` (the face is flat: its sliding does not press),
    ``v^-`` the approach velocity when the contact phase began. The modal force is
    ``F_n -= side int w(x) sin(beta_n x) dx``.

    The pad's uniform samples (``pad.sample_trig``) and the thinnest-film point
    (:func:`~lubelink.contact.thinnest_film_side`) cut it into pieces; on a piece where ``delta > 0``
    somewhere, the integral runs between the zeros of ``delta`` (secant steps) by 3-point
    Gauss-Legendre: a contact of any length, at a pad edge or inside, and a force continuous in the
    state.
    """
    trig = pad.sample_trig
    N = q.shape[0]
    K = trig.shape[2]
    L = rod_length
    s0 = np.empty(N)
    c0 = np.empty(N)
    for n in range(N):
        b = wavenumber(n + 1, L)
        s0[n] = np.sin(b * x0)
        c0[n] = np.cos(b * x0)
    u = np.zeros(K)
    add_deflection(q, s0, c0, trig[0], trig[1], side, u)
    _, x_c, _ = thinnest_film_side(side, q, x0, f.pad_length, f.clearance, L, trig)
    step = f.pad_length / (K - 1)
    k_c = int((x_c - x0) / step)  # x_c inside (k_c, k_c + 1) joins the pieces' ends there
    inside = k_c < K - 1 and x0 + k_c * step < x_c < x0 + (k_c + 1) * step
    film_min = c.min_film - 0.5 * f.clearance
    stiffness = width * c.stiffness  # contact.face_stiffness (lubelink.assembly.make_params)
    total = 0.0
    x_a = x0
    d_a = film_min + u[0]
    for j in range(1, K + (1 if inside else 0)):
        if inside and j == k_c + 1:
            x_b = x_c
            d_b = _face_depth(q, x_c, side, film_min, L)
        else:
            k_b = j - 1 if inside and j > k_c + 1 else j
            x_b = x0 + f.pad_length if k_b == K - 1 else x0 + k_b * step
            d_b = film_min + u[k_b]
        if d_a > 0.0 or d_b > 0.0:
            lo, hi = x_a, x_b
            if d_a <= 0.0:
                lo = _face_root(q, x_a, x_b, d_a, d_b, side, film_min, L)
            elif d_b <= 0.0:
                hi = _face_root(q, x_a, x_b, d_a, d_b, side, film_min, L)
            half = 0.5 * (hi - lo)
            for g in range(3):
                x = 0.5 * (lo + hi) + half * _GAUSS_X[g]
                delta = _face_depth(q, x, side, film_min, L)
                rate = side * deflection_at(q_dot, x, L)
                w = half * _GAUSS_W[g] * lankarani_nikravesh(delta, rate, v_minus, stiffness, 1.0, c.restitution)
                total += w
                for n in range(N):
                    F[n] -= side * w * np.sin(wavenumber(n + 1, L) * x)
        x_a, d_a = x_b, d_b
    return total


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
