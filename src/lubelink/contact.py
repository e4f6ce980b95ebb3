"""Film breakdown and contact at the collar (docs/model.md section 5; paper Eq. 21).

The gap is the thinnest film on the pad (over both films of a two-sided collar); the film breaks
down when it reaches ``xi_min`` (``contact.min_film``). Then either

* the restitution law (paper Eq. 21): Newton's law at the contact point ``x_c`` with an impulse
  on a collar that does not move transversally relative to the rigid link, a jump of the modal
  velocities (:func:`restitution_jump`); or
* the compliant Lankarani-Nikravesh force (:mod:`lubelink.compliant`), switched on while the
  film is below ``xi_min``.

When restitution impacts accumulate (a Zeno sequence: two impacts closer than
``contact.chatter_interval``), the link rides on the collar: sustained contact, a unilateral
constraint ``xi_min = min_film`` at the contact point whose multiplier is the contact force
(:func:`constraint_force`); the contact ends when that force falls to zero (docs/model.md
section 5, docs/breakdown.md).

:class:`ContactLogic` is what the orchestrator asks at every zero of the gap: what to do next.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from ._jit import jitable, stack_empty
from .beam import add_deflection, wavenumber, wavenumbers
from .params import CHOICES

__all__ = [
    "thinnest_film_side",
    "thinnest_film_sides",
    "thinnest_film",
    "approach_velocity",
    "gap_rate",
    "gap_rate_bound",
    "restitution_jump",
    "Impact",
    "impact_energy_loss",
    "impact_energy_change",
    "constraint_force",
    "ContactLogic",
]

NO_LAW, RESTITUTION, COMPLIANT = (CHOICES["contact.law"].index(v) for v in ("none", "restitution", "compliant"))
#: The compiled code's ``contact.law`` of the compliant law over the pad face (``contact.extent = "pad"``), whose
#: ``stiffness`` there is ``contact.face_stiffness``: the parameters compiled code reads keep their fields (one
#: more field in them made every right-hand side 2-3x slower, benchmarks/README.md).
COMPLIANT_PAD = len(CHOICES["contact.law"])


@jitable
def is_compliant(law):
    """Whether the compiled code's ``law`` is the compliant law (at a point or over the pad)."""
    return law == COMPLIANT or law == COMPLIANT_PAD

#: Entries of the thinnest-film search's scratch (``2 N + K``: ``sin``, ``cos`` of ``beta_n x0`` and the
#: ``K = 16 + 4 N`` samples) kept on the stack (:func:`lubelink._jit.stack_empty`): up to 40 modes; more
#: allocate. The search runs at every step (the gap event) and at every sample (``film_min``), where
#: three heap arrays cost about a fifth of it.
STACK_SCRATCH = 256


@jitable
def _u2_derivatives(q, x, rod_length):
    """``u2``, ``u2'``, ``u2''`` at ``x`` [m, -, 1/m]."""
    u = 0.0
    d1 = 0.0
    d2 = 0.0
    for n in range(q.shape[0]):
        b = wavenumber(n + 1, rod_length)
        s = np.sin(b * x)
        c = np.cos(b * x)
        u += s * q[n]
        d1 += b * c * q[n]
        d2 -= b * b * s * q[n]
    return u, d1, d2


@jitable
def thinnest_film_side(side, q, x0, pad_length, clearance, rod_length, trig):
    """Thinnest film ``H/2 - side u2`` on the pad ``[x0, x0 + l]``, where it is, and whether at an edge.

    ``u2`` is sampled at the uniform points of the table ``trig`` (``sin``, ``cos`` of
    ``beta_n X_k``, ``X_k = k l / (K - 1)``, shape ``(2, N, K)``), the best sample polished by Newton iterations on
    ``u2' = 0`` (or kept at a pad edge where the film thins outwards), so that the result is a
    continuous function of the state, as an event function must be.

    Returns
    -------
    xi_min : float
        Smallest film thickness [m].
    x_c : float
        Where it is on the link [m].
    at_edge : bool
        Whether ``x_c`` is a pad edge (it then moves with the collar).
    """
    N = q.shape[0]
    K = trig.shape[2]
    need = 2 * N + K
    ws = stack_empty(STACK_SCRATCH) if need <= STACK_SCRATCH else np.empty(need)
    s0 = ws[:N]
    c0 = ws[N:2 * N]
    u = ws[2 * N:need]
    for n in range(N):
        s0[n] = np.sin(wavenumber(n + 1, rod_length) * x0)
        c0[n] = np.cos(wavenumber(n + 1, rod_length) * x0)
    u[:] = 0.0
    add_deflection(q, s0, c0, trig[0], trig[1], side, u)
    i = np.argmax(u)
    step = pad_length / (K - 1)
    x_i = x0 + pad_length if i == K - 1 else x0 + i * step
    if i == 0 or i == K - 1:
        d1 = side * _u2_derivatives(q, x_i, rod_length)[1]
        if (d1 < 0.0) if i == 0 else (d1 > 0.0):
            return 0.5 * clearance - u[i], x_i, True
    lo = x0 + max(i - 1, 0) * step
    hi = min(x0 + (i + 1) * step, x0 + pad_length)
    x = x_i
    for _ in range(8):
        _, d1, d2 = _u2_derivatives(q, x, rod_length)
        d1 *= side
        d2 *= side
        if d2 >= 0.0:
            break
        x_new = min(max(x - d1 / d2, lo), hi)
        if abs(x_new - x) < 1e-15 * max(1.0, abs(x)):
            x = x_new
            break
        x = x_new
    u_x = side * _u2_derivatives(q, x, rod_length)[0]
    if u_x < u[i]:
        x, u_x = x_i, u[i]
    return 0.5 * clearance - u_x, x, x <= x0 or x >= x0 + pad_length


@jitable
def thinnest_film_sides(q, x0, f, pad, rod_length, only_side):
    """Thinnest film over the films of ``f`` (or on ``only_side`` if non-zero): ``(xi, x_c, at_edge, side)``."""
    trig = pad.sample_trig
    if only_side != 0.0:
        xi, x_c, edge = thinnest_film_side(only_side, q, x0, f.pad_length, f.clearance, rod_length, trig)
        return xi, x_c, edge, only_side
    xi, x_c, edge = thinnest_film_side(1.0, q, x0, f.pad_length, f.clearance, rod_length, trig)
    side = 1.0
    if f.sides == 2:
        xi2, x_c2, edge2 = thinnest_film_side(-1.0, q, x0, f.pad_length, f.clearance, rod_length, trig)
        if xi2 < xi:
            xi, x_c, edge, side = xi2, x_c2, edge2, -1.0
    return xi, x_c, edge, side


def thinnest_film(q, x0, pad_length, clearance, rod_length, samples=None):
    """:func:`thinnest_film_side` of the film ``H/2 - u2`` with ``samples`` points (default ``16 + 4 N``)."""
    q = np.asarray(q, dtype=float)
    Xs = np.linspace(0.0, pad_length, samples or 16 + 4 * q.shape[-1])
    bX = np.outer(wavenumbers(q.shape[-1], rod_length), Xs)
    return thinnest_film_side(1.0, q, x0, pad_length, clearance, rod_length, np.stack([np.sin(bX), np.cos(bX)]))


@jitable
def approach_velocity(q, q_dot, x_c, V_c, rod_length):
    """Normal velocity at which the link closes the gap at ``x_c`` [m/s], positive closing.

    ``v_c = u2_dot(x_c) + u2'(x_c) V_c`` where ``V_c`` is the velocity of the contact point along
    the link: the collar velocity ``V_r`` when ``x_c`` is a pad edge (the collar corner slides
    over the sloped link), 0 at an interior extremum (where ``u2' = 0`` anyway). It is minus the
    rate of the thinnest film (the envelope of the film over the pad).
    """
    v = 0.0
    for n in range(q.shape[0]):
        b = wavenumber(n + 1, rod_length)
        v += np.sin(b * x_c) * q_dot[n] + b * np.cos(b * x_c) * q[n] * V_c
    return v


@jitable
def gap_rate(q, q_dot, x_c, at_edge, side, V_r, rod_length):
    """Rate of the thinnest film [m/s]: minus the approach velocity on ``side`` at ``x_c``."""
    return -side * approach_velocity(q, q_dot, x_c, V_r if at_edge else 0.0, rod_length)


@jitable
def gap_rate_bound(q, q_dot, omega_n, omega, V_r, rod_length):
    """A bound of ``|d xi_min/dt|`` [m/s] while the modes keep their present amplitudes.

    Mode ``n`` oscillating freely at ``w_n = sqrt(omega_n^2 - omega^2)`` (the link spinning at
    ``omega`` softens it) has amplitude ``a_n = sqrt(q_n^2 + (q_dot_n / w_n)^2)`` [m], so
    ``|u2_dot| <= sum w_n a_n`` and the slope term of a pad edge sliding at ``V_r`` adds at most
    ``|V_r| sum beta_n a_n``. The film over the pad moves no faster than that (its minimum neither).
    Returns infinity for a mode that does not oscillate (``omega >= omega_n``).
    """
    bound = 0.0
    for n in range(q.shape[0]):
        w2 = omega_n[n] * omega_n[n] - omega * omega
        if w2 <= 0.0:
            return np.inf
        w = np.sqrt(w2)
        a = np.sqrt(q[n] * q[n] + q_dot[n] * q_dot[n] / w2)
        bound += a * (w + abs(V_r) * wavenumber(n + 1, rod_length))
    return bound


@jitable
def restitution_jump(q_dot, x_c, v_minus, restitution, rod_length):
    """Modal velocities after an impact at ``x_c`` [m/s] (docs/model.md section 5, paper Eq. 21).

    ``Delta q_dot_n = -(1 + e) v_c^- s_n / sum_m s_m^2`` with ``s_n = sin(beta_n x_c)``: Newton's
    law ``v_c^+ = -e v_c^-`` at the contact point with the impulse-consistent (equal modal
    masses: minimum-norm) jump; the displacements do not jump.

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
    N = q_dot.shape[0]
    s = np.sin(wavenumbers(N, rod_length) * x_c)
    return q_dot - (1.0 + restitution) * v_minus * s / np.sum(s * s)


@jitable
def impact_energy_loss(v_minus, x_c, restitution, modes, mass, rod_length):
    """Energy lost in one impact at an interior contact [J]: ``(1 - e^2)/2 * m / sum s_m^2 * (v_c^-)^2``.

    ``mass`` is the modal mass ``rho A L / 2`` [kg]. It holds where ``u2'(x_c) = 0`` (an
    interior extremum of the film) only; at a pad edge see :func:`impact_energy_change`.
    """
    s = np.sin(wavenumbers(modes, rod_length) * x_c)
    return 0.5 * (1.0 - restitution**2) * mass / np.sum(s * s) * v_minus**2


@jitable
def impact_energy_change(v_minus, slope_velocity, x_c, restitution, modes, mass, rod_length):
    """Change of the link's vibration energy in one impact [J], at any contact point.

    ``Delta E = -(1 - e^2)/2 m_eff v^2 + (1 + e) m_eff v w`` with ``m_eff = m / sum s_m^2``,
    ``v = v_c^-`` the approach velocity and ``w = side u2'(x_c) V_c`` [m/s] its part due to the
    contact point sliding along the sloped link (``V_c = V_r`` at a pad edge, 0 inside the pad).
    The first term is the loss at an interior contact (:func:`impact_energy_loss`); the second
    is the work of the impulse ``(1 + e) m_eff v`` through the link's own normal velocity
    ``v - w`` instead of ``v``: at a pad edge the sliding collar drives the approach, and the
    link gains energy when ``w > (1 - e) v / 2``.
    """
    s = np.sin(wavenumbers(modes, rod_length) * x_c)
    m_eff = mass / np.sum(s * s)
    return -0.5 * (1.0 - restitution**2) * m_eff * v_minus**2 + (1.0 + restitution) * m_eff * v_minus * slope_velocity


@jitable
def constraint_force(q, q_dot, acc, x_c, at_edge, envelope, side, gap, V_r, A_r, rate, mass, rod_length):
    """Contact force of a sustained contact [N] (>= 0 pushes the link away from the collar face).

    The constraint is ``g = xi_min - min_film = 0`` at the contact point ``x_c`` (the thinnest
    film). With ``u2``'s time and space derivatives at ``x_c`` (``u2_t``, ``u2_t'``, ``u2_tt``
    from ``q_dot`` and the accelerations ``acc`` without contact force), the free second
    derivative of the gap is ``g_tt = -side (u2_tt + c)``, where the convective part ``c`` is

    * at a pad edge (``x_c`` moving with the collar, ``dx_c/dt = V_r``):
      ``2 u2_t' V_r + u2'' V_r^2 + u2' A_r``;
    * inside the pad: 0 at a material point; ``-u2_t'^2 / u2''`` if ``envelope`` (``x_c`` the
      film's extremum ``u2' = 0``, which moves at ``-u2_t'/u2''``).

    The force ``lambda`` acts on the modal accelerations as ``-side lambda s_n / m``
    (``s_n = sin(beta_n x_c)``), which adds ``lambda sum s_n^2 / m`` to ``g_tt``. It is the one
    that makes ``g_tt + 2 a g_t + a^2 g = 0`` (Baumgarte's stabilisation, rate ``a = rate`` [1/s],
    which pulls the drift of ``g`` and ``g_t`` back to the constraint):
    ``lambda = m_eff (-(g_tt + 2 a g_t + a^2 g))``, ``m_eff = m / sum s_n^2``.

    Parameters
    ----------
    q, q_dot, acc : ndarray, shape ``(N,)``
        Modal coordinates [m], velocities [m/s] and accelerations without the contact [m/s^2].
    x_c : float
        Contact point [m].
    at_edge : bool
        Whether ``x_c`` is a pad edge.
    envelope : bool
        Inside the pad, whether ``x_c`` follows the film's extremum (else a material point).
    side : float
        Film side (+1, -1).
    gap : float
        ``xi_min - min_film`` [m].
    V_r, A_r : float
        Collar velocity [m/s] and acceleration [m/s^2] relative to the link.
    rate : float
        Baumgarte rate ``a`` [1/s].
    mass : float
        Modal mass [kg].
    rod_length : float
        [m].
    """
    _, d1, d2 = _u2_derivatives(q, x_c, rod_length)
    ut, ut1, _ = _u2_derivatives(q_dot, x_c, rod_length)
    utt = _u2_derivatives(acc, x_c, rod_length)[0]
    if at_edge:
        conv = 2.0 * ut1 * V_r + d2 * V_r * V_r + d1 * A_r
        g_t = -side * (ut + d1 * V_r)
    else:
        conv = -ut1 * ut1 / d2 if envelope and side * d2 < 0.0 else 0.0
        g_t = -side * ut
    g_tt = -side * (utt + conv)
    s2 = 0.0
    for n in range(q.shape[0]):
        sn = np.sin(wavenumber(n + 1, rod_length) * x_c)
        s2 += sn * sn
    return -mass / s2 * (g_tt + 2.0 * rate * g_t + rate * rate * gap)


#: A thinnest film this far below ``contact.min_film`` [-, of ``min_film``] under the restitution law is a penetration.
PENETRATION = 0.1


def penetration(t, film_min, side, min_film) -> str:
    """What a restitution run's samples say of a penetration of the collar ("" when none).

    The restitution law keeps the film at or above ``min_film`` [m]: at an impact, and in a
    sustained contact at the one point where it began. A sample more than :data:`PENETRATION`
    ``min_film`` thinner means the link went through the collar face elsewhere (sustained
    contact, ``side`` non-zero: a known limitation, docs/model.md 5.3) or between two samples of
    the gap (free flight).
    """
    film_min = np.asarray(film_min)
    below = film_min < (1.0 - PENETRATION) * min_film * (1.0 - 1e-9)  # (a run's last sample can be that event itself)
    if not below.any():
        return ""
    i = int(np.argmin(np.where(below, film_min, np.inf)))
    held = np.asarray(side)[below] != 0
    where = ("during a sustained contact, which holds the link at the one point where it began "
             "(docs/model.md 5.3)" if held.all() else "partly in free flight")
    first, n = int(np.argmax(below)), int(below.sum())
    return (f"the thinnest film fell below contact.min_film = {min_film:.3g} m, to {film_min[i]:.3g} m at "
            f"t = {t[i]:.6g} s (first at t = {t[first]:.6g} s, {n} sample{'s' if n > 1 else ''}), {where}: "
            "the link went through the collar face, and the results from there on are not physical; "
            "contact.law = 'compliant' follows the thinnest point")


class Impact(NamedTuple):
    """The record of an impact (or of a compliant contact, from its start to its end).

    ``t`` [s], the contact point ``x_c`` [m], the approach velocities before and after ``v_minus``,
    ``v_plus`` [m/s] (the compliant law: at the start and at the end), the ``side`` (a code of
    :func:`lubelink.link.spatial_model.face_of` for the spatial model), and the link's whole sine-mode
    states ``y_before``, ``y_after`` [m, m/s] (the compliant law: at the start and at the end; None
    while it lasts).
    """

    t: float
    x_c: float
    v_minus: float
    v_plus: float
    side: float
    y_before: np.ndarray
    y_after: np.ndarray | None


@dataclass
class ContactLogic:
    """What happens at a zero of the event: the contact law's response, and the record of impacts.

    :meth:`on_event` is called with the states on both sides of the located zero. It returns
    ``(status, message, t, y, phase)``: ``status`` None to go on from ``(t, y)`` in ``phase``
    ``(side, v_minus)`` (None outside contact: a compliant contact, or a sustained contact of
    the restitution law), or the reason to stop (``"film_breakdown"``, ``"chatter"``, ``"penetration"``).
    ``contacts`` lists ``[t_start, t_end, side]`` of every contact phase (``t_end`` NaN while it lasts).
    A side is +1 or -1, or for the spatial model a code of :func:`lubelink.link.spatial_model.face_of`
    (+-2: the faces normal to ``e3``). ``impacts`` holds an :class:`Impact` per impact (and per
    compliant contact).

    Restitution law: two impacts closer than ``contact.chatter_interval`` are a Zeno sequence;
    the impact is then made plastic (``e = 0``, the gap's rate set to zero) and, if the contact
    force that keeps the link on the collar is positive, a sustained contact begins, which ends
    at the next event (the force falling to zero). ``chatter`` is left for a run whose impacts
    exceed ``max_impacts``, or that meets ``stuck_impacts`` impacts in a row within one
    ``chatter_interval`` without a force to hold the link: several points of the pad striking the
    face at once (with several modes the jump at the thinnest point can close the film at
    another), which one impact at a time does not resolve; the run would otherwise repeat such
    impacts at the same instant up to ``max_impacts`` (7 modes, DOP853: 100,000 impacts, 2 min).
    """

    model: object
    impacts: list = field(default_factory=list)
    contacts: list = field(default_factory=list)
    max_impacts: int = 100_000
    stuck_impacts: int = 100

    def on_event(self, t_before, y_before, t_after, y_after, phase):
        model = self.model
        ct = model.config.contact
        if ct.law == "none":
            where = " on the u3 faces" if abs(model.approach(t_after, y_after)[2]) == 2 else ""  # spatial: +-2
            return ("film_breakdown",
                    f"the film thinned to contact.min_film = {ct.min_film} m{where} at t = {t_after:.9g} s and "
                    "contact.law = 'none'; set contact.law = 'restitution' or 'compliant', or a larger "
                    "film.clearance", t_after, y_after, None)
        if ct.law == "compliant":
            v, x_c, side = model.approach(t_after, y_after)
            if phase is None:  # the film closes: contact from the first state below min_film
                self.impacts.append(Impact(t_after, x_c, v, np.nan, side, np.array(y_after), None))
                self.contacts.append([t_after, np.nan, side])
                return None, "", t_after, y_after, (side, v)
            self.impacts[-1] = self.impacts[-1]._replace(v_plus=v, y_after=np.array(y_after))  # the film reopens
            self.contacts[-1][1] = t_after
            return None, "", t_after, y_after, None
        if phase is not None:  # a sustained contact ends: its force fell to zero, or a second point reached the face
            self.contacts[-1][1] = t_after
            xi = model.thinnest_film(t_after, y_after)[0]
            if xi < (1.0 - PENETRATION) * ct.min_film:
                return ("penetration",
                        f"at t = {t_after:.9g} s the link reached the collar face at a second point of the pad "
                        f"(thinnest film {xi:.3g} m, contact.min_film = {ct.min_film} m) while a sustained contact "
                        f"held it at x = {model.contact_position(t_after, phase):.6g} m: the restitution law holds "
                        "one point (docs/model.md 5.3); contact.law = 'compliant' follows the thinnest point",
                        t_after, y_after, None)
            return None, "", t_after, y_after, None
        # restitution: the jump applies to the last state above min_film, so the gap then opens
        y_plus, x_c, v_minus, side = model.impact(t_before, y_before)
        v_plus = -ct.restitution * v_minus if v_minus > 0 else v_minus
        previous = self.impacts[-1][0] if self.impacts else -np.inf
        self.impacts.append(Impact(t_before, x_c, v_minus, v_plus, side, np.array(y_before), np.array(y_plus)))
        if len(self.impacts) > self.max_impacts:
            return ("chatter",
                    f"more than {self.max_impacts} impacts by t = {t_before:.12g} s, the last two "
                    f"{t_before - previous:.3g} s apart, without a sustained contact (its force stays "
                    "negative); try contact.law = 'compliant'", t_before, y_before, None)
        stuck = self.impacts[-self.stuck_impacts][0] if len(self.impacts) >= self.stuck_impacts else -np.inf
        if t_before - stuck < ct.chatter_interval:
            return ("chatter",
                    f"{self.stuck_impacts} impacts within contact.chatter_interval = {ct.chatter_interval:g} s "
                    f"at t = {t_before:.12g} s, without a sustained contact (its force stays negative): the "
                    "link strikes the collar face at several points at once, which the restitution law, "
                    "one impact at a time, does not resolve; try contact.law = 'compliant'",
                    t_before, y_before, None)
        if t_before - previous < ct.chatter_interval and model.params.galerkin is not None:
            return ("chatter",
                    f"impacts at t = {previous:.12g} s and {t_before:.12g} s are closer than "
                    f"contact.chatter_interval = {ct.chatter_interval:g} s; sustained contact is not "
                    "implemented for a variable section (beam.width_ratio, beam.height_ratio); try "
                    "contact.law = 'compliant'", t_before, y_before, None)
        if t_before - previous < ct.chatter_interval:  # Zeno: ride on the collar if it pushes back
            y_rest = model.impact(t_before, y_before, restitution=0.0)[0]
            point = model.contact_point(t_before, y_before)
            if model.sustained_force(t_before, y_rest, side, point)[0] > 0.0:
                self.impacts[-1] = self.impacts[-1]._replace(v_plus=min(v_minus, 0.0), y_after=np.array(y_rest))
                self.contacts.append([t_before, np.nan, side])
                return None, "", t_before, y_rest, (side, 0.0, point)
        return None, "", t_before, y_plus, None
