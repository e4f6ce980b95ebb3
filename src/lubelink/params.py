"""Model parameters: frozen dataclasses in SI units.

Every field is in SI. Values are validated once, at the boundary (:func:`lubelink.config.validate`),
never inside numerical code. The field names are the TOML keys of the corresponding section; the
glossary symbol of docs/model.md is given in brackets after the unit.

Compiled code reads the same parameters as a *view* (:mod:`lubelink.views`): a named tuple with
the dataclass's field names, in which every choice (a string) is replaced by its index in the
tuple of choices declared here, the one list the validation, the physics and the documentation
share.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

__all__ = [
    "Mechanism",
    "Beam",
    "Film",
    "Collar",
    "Contact",
    "Solver",
    "Output",
    "Drive",
    "ModelOptions",
    "Config",
    "CHOICES",
]

#: The allowed values of every choice field, by ``section.key``; a choice's code in compiled code
#: is its index here.
CHOICES = {
    "film.model": ("none", "wedge", "wedge+squeeze"),
    "film.pad_reference": ("edge", "centre"),
    "film.cavitation": ("none", "half-sommerfeld", "reynolds"),
    "film.reynolds": ("1d", "2d", "short"),
    "film.faces": ("u2", "u2+u3"),
    "film.width_series": ("fitted", "sine"),
    "beam.model": ("planar", "spatial"),
    "beam.axial_end": ("fixed", "free"),
    "beam.axial_force": ("auto", "none", "inertial"),
    "contact.law": ("none", "restitution", "compliant"),
    "contact.extent": ("point", "pad"),
    "model.equations": ("corrected", "printed-omega2", "double-count", "printed", "printed-film-sign"),
    "solver.method": ("auto", "exponential", "exponential-adams", "rodas", "DOP853", "bulirsch-stoer", "RK45", "Radau", "BDF", "LSODA"),
    "solver.backend": ("auto", "numba", "numpy"),
    "drive.law": ("speed", "torque", "torque-speed", "controller"),
    "drive.coupling": ("one-way", "two-way"),
}


@dataclass(frozen=True)
class Mechanism:
    """Slider-crank of the paper's Section 6 (docs/model.md §3).

    Attributes
    ----------
    crank_length : float
        Crank length [m] (``OA``).
    rod_length : float
        Length of the flexible connecting rod [m] (``L = OC``).
    crank_speed : float
        Constant crank angular speed [rad/s] (``omega0``).
    guide_distance : float
        Horizontal distance of the collar's vertical guide from the fixed
        crank pivot [m] (``a``).
    gravity : tuple of float
        Gravitational acceleration in the fixed mechanism frame ``(X, Y)``
        [m/s^2]; ``(0, -9.81)`` for a vertical mechanism plane with the
        slider line horizontal. Default: none, as in the paper.
    crank_tilt : float
        Spatial model only (``beam.model = "spatial"``): tilt of the crank axis about the
        slider line [rad] (``tau``), the spatial slider-crank RSSP of docs/spatial.md; 0: the
        planar mechanism.
    slider_offset : float
        Spatial model only: offset of the slider line along the planar mechanism's normal
        ``Z`` [m] (``z_P``); 0: the planar mechanism.
    """

    crank_length: float = 0.07
    rod_length: float = 1.0
    crank_speed: float = 10.0 * math.pi
    guide_distance: float = 0.4
    gravity: tuple = (0.0, 0.0)
    crank_tilt: float = 0.0
    slider_offset: float = 0.0


@dataclass(frozen=True)
class Beam:
    """Pinned-pinned Euler-Bernoulli link of rectangular section (D3).

    Attributes
    ----------
    youngs_modulus : float
        Young's modulus [Pa] (``E``).
    density : float
        Mass density [kg/m^3] (``rho``).
    width : float
        Section width, also the pad width of the film [m] (``B``).
    height : float
        Section height, in the plane of bending [m] (``h``).
    modes : int
        Number of sine modes kept [-] (``N``).
    damping_ratio : float
        Modal viscous damping ratio, the same for every mode [-] (``zeta``); for a variable
        section, of every eigenmode of the Galerkin system.
    width_ratio, height_ratio : float
        Linear taper: width and height at ``x = L`` over their values ``width``, ``height`` at
        ``x = 0`` [-] (1: uniform link; docs/section.md). The film's pad width stays ``width``.
    model : str
        ``"planar"``: in-plane bending ``u2`` only (docs/model.md); ``"spatial"``: axial
        ``u1`` and bending ``u2``, ``u3`` under the spatial slider-crank (docs/spatial.md).
    yield_strength : float
        Yield strength of the material [Pa] (``sigma_y``); inf: not given. The results compare the peak bending
        stress with it (``stress_utilisation``).
    axial_end : str
        Spatial model only: the axial end condition at the slider end ``x = L`` (docs/spatial.md,
        "Boundary conditions"). ``"free"``: no axial force there (``E A u1'(L) = 0``; the massless,
        frictionless slider pushes only normal to its guide), the fixed-free bar's modes
        ``sin((2 n - 1) pi x / (2 L))``; ``"fixed"``: ``u1(L) = 0``, the fixed-fixed bar's
        ``sin(n pi x / L)``. ``u1(0) = 0`` either way (the crank pin).
    axial_force : str
        The axial force ``N(x, t)`` in the link and its geometric stiffness ``(N u2')'`` (docs/model.md §1.5):
        ``"none"`` (the paper: dropped), ``"inertial"``, the axial force of the link's inertia in its rigid
        motion, gravity and the slider's reaction (:mod:`lubelink.link.axial`), or ``"auto"`` (the default):
        ``"inertial"`` where the model has it, ``"none"`` elsewhere (:func:`lubelink.build.axial_force_of`). The
        uniform link under the slider-crank (at constant speed or driven) or a motion that gives the pin's axial
        acceleration ``A_O1``; the spatial link: the same force on ``u2`` and ``u3`` under its slider-crank. The
        paper's scenarios set ``"none"`` (they reproduce the paper).
    """

    youngs_modulus: float = 207e9
    density: float = 7650.0
    width: float = 0.01
    height: float = 0.01
    modes: int = 1
    damping_ratio: float = 0.0
    width_ratio: float = 1.0
    height_ratio: float = 1.0
    model: str = "planar"
    yield_strength: float = math.inf
    axial_end: str = field(default="free", metadata={"kernel": False})  # (compiled code: SpatialTable.axial)
    axial_force: str = field(default="auto", metadata={"kernel": False})  # (compiled code: Params.geometric)

    @property
    def area(self) -> float:
        """Cross-section area at ``x = 0`` [m^2] (``A``)."""
        return self.width * self.height

    @property
    def second_moment(self) -> float:
        """Second moment of area for in-plane bending at ``x = 0`` [m^4] (``I_z``)."""
        return self.width * self.height**3 / 12.0

    @property
    def uniform(self) -> bool:
        """Whether the section is the same all along the link (no taper)."""
        return self.width_ratio == 1.0 and self.height_ratio == 1.0


@dataclass(frozen=True)
class Film:
    """Lubricant film between the collar pad and the link (section 4, D4, D5).

    Attributes
    ----------
    model : str
        ``"none"`` (dry joint), ``"wedge"`` (paper Eq. 16) or
        ``"wedge+squeeze"`` (adds the ``12 mu d(xi)/dt`` term).
    viscosity : float
        Dynamic viscosity [Pa s] (``mu``).
    clearance : float
        Total clearance; the film is ``xi = H/2 - u2`` [m] (``H``).
    pad_length : float
        Length of the collar pad along the link [m] (``l``).
    pad_reference : str
        ``"edge"``: the pad spans ``[x_star, x_star + l]`` (paper Eq. 20);
        ``"centre"``: it spans ``[x_star - l/2, x_star + l/2]``.
    ambient_pressure : float
        Ambient pressure at the pad edges [Pa] (``p_am``). Only gauge pressure
        loads the link, so this value matters for cavitation only.
    quadrature_nodes : int
        Gauss-Legendre nodes on the pad for the film integrals [-].
    sides : int
        1: one film, on the +j side of the link (paper); 2: a collar that
        encloses the link, films ``H/2 - u2`` and ``H/2 + u2``.
    cavitation : str
        ``"none"`` (paper: sub-ambient pressure allowed), ``"half-sommerfeld"``
        (gauge pressure clipped at ``p_cav - p_am``) or ``"reynolds"``
        (Swift-Stieber: pressure and its gradient vanish at rupture).
    cavitation_pressure : float
        Absolute cavitation pressure [Pa] (``p_cav``).
    grid_points : int
        Grid points on the pad for the ``"reynolds"`` cavitation solver and for the
        ``"2d"`` and ``"short"`` films [-].
    reynolds : str
        ``"1d"``: the paper's film averaged across the width (long-bearing limit);
        ``"2d"``: the 2-D Reynolds equation on the pad, ambient at all four edges, by a
        few terms across the width (:mod:`lubelink.film.width`); ``"short"``: the
        short-bearing closed form (the flow along the pad neglected).
    width_modes : int
        Terms across the width of the ``"2d"`` film, one tridiagonal solve along the pad each [-].
    width_series : str
        The terms of the ``"2d"`` film (:func:`lubelink.film.width.width_terms`): ``"fitted"``,
        wavenumbers and weights fitted to the film's width functions, accurate for every pad
        (1 to 8 terms; docs/film2d.md); ``"sine"``, the odd terms of the sine series across the
        width, which converge slowly on wide pads and steep films.
    width_points : int
        Points across the width where the ``"2d"`` film is clipped (half-Sommerfeld) [-].
    thickness_floor : float
        ``h_f`` [m]: where the film ``h`` is below ``2 h_f`` the Reynolds equation sees
        ``h_f + h^2/(4 h_f)``, never thinner than ``h_f``
        (:func:`lubelink.film.reynolds.effective_film`); 0: the film as it is. The default, half
        the default ``contact.min_film``, leaves every smooth film above ``min_film`` unchanged.
        With roughness a floor below ``0.04 sigma`` has no effect and none is needed.
    roughness : float
        Combined RMS roughness of the two surfaces [m] (``sigma``); 0: smooth, no asperity
        contact. With ``sigma > 0`` the asperities carry the Greenwood-Tripp pressure
        (:mod:`lubelink.film.asperity`) beside the film (mixed lubrication), and the 1-D Reynolds
        film is the mean gap of the rough surfaces (:func:`lubelink.film.reynolds.mean_gap`).
    summit_product : float
        ``eta beta sigma`` [-], asperity density times summit radius times roughness (0.03-0.05).
    summit_ratio : float
        ``sigma / beta`` [-], roughness over summit radius (1e-4-1e-2).
    contact_modulus : float
        Composite elastic modulus ``E'`` of the Greenwood-Tripp pressure [Pa]
        (``1/E' = (1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2``; two steels: 1.14e11).
    faces : str
        Spatial model only (``beam.model = "spatial"``): ``"u2"``, the collar's film (and
        contact) on the faces normal to ``e2`` only; ``"u2+u3"``, also a second pair on the
        faces normal to ``e3``: the same collar (pad, clearance, lubricant, sides, cavitation)
        with the film ``H/2 - u3`` (``H/2 + u3`` on the other side) and the pad width ``h``
        (``beam.height``), docs/spatial.md.
    """

    model: str = "wedge"
    viscosity: float = 0.1
    clearance: float = 6.0e-3
    pad_length: float = 0.05
    pad_reference: str = "edge"
    ambient_pressure: float = 101325.0
    quadrature_nodes: int = 32
    sides: int = 1
    cavitation: str = "none"
    cavitation_pressure: float = 0.0
    grid_points: int = 201
    reynolds: str = "1d"
    width_modes: int = 8
    width_series: str = field(default="fitted", metadata={"kernel": False})
    width_points: int = 32
    thickness_floor: float = 2.5e-6
    roughness: float = 0.0
    summit_product: float = 0.04
    summit_ratio: float = 1e-3
    contact_modulus: float = 1.14e11
    faces: str = "u2"

    @property
    def enabled(self) -> bool:
        return self.model != "none"


@dataclass(frozen=True)
class Collar:
    """Collar and the member that carries it on the vertical guide (D7).

    Attributes
    ----------
    mass : float
        Mass of the collar and its guided member [kg] (``m_c``).
    """

    mass: float = 0.0


@dataclass(frozen=True)
class Contact:
    """Film breakdown and impact at the collar (section 5, D8).

    Attributes
    ----------
    law : str
        ``"restitution"`` (paper Eq. 21, instantaneous modal velocity jump),
        ``"compliant"`` (Lankarani-Nikravesh force law) or ``"none"``.
    restitution : float
        Coefficient of restitution [-] (``e``).
    min_film : float
        Film thickness at which the film breaks down [m] (``xi_min``).
    chatter_interval : float
        Impacts closer in time than this are a Zeno sequence: the link then rides on the
        collar (sustained contact) while the contact force is positive [s].
    stiffness : float
        Contact stiffness of the compliant law [N/m^exponent] (``K``).
    exponent : float
        Exponent of the compliant law [-] (``n``; 1.5 Hertzian).
    extent : str
        Where the compliant law acts: ``"point"``, the force ``K delta^n`` at the thinnest film; or
        ``"pad"``, a pressure ``k_f delta(x)`` wherever the film on the pad is below ``min_film``
        (an elastic foundation: the collar face's layer), with the same damping.
    face_stiffness : float
        ``k_f`` of ``extent = "pad"`` [Pa/m]: the constrained modulus of the face layer over its
        thickness (1e12: a 1 mm layer of 1 GPa).
    """

    law: str = "none"
    restitution: float = 0.7
    min_film: float = 5.0e-6
    chatter_interval: float = 1.0e-6
    stiffness: float = 1.0e10
    exponent: float = 1.5
    extent: str = field(default="point", metadata={"kernel": False})
    face_stiffness: float = field(default=1.0e12, metadata={"kernel": False})


@dataclass(frozen=True)
class ModelOptions:
    """Which equations are solved (D1).

    Attributes
    ----------
    equations : str
        ``"corrected"`` (lubelink's, the default), or one of the paper's printed forms, to see
        what its errata change: ``"printed-omega2"`` (Eq. 18's stiffening ``+omega^2``),
        ``"double-count"`` (Eq. 18's ``a_O2 + omega v_O1`` with Section 6's true ``a_O2``),
        ``"printed"`` (both) or ``"printed-film-sign"`` (Eq. 20's film force ``+B p_g``).
    """

    equations: str = "corrected"


@dataclass(frozen=True)
class Solver:
    """Time integration (D9).

    Attributes
    ----------
    method : str
        ``"auto"`` (``"exponential-adams"`` on a planar link without a film or without a contact
        law; otherwise ``"DOP853"`` for one mode and ``"exponential"`` for more: the faster one at the default
        tolerance, see benchmarks/README.md), ``"exponential"`` (exponential Runge-Kutta,
        exact on the modal oscillators), ``"exponential-adams"`` (exponential Adams
        predictor-corrector, the same exactness in two evaluations a step, a smaller stability
        region), ``"DOP853"``, ``"bulirsch-stoer"`` (the paper's), or SciPy's ``"RK45"``,
        ``"Radau"``, ``"BDF"``, ``"LSODA"``.
    rtol : float
        Relative tolerance on ``q``, ``q_dot`` [-].
    atol : float
        Absolute tolerance on ``q`` [m] and ``q_dot`` [m/s].
    t_end : float
        End of the simulated interval, which starts at 0 [s].
    output_step : float
        Spacing of the stored time samples [s].
    max_step : float
        Largest step the integrator may take [s]; ``inf`` for no limit.
    max_wall_time : float
        Wall-clock budget of one run [s]; ``inf`` for no limit.
    backend : str
        ``"auto"`` or ``"numba"``: the kernels compiled by Numba (every
        option has them); ``"numpy"``: the same source run as Python, a
        debugging aid (as when Numba is not installed, or disabled).
    max_deflection : float
        Largest ``max |u2| / L`` of the linear theory's domain [-]; ``inf``: not checked.
    max_slope : float
        Largest ``max |u2'|`` [-] (rad); ``inf``: not checked.
    max_axial_strain : float
        Largest mean stretching strain ``1/(2L) int u2'^2 dx`` [-]; ``inf``: not checked.
        A run whose state leaves the domain stops with status ``out_of_domain``
        (:func:`lubelink.beam.linear_domain`, docs/breakdown.md).
    """

    method: str = "auto"
    rtol: float = 1e-6
    atol: float = 1e-8
    t_end: float = 2.0
    output_step: float = 1e-3
    max_step: float = math.inf
    max_wall_time: float = math.inf
    backend: str = "auto"
    max_deflection: float = 0.05
    max_slope: float = 0.15
    max_axial_strain: float = 0.005


@dataclass(frozen=True)
class Output:
    """What is sampled into the results.

    Attributes
    ----------
    x_points : int
        Points along the link for ``u2(time, x)`` [-].
    pad_points : int
        Points along the pad for ``pressure(time, X)`` [-].
    """

    x_points: int = 101
    pad_points: int = 41


@dataclass(frozen=True)
class Drive:
    """How the crank is driven (docs/model.md, "Driven crank").

    ``"speed"`` prescribes the constant crank speed ``mechanism.crank_speed`` (the paper's, the
    default). The other laws drive the crank and its flywheel with a motor torque, and the crank
    speed follows from the rigid slider-crank's dynamics (:mod:`lubelink.link.drive`), starting at
    ``phi = 0`` with the speed ``mechanism.crank_speed``. With ``coupling = "one-way"`` the link's
    elastic forces do not act back on the crank; ``"two-way"`` adds the torque of the link's elastic
    motion to the crank's equation and iterates crank and link to their common motion
    (:mod:`lubelink.coupling`).

    Attributes
    ----------
    law : str
        ``"speed"`` (prescribed constant speed), ``"torque"`` (constant motor torque ``torque``),
        ``"torque-speed"`` (``stall_torque (1 - phi_dot / no_load_speed)``) or ``"controller"`` (a PI
        speed controller holding ``mechanism.crank_speed``: ``torque + proportional_gain e +
        integral_gain int e dt``, ``e = omega0 - phi_dot``).
    flywheel_inertia : float
        Moment of inertia of the crank and flywheel about the crank axis [kg m^2] (``J_f``).
    torque : float
        Constant motor torque, about +k [N m] (``T``); the controller's feed-forward torque.
    stall_torque : float
        Torque of the torque-speed line at rest [N m] (``T_s``).
    no_load_speed : float
        Speed of the torque-speed line at zero torque [rad/s] (``omega_nl``), of the sign of ``mechanism.crank_speed``.
    proportional_gain : float
        Controller's proportional gain [N m s/rad] (``K_p``).
    integral_gain : float
        Controller's integral gain [N m/rad] (``K_i``).
    slider_mass : float
        Mass of the slider C [kg] (``m_s``).
    slider_force : float
        Constant external force on the slider along +X [N] (``F_s``; a gas force pushing the slider
        away from the crank is positive).
    slider_friction : float
        Coulomb friction force on the slider, opposing its velocity [N] (``F_f >= 0``).
    coupling : str
        ``"one-way"`` (the crank follows the rigid mechanism, the link follows the crank) or ``"two-way"``
        (the link's elastic motion acts back on the crank: a waveform relaxation of crank and link,
        :mod:`lubelink.coupling`).
    """

    law: str = "speed"
    flywheel_inertia: float = 0.1
    torque: float = 0.0
    stall_torque: float = 10.0
    no_load_speed: float = 20.0 * math.pi
    proportional_gain: float = 1.0
    integral_gain: float = 10.0
    slider_mass: float = 0.0
    slider_force: float = 0.0
    slider_friction: float = 0.0
    coupling: str = "one-way"

    @property
    def prescribed(self) -> bool:
        """Whether the crank speed is prescribed (``law = "speed"``)."""
        return self.law == "speed"


@dataclass(frozen=True)
class Config:
    """A complete, validated simulation configuration."""

    mechanism: Mechanism = field(default_factory=Mechanism)
    beam: Beam = field(default_factory=Beam)
    film: Film = field(default_factory=Film)
    collar: Collar = field(default_factory=Collar)
    contact: Contact = field(default_factory=Contact)
    model: ModelOptions = field(default_factory=ModelOptions)
    solver: Solver = field(default_factory=Solver)
    output: Output = field(default_factory=Output)
    drive: Drive = field(default_factory=Drive)

    def replace(self, **sections) -> "Config":
        """Return a copy with whole sections replaced."""
        return replace(self, **sections)


SECTION_TYPES: dict[str, type] = {
    "mechanism": Mechanism,
    "beam": Beam,
    "film": Film,
    "collar": Collar,
    "contact": Contact,
    "model": ModelOptions,
    "solver": Solver,
    "output": Output,
    "drive": Drive,
}


def sample_times(solver):
    """The output times ``0, output_step, ...`` up to ``t_end`` [s] (the last one kept when it rounds up)."""
    n_out = int(np.floor(solver.t_end / solver.output_step * (1 + 1e-12))) + 1
    return np.minimum(np.arange(n_out) * solver.output_step, solver.t_end)
