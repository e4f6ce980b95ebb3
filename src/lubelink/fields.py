"""Unit, symbol and a one-line summary of every parameter field (:data:`FIELDS`).

The dataclasses of :mod:`lubelink.params` hold the values; this table is what the documentation
of a key needs: the template ``lubelink config`` writes, and the units and long names of a sweep's
swept parameters. ``tests/test_template.py`` checks that it names every field once and that its
units are those of the dataclasses' docstrings.
"""

__all__ = ["FIELDS"]

#: Unit, symbol and a one-line summary of every field, by ``section.key``: what ``lubelink config``
#: writes beside each key (with the valid values of :data:`lubelink.config.RULES`), and the units
#: and names of swept parameters. Units are UDUNITS strings (``"1"``: dimensionless, ``""``: a
#: choice); the symbols are those of docs/model.md.
FIELDS = {
    "mechanism.crank_length": ("m", "OA", "crank length; shorter than rod_length"),
    "mechanism.rod_length": ("m", "L", "length of the flexible connecting rod"),
    "mechanism.crank_speed": ("rad s-1", "omega0", "constant crank angular speed; non-zero"),
    "mechanism.guide_distance": ("m", "a", "distance of the collar's guide from the crank pivot (the pad "
                                           "must stay on the rod over a turn)"),
    "mechanism.gravity": ("m s-2", "g", "gravity [g_X, g_Y], fixed frame; [0, -9.81]: vertical plane"),
    "mechanism.crank_tilt": ("rad", "tau", "spatial model: tilt of the crank axis about the slider line (0: planar)"),
    "mechanism.slider_offset": ("m", "z_P", "spatial model: offset of the slider line normal to the planar "
                                            "mechanism's plane (0: planar)"),
    "beam.youngs_modulus": ("Pa", "E", "Young's modulus"),
    "beam.density": ("kg m-3", "rho", "mass density"),
    "beam.width": ("m", "B", "section width, also the pad width"),
    "beam.height": ("m", "h", "section height, in the plane of bending"),
    "beam.modes": ("1", "N", "number of sine modes kept"),
    "beam.damping_ratio": ("1", "zeta", "modal viscous damping ratio of every mode"),
    "beam.width_ratio": ("1", "", "linear taper: width at x = L over width at x = 0 (1: uniform)"),
    "beam.height_ratio": ("1", "", "linear taper: height at x = L over height at x = 0 (1: uniform)"),
    "beam.model": ("", "", "planar: u2 only (paper Eq. 18); spatial: u1, u2, u3 (docs/spatial.md)"),
    "beam.yield_strength": ("Pa", "sigma_y", "yield strength of the link's material (inf: not given); the summary "
                                             "compares the peak bending stress with it"),
    "beam.axial_end": ("", "", "spatial model: u1 at the slider end, free (no axial force: a massless frictionless "
                               "slider) or fixed (u1(L) = 0); docs/spatial.md"),
    "beam.axial_force": ("", "N", "none (paper), inertial: the axial force of the rigid motion's inertia, gravity "
                                  "and the slider, and its geometric stiffness (N u2')', (N u3')' (uniform link), or "
                                  "auto: inertial where the model has it, none elsewhere"),
    "film.model": ("", "", "film model: wedge is paper Eq. 16, wedge+squeeze adds 12 mu dxi/dt"),
    "film.viscosity": ("Pa s", "mu", "dynamic viscosity of the lubricant"),
    "film.clearance": ("m", "H", "total clearance; the film is xi = H/2 - u2"),
    "film.pad_length": ("m", "l", "length of the collar pad along the link"),
    "film.pad_reference": ("", "", "x_star is the pad's edge (paper Eq. 20) or centre"),
    "film.ambient_pressure": ("Pa", "p_am", "ambient pressure at the pad edges (matters for cavitation only)"),
    "film.quadrature_nodes": ("1", "", "Gauss-Legendre nodes on the pad for the film integrals"),
    "film.sides": ("1", "", "films: 1 on the +j side (paper), 2 a collar enclosing the link"),
    "film.cavitation": ("", "", "none (paper), half-Sommerfeld, reynolds: Swift-Stieber"),
    "film.cavitation_pressure": ("Pa", "p_cav", "absolute cavitation pressure; at most ambient_pressure"),
    "film.grid_points": ("1", "", "pad grid points of the reynolds cavitation solver and of the 2d and short films"),
    "film.reynolds": ("", "", "1d: averaged across the width (paper); 2d: finite width; short: short-bearing "
                              "closed form"),
    "film.width_modes": ("1", "", "terms across the width of the 2d film, one solve along the pad each (fitted: "
                                  "at most 8)"),
    "film.width_series": ("", "", "the 2d film's terms: fitted (any pad, 1 to 8 terms) | sine (odd sine terms; "
                                  "slow for wide pads)"),
    "film.width_points": ("1", "", "points across the width where the 2d film is clipped (half-Sommerfeld)"),
    "film.thickness_floor": ("m", "h_f", "below 2 h_f the Reynolds film h is h_f + h^2/(4 h_f); 0: off"),
    "film.roughness": ("m", "sigma", "combined RMS roughness; > 0: Greenwood-Tripp asperity contact, mean-gap film"),
    "film.summit_product": ("1", "eta beta sigma", "asperity density x summit radius x roughness"),
    "film.summit_ratio": ("1", "sigma/beta", "roughness over summit radius"),
    "film.contact_modulus": ("Pa", "E'", "composite elastic modulus of the asperity contact"),
    "film.faces": ("", "", "spatial model: the collar's film and contact on the u2 faces only, or also on the u3 "
                           "faces (a second pair, the film H/2 - u3; docs/spatial.md)"),
    "collar.mass": ("kg", "m_c", "mass of the collar and its guided member (joint reaction)"),
    "contact.law": ("", "", "restitution: paper Eq. 21, compliant: Lankarani-Nikravesh"),
    "contact.restitution": ("1", "e", "coefficient of restitution"),
    "contact.min_film": ("m", "xi_min", "film thickness at which the film breaks down; below clearance / 2"),
    "contact.chatter_interval": ("s", "", "impacts closer in time than this switch to sustained contact"),
    "contact.stiffness": ("N m-n", "K", "stiffness of the compliant law (n = exponent)"),
    "contact.exponent": ("1", "n", "exponent of the compliant law (1.5: Hertz)"),
    "contact.extent": ("", "", "where the compliant law acts: point (the thinnest film) or pad (wherever the face is "
                               "reached, a foundation of face_stiffness)"),
    "contact.face_stiffness": ("Pa m-1", "k_f", "pressure per penetration of the collar face (extent pad): E'/t of a "
                                                "face layer of constrained modulus E' and thickness t"),
    "model.equations": ("", "", "corrected (lubelink's) or a printed form of the paper"),
    "solver.method": ("", "", "auto: exponential-adams on the planar link without a film or without a contact law, "
                              "else DOP853 for 1 mode and exponential for more"),
    "solver.rtol": ("1", "", "relative tolerance on q, q_dot"),
    "solver.atol": ("m", "", "absolute tolerance on q [m] and q_dot [m/s]"),
    "solver.t_end": ("s", "", "end of the simulated interval, which starts at 0"),
    "solver.output_step": ("s", "", "spacing of the stored time samples; below t_end"),
    "solver.max_step": ("s", "", "largest step of the integrator (inf: no limit)"),
    "solver.max_wall_time": ("s", "", "wall-clock budget (inf: none); past it the run stops, status "
                                      "timeout, keeping its results"),
    "solver.backend": ("", "", "auto: compiled (Numba) where it applies"),
    "solver.max_deflection": ("1", "", "linear theory's domain: largest max |u2| / L (inf: not checked)"),
    "solver.max_slope": ("1", "", "largest slope max |u2'| (a ratio, in rad; inf: not checked)"),
    "solver.max_axial_strain": ("1", "", "largest mean stretching strain 1/(2L) int u2'^2 dx (inf: not checked)"),
    "output.x_points": ("1", "", "samples of u2 along the link"),
    "output.pad_points": ("1", "", "samples of the film pressure along the pad"),
    "drive.law": ("", "", "speed: constant mechanism.crank_speed (paper); torque, torque-speed, controller: a motor "
                          "through a flywheel, the speed from the rigid mechanism (docs/model.md section 3.7)"),
    "drive.flywheel_inertia": ("kg m2", "J_f", "crank and flywheel about the crank axis"),
    "drive.torque": ("N m", "T", "constant motor torque (law torque); the controller's feed-forward"),
    "drive.stall_torque": ("N m", "T_s", "torque at rest of the torque-speed line"),
    "drive.no_load_speed": ("rad s-1", "omega_nl", "speed at zero torque of the torque-speed line"),
    "drive.proportional_gain": ("N m s rad-1", "K_p", "PI controller's proportional gain (set speed: crank_speed)"),
    "drive.integral_gain": ("N m rad-1", "K_i", "PI controller's integral gain"),
    "drive.slider_mass": ("kg", "m_s", "mass of the slider C"),
    "drive.slider_force": ("N", "F_s", "constant external force on the slider along +X"),
    "drive.slider_friction": ("N", "F_f", "Coulomb friction on the slider, against its velocity"),
    "drive.coupling": ("", "", "one-way: the link follows the crank; two-way: its elastic motion acts back on the "
                               "crank, iterated to convergence (docs/model.md section 3.8)"),
}
