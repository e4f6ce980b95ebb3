"""Saltation matrices: the jump of the flow's Jacobian at an event, and the monodromy through events.

A trajectory of ``dy/dt = f_-(t, y)`` reaches the event surface ``g(t, y) = 0`` at ``t_e`` in the
state ``y_-``; a reset ``y_+ = R(t_e, y_-)`` follows (the identity for a pure switch of the
vector field), and then ``dy/dt = f_+(t, y)``. A perturbation ``dy`` just before the event meets
the surface ``tau = -grad g . dy / g_t`` later (``g_t = grad g . f_- + dg/dt``, the rate of ``g``
along the flow), so just after the event it is ``S dy`` with the *saltation matrix*

    S = DR + (f_+ - DR f_- - dR/dt) grad g^T / g_t

(R. I. Leine and H. Nijmeijer, *Dynamics and Bifurcations of Non-Smooth Mechanical Systems*,
Springer 2004, §7.2; M. di Bernardo et al., *Piecewise-smooth Dynamical Systems*, Springer 2008,
§2.5). The monodromy matrix of a period with events at ``t_1 < ... < t_k`` is
``Phi(T, t_k) S_k ... S_1 Phi(t_1, 0)``, each ``Phi`` from the variational equations of a smooth
stretch (:mod:`.variational`).

At a graze (``g_t`` near zero: the trajectory touches the surface) ``S`` is unbounded and the
map is not differentiable; :func:`saltation_matrix` raises :class:`Grazing` there rather than
divide by a rate near zero. Nothing here knows the model: the caller hands over the pieces.
"""

from __future__ import annotations

import numpy as np

__all__ = ["Grazing", "GRAZING", "saltation_matrix", "compose"]

#: An event whose rate ``|g_t|`` is below this fraction of the largest rate the orbit's sizes allow,
#: ``sum_i |dg/dy_i| rate_scale_i``, is a graze: the saltation matrix's correction term, ``1/g_t``, is
#: then more than a thousand times its size at a typical crossing.
GRAZING = 1e-3


class Grazing(ArithmeticError):
    """An event too close to a graze for a saltation matrix (its rate along the flow is about zero)."""


def saltation_matrix(reset_jacobian, reset_rate, gradient, rate, f_minus, f_plus, rate_scale, grazing=None,
                     where="the event"):
    """The saltation matrix ``S`` of one event (module docstring), shape ``(n, n)``.

    Parameters
    ----------
    reset_jacobian : ndarray, shape ``(n, n)``
        ``DR = dR/dy`` at ``y_-`` (the identity for a switch).
    reset_rate : ndarray, shape ``(n,)``
        ``dR/dt`` at ``(t_e, y_-)``, the reset's explicit dependence on time (zeros if none).
    gradient : ndarray, shape ``(n,)``
        ``grad_y g`` at ``(t_e, y_-)``.
    rate : float
        ``g_t = grad g . f_- + dg/dt``: the rate of the event function along the flow before the event.
    f_minus, f_plus : ndarray, shape ``(n,)``
        The vector fields at ``(t_e, y_-)`` and ``(t_e, y_+)``.
    rate_scale : ndarray, shape ``(n,)``
        A typical size of each component of ``dy/dt`` on the orbit (for the graze test).
    grazing : float, optional
        The graze threshold (default :data:`GRAZING`).
    where : str
        Names the event in the :class:`Grazing` message.

    Raises
    ------
    Grazing
        If ``|g_t| <= grazing * sum_i |grad_i g| rate_scale_i`` (or either is not finite).
    """
    grazing = GRAZING if grazing is None else grazing
    DR = np.asarray(reset_jacobian, dtype=float)
    gradient = np.asarray(gradient, dtype=float)
    reference = float(np.sum(np.abs(gradient) * np.asarray(rate_scale, dtype=float)))
    if not (np.isfinite(rate) and np.isfinite(reference) and abs(rate) > grazing * reference):
        raise Grazing(f"{where} is a graze: the event function's rate along the flow, {rate:.3g}, is "
                      f"{abs(rate) / reference if reference > 0 else np.inf:.2g} of its typical size {reference:.3g} "
                      f"(threshold {grazing:g}), so the period map is not differentiable there and a saltation "
                      "matrix would divide by about zero")
    jump = np.asarray(f_plus, dtype=float) - DR @ np.asarray(f_minus, dtype=float) - np.asarray(reset_rate, dtype=float)
    return DR + np.outer(jump, gradient) / rate


def compose(flows, jumps):
    """``Phi_k S_k ... Phi_1 S_1 Phi_0``: the monodromy of smooth stretches ``flows`` (``k + 1``) and the
    saltation matrices ``jumps`` (``k``) between them."""
    if len(flows) != len(jumps) + 1:
        raise ValueError(f"{len(flows)} flows and {len(jumps)} jumps: one flow more than jumps is needed")
    M = np.asarray(flows[0], dtype=float)
    for S, Phi in zip(jumps, flows[1:]):
        M = Phi @ (S @ M)
    return M
