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
``beam``           sine modes, frequencies, modal loads, deflection
``film``           Reynolds film pressure and modal film force
``contact``        film breakdown, restitution impact, penetration check
``link``           the link's model layer: rigid motion, section, the collar's
                   faces, the planar and spatial right-hand sides
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

import importlib as _importlib
import sys as _sys
import types as _types

#: The public names and the module that serves each. Nothing is imported until a name is first used
#: (PEP 562): ``import lubelink`` takes milliseconds, so the ``lubelink`` command can catch Ctrl-C
#: from its first line on, and the heavy libraries (Numba, xarray) load when a run needs them.
_SERVED_BY = {
    "simulate": "simulate", "load": "netcdf", "save": "netcdf", "ResultsFileError": "netcdf",
    "load_config": ("config", "load"), "resolve_config": ("config", "resolve"), "SCENARIOS": "config",
    "ConfigError": "errors", "Config": "params", "Mechanism": "params", "Beam": "params", "Film": "params",
    "Collar": "params", "Contact": "params", "Solver": "params", "Output": "params",
    "ShootingError": "steady", "continuation": "steady", "periodic": "steady",
    "load_sweep": "sweep", "run_sweep": "sweep",
    "PrescribedMotion": "link.kinematics", "sampled_motion": "link.kinematics",
    "SpatialPrescribedMotion": "link.spatial_motion", "sampled_spatial_motion": "link.spatial_motion",
    "Section": "link.section",
}


def __getattr__(name):
    if name == "__version__":
        from importlib.metadata import PackageNotFoundError, version

        try:
            value = version("lubelink")
        except PackageNotFoundError:  # running from a source tree
            value = "0+unknown"
    elif name in _SERVED_BY:
        module, attr = _SERVED_BY[name] if isinstance(_SERVED_BY[name], tuple) else (_SERVED_BY[name], name)
        value = getattr(_importlib.import_module(f".{module}", __name__), attr)
    else:
        try:
            return _importlib.import_module(f".{name}", __name__)  # a submodule, as ``import lubelink.x`` gives
        except ModuleNotFoundError as exc:
            if exc.name != f"{__name__}.{name}":
                raise
            raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_SERVED_BY) | {"__version__"})


class _Package(_types.ModuleType):
    """The package's module: ``lubelink.simulate`` stays the function when the import system binds
    the submodule of the same name to the package (as the eager ``from .simulate import simulate``
    of a non-lazy package would leave it)."""

    def __setattr__(self, name, value):
        if isinstance(value, _types.ModuleType) and name in _SERVED_BY and getattr(value, name, None) is not None:
            value = getattr(value, name)
        super().__setattr__(name, value)


_sys.modules[__name__].__class__ = _Package

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
