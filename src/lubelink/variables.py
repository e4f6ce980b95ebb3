"""The results' variable registry: every variable and coordinate of a results Dataset, declared once.

The Dataset, the files, the sweep store and the plots read dimensions, units (UDUNITS) and long names here.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["Variable", "VARIABLES", "VARIABLE_ATTRS", "CONVENTIONS", "variable", "entry"]


class Variable(NamedTuple):
    """A result variable: dimensions, units (UDUNITS) and long name."""

    dims: tuple
    units: str
    long_name: str


#: Every variable and coordinate of a results Dataset.
VARIABLES = {
    "time": Variable(("time",), "s", "time"),
    "crank_angle": Variable(("time",), "rad", "crank angle phi (slider-crank: omega0 t, or integrated where the crank is "
                                              "driven)"),
    "revolution": Variable(("revolution",), "1", "whole revolution of the crank: the k-th spans [(k - 1) T, k T)"),
    "x": Variable(("x",), "m", "position along the link from the crank pin O"),
    "mode": Variable(("mode",), "1", "mode number"),
    "direction": Variable(("direction",), "1", "displacement direction (spatial model): 1 axial u1, 2 in-plane u2, "
                                               "3 out-of-plane u3"),
    "x_pad": Variable(("x_pad",), "m", "position X along the pad from its start"),
    "impact": Variable(("impact",), "1", "impact number"),
    "q": Variable(("time", "mode"), "m", "modal coordinate"),
    "q_dot": Variable(("time", "mode"), "m s-1", "modal velocity"),
    "u2": Variable(("time", "x"), "m", "transverse deflection"),
    "u2_mid": Variable(("time",), "m", "midpoint deflection"),
    "u1": Variable(("time", "x"), "m", "axial displacement (spatial model)"),
    "u3": Variable(("time", "x"), "m", "out-of-plane deflection (spatial model)"),
    "u3_mid": Variable(("time",), "m", "midpoint out-of-plane deflection (spatial model)"),
    "bending_stress": Variable(("time", "x"), "Pa", "largest bending stress in the section (spatial: at a corner)"),
    "x_star": Variable(("time",), "m", "collar position along the link"),
    "crank_speed": Variable(("time",), "rad s-1", "crank angular speed phi_dot (driven crank)"),
    "motor_torque": Variable(("time",), "N m", "motor torque on the crank (driven crank)"),
    "V_r": Variable(("time",), "m s-1", "collar velocity relative to the link"),
    "omega_n": Variable(("mode",), "rad s-1", "natural circular frequency"),
    "omega_spatial": Variable(("direction", "mode"), "rad s-1", "natural circular frequencies of the axial, "
                                                               "in-plane and out-of-plane modes (spatial model)"),
    "film_min": Variable(("time",), "m", "thinnest film on the pad (spatial model: of the u2 faces)"),
    "pressure": Variable(("time", "x_pad"), "Pa", "gauge film pressure P - p_am (film at H/2 - u2, the paper's; "
                         "on the centre line Z = 0 with film.reynolds '2d' or 'short')"),
    "pressure_lower": Variable(("time", "x_pad"), "Pa", "gauge film pressure of the film at H/2 + u2"),
    "film_force": Variable(("time",), "N", "resultant film force on the link along +j"),
    "asperity_force": Variable(("time",), "N", "resultant asperity contact force on the link along +j "
                                                "(Greenwood-Tripp, mixed lubrication)"),
    "film_min_u3": Variable(("time",), "m", "thinnest film of the pair on the u3 faces (spatial model, film.faces "
                                          "u2+u3)"),
    "film_force_u3": Variable(("time",), "N", "resultant film force of the pair on the u3 faces on the link along +e3 "
                                              "(spatial model, film.faces u2+u3)"),
    "asperity_force_u3": Variable(("time",), "N", "resultant asperity contact force of the u3 faces along +e3 "
                                                  "(spatial model, film.faces u2+u3)"),
    "film_friction": Variable(("time",), "N", "viscous shear force of the films on the link along +i (1-D film)"),
    "film_power_loss": Variable(("time",), "W", "power dissipated in the films by viscous shear (1-D film)"),
    "contact_phase": Variable(("time",), "1", "contact phase of the sample: 0 free, 1 in contact with the collar"),
    "contact_force": Variable(("time",), "N", "contact force of the collar on the link, pushing it from the collar "
                                              "face (sustained or compliant contact)"),
    "crank_pin_force_X": Variable(("time",), "N", "force of the crank pin on the link along +X (planar slider-crank)"),
    "crank_pin_force_Y": Variable(("time",), "N", "force of the crank pin on the link along +Y (planar slider-crank)"),
    "slider_pin_force": Variable(("time",), "N", "force of the slider pin on the link along +Y (planar slider-crank; "
                                                 "a massless, frictionless slider)"),
    "collar_force": Variable(("time",), "N", "resultant normal load of the collar on the link along +j: film, "
                                             "asperity and contact forces and the collar mass's joint reaction"),
    "guide_force": Variable(("time",), "N", "force of the vertical guide on the collar's member along +X: the "
                                            "collar's loads on the link, normal and shear, along X"),
    "energy": Variable(("time",), "J", "vibration energy of the link relative to its rigid motion (kinetic plus strain)"),
    "work_rigid": Variable(("time",), "J", "work done on the vibration by the rigid motion's inertial loads and gravity"),
    "work_damping": Variable(("time",), "J", "work of the structural damping (beam.damping_ratio)"),
    "work_film": Variable(("time",), "J", "work of the film force on the link"),
    "work_asperity": Variable(("time",), "J", "work of the asperity contact force on the link"),
    "work_reaction": Variable(("time",), "J", "work of the collar's joint reaction on the link"),
    "work_contact": Variable(("time",), "J", "work of the contact force (compliant, or a sustained contact's)"),
    "work_impacts": Variable(("time",), "J", "change of the vibration energy in the restitution impacts so far"),
    "energy_residual": Variable(("time",), "J", "energy - energy(0) minus the sum of the works: the balance's "
                                                "residual (integration and sampling error)"),
    "revolution_start": Variable(("revolution",), "s", "time the revolution starts"),
    "revolution_peak_u2_mid": Variable(("revolution",), "m", "largest midpoint deflection |u2_mid| in the revolution"),
    "revolution_peak_stress": Variable(("revolution",), "Pa", "largest bending stress in the revolution"),
    "revolution_film_min": Variable(("revolution",), "m", "thinnest film in the revolution"),
    "revolution_film_loss": Variable(("revolution",), "J", "energy dissipated in the films in the revolution"),
    "revolution_energy_lost": Variable(("revolution",), "J", "energy lost in the revolution: in the films, by "
                                                             "structural damping and in impacts"),
    "impact_time": Variable(("impact",), "s", "impact time (contact start)"),
    "impact_position": Variable(("impact",), "m", "contact point on the link"),
    "impact_velocity": Variable(("impact",), "m s-1", "normal approach velocity before impact (positive closing)"),
    "impact_velocity_after": Variable(("impact",), "m s-1",
                                      "normal approach velocity after impact (negative opening)"),
    "impact_side": Variable(("impact",), "1", "film side of the contact: 1 the film H/2 - u2 (the link's +j side), "
                                              "-1 the film H/2 + u2 (its -j side)"),
    "impact_face": Variable(("impact",), "1", "face pair of the contact (spatial model, film.faces u2+u3): 2 the u2 "
                                              "faces, 3 the u3 faces (impact_side then the film H/2 -+ u3)"),
    "impact_energy_change": Variable(("impact",), "J", "change of the link's vibration energy in the impact"),
    "impact_dissipation": Variable(("impact",), "J", "energy lost at the contact point, in the frame of the collar "
                                                    "face (>= 0)"),
    "impact_collar_work": Variable(("impact",), "J", "work of the collar's impulse on the link: energy change plus "
                                                    "dissipation"),
}

#: Attributes beyond units and long name: CF's flags of the flag variables, the axis of x and x_pad (of time none).
VARIABLE_ATTRS = {
    "x": {"axis": "X"}, "x_pad": {"axis": "X"},
    "impact_side": {"flag_values": np.array([1, -1], dtype=np.int64),
                    "flag_meanings": "positive_j_side negative_j_side"},
    "impact_face": {"flag_values": np.array([2, 3], dtype=np.int64), "flag_meanings": "u2_faces u3_faces"},
}

#: The CF conventions the results files follow (global attribute ``Conventions``).
CONVENTIONS = "CF-1.10"


def variable(dims, data, units, long_name, **attrs):
    """``(dims, data, attrs)`` tuple for :class:`xarray.Dataset` construction."""
    return dims, np.asarray(data), {"units": units, "long_name": long_name, **attrs}


def entry(name, data, **attrs):
    """The ``(dims, data, attrs)`` tuple of registered variable ``name``."""
    v = VARIABLES[name]
    return variable(v.dims, data, v.units, v.long_name, **VARIABLE_ATTRS.get(name, {}), **attrs)
