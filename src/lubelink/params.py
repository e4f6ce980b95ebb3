"""Model parameters: frozen dataclasses in SI units.

Every field is in SI. Values are validated once, at the boundary
(:func:`lubelink.config.validate`), never inside numerical code. The field
names are the TOML keys of the corresponding section; MODEL.md's glossary
symbol is given in brackets after the unit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

__all__ = [
    "Mechanism",
    "Beam",
    "Film",
    "Collar",
    "Contact",
    "Solver",
    "Output",
    "Config",
]


@dataclass(frozen=True)
class Mechanism:
    """Slider-crank of the paper's Section 6 (MODEL.md section 3).

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
    """

    crank_length: float = 0.07
    rod_length: float = 1.0
    crank_speed: float = 10.0 * math.pi
    guide_distance: float = 0.4
    gravity: tuple = (0.0, 0.0)


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
        Modal viscous damping ratio, the same for every mode [-] (``zeta``).
    """

    youngs_modulus: float = 207e9
    density: float = 7650.0
    width: float = 0.01
    height: float = 0.01
    modes: int = 1
    damping_ratio: float = 0.0

    @property
    def area(self) -> float:
        """Cross-section area [m^2] (``A``)."""
        return self.width * self.height

    @property
    def second_moment(self) -> float:
        """Second moment of area for in-plane bending [m^4] (``I_z``)."""
        return self.width * self.height**3 / 12.0


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
        Grid points on the pad for the ``"reynolds"`` cavitation solver [-].
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
        Impacts closer in time than this end the run as chattering [s].
    stiffness : float
        Contact stiffness of the compliant law [N/m^exponent] (``K``).
    exponent : float
        Exponent of the compliant law [-] (``n``; 1.5 Hertzian).
    """

    law: str = "none"
    restitution: float = 0.7
    min_film: float = 5.0e-6
    chatter_interval: float = 1.0e-6
    stiffness: float = 1.0e10
    exponent: float = 1.5


@dataclass(frozen=True)
class Solver:
    """Time integration (D9).

    Attributes
    ----------
    method : str
        ``"DOP853"``, ``"RK45"``, ``"Radau"``, ``"LSODA"`` or
        ``"bulirsch-stoer"``.
    rtol, atol : float
        Relative [-] and absolute [m, m/s] tolerances on ``q``, ``q_dot``.
    t_end : float
        End of the simulated interval, which starts at 0 [s].
    output_step : float
        Spacing of the stored time samples [s].
    max_step : float
        Largest step the integrator may take [s]; ``inf`` for no limit.
    max_wall_time : float
        Wall-clock budget of one run [s]; ``inf`` for no limit.
    backend : str
        ``"auto"`` (the compiled Numba path where it applies), ``"numba"``
        or ``"numpy"`` (the reference right-hand side).
    """

    method: str = "DOP853"
    rtol: float = 1e-8
    atol: float = 1e-12
    t_end: float = 2.0
    output_step: float = 1e-3
    max_step: float = math.inf
    max_wall_time: float = math.inf
    backend: str = "auto"


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
class Config:
    """A complete, validated simulation configuration."""

    mechanism: Mechanism = field(default_factory=Mechanism)
    beam: Beam = field(default_factory=Beam)
    film: Film = field(default_factory=Film)
    collar: Collar = field(default_factory=Collar)
    contact: Contact = field(default_factory=Contact)
    solver: Solver = field(default_factory=Solver)
    output: Output = field(default_factory=Output)

    def replace(self, **sections) -> "Config":
        """Return a copy with whole sections replaced."""
        return replace(self, **sections)


SECTION_TYPES: dict[str, type] = {
    "mechanism": Mechanism,
    "beam": Beam,
    "film": Film,
    "collar": Collar,
    "contact": Contact,
    "solver": Solver,
    "output": Output,
}
