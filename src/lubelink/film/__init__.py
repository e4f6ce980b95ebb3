"""Reynolds film between the collar pad and the link (docs/model.md section 4; paper Eqs. 14-17, 20).

The pad spans ``X in [0, l]`` from its start ``x0`` on the link. The film thickness is
``xi(X) = H/2 - u2(x0 + X)`` and the gauge pressure ``p_g`` solves the 1-D Reynolds equation in
the link frame (paper Eq. 16, plus the squeeze term the paper drops):

    (xi^3 p_g')' = 6 mu V_r xi' + 12 mu xi_t,     p_g(0) = p_g(l) = 0,

``V_r`` the collar velocity relative to the link, ``xi_t`` the rate of the film at a fixed point
of the link. Integrating once (:func:`pressure_gradient`)::

    xi^3 p_g' = 6 mu V_r xi + 12 mu Q + C,    Q(X) = int_0^X xi_t,

and ``p_g(l) = 0`` fixes the constant (:func:`reynolds_constant`)::

    C = -(6 mu V_r I1 + 12 mu I3) / I2,   I1 = int_0^l xi^-2,  I2 = int_0^l xi^-3,  I3 = int_0^l Q xi^-3.

The force per unit length on the link is ``f2 = -B p_g`` (the film pushes the link away from the
collar face). Its sine transform is taken by parts, ``F_n = -B int p_g sin(beta_n x) dX =
B int p_g' W_n dX`` with ``W_n(X) = int_0^X sin(beta_n (x0 + s)) ds`` in closed form, so one
Gauss-Legendre pass over the pad gives the modal forces (:func:`modal_film_force`); the pressure
itself is the running integral of ``p_g'`` (half-Sommerfeld cavitation, the pressure output).
The Swift-Stieber (Reynolds) cavitation condition is an obstacle problem solved on a pad grid
(:func:`reynolds_cavitation`).

The film of finite width (``film.reynolds = "2d"`` or ``"short"``): :mod:`.width` (a few terms
across the width, the short-bearing closed form), what the right-hand side executes;
:func:`pressure_2d` the 2-D Reynolds equation for any film ``xi(X, Z)``.
"""

from .force import (COS, SIN, VERS, PadTables, film_force_many, gauss_legendre, integration_matrix, modal_film_force,
                    modal_force, pad_tables, resultant_force)
from .pressure import (film_thickness, mode_film, mode_film_rate, pad_pressure, pad_pressure_many, pressure,
                       pressure_on_breaks, pressure_points)
from .reynolds2d import pressure_2d, reynolds_2d_system
from .width import (ONE_D, SHORT, TWO_D, centre_pressure_many, width_film, width_mean, width_pressure, width_profile,
                    width_terms)
from .reynolds import (CENTRE, FULL, HALF_SOMMERFELD, NO_FILM, REYNOLDS, WEDGE, WEDGE_SQUEEZE, pad_start,
                       pressure_gradient, reynolds_cavitation, reynolds_constant)

__all__ = [
    "PadTables",
    "pad_tables",
    "gauss_legendre",
    "integration_matrix",
    "pad_start",
    "reynolds_constant",
    "pressure_gradient",
    "reynolds_cavitation",
    "modal_film_force",
    "film_force_many",
    "pressure_on_breaks",
    "pad_pressure_many",
    "pressure",
    "modal_force",
    "pad_pressure",
    "resultant_force",
    "pressure_points",
    "film_thickness",
    "mode_film",
    "mode_film_rate",
    "pressure_2d",
    "reynolds_2d_system",
    "width_film",
    "width_pressure",
    "centre_pressure_many",
    "width_terms",
    "width_mean",
    "width_profile",
]
