"""The spatial link (paper Eqs. 10-12, corrected; docs/spatial.md): modal equations of a uniform link.

The link moves in space with the rigid motion of its frame ``(O; e1, e2, e3)``, ``e1`` along the
link: angular velocity ``w`` and acceleration ``alpha``, true acceleration of O ``a_O``, all three
in link-frame components. Bending ``u2`` (in the ``e1 e2`` plane, stiffness ``E I_z``) and ``u3``
(``E I_y``) are expanded in the pinned-pinned sine modes ``sin(beta_n x)``; the axial ``u1`` in the
modes of the bar with the end condition ``beam.axial_end`` (docs/spatial.md, "Boundary
conditions"): ``"fixed"``, ``u1(0) = u1(L) = 0``, the same sines; ``"free"``, ``u1(0) = 0`` and no
axial force at ``L`` (the slider), ``sin(gamma_n x)``, ``gamma_n = (2 n - 1) pi / (2 L)``
(:func:`free_wavenumbers`). The acceleration of a material point,
``a = a_O + alpha x r + w x (w x r) + 2 w x r_t + r_tt`` with ``r = (x + u1, u2, u3)``, is then
projected on the modes. With the fixed end every term couples only the three coordinates of the
same mode ``n``, ``Q = (q1_n, q2_n, q3_n)``:

    Q_tt + 2 w x Q_t + alpha x Q + w x (w x Q) + diag(W_n^2) Q + 2 zeta diag(W_n) Q_t
        = - [a_O c0_n + (alpha x e1 + w x (w x e1)) c1_n] + F_n / m

``W_n = (beta_n sqrt(E/rho), beta_n^2 sqrt(E I_z/(rho A)), beta_n^2 sqrt(E I_y/(rho A)))``,
``c0_n``, ``c1_n`` the sine transforms of 1 and ``x`` per unit modal mass ``m = rho A L / 2``
(:func:`lubelink.beam.rigid_load`), ``F_n`` the modal forces [N] (film on the ``u2`` faces).
With the free end the axial modes are ``gamma_n sqrt(E/rho)``, their rigid load the transforms of
:class:`AxialBasis`, and a frame term of one direction reads the other directions' displacements
projected on its own basis (:func:`coupled_frame_terms`: the matrix ``C`` of :func:`free_axial_basis`
from the bending sines to the axial modes, ``C^T`` back).
The planar motion ``w = (0, 0, omega)``, ``alpha = (0, 0, alpha)`` leaves ``u3 = 0`` and differs
from the planar model (docs/model.md section 2) only by ``2 omega u1_t + alpha u1`` projected on
the ``u2`` modes (the axial-bending Coriolis and Euler terms) and by the axial equation itself.

State ``y = [q1_1..q1_N, q2_1..q2_N, q3_1..q3_N, and their velocities]``: 3N oscillators with the
diagonal linear part ``diag(W^2)`` of :func:`frequencies` (the exponential integrator's form).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._jit import jitable
from ..beam import rigid_load, wavenumbers

__all__ = ["SpatialRigidMotion", "AxialBasis", "free_wavenumbers", "axial_wavenumbers", "free_axial_basis",
           "frequencies", "axis_acceleration", "rigid_loads", "axial_rigid_load", "frame_terms", "coupled_frame_terms",
           "accelerations", "oscillator_jacobian", "deflections"]


class AxialBasis(NamedTuple):
    """The free-end axial modes ``psi_n`` for compiled code (``beam.axial_end = "free"``; the fixed end has none:
    its axial modes are the bending sines themselves). Two arrays (each array a compiled call passes costs
    reference counts):

    ``projection`` ``(2, N, N)``: ``[0]`` the axial coordinates of the Galerkin projection of a field given in the
    bending sine coordinates, ``M11^-1 M12`` (``M11_mn = int rho A psi_m psi_n dx``,
    ``M12_mn = int rho A psi_m s_n dx``, ``s_n = sin(beta_n x)``); ``[1]`` the sine coordinates of the projection of
    an axial field, ``M22^-1 M21``. ``rigid`` ``(2, N)``: ``int rho A psi_n dx`` [kg] and ``int rho A x psi_n dx``
    [kg m], the rigid-load vectors of the axial modes.
    """

    projection: np.ndarray
    rigid: np.ndarray


def free_wavenumbers(modes, rod_length):
    """``gamma_n = (2 n - 1) pi / (2 L)`` [1/m], ``n = 1..modes``: the fixed-free bar's modes ``sin(gamma_n x)``
    (``u1(0) = 0``, ``u1'(L) = 0``)."""
    return (2.0 * np.arange(1, modes + 1) - 1.0) * np.pi / (2.0 * rod_length)


def axial_wavenumbers(modes, rod_length, axial_end):
    """Wavenumbers [1/m] of the axial modes ``sin(k_n x)`` of the end condition ``axial_end``: ``"fixed"``
    ``n pi / L`` (:func:`lubelink.beam.wavenumbers`), ``"free"`` :func:`free_wavenumbers`."""
    if axial_end == "fixed":
        return wavenumbers(modes, rod_length)
    if axial_end == "free":
        return free_wavenumbers(modes, rod_length)
    raise ValueError(f"axial_end = {axial_end!r}: must be 'fixed' or 'free'")


def free_axial_basis(modes, rod_length, linear_density):
    """The :class:`AxialBasis` of a uniform link [SI] (``linear_density`` ``rho A`` [kg/m]), in closed form.

    ``psi_m = sin(gamma_m x)`` and ``s_n = sin(beta_n x)`` both have the mass ``rho A L / 2``, so the
    projections are ``C`` and ``C^T`` with ``C_mn = (2/L) int_0^L psi_m s_n dx
    = (1/L) [sin((gamma_m - beta_n) L) / (gamma_m - beta_n) - sin((gamma_m + beta_n) L) / (gamma_m + beta_n)]``
    (``gamma_m != beta_n`` always); ``r0_n = rho A / gamma_n``, ``r1_n = rho A (-1)^(n+1) / gamma_n^2``
    (``cos(gamma_n L) = 0``, ``sin(gamma_n L) = (-1)^(n+1)``).
    """
    g = free_wavenumbers(modes, rod_length)
    b = wavenumbers(modes, rod_length)
    minus, plus = g[:, None] - b[None, :], g[:, None] + b[None, :]
    C = (np.sin(minus * rod_length) / minus - np.sin(plus * rod_length) / plus) / rod_length
    sign = 1.0 - 2.0 * ((np.arange(1, modes + 1) + 1) % 2)  # (-1)^(n+1)
    return AxialBasis(np.ascontiguousarray(np.stack([C, C.T])), np.stack([linear_density / g,
                                                                          linear_density * sign / g**2]))


def frequencies(modes, rod_length, youngs_modulus, density, area, I_z, I_y, axial_end="fixed"):
    """``[axial, in-plane, out-of-plane]`` natural frequencies [rad/s], shape ``(3 N,)``.

    Axial: the bar ``k_n sqrt(E / rho)`` with ``k_n`` the :func:`axial_wavenumbers` of ``axial_end``
    (fixed-fixed ``n pi / L``, fixed-free ``(2 n - 1) pi / (2 L)``); bending ``beta_n^2 sqrt(E I / (rho A))``.
    """
    beta = wavenumbers(modes, rod_length)
    return np.concatenate([axial_wavenumbers(modes, rod_length, axial_end) * np.sqrt(youngs_modulus / density),
                           beta**2 * np.sqrt(youngs_modulus * I_z / (density * area)),
                           beta**2 * np.sqrt(youngs_modulus * I_y / (density * area))])


@jitable(inline=True)
def axis_acceleration(w, al):
    """``g = alpha x e1 + w x (w x e1) = (-(w2^2 + w3^2), alpha3 + w1 w2, w1 w3 - alpha2)``: the acceleration
    of the point ``x e1`` per unit ``x`` [1/s^2], a 3-tuple."""
    return (-(w[1] * w[1] + w[2] * w[2]), al[2] + w[0] * w[1], w[0] * w[2] - al[1])


@jitable
def rigid_loads(a_O, w, al, n, rod_length):
    """Modal load of the rigid-motion inertia per unit modal mass, mode ``n``, directions 1-3 [m/s^2].

    ``-(a_O c0_n + g c1_n)`` with ``g`` the :func:`axis_acceleration`.
    """
    g1, g2, g3 = axis_acceleration(w, al)
    return (rigid_load(a_O[0], g1, n, rod_length), rigid_load(a_O[1], g2, n, rod_length),
            rigid_load(a_O[2], g3, n, rod_length))


@jitable(inline=True)
def axial_rigid_load(rigid, A1, g1, n):
    """Load [N] of the rigid-motion inertia ``-rho A (A1 + g1 x)`` on the free-end axial mode ``n`` (from 0):
    ``-(A1 r0_n + g1 r1_n)`` (``rigid = [r0, r1]``, :class:`AxialBasis` ``.rigid``; ``A1`` [m/s^2], ``g1`` the axial
    :func:`axis_acceleration` [1/s^2])."""
    return -(A1 * rigid[0, n] + g1 * rigid[1, n])


@jitable(inline=True)
def frame_terms(w, al, x, v):
    """``2 w x v + alpha x x + w x (w x x)`` [m/s^2], a 3-tuple: the Coriolis, Euler and centrifugal
    accelerations of a displacement ``x`` [m] moving at ``v`` [m/s] relative to the link frame (3-tuples
    of one mode's coordinates, the same in every basis the mass matrix is common to)."""
    w1, w2, w3 = w[0], w[1], w[2]
    # w x (w x x) = w (w . x) - |w|^2 x
    wq = w1 * x[0] + w2 * x[1] + w3 * x[2]
    ww = w1 * w1 + w2 * w2 + w3 * w3
    return (2.0 * (w2 * v[2] - w3 * v[1]) + (al[1] * x[2] - al[2] * x[1]) + (w1 * wq - ww * x[0]),
            2.0 * (w3 * v[0] - w1 * v[2]) + (al[2] * x[0] - al[0] * x[2]) + (w2 * wq - ww * x[1]),
            2.0 * (w1 * v[1] - w2 * v[0]) + (al[0] * x[1] - al[1] * x[0]) + (w3 * wq - ww * x[2]))


@jitable(inline=True)
def coupled_frame_terms(T, w, al, y, n):
    """:func:`frame_terms` [m/s^2] of mode ``n`` (from 0) of the state ``y`` ``(6 N,)`` whose axial block holds the
    coordinates of the free-end modes, a 3-tuple; ``T`` their projections (:class:`AxialBasis` ``.projection``).

    Each direction's term is the Galerkin projection on its own modes: the axial one reads the bending
    coordinates projected on the axial modes (``T[0]``), the bending ones the axial coordinates projected on the
    sines (``T[1]``); the same-basis couplings stay mode by mode. (The arrays, not the table: a loop that calls it
    reads them once.)
    """
    N = T.shape[1]
    M = 3 * N
    x2 = x3 = v2 = v3 = x1 = v1 = 0.0
    for k in range(N):
        P = T[0, n, k]
        x2 += P * y[N + k]
        x3 += P * y[2 * N + k]
        v2 += P * y[M + N + k]
        v3 += P * y[M + 2 * N + k]
        S = T[1, n, k]
        x1 += S * y[k]
        v1 += S * y[M + k]
    c1 = frame_terms(w, al, (y[n], x2, x3), (y[M + n], v2, v3))[0]
    c = frame_terms(w, al, (x1, y[N + n], y[2 * N + n]), (v1, y[M + N + n], y[M + 2 * N + n]))
    return c1, c[1], c[2]


@jitable
def _subtract_block(Jq, Jv, row, col, cx, cv, P):
    """``Jq[row block, col block] -= cx P``, ``Jv[...] -= cv P`` (``N x N`` blocks; ``P`` None: the identity)."""
    N = Jq.shape[0] // 3
    if P is None:
        for n in range(N):
            Jq[row + n, col + n] -= cx
            Jv[row + n, col + n] -= cv
    else:
        for n in range(N):
            for k in range(N):
                Jq[row + n, col + k] -= cx * P[n, k]
                Jv[row + n, col + k] -= cv * P[n, k]


@jitable
def oscillator_jacobian(W, zeta, w, al, Jq, Jv, axial=None):
    """Add ``d Q_tt / d Q`` and ``d Q_tt / d Q_t`` [1/s^2, 1/s] of :func:`accelerations` without its loads to ``Jq``,
    ``Jv`` ``(3 N, 3 N)``: the oscillators ``-W^2``, ``-2 zeta W`` on the diagonals and the link frame's
    accelerations of each mode's three coordinates (``axial`` an :class:`AxialBasis`: between the axial and the
    bending blocks, those of :func:`coupled_frame_terms`).

    :func:`frame_terms` is linear in the displacement and its velocity, so its columns are its values at unit
    vectors: the Jacobian of the very function the right-hand side calls.
    """
    N = W.shape[0] // 3
    zero = (0.0, 0.0, 0.0)
    for e in range(3):
        unit = (1.0 if e == 0 else 0.0, 1.0 if e == 1 else 0.0, 1.0 if e == 2 else 0.0)
        cx = frame_terms(w, al, unit, zero)
        cv = frame_terms(w, al, zero, unit)
        for d in range(3):
            if axial is None:
                _subtract_block(Jq, Jv, d * N, e * N, cx[d], cv[d], None)
            elif d == 0 and e != 0:
                _subtract_block(Jq, Jv, d * N, e * N, cx[d], cv[d], axial.projection[0])
            elif e == 0 and d != 0:
                _subtract_block(Jq, Jv, d * N, e * N, cx[d], cv[d], axial.projection[1])
            else:
                _subtract_block(Jq, Jv, d * N, e * N, cx[d], cv[d], None)
    for i in range(3 * N):
        Jq[i, i] -= W[i] * W[i]
        Jv[i, i] -= 2.0 * zeta * W[i]


@jitable(inline=True)
def _mode_acceleration(W, zeta, F, modal_mass, i, x, v, r, c):
    """Acceleration [m/s^2] of coordinate ``i`` at ``x`` [m], ``v`` [m/s]: its oscillator (``W`` [rad/s], ``zeta``), its
    force ``F[i]`` [N] per modal mass [kg], the rigid load ``r`` and the frame term ``c`` [m/s^2]."""
    return -W[i] ** 2 * x - 2.0 * zeta * W[i] * v + F[i] / modal_mass + r - c


@jitable
def accelerations(y, W, zeta, a_O, w, al, F, modal_mass, rod_length, out, axial=None):
    """``out = dy/dt`` of the spatial modal equations (module docstring) [SI].

    Parameters
    ----------
    y : ndarray, shape ``(6 N,)``
        ``[q1, q2, q3, q1_t, q2_t, q3_t]`` [m, m/s].
    W : ndarray, shape ``(3 N,)``
        Natural frequencies of :func:`frequencies` [rad/s].
    zeta : float
        Modal damping ratio [-].
    a_O, w, al : sequences of 3 floats
        True acceleration of O [m/s^2], angular velocity [rad/s] and acceleration [rad/s^2] of
        the link frame, in its components.
    F : ndarray, shape ``(3 N,)``
        Modal forces [N] along ``e1``, ``e2``, ``e3`` (may alias ``out[3N:]``: read first).
    modal_mass : float
        ``rho A L / 2`` [kg].
    axial : AxialBasis or None
        The free-end axial modes (``y``'s axial block their coordinates); None: the fixed end's sines.
    """
    if axial is not None:
        _free_accelerations(axial.projection, axial.rigid, y, W, zeta, a_O, w, al, F, modal_mass, rod_length, out)
        return
    N = W.shape[0] // 3
    M = 3 * N
    for n in range(N):
        i1, i2, i3 = n, N + n, 2 * N + n
        x1, x2, x3 = y[i1], y[i2], y[i3]
        v1, v2, v3 = y[M + i1], y[M + i2], y[M + i3]
        r1, r2, r3 = rigid_loads(a_O, w, al, n + 1, rod_length)
        c1, c2, c3 = frame_terms(w, al, (x1, x2, x3), (v1, v2, v3))
        out[M + i1] = _mode_acceleration(W, zeta, F, modal_mass, i1, x1, v1, r1, c1)
        out[M + i2] = _mode_acceleration(W, zeta, F, modal_mass, i2, x2, v2, r2, c2)
        out[M + i3] = _mode_acceleration(W, zeta, F, modal_mass, i3, x3, v3, r3, c3)
        out[i1] = v1
        out[i2] = v2
        out[i3] = v3


@jitable
def _free_accelerations(projection, rigid, y, W, zeta, a_O, w, al, F, modal_mass, rod_length, out):
    """:func:`accelerations` with the free-end axial modes (:class:`AxialBasis` ``projection``, ``rigid``): the axial
    rigid load of :func:`axial_rigid_load`, the frame terms of :func:`coupled_frame_terms`."""
    N = W.shape[0] // 3
    M = 3 * N
    g1 = axis_acceleration(w, al)[0]
    for n in range(N):
        i1, i2, i3 = n, N + n, 2 * N + n
        r2, r3 = rigid_loads(a_O, w, al, n + 1, rod_length)[1:]
        r1 = axial_rigid_load(rigid, a_O[0], g1, n) / modal_mass
        c1, c2, c3 = coupled_frame_terms(projection, w, al, y, n)
        out[M + i1] = _mode_acceleration(W, zeta, F, modal_mass, i1, y[i1], y[M + i1], r1, c1)
        out[M + i2] = _mode_acceleration(W, zeta, F, modal_mass, i2, y[i2], y[M + i2], r2, c2)
        out[M + i3] = _mode_acceleration(W, zeta, F, modal_mass, i3, y[i3], y[M + i3], r3, c3)
    for i in range(M):
        out[i] = y[M + i]


def deflections(y, x, rod_length, axial_end="fixed"):
    """``(u1, u2, u3)`` [m] at ``x`` of states ``y`` shape ``(..., 6 N)``; each shape ``(..., len(x))``.

    ``u1`` in the axial modes of ``axial_end`` (:func:`axial_wavenumbers`), ``u2``, ``u3`` in the sines.
    """
    y = np.asarray(y, dtype=float)
    N = y.shape[-1] // 6
    x = np.asarray(x, dtype=float)
    S = np.sin(np.outer(wavenumbers(N, rod_length), x))
    S1 = S if axial_end == "fixed" else np.sin(np.outer(axial_wavenumbers(N, rod_length, axial_end), x))
    return (y[..., :N] @ S1, y[..., N:2 * N] @ S, y[..., 2 * N:3 * N] @ S)


@jitable
def _v3(a):
    """The 3-tuple of floats of a sequence of 3 numbers."""
    return (float(a[0]), float(a[1]), float(a[2]))


@jitable
def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@jitable
def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@jitable
def _lin(ca, a, cb, b):
    """``ca a + cb b`` of two 3-tuples."""
    return (ca * a[0] + cb * b[0], ca * a[1] + cb * b[1], ca * a[2] + cb * b[2])


@jitable
def _lin3(ca, a, cb, b, cc, c):
    """``ca a + cb b + cc c`` of three 3-tuples."""
    return (ca * a[0] + cb * b[0] + cc * c[0], ca * a[1] + cb * b[1] + cc * c[1], ca * a[2] + cb * b[2] + cc * c[2])


@jitable
def _frame(a, e1, e2, e3):
    """Components ``(a . e1, a . e2, a . e3)`` of ``a`` in the frame ``e``."""
    return (_dot(a, e1), _dot(a, e2), _dot(a, e3))


class SpatialRigidMotion(NamedTuple):
    """Rigid motion of the spatial link at one time (or at samples: arrays over time in front).

    The layout of the planar :class:`~lubelink.link.kinematics.RigidMotion`: ``omega``, ``alpha``,
    ``x_star``, ``V_r`` at positions 1-4.

    Attributes
    ----------
    A_O : 3-tuple
        True acceleration of O, link-frame components [m/s^2].
    omega, alpha : 3-tuple
        Angular velocity [rad/s] and acceleration [rad/s^2] of the link frame, link-frame components.
    x_star : float
        Collar position along the link, from O [m].
    V_r : float
        Collar velocity relative to the link, along ``e1`` [m/s].
    e1, e2, e3 : 3-tuple
        The link frame in fixed components [-].
    v_O : 3-tuple
        Velocity of O, link-frame components [m/s] (NaN for a motion given as samples or callables).
    O : 3-tuple
        Position of O in the fixed frame [m] (NaN as ``v_O``).
    """

    A_O: tuple
    omega: tuple
    alpha: tuple
    x_star: float
    V_r: float
    e1: tuple
    e2: tuple
    e3: tuple
    v_O: tuple
    O: tuple


@jitable
def rssp_tuples(t, crank_length, rod_length, crank_speed, guide, crank_axis, crank_ref, slider_point, slider_dir):
    """:func:`slider_crank_rssp` with every vector a 3-tuple of floats (the form compiled callers use: no allocation):
    a :class:`SpatialRigidMotion`."""
    k = _v3(crank_axis)
    a = _v3(crank_ref)
    P = _v3(slider_point)
    d = _v3(slider_dir)
    b = _cross(k, a)
    phi = crank_speed * float(t)
    c, s_ = math.cos(phi), math.sin(phi)
    O = _lin(crank_length * c, a, crank_length * s_, b)
    O_t = _lin(-crank_length * crank_speed * s_, a, crank_length * crank_speed * c, b)
    O_tt = _lin(-crank_speed * crank_speed, O, 0.0, O)
    p = _lin(1.0, P, -1.0, O)
    dp = _dot(d, p)
    disc = dp * dp - _dot(p, p) + rod_length * rod_length  # < 0: the slider is out of reach (s = nan)
    s = -dp + (math.sqrt(disc) if disc >= 0.0 else math.nan)
    g = _lin3(1.0, P, s, d, -1.0, O)
    gd = _dot(g, d)
    s_t = _dot(g, O_t) / gd
    g_t = _lin(s_t, d, -1.0, O_t)
    s_tt = (_dot(g, O_tt) - _dot(g_t, g_t)) / gd
    g_tt = _lin(s_tt, d, -1.0, O_tt)
    e1 = _lin(1.0 / rod_length, g, 0.0, g)
    e1_t = _lin(1.0 / rod_length, g_t, 0.0, g_t)
    e1_tt = _lin(1.0 / rod_length, g_tt, 0.0, g_tt)
    ke, ke_t, ke_tt = _dot(k, e1), _dot(k, e1_t), _dot(k, e1_tt)
    v = _lin(1.0, k, -ke, e1)
    v_t = _lin(-ke_t, e1, -ke, e1_t)
    v_tt = _lin3(-ke_tt, e1, -2.0 * ke_t, e1_t, -ke, e1_tt)
    nu = math.sqrt(_dot(v, v))
    e3 = _lin(1.0 / nu, v, 0.0, v)
    nu_t = _dot(e3, v_t)
    e3_t = _lin(1.0 / nu, v_t, -nu_t / nu, e3)
    nu_tt = _dot(e3_t, v_t) + _dot(e3, v_tt)
    e3_tt = _lin3(1.0 / nu, v_tt, -2.0 * nu_t / nu, e3_t, -nu_tt / nu, e3)
    e2 = _cross(e3, e1)
    e2_t = _lin(1.0, _cross(e3_t, e1), 1.0, _cross(e3, e1_t))
    e2_tt = _lin3(1.0, _cross(e3_tt, e1), 2.0, _cross(e3_t, e1_t), 1.0, _cross(e3, e1_tt))
    # e_i_t = w x e_i:  w1 = e2_t . e3, w2 = e3_t . e1, w3 = e1_t . e2; alpha = their derivatives
    w = (_dot(e2_t, e3), _dot(e3_t, e1), _dot(e1_t, e2))
    alpha = (_dot(e2_tt, e3) + _dot(e2_t, e3_t), _dot(e3_tt, e1) + _dot(e3_t, e1_t),
             _dot(e1_tt, e2) + _dot(e1_t, e2_t))
    A_O = _frame(O_tt, e1, e2, e3)
    v_O = _frame(O_t, e1, e2, e3)
    num = guide - _dot(d, O)
    den = _dot(d, e1)
    x_star = num / den
    V_r = (-_dot(d, O_t) * den - num * _dot(d, e1_t)) / (den * den)
    return SpatialRigidMotion(A_O, w, alpha, x_star, V_r, e1, e2, e3, v_O, O)


def slider_crank_rssp(t, crank_length, rod_length, crank_speed, guide, crank_axis, crank_ref, slider_point,
                      slider_dir):
    """Closed-form kinematics of the spatial slider-crank (RSSP) at time ``t`` [s] (docs/spatial.md).

    The crank (revolute about the unit ``crank_axis`` through the origin, length ``r``) carries the
    link end O, ``O = r (cos phi a + sin phi b)``, ``phi = crank_speed t``, ``a = crank_ref``
    (unit, normal to the axis), ``b = axis x a``. The link ``OC`` (spherical joints, length ``L``)
    ends at the slider ``C = P + s d`` (``P = slider_point``, unit ``d = slider_dir``), ``s`` the
    larger root of ``|C - O| = L``. Link frame: ``e1 = (C - O)/L``; the spin of an S-S link about
    its own axis is idle, so ``e3`` is fixed by convention as the normalised part of the crank axis
    normal to ``e1`` (the planar frame when the axis is normal to the slider line), ``e2 = e3 x e1``.
    The collar is where the link crosses the guide plane ``d . p = guide``.

    Returns
    -------
    SpatialRigidMotion
        Its vectors NumPy arrays; compiled callers use :func:`rssp_tuples`, the same values as 3-tuples.
    """
    k = rssp_tuples(t, crank_length, rod_length, crank_speed, guide, crank_axis, crank_ref, slider_point, slider_dir)
    return SpatialRigidMotion(*(v if isinstance(v, float) else np.array(v) for v in k))
