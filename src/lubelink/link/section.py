"""Variable cross-section: the Galerkin system of the sine modes and its eigenbasis (docs/section.md).

For a link of section ``A(x)``, ``I(x)`` the sine modes ``s_n(x) = sin(beta_n x)`` are no longer
orthogonal: the transverse equation ``rho A (u2_tt - omega^2 u2) + (E I u2'')'' = f`` projected on
them gives

    M q_ddot - omega^2 M q + K q = F - A_O2 r0 - alpha r1,
    M_mn = int rho A s_m s_n dx,   K_mn = int E I beta_m^2 beta_n^2 s_m s_n dx,
    r0_n = int rho A s_n dx,       r1_n = int rho A x s_n dx

(``F``: the sine transforms of the film, contact and collar forces, as for the uniform link).
Both matrices are computed by composite Gauss-Legendre quadrature (:func:`galerkin_matrices`).
The integrator's state is the eigen-coordinates ``eta`` of ``K v = w^2 M v``, with
``q = Phi eta`` and ``Phi^T M Phi = m_ref I``, ``Phi^T K Phi = m_ref diag(w_k^2)``, ``m_ref``
the mean modal mass ``int rho A dx / 2`` (so ``eta`` is a length like ``q``, and the absolute
tolerances keep their meaning): every eigen-coordinate is again a damped oscillator with a load,

    eta_ddot_k = -(w_k^2 - omega^2) eta_k - 2 zeta w_k eta_dot_k + [Phi^T (F - A_O2 r0 - alpha r1)]_k / m_ref,

the form the exponential integrator treats exactly. A uniform link needs none of this (its
``Phi`` would be the identity): :func:`galerkin_table` returns None for it and the compiled code
keeps the diagonal sine-mode path.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, NamedTuple

import numpy as np

from .._jit import jitable
from ..beam import curvature, wavenumbers

__all__ = ["Section", "GalerkinTable", "taper", "bending_stress", "galerkin_matrices", "galerkin_table", "physical", "state",
           "eigen_accelerations", "eigen_rate_bound", "eigen_restitution_jump"]


def _profile(spec, name):
    """A vectorised function of ``x`` from a callable or a table ``(x, values)`` (linear interpolation)."""
    if callable(spec):
        return spec
    try:
        xs, vs = (np.asarray(c, dtype=float) for c in spec)
    except (TypeError, ValueError):
        raise ValueError(f"section {name}: must be a callable of x [m] or a table (x, values), got "
                         f"{type(spec).__name__}") from None
    if xs.ndim != 1 or xs.shape != vs.shape or xs.size < 2 or np.any(np.diff(xs) <= 0):
        raise ValueError(f"section {name}: a table needs x and values of the same length >= 2, x increasing")
    return lambda x: np.interp(x, xs, vs)


@dataclass(frozen=True)
class Section:
    """Cross-section along the link: ``area(x)`` [m^2], ``second_moment(x)`` [m^4] (``I_z``: bending in
    the plane, ``u2``) and ``second_moment_y(x)`` [m^4] (``I_y``: bending out of the plane, ``u3``;
    needed by the spatial model only, docs/spatial.md).

    Each is a vectorised callable of ``x`` [m] (``0 <= x <= L``) or a sampled table ``(x, values)``
    (interpolated linearly; it must cover ``[0, L]``).
    """

    area: Callable | tuple
    second_moment: Callable | tuple
    second_moment_y: Callable | tuple | None = None

    def functions(self):
        """``(A, I)`` as vectorised callables."""
        return _profile(self.area, "area"), _profile(self.second_moment, "second_moment")

    def profile(self, name):
        """The vectorised callable of the field ``name`` (``"area"``, ``"second_moment"``, ``"second_moment_y"``).

        Raises ValueError if it is not given (``second_moment_y`` is optional).
        """
        spec = getattr(self, name)
        if spec is None:
            raise ValueError(f"section {name}: not given (None); the spatial model (beam.model = 'spatial') needs "
                             "I_y(x) [m^4], the second moment of area for out-of-plane bending u3, as a callable of "
                             "x [m] or a table (x, values)")
        return _profile(spec, name)


def taper(beam, rod_length) -> Section:
    """The linear taper of ``beam.width_ratio``, ``beam.height_ratio`` (value at ``x = L`` over value at 0).

    Width ``B(x) = B (1 + (r_B - 1) x/L)``, height ``h(x)`` alike; ``A = B h``, ``I_z = B h^3 / 12``,
    ``I_y = h B^3 / 12`` [SI] (the height ``h`` lies in the plane of ``u2``, the width along ``e3``).
    """
    rb = getattr(beam, "width_ratio", 1.0)
    rh = getattr(beam, "height_ratio", 1.0)

    def width(x):
        return beam.width * (1.0 + (rb - 1.0) * np.asarray(x, dtype=float) / rod_length)

    def height(x):
        return beam.height * (1.0 + (rh - 1.0) * np.asarray(x, dtype=float) / rod_length)

    return Section(area=lambda x: width(x) * height(x), second_moment=lambda x: width(x) * height(x) ** 3 / 12.0,
                   second_moment_y=lambda x: height(x) * width(x) ** 3 / 12.0)


def bending_stress(section: Section, youngs_modulus, q, x, rod_length, moment="second_moment"):
    """The largest bending stress in the section [Pa] at ``x`` [m] of the sine-mode coordinates ``q`` [m], shape
    ``(..., N)``: ``E c |u''|`` with ``c = sqrt(3 I / A)`` the outer fibre of a rectangle (``h / 2`` of a ``B`` x
    ``h`` one) for bending with the second moment ``moment`` (``"second_moment"``: in the plane, ``u2``;
    ``"second_moment_y"``: out of it, ``u3``). Shape ``(..., x.size)``."""
    x = np.asarray(x, dtype=float)
    fibre = np.sqrt(3.0 * np.asarray(section.profile(moment)(x), dtype=float)
                    / np.asarray(section.profile("area")(x), dtype=float))
    stress = np.abs(curvature(q, x, rod_length))
    stress *= youngs_modulus * fibre
    return stress


def quadrature(rod_length, modes, nodes=8):
    """Composite Gauss-Legendre nodes and weights on ``[0, L]`` [m]: ``modes + 8`` panels of ``nodes``.

    Each panel spans less than half the shortest wavelength of a product of two modes, so the
    products times a smooth section are integrated to round-off (a uniform link's ``M`` is then
    ``rho A L / 2`` times the identity to 1e-15).
    """
    s, w = np.polynomial.legendre.leggauss(nodes)
    panels = modes + 8
    edges = np.linspace(0.0, rod_length, panels + 1)
    half = 0.5 * np.diff(edges)
    x = (edges[:-1, None] + half[:, None] * (s + 1.0)).ravel()
    return x, (half[:, None] * w).ravel()


def sampled(section: Section, name, x, rod_length):
    """The field ``name`` of ``section`` at the points ``x`` [m]; ValueError unless positive and finite."""
    v = np.asarray(section.profile(name)(x), dtype=float) * np.ones_like(x)
    if not np.all(np.isfinite(v)) or np.any(v <= 0.0):
        bad = ~(np.isfinite(v) & (v > 0))
        raise ValueError(f"section {name}: must be positive and finite on [0, {rod_length}] m; "
                         f"at x = {x[bad][0]:.6g} m it is {v[bad][0]!r}")
    return v


def galerkin_matrices(section: Section, youngs_modulus, density, modes, rod_length, moment="second_moment"):
    """``(M, K, r0, r1)`` of the sine modes (module docstring) [kg, N/m, kg, kg m].

    ``moment``: the field of ``section`` that is ``I`` (``"second_moment_y"``: the out-of-plane
    bending of the spatial model). Raises ValueError if the section is not positive and finite
    on ``[0, L]``.
    """
    x, w = quadrature(rod_length, modes)
    A = sampled(section, "area", x, rod_length)
    I = sampled(section, moment, x, rod_length)
    beta = wavenumbers(modes, rod_length)
    S = np.sin(np.outer(x, beta))  # (nodes, N)
    mass = density * A * w
    M = S.T @ (mass[:, None] * S)
    B2 = S * beta**2
    K = B2.T @ ((youngs_modulus * I * w)[:, None] * B2)
    return 0.5 * (M + M.T), 0.5 * (K + K.T), S.T @ mass, S.T @ (mass * x)


class GalerkinTable(NamedTuple):
    """The eigenbasis of a variable section, for compiled code.

    ``phi`` ``(N, N)``: ``q = phi @ eta``; ``phi_inv``: ``eta = phi_inv @ q`` (``phi^T M / m_ref``);
    ``r0`` [kg], ``r1`` [kg m]: the rigid-load vectors of the sine modes; ``bound_u`` [-],
    ``bound_slope`` [1/m]: ``sum_n |phi_nk|`` and ``sum_n beta_n |phi_nk|`` of each eigenmode
    (bounds of its shape and slope).
    """

    phi: np.ndarray
    phi_inv: np.ndarray
    r0: np.ndarray
    r1: np.ndarray
    bound_u: np.ndarray
    bound_slope: np.ndarray


def eigenbasis(M, K, m_ref):
    """``(w, Phi)``: ``K Phi = M Phi diag(w^2)``, ``Phi^T M Phi = m_ref I``, ``w`` ascending [rad/s].

    By the Cholesky factor of ``M``; each column's largest component is made positive, so that a
    mildly tapered link's eigenmode ``k`` is close to sine mode ``k``.
    """
    C = np.linalg.cholesky(M)
    Ci = np.linalg.inv(C)
    lam, V = np.linalg.eigh(Ci @ K @ Ci.T)
    Phi = Ci.T @ V * np.sqrt(m_ref)
    k = np.argmax(np.abs(Phi), axis=0)
    Phi *= np.sign(Phi[k, np.arange(Phi.shape[1])])
    return np.sqrt(np.maximum(lam, 0.0)), Phi


def galerkin_table(section, youngs_modulus, density, modes, rod_length, moment="second_moment"):
    """``(omega_n [rad/s], m_ref [kg], GalerkinTable)`` of ``section`` (module docstring; ``moment``: that
    of :func:`galerkin_matrices`)."""
    M, K, r0, r1 = galerkin_matrices(section, youngs_modulus, density, modes, rod_length, moment)
    x, w = quadrature(rod_length, modes)
    m_ref = 0.5 * float(np.sum(density * np.asarray(section.functions()[0](x)) * w))
    omega_n, Phi = eigenbasis(M, K, m_ref)
    beta = wavenumbers(modes, rod_length)
    c = np.ascontiguousarray
    table = GalerkinTable(c(Phi), c(Phi.T @ M / m_ref), c(r0), c(r1), c(np.abs(Phi).sum(axis=0)),
                          c((beta[:, None] * np.abs(Phi)).sum(axis=0)))
    return c(omega_n), m_ref, table


# --- compiled: coordinates and the eigen-coordinate right-hand side ----------------------------------------
@jitable
def uniform(g):
    """Whether the link is uniform (no eigenbasis ``g``: its state is the sine modes themselves)."""
    return g is None


@jitable
def _transform(M, y):
    """``[M y[:N], M y[N:]]``: a change of modal basis applied to a state ``[q, q_dot]``."""
    N = M.shape[0]
    out = np.zeros(2 * N)
    for n in range(N):
        a = 0.0
        b = 0.0
        for k in range(N):
            a += M[n, k] * y[k]
            b += M[n, k] * y[N + k]
        out[n] = a
        out[N + n] = b
    return out


@jitable
def physical(g, y):
    """The sine-mode state ``[q, q_dot]`` of the integrator's state ``y`` (``y`` itself for a uniform link)."""
    if g is None:
        return y
    return _transform(g.phi, y)


@jitable
def state(g, yq):
    """The integrator's state ``[eta, eta_dot]`` of the sine-mode state ``yq`` (inverse of :func:`physical`)."""
    if g is None:
        return yq
    return _transform(g.phi_inv, yq)


@jitable
def eigen_accelerations(g, y, F, A_eff, alpha, omega, omega_n, zeta, m_ref, stiffening, out):
    """``out = d[eta, eta_dot]/dt`` from the sine-mode forces ``F`` [N] (module docstring).

    ``F`` may alias ``out[N:]``: it is read fully before ``out`` is written.
    """
    N = g.phi.shape[0]
    f = np.empty(N)
    for n in range(N):
        f[n] = F[n] - A_eff * g.r0[n] - alpha * g.r1[n]
    for k in range(N):
        load = 0.0
        for n in range(N):
            load += g.phi[n, k] * f[n]
        load /= m_ref
        if stiffening:
            load -= 2.0 * omega * omega * y[k]
        out[N + k] = -(omega_n[k] ** 2 - omega**2) * y[k] - 2.0 * zeta * omega_n[k] * y[N + k] + load
        out[k] = y[N + k]


@jitable
def eigen_rate_bound(g, y, omega_n, omega, V_r):
    """A bound of the thinnest film's rate [m/s], as :func:`lubelink.contact.gap_rate_bound`, by eigenmodes.

    Eigenmode ``k`` oscillating freely at ``w_k = sqrt(omega_k^2 - omega^2)`` with amplitude
    ``a_k`` moves ``u2`` no faster than ``w_k a_k sum_n |phi_nk|`` and its slope is at most
    ``a_k sum_n beta_n |phi_nk|``.
    """
    N = g.phi.shape[0]
    bound = 0.0
    for k in range(N):
        w2 = omega_n[k] * omega_n[k] - omega * omega
        if w2 <= 0.0:
            return np.inf
        a = np.sqrt(y[k] * y[k] + y[N + k] * y[N + k] / w2)
        bound += a * (np.sqrt(w2) * g.bound_u[k] + abs(V_r) * g.bound_slope[k])
    return bound


@jitable
def eigen_restitution_jump(g, q_dot, x_c, v_minus, restitution, rod_length):
    """Sine-mode velocities after an impact at ``x_c`` [m/s] for a variable section.

    Newton's law ``v_c^+ = -e v_c^-`` with the impulse-consistent jump: in eigen-coordinates
    (equal modal masses ``m_ref``) ``Delta eta_dot = -(1 + e) v_c^- c / |c|^2``, ``c = Phi^T s``,
    ``s_n = sin(beta_n x_c)``; that is ``Delta q_dot = -(1 + e) v_c^- M^-1 s / (s^T M^-1 s)``.
    """
    N = q_dot.shape[0]
    s = np.sin(wavenumbers(N, rod_length) * x_c)
    c = g.phi.T @ s
    d_eta = -(1.0 + restitution) * v_minus * c / np.sum(c * c)
    return q_dot + g.phi @ d_eta
