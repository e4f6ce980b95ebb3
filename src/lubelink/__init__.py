"""lubelink: vibration of a flexible link carrying a lubricated prismatic joint.

Implements, corrects and extends Marghitu & Guran, "The Dynamics of a
Flexible Beam With a Lubricated Prismatic Kinematic Pair" (J. Vibration and
Acoustics). See the README and docs/ for the model and its relation to the
paper.

=================  ===========================================================
module             job
=================  ===========================================================
``params``         frozen parameter dataclasses in SI
``config``         TOML <-> parameters, scenarios, validation
``kinematics``     prescribed rigid motion (slider-crank, user motion)
``beam``           sine modes, frequencies, modal loads, deflection
``film``           Reynolds film pressure and modal film force
``contact``        film breakdown, restitution impact, penetration check
``model``          the modal ODE right-hand side
``integrate``      step driver, Bulirsch-Stoer
``simulate``       orchestrator: configuration -> Dataset
``results``        the variable registry, a run's results (Dataset)
``netcdf``         results files: write, save, load
``paper``          the paper's figures, Fig. 9 calibration, animation
``plots``          plotting functions on result Datasets
``sweep``          parameter sweeps on Dask, resumable stores
``steady``         periodic steady state: shooting, Floquet multipliers,
                   continuation (response curves)
=================  ===========================================================
"""

from .config import ConfigError, SCENARIOS, load as load_config, resolve as resolve_config
from .params import Beam, Collar, Config, Contact, Film, Mechanism, Output, Solver
from .netcdf import ResultsFileError, load, save
from .simulate import simulate

#: Names served by their subpackage on first use (``lubelink run`` does not import them).
_LAZY = {"ShootingError": "steady", "continuation": "steady", "periodic": "steady",
         "load_sweep": "sweep", "run_sweep": "sweep"}


def __getattr__(name):
    if name in _LAZY:
        import importlib

        value = getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'lubelink' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY))

try:
    from importlib.metadata import version as _version

    __version__ = _version("lubelink")
except Exception:  # not installed (running from a source tree)
    __version__ = "0+unknown"

__all__ = [
    "simulate",
    "periodic",
    "continuation",
    "ShootingError",
    "run_sweep",
    "load_sweep",
    "load",
    "save",
    "load_config",
    "resolve_config",
    "ConfigError",
    "ResultsFileError",
    "SCENARIOS",
    "Config",
    "Mechanism",
    "Beam",
    "Film",
    "Collar",
    "Contact",
    "Solver",
    "Output",
    "__version__",
]
