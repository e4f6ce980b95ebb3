"""The events of a period for the saltation matrices: impacts, and the starts and ends of contact phases.

A period of the planar link with a contact law is a sequence of smooth stretches between events
(docs/model.md section 5): restitution impacts (a jump, :mod:`lubelink.jumps`), and contact phases.
A contact phase has a *parameter* ``P`` fixed at its start that its vector field depends on and the
state does not carry:

* the compliant contact (:mod:`lubelink.compliant`): the Lankarani-Nikravesh force
  ``K delta^n (1 + 3 (1 - e^2)/4 delta_dot / v^-)`` depends on the approach velocity ``v^-`` at the
  start. Here ``P = 1 / v^-``, in which the force is affine (where it is not clipped at zero), so
  that a central difference of the right-hand side in ``P`` is exact up to rounding whatever its step;
* the sustained contact of the restitution law (:func:`lubelink.contact.constraint_force`): the
  constraint holds the material point ``P = x_c`` where it began inside the pad (at a pad edge the
  point slides with the collar: no parameter).

The standard treatment (Leine and Nijmeijer 2004, §7.2; di Bernardo et al. 2008, §2.5 and §7.2 for
the parameters of a mode) carries ``P`` as a state with ``dP/dt = 0``: in the augmented state
``z = [y, P]`` a phase's start is an event with the reset ``R(t, y) = [R_y(t, y), P(t, y)]``, so its
ordinary saltation matrix (:func:`lubelink.steady.saltation.saltation_matrix`) has the row
``dP/dy + (dP/dt + dP/dy f_-) (-grad g^T / g_t)``: the chain rule through the start's state and its
time, which moves with the perturbation. The phase's flow carries the column ``dy/dP``
(``d/dt dy/dP = J dy/dP + df/dP``, :func:`lubelink.steady.variational.flow_with_jacobian`).
A phase's *end* is a switch of the vector field with no reset: the compliant force is zero where the
film reopens (``delta = 0``, or clipped at zero before), the sustained contact's force is zero at
its end event, so ``f_+ = f_-`` there and the saltation matrix is the identity (``S = I +
(f_+ - f_-) grad g^T / g_t``); where the event is located does not matter to first order.

Before a phase's start ``P`` is unused, so the monodromy of ``y`` is the ``y`` block of the
augmented one (a period starts outside contact: :meth:`lubelink.steady.problem.PeriodMap.run`).

What it takes of the model: for the uniform planar link the derivatives of ``v^-`` and ``x_c`` are
written out (:func:`lubelink.jumps.approach_jacobian`); for a variable section they are central
differences of the model's :meth:`~lubelink.assembly.Model.approach` and
:meth:`~lubelink.assembly.Model.thinnest_film`. ``df/dP`` is always a central difference of the
model's right-hand side (the model has no derivative with respect to a phase's parameter); the
phase's Jacobian ``df/dy`` is the model's analytic one where it has one (the compliant contact at a
point, :func:`lubelink.compliant.compliant_jacobian`), else differences (over the pad; the sustained
contact), as :meth:`~lubelink.assembly.Model.jacobian_missing` says.
"""

from __future__ import annotations

from typing import Callable, NamedTuple

import numpy as np

from .beam import wavenumbers
from .jumps import (REL_STEP, EventTerms, approach_jacobian, central_differences, collar_acceleration_at, event_rate,
                    fields, restitution_terms)

__all__ = ["Parameter", "Event", "period_events", "compliant_start", "sustained_start", "augmented", "STEP_INVERSE",
           "STEP_POINT"]

#: Step of the central difference ``df/dP`` of the compliant contact, relative to ``P = 1/v^-``: the force
#: is affine in ``P``, so the step only keeps both sides on the same side of the force's clipping at zero.
STEP_INVERSE = 1e-3
#: Step of ``df/dP`` of a sustained contact's point [-, of the shortest half-wave ``L / N``]: truncation
#: ``(pi h)^2 / 6`` about 2e-10, rounding about 1e-11 of ``df/dP``.
STEP_POINT = 1e-5


class Parameter(NamedTuple):
    """A contact phase's parameter ``P`` carried by the variational equations (``dP/dt = 0``).

    ``value`` [SI], ``step`` of the central difference ``df/dP``, ``size`` its typical size (for the
    tolerance), ``phase(P)`` the phase tuple of :meth:`~lubelink.assembly.Model.with_phase` at ``P``.
    """

    value: float
    step: float
    size: float
    phase: Callable


class Event(NamedTuple):
    """An event of a period and the stretch after it.

    ``t`` [s]; ``y_after`` the sine-mode state the stretch starts from (None: where the flow arrives);
    ``phase`` of the stretch (None: free flight); ``parameter`` (:class:`Parameter` or None);
    ``terms`` the :class:`~lubelink.jumps.EventTerms` of the augmented state ``[y, P]`` (``n + 1``),
    None for a switch without a jump of the vector field (the saltation matrix is the identity);
    ``where`` names it; ``grazing`` the graze threshold of its saltation matrix (None: the default,
    :data:`lubelink.steady.saltation.GRAZING`; 0 for the impacts of a Zeno cascade, :func:`period_events`).
    """

    t: float
    y_after: np.ndarray | None
    phase: tuple | None
    parameter: Parameter | None
    terms: EventTerms | None
    where: str
    grazing: float | None = None


def augmented(terms, row=None, row_rate=0.0):
    """``terms`` of ``y`` (``n``) as terms of ``[y, P]``: the reset sets ``P`` to ``P(t, y)`` with the
    derivatives ``row`` (``dP/dy``, ``(n,)``) and ``row_rate`` (``dP/dt``), or keeps it (``row`` None)."""
    n = terms.gradient.size
    DR = np.eye(n + 1)
    DR[:n, :n] = terms.reset_jacobian
    if row is not None:
        DR[n, :n], DR[n, n] = row, 0.0
    return EventTerms(DR, np.append(terms.reset_rate, row_rate if row is not None else 0.0),
                      np.append(terms.gradient, 0.0), terms.rate, np.append(terms.f_minus, 0.0),
                      np.append(terms.f_plus, 0.0))


def _entry(model, t, y, scale, time_scale):
    """``(v, dv/dy, dv/dt, x_c, dx_c/dy, dx_c/dt, at_edge, side, grad g)`` at a phase's start ``(t, y)`` (sine modes)."""
    y = np.asarray(y, dtype=float)
    n = y.size
    _, x_c, edge, side = model.thinnest_film(t, y)
    L = model.config.mechanism.rod_length
    if model.uniform:
        N = n // 2
        A_r = collar_acceleration_at(model, t) if edge else 0.0
        v, dv_dq, dv_dqd, dv_dt, dx_dq, dx_dt = approach_jacobian(y[:N], y[N:], x_c, edge, side,
                                                                  model.kinematics(t).V_r, A_r, L)
        gradient = np.concatenate([-side * np.sin(wavenumbers(N, L) * x_c), np.zeros(N)])
        return (v, np.concatenate([dv_dq, dv_dqd]), dv_dt, x_c, np.concatenate([dx_dq, np.zeros(N)]), dx_dt, edge,
                side, gradient)
    steps = REL_STEP * np.asarray(scale, dtype=float)
    tau = REL_STEP * time_scale

    def pieces(t_, y_):
        return np.array([model.approach(t_, y_)[0], model.thinnest_film(t_, y_)[1],
                         model.gap(t_, model.to_state(y_))])

    D, rates = central_differences(pieces, t, y, steps, tau)
    v = model.approach(t, y)[0]
    return v, D[0], rates[0], x_c, (np.zeros(n) if edge else D[1]), rates[1] if edge else 0.0, edge, side, D[2]


def compliant_start(model, t, y, scale, time_scale):
    """The :class:`Event` of a compliant contact starting at ``(t, y)`` [s, sine-mode state].

    The phase is ``(side, v^-)`` with ``v^-`` the approach velocity there; its parameter
    ``P = 1 / v^-`` [s/m], reset to ``P(t, y)`` with ``dP = -dv / v^2``; the state does not jump
    (``DR_y = I``); the fields on both sides are the free one and the contact's at ``delta = 0``.
    """
    y = np.asarray(y, dtype=float)
    n = y.size
    v, dv_dy, dv_dt, _, _, _, _, side, gradient = _entry(model, t, y, scale, time_scale)
    phase = (float(side), float(v))
    f_minus, f_plus = fields(model, t, y, y, phase)
    terms = augmented(EventTerms(np.eye(n), np.zeros(n), gradient, event_rate(model, t, y), f_minus, f_plus),
                      -dv_dy / v**2, -dv_dt / v**2)
    u = 1.0 / v if v > 0.0 else np.inf
    parameter = Parameter(u, STEP_INVERSE * u, u, lambda P, s=float(side): (s, 1.0 / P))
    return Event(float(t), y, phase, parameter, terms, f"the compliant contact's start at t = {t:.9g} s")


def sustained_start(model, t, y_minus, y_plus, scale, time_scale):
    """The :class:`Event` of a sustained contact starting with the plastic impact at ``(t, y_minus)`` giving ``y_plus``.

    The reset is the restitution law with ``e = 0`` (:func:`lubelink.jumps.restitution_terms`), the field after
    it the constraint's (phase ``(side, 0, point)``); inside the pad the parameter ``P = x_c``, the material point
    held [m], reset to the thinnest film's point with ``dx_c/dy`` (at a pad edge the point slides with the collar:
    no parameter).
    """
    y_minus = np.asarray(y_minus, dtype=float)
    point = model.contact_point(t, y_minus)
    _, _, _, x_c, dx_dy, dx_dt, edge, side, _ = _entry(model, t, y_minus, scale, time_scale)
    phase = (float(side), 0.0, float(point))
    terms = restitution_terms(model, t, y_minus, y_plus, scale, time_scale, restitution=0.0, phase=phase)
    where = f"the sustained contact's start at t = {t:.9g} s"
    if edge or point < 0.0:
        return Event(float(t), np.asarray(y_plus, dtype=float), phase, None, augmented(terms), where)
    h = STEP_POINT * model.config.mechanism.rod_length / model.modes
    parameter = Parameter(float(point), h, h / STEP_POINT,
                          lambda P, s=float(side): (s, 0.0, float(P)))
    return Event(float(t), np.asarray(y_plus, dtype=float), phase, parameter, augmented(terms, dx_dy, dx_dt), where)


def period_events(model, run, scale, time_scale):
    """The :class:`Event` list of ``run`` (a period from a state outside contact), in time order.

    ``scale`` the state's sizes and ``time_scale`` [s] for the differences where needed. The run's
    ``impacts`` and ``contacts`` (:class:`~lubelink.contact.ContactLogic`) say what happened: under the
    compliant law an impact record per contact (its start state and its end state), under the
    restitution law an impact record per impact, the plastic one starting a sustained contact at the
    same instant as that contact. Call :func:`lubelink.jumps.unsupported` first.

    The impacts of the Zeno cascade that starts a sustained contact (the plastic one, and those before it
    on its side, each slower than the one before) approach at velocities falling geometrically to about ``contact.chatter_interval`` times the
    acceleration, far below the graze threshold's fraction of the orbit's velocities; they are crossings
    all the same (``v^- > 0``, known to the rounding of the state, and a perturbation smaller than
    ``v^-`` keeps their number), so their saltation matrices are taken with no graze threshold. (Their
    large entries, ``1 / v^-``, cancel in the product: a period of one mode that ends the cascade in a
    sustained contact has the monodromy 0, ``tests/test_saltation_contact.py``.)
    """
    law = model.config.contact.law
    ends = {float(c[0]): float(c[1]) for c in run.contacts}
    cascade = set()
    for k, impact in enumerate(run.impacts):
        if law == "restitution" and float(impact.t) in ends:
            j = k - 1
            while j >= 0 and run.impacts[j].side == impact.side and run.impacts[j].v_minus > run.impacts[j + 1].v_minus:
                cascade.add(j)
                j -= 1
    events = []
    for k, impact in enumerate(run.impacts):
        if law == "compliant":
            start = compliant_start(model, impact.t, impact.y_before, scale, time_scale)
            events.append(start)
            end = ends[float(impact.t)]
            events.append(Event(end, np.asarray(impact.y_after, dtype=float), None, None, None,
                                f"the compliant contact's end at t = {end:.9g} s"))
        elif float(impact.t) in ends:
            events.append(sustained_start(model, impact.t, impact.y_before, impact.y_after, scale,
                                          time_scale)._replace(grazing=0.0))
            end = ends[float(impact.t)]
            events.append(Event(end, None, None, None, None, f"the sustained contact's end at t = {end:.9g} s"))
        else:
            terms = restitution_terms(model, impact.t, impact.y_before, impact.y_after, scale, time_scale)
            events.append(Event(float(impact.t), np.asarray(impact.y_after, dtype=float), None, None, augmented(terms),
                                f"the impact at t = {impact.t:.9g} s", 0.0 if k in cascade else None))
    return events
