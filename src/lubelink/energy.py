"""The energy budget of a run: the link's vibration energy and the work of every load on it (docs/model.md section 2.5).

The vibration energy of the link relative to its rigid motion, kinetic plus strain, is in the
sine modes of a uniform link (modal mass ``m = rho A L / 2``, orthogonal modes)::

    E = m/2 sum_n (q_dot_n^2 + omega_n^2 q_n^2)       [J]   (lubelink.beam.modal_energy)

and the modal equation (:func:`lubelink.model.rhs_given`) makes its rate the sum of the powers
of the loads on the link, each of the form ``sum_n q_dot_n F_n``:

* the rigid motion's inertial loads and gravity, ``m sum q_dot_n (omega^2 q_n + a_n)`` with
  ``a_n`` the rigid-motion load of :func:`lubelink.beam.rigid_load` (the centrifugal softening
  included);
* the structural damping, ``-2 zeta m sum omega_n q_dot_n^2 <= 0``;
* the film, the asperity contact, the joint reaction of the collar;
* the contact force (compliant, or the constraint of a sustained contact), and at every
  restitution impact a jump of ``E``.

:func:`powers_given` evaluates the powers with the functions the right-hand side calls;
:func:`budget` integrates them over the samples (cumulative Simpson) and returns the residual
``E(t) - E(0) - sum W(t)``, which measures how well the integrated state satisfies its own
equations: it stays at the integration tolerance and the quadrature error of the sampling.

At an impact the link's energy changes by the work of the collar's impulse. Seen from the
contact point (the frame in which the collar face is at rest) the loss
``(m_eff / 2) (v^-^2 - v^+^2) >= 0`` (``m_eff = m / sum sin^2(beta_n x_c)``, ``v`` the approach
velocities) is the dissipation; the rest is the work of the collar that drives the contact
(:func:`impact_terms`).
"""

from __future__ import annotations

import numpy as np

from . import beam, film
from ._jit import jitable, kernel
from .beam import wavenumber
from .kinematics import motion_at
from .model import PRINTED_FILM_SIGN, asperity_term, effective_acceleration, stiffened

__all__ = ["LOADS", "powers_given", "powers_many", "impact_terms", "budget"]

#: The loads whose powers :func:`powers_given` returns, in its order (the results' ``work_<load>``).
LOADS = ("rigid", "damping", "film", "asperity", "reaction")


@jitable
def powers_given(kin, y, p, out):
    """The vibration energy [J] into ``out[0]`` and the powers [W] of :data:`LOADS` into ``out[1:]``.

    ``kin`` the rigid motion (:func:`~lubelink.kinematics.motion_at`), ``y`` the sine-mode state of a
    uniform planar link. The contact force is not among them (:func:`budget` adds it).
    """
    omega, alpha, x_star, V_r, reaction = kin[1], kin[2], kin[3], kin[4], kin[5]
    N = p.basis.modes
    L = p.basis.rod_length
    m = p.basis.modal_mass
    q = y[:N]
    q_dot = y[N:]
    out[0] = beam.modal_energy(q, q_dot, p.basis.omega_n, m)
    A_eff = effective_acceleration(kin[0], omega, kin[6], kin[7], p.mechanism.gravity, p.model.equations)
    softening = -omega * omega if stiffened(p.model.equations) else omega * omega
    rigid = 0.0
    damping = 0.0
    R = 0.0
    for n in range(N):
        rigid += q_dot[n] * (beam.rigid_load(A_eff, alpha, n + 1, L) + softening * q[n])
        damping -= 2.0 * p.beam.damping_ratio * p.basis.omega_n[n] * q_dot[n] * q_dot[n]
        if reaction != 0.0:
            R += q_dot[n] * beam.point_load(reaction, x_star, wavenumber(n + 1, L))
    out[1] = m * rigid
    out[2] = m * damping
    F = np.zeros(N)
    if p.film.model != film.NO_FILM:
        film.modal_film_force(q, q_dot, x_star, V_r, p.film, p.beam.width, p.pad, L, F)
        if p.model.equations == PRINTED_FILM_SIGN:
            F *= -1.0
    out[3] = np.dot(q_dot, F)
    F[:] = 0.0
    if p.film.roughness > 0.0:
        asperity_term(p.rough, q, x_star, p, p.beam.width, F)
    out[4] = np.dot(q_dot, F)
    out[5] = R


@kernel
def powers_many(t, y, p):
    """:func:`powers_given` at every sample: ``t`` ``(T,)`` [s], ``y`` ``(T, 2N)``; returns ``(T, 1 + len(LOADS))``."""
    out = np.empty((t.shape[0], 6))
    for i in range(t.shape[0]):
        powers_given(motion_at(t[i], p.motion), y[i], p, out[i])
    return out


def impact_terms(impacts, restitution_law, mass, rod_length):
    """Per impact: the change of the link's energy [J], the dissipation at the contact point [J] (>= 0) and
    the work of the collar [J] (their sum).

    ``impacts`` the records of :class:`lubelink.contact.ContactLogic` (time, point, approach velocities
    before and after, side, ``q``, ``q_dot`` before and after). A compliant contact's records hold no
    jump: its work is the contact force's power over the samples.
    """
    k = len(impacts)
    change, loss = np.zeros(k), np.zeros(k)
    if not restitution_law:
        return change, loss, np.zeros(k)
    for i, (_, x_c, v_minus, v_plus, _, _, before, after) in enumerate(impacts):
        change[i] = 0.5 * mass * float(np.sum(after**2 - before**2))
        s = np.sin(beam.wavenumbers(before.shape[0], rod_length) * x_c)
        loss[i] = 0.5 * mass / float(np.sum(s * s)) * (v_minus**2 - v_plus**2)
    return change, loss, change + loss


def _cumulative(t, power):
    """``int`` of ``power`` from the first of the times ``t`` to each [J]: Simpson's rule on the (non-uniform)
    points, the trapezoid for two; a point at the time of the one before it (simultaneous impacts, a sample
    at an impact) adds nothing."""
    from scipy.integrate import cumulative_simpson, cumulative_trapezoid

    if t.size < 2:
        return np.zeros(power.shape)
    steps = np.diff(t)
    keep = np.r_[True, steps > 0.0]
    if keep.all() and np.ptp(steps) <= 1e-9 * steps[0]:  # uniform samples: SciPy's faster equal-step rule
        return cumulative_simpson(power, dx=float(steps.mean()), initial=0.0) if t.size > 2 else \
            cumulative_trapezoid(power, t, initial=0.0)
    tu, pu = t[keep], power[..., keep]
    if tu.size < 3:
        work = cumulative_trapezoid(pu, tu, initial=0.0)
    else:
        work = cumulative_simpson(pu, x=tu, initial=0.0)
    return work[..., np.cumsum(keep) - 1]


def budget(t, energy, powers, starts=(), jumps=()):
    """The works of the loads and the residual of the energy balance at the points ``t``.

    Parameters
    ----------
    t : ndarray, shape ``(T,)``
        Times [s], non-decreasing.
    energy : ndarray, shape ``(T,)``
        Vibration energy [J].
    powers : dict of ndarray
        Power of each load at the points [W].
    starts : sequence of int
        Points where a smooth piece begins (after an impact, whose state is the point before it and
        this one at the same time): the powers are integrated piece by piece.
    jumps : sequence of float
        The energy change [J] of the impact that ends before each of ``starts``.

    Returns
    -------
    works : dict of ndarray
        ``int`` of each power from ``t[0]`` [J], and ``"impacts"``: the sum of the jumps so far [J].
    residual : ndarray
        ``E(t) - E(t[0]) - sum of the works`` [J].
    """
    bounds = [0, *starts, t.size]
    P = np.array([np.asarray(power, dtype=float) for power in powers.values()]).reshape(len(powers), t.size)
    W = np.empty_like(P)
    total = np.zeros(len(powers))
    for a, b in zip(bounds[:-1], bounds[1:]):
        if b > a:
            W[:, a:b] = total[:, None] + _cumulative(t[a:b], P[:, a:b])
            total = W[:, b - 1]
    works = dict(zip(powers, W))
    steps = np.zeros(t.size)
    for start, change in zip(starts, jumps):
        steps[start:] += change
    works["impacts"] = steps
    residual = energy - energy[0] - sum(works.values())
    return works, residual


def missing(model) -> str:
    """Why a run of ``model`` has no energy budget (``""`` if it has one)."""
    if model.params.spatial is not None:
        return "the spatial model (its budget is not written yet)"
    if not model.uniform:
        return "a variable section (its energy is not the sine modes' sum)"
    return ""


def _table(model, t, y):
    """:func:`powers_given` at the times ``t`` and sine-mode states ``y``."""
    if model.motion.table() is not None:
        return (powers_many if model.compiled else powers_many.py_func)(t, y, model.params)
    table = np.empty((t.size, 1 + len(LOADS)))
    for i in range(t.size):
        powers_given(model.kinematics(t[i]), y[i], model.params, table[i])
    return table


def of_run(result, t, y, phase_side):
    """The energy budget of a :class:`~lubelink.results.Run` at its samples ``t``, sine-mode states ``y``.

    The powers are integrated over the samples and, under the restitution law, the states just before
    and after every impact (the records of :class:`~lubelink.contact.ContactLogic`), so that the
    quadrature never spans a jump of the velocities or of a sustained contact's force.

    Returns ``(series, per_impact, residual)``: the vibration energy, the works of :data:`LOADS`, of
    the contact and of the impacts at the samples [J]; per impact the energy change, the dissipation
    and the collar's work [J]; the largest residual of the balance [J].
    """
    model = result.model
    N = model.modes
    law = model.config.contact.law
    restitution = law == "restitution"
    zeros = np.zeros(t.size)
    v = result.phase_v if result.phase_v is not None else zeros
    point = result.phase_point if result.phase_point is not None else zeros
    T, Y, side, vel, where, kind = t, y, np.asarray(phase_side, dtype=float), v, point, np.full(t.size, 2)
    impacts = result.impacts if restitution else []
    if impacts:
        k = len(impacts)
        held = {c[0] for c in result.contacts}  # sustained contacts, by their start
        extra = np.empty((2 * k, 2 * N))
        extra_side = np.zeros(2 * k)
        extra_point = np.zeros(2 * k)
        for j, (t_i, _, _, _, s_i, q, before, after) in enumerate(impacts):
            extra[2 * j] = np.r_[q, before]
            extra[2 * j + 1] = np.r_[q, after]
            if t_i in held:
                extra_side[2 * j + 1] = s_i
                extra_point[2 * j + 1] = model.contact_point(t_i, extra[2 * j])
        T = np.r_[t, np.repeat([i[0] for i in impacts], 2)]
        Y = np.concatenate([y, extra])
        side = np.r_[side, extra_side]
        vel = np.r_[vel, np.zeros(2 * k)]
        where = np.r_[where, extra_point]
        kind = np.r_[kind, np.tile([0, 1], k)]
        order = np.lexsort((kind, T))
        T, Y, side, vel, where, kind = T[order], np.ascontiguousarray(Y[order]), side[order], vel[order], \
            where[order], kind[order]
        sample = order < t.size
    else:
        sample = slice(None)
    table = _table(model, T, Y)
    powers = {name: table[:, k + 1] for k, name in enumerate(LOADS)}
    contact = np.zeros(T.size)
    if law == "compliant":
        contact = model.compliant_loads(T, Y, side, vel)[1]
    elif restitution:
        for j in np.flatnonzero(side):
            contact[j] = float(np.dot(Y[j, N:], model.sustained_loads(T[j], Y[j], side[j], where[j])))
    powers["contact"] = contact
    change, loss, collar = impact_terms(impacts, restitution, model.modal_mass, model.config.mechanism.rod_length)
    works, residual = budget(T, table[:, 0], powers, np.flatnonzero(kind == 1), change)
    series = {"energy": table[sample, 0], **{f"work_{name}": value[sample] for name, value in works.items()},
              "energy_residual": residual[sample]}
    return series, (change, loss, collar), float(np.max(np.abs(residual))) if t.size else 0.0
