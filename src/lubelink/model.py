"""The modal ODE right-hand side assembled from the physics modules.

State ``y = [q_1..q_N, q_dot_1..q_dot_N]``. The right-hand side is the
corrected modal equation of MODEL.md section 2:

    q_ddot_n = -(omega_n^2 - omega^2) q_n - 2 zeta omega_n q_dot_n
               - 2/(L beta_n) {A_O2 [1 + (-1)^(n+1)] + alpha L (-1)^(n+1)}
               + (F_n^film + R sin(beta_n x_star)) / (rho A L / 2)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import beam, contact, film
from .kinematics import SliderCrank
from .params import Config

__all__ = ["Model", "build_model"]


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

    def initial_state(self):
        """Zero initial conditions (the paper's)."""
        return np.zeros(2 * self.modes)

    def loads(self, t, y):
        """Modal film force [N], resultant film force [N] and joint reaction [N] at ``t``."""
        cfg = self.config
        N = self.modes
        q, q_dot = y[:N], y[N:]
        kin = self.motion(t)
        F = np.zeros(N)
        total = 0.0
        if cfg.film.enabled:
            fm = cfg.film
            x0 = film.pad_start(float(kin.x_star), fm.pad_length, fm.pad_reference)
            F, total, _ = film.modal_force(
                q, q_dot, x0, float(kin.V_r), mu=fm.viscosity, clearance=fm.clearance,
                pad_length=fm.pad_length, width=cfg.beam.width,
                rod_length=cfg.mechanism.rod_length, squeeze=fm.model == "wedge+squeeze",
                nodes=fm.quadrature_nodes)
        R = 0.0
        if cfg.collar.mass > 0.0:
            R = float(self.motion.joint_reaction(t, cfg.collar.mass))
            F = F + beam.project_point_load(R, float(kin.x_star), N, cfg.mechanism.rod_length)
        return F, total, R, kin

    def rhs(self, t, y):
        """``dy/dt`` of the modal ODE."""
        N = self.modes
        F, _, _, kin = self.loads(t, y)
        L = self.config.mechanism.rod_length
        forcing = beam.rigid_forcing(float(kin.A_O2), float(kin.alpha), N, L) + F / self.modal_mass
        q_ddot = beam.modal_acceleration(y[:N], y[N:], self.omega_n, self.config.beam.damping_ratio,
                                         float(kin.omega), forcing)
        return np.concatenate([y[N:], q_ddot])

    def pad_start(self, t):
        fm = self.config.film
        return film.pad_start(float(self.motion(t).x_star), fm.pad_length, fm.pad_reference)

    def thinnest_film(self, t, y):
        """``(xi_min, x_c, at_edge)`` on the pad at ``t`` (see :func:`contact.thinnest_film`)."""
        fm = self.config.film
        return contact.thinnest_film(y[: self.modes], self.pad_start(t), fm.pad_length,
                                     fm.clearance, self.config.mechanism.rod_length)

    def gap(self, t, y):
        """Event function: film thickness above breakdown, ``xi_min - min_film`` [m]."""
        return self.thinnest_film(t, y)[0] - self.config.contact.min_film

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
        """
        N = self.modes
        L = self.config.mechanism.rod_length
        _, x_c, at_edge = self.thinnest_film(t, y)
        V_c = float(self.motion(t).V_r) if at_edge else 0.0
        v_minus = contact.approach_velocity(y[:N], y[N:], x_c, V_c, L)
        y_plus = y.copy()
        if v_minus > 0.0:
            y_plus[N:] = contact.restitution_jump(y[N:], x_c, v_minus, self.config.contact.restitution, L)
        return y_plus, x_c, v_minus


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
