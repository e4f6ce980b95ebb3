"""The spatial link of variable section: three Galerkin eigenbases and their right-hand side (docs/spatial.md).

For a section ``A(x)``, ``I_z(x)``, ``I_y(x)`` the sine modes ``s_n = sin(beta_n x)`` of the three
directions are no longer orthogonal. Projecting ``rho A a_d + (stiffness) u_d = f_d`` on them,
with ``a`` the acceleration of :mod:`lubelink.link.spatial` and ``Q = (q1, q2, q3)`` the sine
coordinates of ``(u1, u2, u3)``, every inertia term is ``rho A`` times a displacement times a
function of time only, so all of them project on the one mass matrix ``M``:

    M [Q_tt + 2 w x Q_t + alpha x Q + w x (w x Q)] + K_d Q = F - (A_O r0 + g r1)

    M_mn   = int rho A s_m s_n dx                          (the three directions)
    K1_mn  = int E A s_m' s_n' dx                          (axial, fixed-fixed bar)
    K2_mn  = int E I_z s_m'' s_n'' dx,  K3 likewise with I_y  (bending, pinned-pinned)
    r0_n   = int rho A s_n dx,          r1_n = int rho A x s_n dx

With a free axial end (``beam.axial_end = "free"``) the axial trial functions are the fixed-free
bar's ``psi_n = sin(gamma_n x)`` (:func:`lubelink.link.spatial.free_wavenumbers`): the axial block
has its own ``M11 = int rho A psi psi``, ``K1 = int E A psi' psi'`` and rigid-load vectors, and
its coupling with the bending blocks the mixed mass ``M12 = int rho A psi_m s_n``
(:func:`axial_matrices`); the frame terms then read the other directions projected on each
direction's own functions (:func:`lubelink.link.spatial.coupled_frame_terms`).

(the cross products act on the direction index, ``M`` on the mode index; ``g`` the
:func:`lubelink.link.spatial.axis_acceleration`). Each direction ``d`` is integrated in its own
eigenbasis ``Q_d = Phi_d eta_d``, ``K_d Phi_d = M Phi_d diag(W_d^2)``,
``Phi_d^T M Phi_d = m_ref I`` (:func:`lubelink.link.section.eigenbasis`). Multiplying the equation of
direction ``d`` by ``Phi_d^T / m_ref``, and ``Phi_d^T M / m_ref = Phi_d^-1``:

    eta_d_tt = -W_d^2 eta_d - 2 zeta W_d eta_d_t + Phi_d^T (F_d - A_Od r0 - g_d r1) / m_ref
               - Phi_d^-1 [2 w x Q_t + alpha x Q + w x (w x Q)]_d

the frame terms computed mode by mode on the sine coordinates ``Q = Phi eta`` exactly as for
the uniform link (:func:`lubelink.link.spatial.frame_terms`), then carried into the eigenbasis of
``d`` (the cross-direction blocks are ``Phi_d^-1 Phi_j = Phi_d^T M Phi_j / m_ref``). The linear
part of the state is again ``diag(W^2)``, the ``3 N`` eigenvalues: what the exponential
integrator treats exactly. A uniform link keeps the sine-mode path (:func:`physical` is the
identity, the table is None and the code for it is not compiled).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._jit import jitable
from ..beam import wavenumbers
from . import section
from .spatial import AxialBasis, axial_rigid_load, axis_acceleration, coupled_frame_terms, frame_terms, \
    free_wavenumbers

__all__ = ["SpatialGalerkin", "axial_stiffness", "axial_matrices", "spatial_galerkin", "physical", "state",
           "change_basis", "trial_loads", "eigen_accelerations"]


class SpatialGalerkin(NamedTuple):
    """The three eigenbases of a variable section, for compiled code.

    ``phi`` ``(3, N, N)``: ``Q_d = phi[d] @ eta_d`` (directions axial, in-plane, out-of-plane);
    ``phi_inv`` ``(3, N, N)``: ``eta_d = phi_inv[d] @ Q_d``; ``r0`` [kg], ``r1`` [kg m]: the
    rigid-load vectors of the sine modes (:func:`lubelink.link.section.galerkin_matrices`).
    """

    phi: np.ndarray
    phi_inv: np.ndarray
    r0: np.ndarray
    r1: np.ndarray


def axial_stiffness(sec, youngs_modulus, modes, rod_length):
    """``K1_mn = int E A s_m' s_n' dx`` [N/m] of the sine modes (the fixed-fixed bar), by the quadrature of
    :func:`lubelink.link.section.quadrature`."""
    x, w = section.quadrature(rod_length, modes)
    A = section.sampled(sec, "area", x, rod_length)
    beta = wavenumbers(modes, rod_length)
    D = np.cos(np.outer(x, beta)) * beta  # s_n'(x)
    K = D.T @ ((youngs_modulus * A * w)[:, None] * D)
    return 0.5 * (K + K.T)


def axial_matrices(sec, youngs_modulus, density, modes, rod_length):
    """``(M11 [kg], K1 [N/m], M12 [kg], r0 [kg], r1 [kg m])`` of the fixed-free axial functions
    ``psi_n = sin(gamma_n x)`` (module docstring): ``int rho A psi_m psi_n``, ``int E A psi_m' psi_n'``,
    ``int rho A psi_m s_n`` with the bending sines ``s_n``, ``int rho A psi_n``, ``int rho A x psi_n``, by the
    quadrature of :func:`lubelink.link.section.quadrature`."""
    x, w = section.quadrature(rod_length, modes)
    A = section.sampled(sec, "area", x, rod_length)
    g = free_wavenumbers(modes, rod_length)
    P = np.sin(np.outer(x, g))  # psi_n(x)
    D = np.cos(np.outer(x, g)) * g  # psi_n'(x)
    S = np.sin(np.outer(x, wavenumbers(modes, rod_length)))
    mass = density * A * w
    M11 = P.T @ (mass[:, None] * P)
    K1 = D.T @ ((youngs_modulus * A * w)[:, None] * D)
    return 0.5 * (M11 + M11.T), 0.5 * (K1 + K1.T), P.T @ (mass[:, None] * S), P.T @ mass, P.T @ (mass * x)


def spatial_galerkin(sec, youngs_modulus, density, modes, rod_length, inplane=None, axial_end="fixed"):
    """``(W [rad/s] (3 N,), m_ref [kg], SpatialGalerkin, AxialBasis or None)`` of the section ``sec`` (module
    docstring).

    ``inplane``: the ``(omega_n, m_ref, GalerkinTable)`` of :func:`lubelink.link.section.galerkin_table` for
    ``I_z`` when already computed. ``axial_end``: ``"fixed"`` (the axial functions are the sines; no
    :class:`~lubelink.link.spatial.AxialBasis`) or ``"free"`` (:func:`axial_matrices`). Raises ValueError naming a
    field of ``sec`` that is missing or not positive and finite on ``[0, L]``.
    """
    E, rho, N, L = youngs_modulus, density, modes, rod_length
    w2, m_ref, g2 = section.galerkin_table(sec, E, rho, N, L) if inplane is None else inplane
    w3, _, g3 = section.galerkin_table(sec, E, rho, N, L, moment="second_moment_y")
    M, _, r0, r1 = section.galerkin_matrices(sec, E, rho, N, L)
    c = np.ascontiguousarray
    if axial_end == "fixed":
        M11, axial = M, None
        w1, phi1 = section.eigenbasis(M, axial_stiffness(sec, E, N, L), m_ref)
    else:
        M11, K1, M12, a0, a1 = axial_matrices(sec, E, rho, N, L)
        w1, phi1 = section.eigenbasis(M11, K1, m_ref)
        axial = AxialBasis(c(np.stack([np.linalg.solve(M11, M12), np.linalg.solve(M, M12.T)])), c(np.stack([a0, a1])))
    phi = c(np.stack([phi1, g2.phi, g3.phi]))
    phi_inv = c(np.stack([phi1.T @ M11 / m_ref, g2.phi_inv, g3.phi_inv]))
    return c(np.concatenate([w1, w2, w3])), m_ref, SpatialGalerkin(phi, phi_inv, c(r0), c(r1)), axial


def change_basis(T, y):
    """States ``y`` ``(..., 6 N)`` with the blocks of direction ``d`` (coordinates and velocities) mapped by
    ``T[d]`` ``(N, N)``: the vectorised twin of :func:`physical` (``T = phi``) and :func:`state`."""
    y = np.asarray(y, dtype=float)
    N = T.shape[1]
    return np.concatenate([y[..., k * N:(k + 1) * N] @ T[k % 3].T for k in range(6)], axis=-1)


# --- compiled -----------------------------------------------------------------------------------------------
@jitable
def _transform(T, y):
    """``y`` ``(6 N,)`` with the blocks of direction ``d`` mapped by ``T[d]``."""
    N = T.shape[1]
    out = np.zeros(6 * N)
    for k in range(6):
        d = k % 3
        for n in range(N):
            a = 0.0
            for j in range(N):
                a += T[d, n, j] * y[k * N + j]
            out[k * N + n] = a
    return out


@jitable
def physical(g, y):
    """The sine-mode state ``[Q, Q_t]`` of the integrator's state ``y`` (``y`` itself for a uniform link, ``g`` None;
    with a free axial end, ``Q``'s axial block holds the coordinates of its functions ``psi_n``)."""
    if g is None:
        return y
    return _transform(g.phi, y)


@jitable
def state(g, yq):
    """The integrator's state ``[eta, eta_t]`` of the sine-mode state ``yq`` (inverse of :func:`physical`)."""
    if g is None:
        return yq
    return _transform(g.phi_inv, yq)


@jitable
def trial_loads(g, axial, yq, a_O, w, al, F, f, c):
    """The loads ``f`` [N] and the frame accelerations ``c`` [m/s^2] ``(3 N,)`` on the trial functions (the sines;
    with an :class:`~lubelink.link.spatial.AxialBasis` ``axial``, the free-end axial functions for ``u1``) of the
    state ``yq`` ``(6 N,)`` in their coordinates: ``f = F - A_O r0 - g r1`` with the forces ``F`` [N] on them, ``c``
    the frame terms (module docstring); ``a_O``, ``w``, ``al`` as in :func:`eigen_accelerations`."""
    N = g.r0.shape[0]
    M = 3 * N
    ax = axis_acceleration(w, al)
    for n in range(N):
        i1, i2, i3 = n, N + n, 2 * N + n
        for d in range(3):
            f[d * N + n] = F[d * N + n] - a_O[d] * g.r0[n] - ax[d] * g.r1[n]
        c1, c2, c3 = frame_terms(w, al, (yq[i1], yq[i2], yq[i3]), (yq[M + i1], yq[M + i2], yq[M + i3]))
        c[i1], c[i2], c[i3] = c1, c2, c3
    if axial is not None:
        _free_trial_loads(axial.projection, axial.rigid, yq, a_O[0], ax[0], w, al, F, f, c)


@jitable
def _free_trial_loads(projection, rigid, yq, A1, g1, w, al, F, f, c):
    """The free axial end's terms of :func:`trial_loads` in place of the sines' ones: the axial rigid load
    (:func:`~lubelink.link.spatial.axial_rigid_load`) and the frame terms of
    :func:`~lubelink.link.spatial.coupled_frame_terms`."""
    N = rigid.shape[1]
    for n in range(N):
        f[n] = F[n] + axial_rigid_load(rigid, A1, g1, n)
        c[n], c[N + n], c[2 * N + n] = coupled_frame_terms(projection, w, al, yq, n)


@jitable
def eigen_accelerations(g, y, yq, W, zeta, a_O, w, al, F, m_ref, out, axial=None):
    """``out = d[eta, eta_t]/dt`` (module docstring) [SI].

    ``y``: the eigen-coordinate state ``(6 N,)``; ``yq``: the same state in the coordinates of the trial
    functions (:func:`physical`); ``W`` ``(3 N,)`` the eigenvalues [rad/s]; ``a_O``, ``w``, ``al`` as in
    :func:`lubelink.link.spatial.accelerations`; ``F`` ``(3 N,)`` the sine-mode forces [N] (may alias
    ``out[3N:]``: read fully first); ``m_ref`` [kg]; ``axial`` the free-end axial functions' couplings (None: the
    fixed end).
    """
    N = W.shape[0] // 3
    M = 3 * N
    f = np.empty(M)  # loads [N] of the trial functions
    c = np.empty(M)  # frame accelerations [m/s^2] of the trial functions
    trial_loads(g, axial, yq, a_O, w, al, F, f, c)
    for d in range(3):
        for k in range(N):
            load = 0.0
            frame = 0.0
            for n in range(N):
                load += g.phi[d, n, k] * f[d * N + n]
                frame += g.phi_inv[d, k, n] * c[d * N + n]
            i = d * N + k
            out[M + i] = -W[i] ** 2 * y[i] - 2.0 * zeta * W[i] * y[M + i] + load / m_ref - frame
            out[i] = y[M + i]
