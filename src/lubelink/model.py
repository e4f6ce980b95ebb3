"""The modal ODE right-hand side assembled from the physics modules.

State ``y = [q_1..q_N, q_dot_1..q_dot_N]``. The right-hand side is the
corrected modal equation of MODEL.md section 2:

    q_ddot_n = -(omega_n^2 - omega^2) q_n - 2 zeta omega_n q_dot_n
               - 2/(L beta_n) {(A_O2 - g_j) [1 + (-1)^(n+1)] + alpha L (-1)^(n+1)}
               + (F_n^film + F_n^contact + R sin(beta_n x_star)) / (rho A L / 2)

``g_j`` is gravity along the link's ``j`` axis (zero unless configured).
A side ``s = +1`` is the film at ``H/2 - u2`` (the paper's), ``s = -1`` the
film at ``H/2 + u2`` of a collar that encloses the link; every one-sided
function is applied to the mirrored state ``s q`` and its result mirrored
back.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import beam, contact, film
from .kinematics import SliderCrank
from .params import Config

__all__ = ["Model", "build_model", "ContactPhase"]


@dataclass
class ContactPhase:
    """A compliant contact in progress: which side, and its approach velocity [m/s]."""

    side: int
    v_minus: float


@dataclass(frozen=True)
class Model:
    """Everything the integrator and the event logic need, precomputed."""

    config: Config
    motion: object
    omega_n: np.ndarray
    modal_mass: float

    @property
    def modes(self) -> int:
        return self.config.beam.modes

    @property
    def sides(self) -> tuple:
        return (1, -1) if self.config.film.sides == 2 else (1,)

    def initial_state(self):
        """Zero initial conditions (the paper's)."""
        return np.zeros(2 * self.modes)

    def gravity_j(self, t):
        """Gravity along the link's ``j`` axis [m/s^2] at ``t``."""
        gX, gY = self.config.mechanism.gravity
        if gX == 0.0 and gY == 0.0:
            return 0.0
        psi = self.motion.link_angle(t)  # link angle about +k from +X
        return -gX * np.sin(psi) + gY * np.cos(psi)

    def film_loads(self, t, y, kin=None):
        """Modal film force [N] and resultant film force along +j [N]."""
        cfg = self.config
        fm = cfg.film
        N = self.modes
        if not fm.enabled:
            return np.zeros(N), 0.0
        kin = self.motion(t) if kin is None else kin
        q, q_dot = y[:N], y[N:]
        x0 = film.pad_start(float(kin.x_star), fm.pad_length, fm.pad_reference)
        F, total = np.zeros(N), 0.0
        for side in self.sides:
            F_s, total_s, _ = film.modal_force(
                side * q, side * q_dot, x0, float(kin.V_r), mu=fm.viscosity, clearance=fm.clearance,
                pad_length=fm.pad_length, width=cfg.beam.width, rod_length=cfg.mechanism.rod_length,
                squeeze=fm.model == "wedge+squeeze", nodes=fm.quadrature_nodes, cavitation=fm.cavitation,
                p_cav=fm.cavitation_pressure - fm.ambient_pressure, grid_points=fm.grid_points)
            F = F + side * F_s
            total += side * total_s
        return F, total

    def contact_force(self, t, y, phase: ContactPhase, kin=None):
        """Modal force [N] and magnitude [N] of the compliant (Lankarani-Nikravesh) contact.

        ``F = K delta^n (1 + 3 (1 - e^2)/4 * delta_dot / v_minus)``, ``delta``
        the penetration below ``min_film``, acting at the thinnest-film point
        against the side's normal; never adhesive (``F >= 0``).
        """
        ct = self.config.contact
        N = self.modes
        L = self.config.mechanism.rod_length
        side = phase.side
        kin = self.motion(t) if kin is None else kin
        xi, x_c, at_edge = self._thinnest(t, side * y[:N], kin)
        delta = ct.min_film - xi
        if delta <= 0.0:
            return np.zeros(N), 0.0
        V_c = float(kin.V_r) if at_edge else 0.0
        delta_dot = contact.approach_velocity(side * y[:N], side * y[N:], x_c, V_c, L)
        force = contact.lankarani_nikravesh(delta, delta_dot, phase.v_minus, ct.stiffness, ct.exponent,
                                            ct.restitution)
        return -side * beam.project_point_load(force, x_c, N, L), force

    def rhs(self, t, y, phase: ContactPhase | None = None):
        """``dy/dt`` of the modal ODE."""
        cfg = self.config
        N = self.modes
        L = cfg.mechanism.rod_length
        kin = self.motion(t)
        F, _ = self.film_loads(t, y, kin)
        if cfg.collar.mass > 0.0:
            R = float(self.motion.joint_reaction(t, cfg.collar.mass))
            F = F + beam.project_point_load(R, float(kin.x_star), N, L)
        if phase is not None:
            F = F + self.contact_force(t, y, phase, kin)[0]
        A_eff = float(kin.A_O2) - self.gravity_j(t)
        forcing = beam.rigid_forcing(A_eff, float(kin.alpha), N, L) + F / self.modal_mass
        q_ddot = beam.modal_acceleration(y[:N], y[N:], self.omega_n, cfg.beam.damping_ratio,
                                         float(kin.omega), forcing)
        return np.concatenate([y[N:], q_ddot])

    def _thinnest(self, t, q_side, kin=None):
        fm = self.config.film
        kin = self.motion(t) if kin is None else kin
        x0 = film.pad_start(float(kin.x_star), fm.pad_length, fm.pad_reference)
        return contact.thinnest_film(q_side, x0, fm.pad_length, fm.clearance, self.config.mechanism.rod_length)

    def thinnest_film(self, t, y):
        """``(xi_min, x_c, at_edge, side)``: the thinnest film over the pad and the sides."""
        q = y[: self.modes]
        best = None
        for side in self.sides:
            xi, x_c, edge = self._thinnest(t, side * q)
            if best is None or xi < best[0]:
                best = (xi, x_c, edge, side)
        return best

    def gap(self, t, y):
        """Event function: film thickness above breakdown, ``xi_min - min_film`` [m]."""
        return self.thinnest_film(t, y)[0] - self.config.contact.min_film

    def approach(self, t, y):
        """``(v, x_c, side)``: normal approach velocity at the thinnest film [m/s], positive closing."""
        N = self.modes
        _, x_c, at_edge, side = self.thinnest_film(t, y)
        V_c = float(self.motion(t).V_r) if at_edge else 0.0
        v = contact.approach_velocity(side * y[:N], side * y[N:], x_c, V_c,
                                      self.config.mechanism.rod_length)
        return v, x_c, side

    def impact(self, t, y):
        """Apply the restitution law at ``t``.

        Returns
        -------
        y_plus : ndarray
            State after the impact.
        x_c : float
            Contact point [m].
        v_minus : float
            Approach velocity before the impact [m/s] (positive closing).
        side : int
            Film side of the contact.
        """
        N = self.modes
        v_minus, x_c, side = self.approach(t, y)
        y_plus = y.copy()
        if v_minus > 0.0:
            y_plus[N:] = side * contact.restitution_jump(side * y[N:], x_c, v_minus,
                                                         self.config.contact.restitution,
                                                         self.config.mechanism.rod_length)
        return y_plus, x_c, v_minus, side


def build_model(config: Config, motion=None) -> Model:
    """Assemble the model of a validated configuration.

    Parameters
    ----------
    config : Config
        Validated parameters.
    motion : object, optional
        A motion provider (see :mod:`lubelink.kinematics`); default: the
        slider-crank of ``config.mechanism``.
    """
    b = config.beam
    L = config.mechanism.rod_length
    omega_n = beam.natural_frequencies(b.modes, L, b.youngs_modulus, b.second_moment, b.density, b.area)
    return Model(
        config=config,
        motion=SliderCrank(config.mechanism) if motion is None else motion,
        omega_n=omega_n,
        modal_mass=beam.modal_mass(b.density, b.area, L),
    )
