"""The energy budget of a run: the link's vibration energy and the work of every load on it (docs/model.md section 2.5).

The vibration energy of the link relative to its rigid motion, kinetic plus strain, is that of
the integrator's coordinates: the sine modes of a uniform link (modal mass ``m = rho A L / 2``),
or the eigen-coordinates ``eta`` of a variable section (:mod:`lubelink.link.section`, mass ``m_ref``),
each a decoupled oscillator of frequency ``W_i``; for the spatial link, of the three directions::

    E = m/2 sum_i (eta_dot_i^2 + W_i^2 eta_i^2)       [J]   (lubelink.beam.modal_energy)

and the modal equations make its rate the sum of the powers of the loads on the link, each
``sum_n q_dot_n F_n`` with ``q_dot`` the sine-mode velocities and ``F`` the load's sine-mode
forces [N] (the spatial link's axial block with a free end: its own modes' velocities and forces):

* the rigid motion's inertial loads and gravity (:func:`lubelink.beam.rigid_load`; the spatial
  link's :func:`lubelink.link.spatial.rigid_loads`), and the link frame's Euler, centrifugal and
  Coriolis accelerations of the deflection (planar: the centrifugal softening ``omega^2 q``;
  spatial: :func:`lubelink.link.spatial.frame_terms`, whose Coriolis part does no work), and the geometric
  stiffness of the rigid motion's axial force (``beam.axial_force``, :mod:`lubelink.link.axial`: a stiffness
  that changes in time, so a load that works rather than a potential; on both bending directions of the spatial
  link) with the inertia of the chord's rotation under the slider (its modal forces at the run's accelerations,
  :func:`lubelink.link.axial.frame_chord_rotation_force`; on the spatial link about both transverse axes);
* the structural damping, ``-2 zeta m sum W_i eta_dot_i^2 <= 0``;
* the film, the asperity contact (on each pair of faces, :mod:`lubelink.link.faces`), the joint
  reaction of the collar;
* the contact force (compliant, or the constraint of a sustained contact), and at every
  restitution impact a jump of ``E``.

:func:`powers_given` and :func:`spatial_powers_given` evaluate the powers with the functions the
right-hand sides call; :func:`budget` integrates them over the samples (cumulative Simpson) and
returns the residual ``E(t) - E(0) - sum W(t)``, which measures how well the integrated state
satisfies its own equations: it stays at the integration tolerance and the quadrature error of
the sampling.

At an impact the link's energy changes by the work of the collar's impulse. Seen from the
contact point (the frame in which the collar face is at rest) the loss
``(m_eff / 2) (v^-^2 - v^+^2) >= 0`` (``m_eff`` the link's mass at the contact point, ``v`` the
approach velocities) is the dissipation; the rest is the work of the collar that drives the
contact (:func:`impact_terms`).
"""

from __future__ import annotations

import numpy as np

from . import beam
from ._jit import jitable, kernel
from .beam import wavenumber
from .film import NO_FILM
from .integrate.cumulative import cumulative_simpson
from .link import section, spatial, spatial_section
from .link.faces import asperity_on, film_on
from .link.kinematics import motion_at
from .link.model import chord_power, geometric_on, effective_acceleration, stiffened
from .link.spatial_model import U2_U3, spatial_chord_power, spatial_geometric_on
from .link.spatial_model import effective_acceleration as spatial_effective_acceleration
from .link.spatial_motion import spatial_motion_at

__all__ = ["LOADS", "powers_given", "spatial_powers_given", "powers_many", "impact_terms", "budget", "of_run"]

#: The loads whose powers :func:`powers_given` returns, in its order (the results' ``work_<load>``).
LOADS = ("rigid", "damping", "film", "asperity", "reaction")


@jitable(inline=True)
def _oscillators(y, W, zeta, m, out):
    """The vibration energy [J] into ``out[0]`` and the damping's power [W] into ``out[2]`` of the integrator's
    state ``y`` (oscillators of frequencies ``W`` [rad/s], mass ``m`` [kg], damping ratio ``zeta``)."""
    K = W.shape[0]
    out[0] = beam.modal_energy(y[:K], y[K:], W, m)
    damping = 0.0
    for i in range(K):
        damping -= 2.0 * zeta * W[i] * y[K + i] * y[K + i]
    out[2] = m * damping


@jitable(inline=True)
def _face_powers(q, q_t, x_star, V_r, p, width, out):
    """Add the powers [W] of the film (``out[3]``) and of the asperity contact (``out[4]``) on one pair of faces
    of sine-mode coordinates ``q``, ``q_t``."""
    F = np.zeros(q.shape[0])
    L = p.basis.rod_length
    if p.film.model != NO_FILM:
        film_on(q, q_t, x_star, V_r, p.film, width, p.pad, L, p.model.equations, F)
        out[3] += np.dot(q_t, F)
    if p.film.roughness > 0.0:
        F[:] = 0.0
        asperity_on(p.rough, q, x_star, p.film, width, p.pad, L, F)
        out[4] += np.dot(q_t, F)


@jitable
def _rigid_power(g, y, yq, A_eff, alpha, softening, p):
    """The power [W] of the rigid motion's loads and the centrifugal ``softening`` [1/s^2] on the planar link:
    by sine modes (``g`` None), or by the eigenbasis ``g`` (``y`` its coordinates, ``yq`` the sine modes')."""
    N = p.basis.modes
    m = p.basis.modal_mass
    power = 0.0
    if g is None:
        for n in range(N):
            power += yq[N + n] * (beam.rigid_load(A_eff, alpha, n + 1, p.basis.rod_length) + softening * yq[n])
        return m * power
    for n in range(N):
        power -= yq[N + n] * (A_eff * g.r0[n] + alpha * g.r1[n])
    for k in range(N):
        power += m * softening * y[k] * y[N + k]
    return power


@jitable
def _geometric_power(g, t, kin, q, q_dot, p):
    """The power [W] of the axial force's geometric stiffness and of the chord's rotation on the planar link
    (``g`` None: none, compiled out)."""
    if g is None:
        return 0.0
    F = np.zeros(q.shape[0])
    geometric_on(g, t, kin, q, p, F)
    return np.dot(q_dot, F) + chord_power(g, t, kin, np.concatenate((q, q_dot)), p)


@jitable
def powers_given(t, kin, yq, p, out):
    """The vibration energy [J] into ``out[0]`` and the powers [W] of :data:`LOADS` into ``out[1:]``.

    ``t`` [s] the time, ``kin`` the rigid motion (:class:`~lubelink.link.kinematics.RigidMotion`), ``yq`` the sine-mode state
    of the planar link (of a variable section too). The contact force is not among them (:func:`budget`
    adds it).
    """
    omega, alpha, x_star, V_r, reaction = kin.omega, kin.alpha, kin.x_star, kin.V_r, kin.reaction
    N = p.basis.modes
    L = p.basis.rod_length
    y = section.state(p.galerkin, yq)
    q = yq[:N]
    q_dot = yq[N:]
    out[:] = 0.0
    _oscillators(y, p.basis.omega_n, p.beam.damping_ratio, p.basis.modal_mass, out)
    A_eff = effective_acceleration(kin.A_O2, omega, kin.angle, kin.v_O1, p.mechanism.gravity, p.model.equations)
    softening = -omega * omega if stiffened(p.model.equations) else omega * omega
    out[1] = (_rigid_power(p.galerkin, y, yq, A_eff, alpha, softening, p)
              + _geometric_power(p.geometric, t, kin, q, q_dot, p))
    _face_powers(q, q_dot, x_star, V_r, p, p.beam.width, out)
    if reaction != 0.0:
        for n in range(N):
            out[5] += q_dot[n] * beam.point_load(reaction, x_star, wavenumber(n + 1, L))


@jitable
def _spatial_rigid_power(g, axial, y, yq, A, w, al, p):
    """The power [W] of the rigid motion's loads and the frame's accelerations of the deflection on the spatial
    link (:func:`lubelink.link.spatial.accelerations`; of a variable section, with the eigenbases ``g``:
    :func:`lubelink.link.spatial_section.eigen_accelerations`; ``axial`` the free axial end's couplings, None for
    the fixed end)."""
    N = p.basis.modes
    M = 3 * N
    m = p.basis.modal_mass
    power = 0.0
    if g is None:
        for n in range(N):
            r1, r2, r3 = spatial.rigid_loads(A, w, al, n + 1, p.basis.rod_length)
            if axial is None:
                c1, c2, c3 = spatial.frame_terms(w, al, (yq[n], yq[N + n], yq[2 * N + n]),
                                                 (yq[M + n], yq[M + N + n], yq[M + 2 * N + n]))
            else:
                c1, c2, c3 = spatial.coupled_frame_terms(axial.projection, w, al, yq, n)
                r1 = spatial.axial_rigid_load(axial.rigid, A[0], spatial.axis_acceleration(w, al)[0], n) / m
            power += yq[M + n] * (r1 - c1)
            power += yq[M + N + n] * (r2 - c2)
            power += yq[M + 2 * N + n] * (r3 - c3)
        return m * power
    f = np.empty(M)
    c = np.empty(M)
    spatial_section.trial_loads(g, axial, yq, A, w, al, np.zeros(M), f, c)
    for i in range(M):
        power += yq[M + i] * f[i]
    for d in range(3):
        for k in range(N):
            frame = 0.0
            for n in range(N):
                frame += g.phi_inv[d, k, n] * c[d * N + n]
            power -= m * y[M + d * N + k] * frame
    return power


@jitable
def _spatial_geometric_power(g, kin, yq, p):
    """The power [W] of the axial force's geometric stiffness on both bending directions of the spatial link and of
    the chord's rotation (``g`` None: none, compiled out)."""
    if g is None:
        return 0.0
    M = 3 * p.basis.modes
    F = np.zeros(M)
    spatial_geometric_on(g, kin, yq, p, F)
    return np.dot(yq[M:], F) + spatial_chord_power(g, kin, yq, p)


@jitable
def spatial_powers_given(kin, yq, p, out):
    """:func:`powers_given` of the spatial link: ``kin`` a :class:`~lubelink.link.spatial.SpatialRigidMotion`, ``yq``
    the sine-mode state ``(6 N,)``; the film and the asperity contact of every pair of faces the collar guides."""
    N = p.basis.modes
    M = 3 * N
    g = p.spatial.galerkin
    y = spatial_section.state(g, yq)
    out[:] = 0.0
    _oscillators(y, p.spatial.W, p.beam.damping_ratio, p.basis.modal_mass, out)
    A = spatial_effective_acceleration(kin.A_O, kin.e1, kin.e2, kin.e3, p.mechanism.gravity)
    out[1] = (_spatial_rigid_power(g, p.spatial.axial, y, yq, A, kin.omega, kin.alpha, p)
              + _spatial_geometric_power(p.geometric, kin, yq, p))
    _face_powers(yq[N:2 * N], yq[M + N:M + 2 * N], kin.x_star, kin.V_r, p, p.beam.width, out)
    if p.film.faces == U2_U3:
        _face_powers(yq[2 * N:M], yq[M + 2 * N:], kin.x_star, kin.V_r, p, p.beam.height, out)


@kernel
def powers_many(t, y, p):
    """:func:`powers_given` (or :func:`spatial_powers_given`) at every sample: ``t`` ``(T,)`` [s], sine-mode
    states ``y`` ``(T, 2N)`` (``(T, 6N)``); returns ``(T, 1 + len(LOADS))``."""
    out = np.empty((t.shape[0], 6))
    for i in range(t.shape[0]):
        _powers_at(p.spatial, t[i], y[i], p, out[i])
    return out


@jitable
def _powers_at(table, t, yq, p, out):
    """:func:`powers_given` at ``t`` [s], or :func:`spatial_powers_given` with the spatial ``table``."""
    if table is None:
        powers_given(t, motion_at(t, p.motion), yq, p, out)
    else:
        spatial_powers_given(spatial_motion_at(t, table.motion), yq, p, out)


def impact_terms(impacts, energy_before, energy_after, model):
    """Per impact: the change of the link's energy [J], the dissipation at the contact point [J] (>= 0) and
    the work of the collar [J] (their sum).

    ``impacts`` the :class:`~lubelink.contact.Impact` records of a restitution-law run, ``energy_before``,
    ``energy_after`` the link's energy [J] in the states before and after each. The dissipation is
    ``(m_eff / 2) (v^-^2 - v^+^2)`` with ``m_eff = 1 / (s^T M^-1 s)`` the mass of the link's pair of faces at the
    contact point (``s_n = sin(beta_n x_c)``, ``M`` the sine modes' mass matrix: ``m I`` for a uniform link,
    ``m_ref (Phi Phi^T)^-1`` for a variable section).
    """
    k = len(impacts)
    change = np.asarray(energy_after, dtype=float) - np.asarray(energy_before, dtype=float)
    loss = np.zeros(k)
    L = model.config.mechanism.rod_length
    g = model.params.galerkin
    for i, imp in enumerate(impacts):
        s = np.sin(beam.wavenumbers(model.modes, L) * imp.x_c)
        flexibility = float(np.sum(s * s)) if g is None else float(np.sum((g.phi.T @ s) ** 2))
        loss[i] = 0.5 * model.modal_mass / flexibility * (imp.v_minus**2 - imp.v_plus**2)
    return change, loss, change + loss


def _cumulative(t, power):
    """``int`` of ``power`` from the first of the times ``t`` to each [J]: Simpson's rule on the (non-uniform)
    points, the trapezoid for two; a point at the time of the one before it (simultaneous impacts, a sample
    at an impact) adds nothing."""
    if t.size < 2:
        return np.zeros(power.shape)
    keep = np.r_[True, np.diff(t) > 0.0]
    work = cumulative_simpson(power[..., keep], t[keep])
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


def _table(model, t, y):
    """:func:`powers_given` (:func:`spatial_powers_given`) at the times ``t`` and sine-mode states ``y``."""
    if model.motion.table() is not None:
        return (powers_many if model.compiled else powers_many.py_func)(t, y, model.params)
    table = np.empty((t.size, 1 + len(LOADS)))
    for i in range(t.size):  # a motion of callables: its kinematics from Python
        if model.params.spatial is None:
            powers_given(t[i], model.kinematics(t[i]), y[i], model.params, table[i])
        else:
            spatial_powers_given(model.motion.at(t[i]), y[i], model.params, table[i])
    return table


def of_run(result, t, y, phase_side):
    """The energy budget of a :class:`~lubelink.results.Run` at its samples ``t``, sine-mode states ``y``.

    The powers are integrated over the samples and, under the restitution law, the states just before
    and after every impact (the :class:`~lubelink.contact.Impact` records), so that the quadrature never
    spans a jump of the velocities or of a sustained contact's force.

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
    k = len(impacts)
    if impacts:
        held = {c[0] for c in result.contacts}  # sustained contacts, by their start
        extra = np.empty((2 * k, y.shape[1]))
        extra_side = np.zeros(2 * k)
        extra_point = np.zeros(2 * k)
        for j, imp in enumerate(impacts):
            extra[2 * j] = imp.y_before
            extra[2 * j + 1] = imp.y_after
            if imp.t in held:
                extra_side[2 * j + 1] = imp.side
                extra_point[2 * j + 1] = model.contact_point(imp.t, imp.y_before)
        T = np.r_[t, np.repeat([imp.t for imp in impacts], 2)]
        Y = np.concatenate([y, extra])
        side = np.r_[side, extra_side]
        vel = np.r_[vel, np.zeros(2 * k)]
        where = np.r_[where, extra_point]
        kind = np.r_[kind, np.tile([0, 1], k)]
        order = np.lexsort((kind, T))
        T, Y, side, vel, where, kind = T[order], np.ascontiguousarray(Y[order]), side[order], vel[order], \
            where[order], kind[order]
        sample = order < t.size
        position = np.argsort(order)[t.size:]  # where the states of the impacts went: before, after, ...
    else:
        sample = slice(None)
        position = np.zeros(0, dtype=int)
    table = _table(model, T, Y)
    powers = {name: table[:, j + 1] for j, name in enumerate(LOADS)}
    contact = np.zeros(T.size)
    if law == "compliant":
        contact = model.compliant_loads(T, Y, side, vel)[1]
    elif restitution:
        for j in np.flatnonzero(side):
            contact[j] = float(np.dot(model.face_block(Y[j], side[j])[0][N:],
                                      model.sustained_loads(T[j], Y[j], side[j], where[j])))
    powers["contact"] = contact
    change, loss, collar = impact_terms(impacts, table[position[0::2], 0], table[position[1::2], 0], model)
    works, residual = budget(T, table[:, 0], powers, np.flatnonzero(kind == 1), change)
    series = {"energy": table[sample, 0], **{f"work_{name}": value[sample] for name, value in works.items()},
              "energy_residual": residual[sample]}
    return series, (change, loss, collar), float(np.max(np.abs(residual))) if t.size else 0.0
