"""What a saltation matrix needs at a restitution impact, from the model (docs/periodic.md, "Through impacts").

At an impact (docs/model.md section 5) the event function is the gap ``g = xi_min - min_film``,
``xi_min = H/2 - side u2(x_c)`` at the thinnest point ``x_c`` of the film, and the reset is the
restitution law :func:`lubelink.contact.restitution_jump`,
``q_dot+ = q_dot - side (1 + e) v w`` with ``w = s / (s . s)``, ``s_n = sin(beta_n x_c)`` and the
approach velocity ``v = side (s . q_dot + V_c u2'(x_c))`` (``V_c = V_r`` at a pad edge, else 0);
the displacements do not jump. :func:`restitution_terms` gives the pieces of
:func:`lubelink.steady.saltation.saltation_matrix`: ``DR``, ``dR/dt``, ``grad g``, the rate of
``g`` (the event function's own, ``-v``) and the vector fields on both sides.

For the uniform planar link they are written out (:func:`restitution_jacobian`, ``grad_q g =
-side s`` by the envelope theorem, at an interior minimum and at a pad edge alike); for the
spatial link and a variable section they are central differences of the model's own impact and
gap (:func:`restitution_terms_by_differences`), which the test of the closed forms also uses as
their reference. Contact phases (compliant, sustained) are :mod:`lubelink.phases`'s, from the pieces
here; :func:`unsupported` says which periods have events that no saltation matrix here describes.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .beam import wavenumbers
from .link.kinematics import collar_acceleration

__all__ = ["EventTerms", "approach_jacobian", "restitution_jacobian", "restitution_terms",
           "restitution_terms_by_differences", "central_differences", "fields", "event_rate", "collar_acceleration_at", "unsupported",
           "REL_STEP"]

#: Relative step of the central differences (of the state's scale; of the time scale ``T / 2 pi``).
REL_STEP = 1e-6


class EventTerms(NamedTuple):
    """The pieces of a saltation matrix at an event, in the sine-mode state ``[q, q_dot]`` [SI].

    ``reset_jacobian`` ``dR/dy`` ``(n, n)``, ``reset_rate`` ``dR/dt`` ``(n,)``, ``gradient``
    ``grad_y g`` ``(n,)`` [m per unit of y], ``rate`` ``dg/dt`` along the flow before the event
    [m/s], ``f_minus``, ``f_plus`` the vector fields before and after ``(n,)``.
    """

    reset_jacobian: np.ndarray
    reset_rate: np.ndarray
    gradient: np.ndarray
    rate: float
    f_minus: np.ndarray
    f_plus: np.ndarray


def approach_jacobian(q, q_dot, x_c, at_edge, side, V_r, A_r, rod_length):
    """The approach velocity ``v`` at the thinnest film ``x_c`` of the uniform planar link and the derivatives
    of ``v`` and ``x_c`` with respect to the state and to time.

    ``v = side (s . q_dot + V_c u2'(x_c))`` with ``s_n = sin(beta_n x_c)`` (``V_c = V_r`` at a pad edge,
    else 0; :func:`lubelink.contact.approach_velocity`). Inside the pad ``x_c`` is the film's extremum,
    ``u2'(x_c) = 0``, so it moves with ``q`` (``dx_c/dq_n = -beta_n cos(beta_n x_c) / u2''``) and not
    with time; at a pad edge it moves with the collar (``dx_c/dt = V_r``) and not with ``q``.

    Parameters are those of :func:`restitution_jacobian` (without ``restitution``).

    Returns
    -------
    v : float
        [m/s].
    dv_dq, dv_dqd : ndarray, shape ``(N,)``
        [1/s], [-].
    dv_dt : float
        At fixed state [m/s^2].
    dx_dq : ndarray, shape ``(N,)``
        ``d x_c / d q`` [-].
    dx_dt : float
        ``d x_c / dt`` at fixed state [m/s].
    """
    beta = wavenumbers(q.shape[0], rod_length)
    s, bc = np.sin(beta * x_c), beta * np.cos(beta * x_c)
    d1, d2 = float(bc @ q), float(-(beta * beta * s) @ q)  # u2', u2'' at x_c
    ut1 = float(bc @ q_dot)  # u2_t'
    V_c = V_r if at_edge else 0.0
    v = side * (float(s @ q_dot) + V_c * d1)
    if at_edge:
        dx_dq, dx_dt = np.zeros(q.shape[0]), V_r
        dv_dq = side * V_r * bc
        dv_dt = side * (ut1 * V_r + d2 * V_r * V_r + d1 * A_r)
    else:
        dx_dq, dx_dt = -bc / d2, 0.0
        dv_dq = side * ut1 * dx_dq
        dv_dt = 0.0
    return v, dv_dq, side * s, dv_dt, dx_dq, dx_dt


def restitution_jacobian(q, q_dot, x_c, at_edge, side, V_r, A_r, restitution, rod_length):
    """``(dqd_dq, dqd_dqd, dqd_dt)``: derivatives of the velocities after an impact of the uniform planar link.

    ``q_dot+ = q_dot - side (1 + e) v w`` (module docstring) at the thinnest point ``x_c`` [m], with
    ``v`` and ``x_c`` moving with the state and time as :func:`approach_jacobian` says
    (``w = s / (s . s)`` moves with ``x_c``).

    Parameters
    ----------
    q, q_dot : ndarray, shape ``(N,)``
        Modal coordinates [m] and velocities [m/s] before the impact.
    x_c : float
        Contact point [m].
    at_edge : bool
        Whether ``x_c`` is a pad edge.
    side : float
        Film side (+1, -1).
    V_r, A_r : float
        Collar velocity [m/s] and acceleration [m/s^2] relative to the link.
    restitution : float
        ``e`` [-].
    rod_length : float
        [m].

    Returns
    -------
    dqd_dq : ndarray, shape ``(N, N)``
        ``d q_dot+ / d q`` [1/s].
    dqd_dqd : ndarray, shape ``(N, N)``
        ``d q_dot+ / d q_dot`` [-].
    dqd_dt : ndarray, shape ``(N,)``
        ``d q_dot+ / dt`` at fixed ``y`` [m/s^2].
    """
    beta = wavenumbers(q.shape[0], rod_length)
    s, bc = np.sin(beta * x_c), beta * np.cos(beta * x_c)
    S2 = float(s @ s)
    w = s / S2
    w_x = bc / S2 - 2.0 * s * float(s @ bc) / S2**2  # dw/dx_c
    v, dv_dq, _, dv_dt, dx_dq, dx_dt = approach_jacobian(q, q_dot, x_c, at_edge, side, V_r, A_r, rod_length)
    k = side * (1.0 + restitution)
    dqd_dqd = np.eye(q.shape[0]) - (1.0 + restitution) * np.outer(w, s)
    dqd_dq = -k * (np.outer(w, dv_dq) + v * np.outer(w_x, dx_dq))
    dqd_dt = -k * (w * dv_dt + v * w_x * dx_dt)
    return dqd_dq, dqd_dqd, dqd_dt


def fields(model, t, y_minus, y_plus, phase=None):
    """The vector fields ``(f_-, f_+)`` at the states around an event (sine-mode states): free flight before,
    the contact ``phase`` (:meth:`~lubelink.assembly.Model.with_phase`; None: free flight) after."""
    def f(y, ph):
        return model.to_physical(model.rhs(t, model.to_state(np.asarray(y, dtype=float)), ph))

    return f(y_minus, None), f(y_plus, phase)


def event_rate(model, t, y):
    """The gap's rate along the flow at ``(t, y)`` [m/s] (sine-mode state, free flight)."""
    event = model.functions()[1]
    return float(event(float(t), np.ascontiguousarray(model.to_state(np.asarray(y, dtype=float))), model.params)[1])


def collar_acceleration_at(model, t):
    """The collar's acceleration relative to the link at ``t`` [m/s^2]."""
    if model.motion.table() is not None:
        return float(collar_acceleration(t, model.params.motion))
    return float(model.motion.collar_acceleration(t))


def restitution_terms(model, t, y_minus, y_plus, scale, time_scale, restitution=None, phase=None):
    """The :class:`EventTerms` of the restitution impact at ``(t, y_minus)`` [s, sine-mode state] giving ``y_plus``.

    Written out for the uniform planar link (:func:`restitution_jacobian`); else
    :func:`restitution_terms_by_differences` with steps :data:`REL_STEP` of ``scale`` (the state's
    sizes) and of ``time_scale`` [s]. ``restitution`` replaces ``contact.restitution`` (0: the plastic
    impact that starts a sustained contact); ``phase`` is the contact phase after it (None: free flight).
    """
    e = model.config.contact.restitution if restitution is None else restitution
    if not (model.uniform and model.config.beam.model == "planar"):
        return restitution_terms_by_differences(model, t, y_minus, y_plus, scale, time_scale, e, phase)
    y_minus = np.asarray(y_minus, dtype=float)
    N = model.modes
    _, x_c, edge, side = model.thinnest_film(t, y_minus)
    A_r = collar_acceleration_at(model, t) if edge else 0.0
    dq, dv, dt = restitution_jacobian(y_minus[:N], y_minus[N:], x_c, edge, side, model.kinematics(t).V_r, A_r,
                                      e, model.config.mechanism.rod_length)
    DR = np.eye(2 * N)
    DR[N:, :N], DR[N:, N:] = dq, dv
    gradient = np.zeros(2 * N)
    gradient[:N] = -side * np.sin(wavenumbers(N, model.config.mechanism.rod_length) * x_c)
    f_minus, f_plus = fields(model, t, y_minus, y_plus, phase)
    return EventTerms(DR, np.concatenate([np.zeros(N), dt]), gradient, event_rate(model, t, y_minus), f_minus, f_plus)


def central_differences(f, t, y, steps, tau):
    """``(df/dy, df/dt)`` of ``f(t, y)`` (a 1-D array) by central differences: column ``j`` with the step
    ``steps[j]`` in ``y[j]``, the time derivative with the step ``tau`` [s]."""
    y = np.asarray(y, dtype=float)
    n = y.size
    D = np.empty((np.size(f(t, y)), n))
    for j in range(n):
        e = np.zeros(n)
        e[j] = steps[j]
        D[:, j] = (f(t, y + e) - f(t, y - e)) / (2.0 * steps[j])
    return D, (f(t + tau, y) - f(t - tau, y)) / (2.0 * tau)


def restitution_terms_by_differences(model, t, y_minus, y_plus, scale, time_scale, restitution=None, phase=None):
    """:class:`EventTerms` with ``DR``, ``dR/dt`` and ``grad g`` by central differences of the model's
    :meth:`~lubelink.assembly.Model.impact` and gap (any model: planar or spatial, any section)."""
    y_minus = np.asarray(y_minus, dtype=float)
    n = y_minus.size
    steps = REL_STEP * np.asarray(scale, dtype=float)
    tau = REL_STEP * time_scale

    def reset_and_gap(t_, y):
        return np.append(model.impact(t_, y, restitution=restitution)[0], model.gap(t_, model.to_state(y)))

    D, rates = central_differences(reset_and_gap, t, y_minus, steps, tau)
    DR, gradient, reset_rate = D[:n], D[n], rates[:n]
    f_minus, f_plus = fields(model, t, y_minus, y_plus, phase)
    return EventTerms(DR, reset_rate, gradient, event_rate(model, t, y_minus), f_minus, f_plus)


def unsupported(model, run) -> str:
    """Why the events of ``run`` (a :class:`~lubelink.results.Run`) have no saltation matrices here; ``""`` if they do.

    Supported (:func:`lubelink.phases.period_events`): restitution impacts in free flight (each with a
    jump); the compliant contact's start and end (at a point or over the pad; planar link); the
    sustained contact's plastic start and its end (planar link). Not: an impact without a jump (a
    graze of the restitution law), a contact phase of the spatial link, a contact phase still on at
    the end of the period. A graze of any event is found later, by
    :func:`lubelink.steady.saltation.saltation_matrix`.
    """
    law = model.config.contact.law
    if law not in ("restitution", "compliant"):
        return f"contact.law = {law!r} has no impacts"
    if run.contacts and model.config.beam.model != "planar":
        return "a contact phase of the spatial link (its phase parameters are not carried yet)"
    for start, end, _ in run.contacts:
        if not np.isfinite(end):
            return f"a contact phase from t = {start:.9g} s still on at the end of the period"
    if law == "restitution":
        for impact in run.impacts:
            if not impact.v_minus > 0.0:
                return (f"an event without a jump at t = {impact.t:.9g} s (approach velocity "
                        f"{impact.v_minus:.3g} m/s)")
    return ""
