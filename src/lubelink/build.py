"""A configuration assembled for integration: the planar model, or the spatial model for ``beam.model = "spatial"``.

The one entry both families share, above both (:mod:`lubelink.assembly`, :mod:`lubelink.link.spatial_model`),
so that neither imports the other's builder.
"""

from __future__ import annotations

from dataclasses import replace

from .assembly import Model, _backend, make_params
from .errors import BackendError
from .link.kinematics import SliderCrank
from .params import Config

__all__ = ["build_model", "axial_force_of"]


def axial_force_of(config: Config, motion=None, section=None) -> str:
    """The ``beam.axial_force`` a configuration runs with under ``motion`` and ``section`` (:func:`build_model`'s):
    the key itself, or for ``"auto"`` ``"inertial"`` where the model has the axial force, ``"none"`` elsewhere.

    The model has it (docs/model.md §1.5) on a uniform link (no taper, no ``section``) under the slider-crank of
    ``[mechanism]`` (at constant speed, or driven with a massless, unloaded slider: ``motion`` None), or, for the
    planar link, under a motion that gives the pin's axial acceleration ``A_O1`` (``gives_axial_acceleration``;
    the slider taken on the +X line).
    """
    b, d = config.beam, config.drive
    if b.axial_force != "auto":
        return b.axial_force
    if not b.uniform or section is not None:
        return "none"
    if not d.prescribed and (d.slider_mass != 0.0 or d.slider_force != 0.0 or d.slider_friction != 0.0):
        return "none"  # the axial force's slider is massless and frictionless (validation refuses "inertial")
    if motion is None:
        return "inertial"
    if b.model == "spatial":
        from .link.spatial_motion import SpatialSliderCrank

        return "inertial" if isinstance(motion, SpatialSliderCrank) else "none"
    return "inertial" if getattr(motion, "gives_axial_acceleration", False) else "none"


def build_model(config: Config, motion=None, section=None) -> Model:
    """Assemble the model of a validated configuration.

    Parameters
    ----------
    config : Config
        Validated parameters.
    motion : object, optional
        A motion provider (see :mod:`lubelink.link.kinematics`); default: the slider-crank of
        ``config.mechanism`` at its constant speed, or driven (:func:`lubelink.link.drive.driven_motion`)
        where ``drive.law`` is not ``"speed"`` (which takes no other motion than a driven one).
    section : lubelink.link.section.Section, optional
        ``A(x)``, ``I(x)`` replacing the beam's (uniform or ``beam.width_ratio``/``height_ratio``
        tapered) section.

    Raises
    ------
    BackendError
        ``solver.backend = "numba"`` for a configuration the compiled path cannot run.

    The model's configuration is ``config`` with ``beam.axial_force = "auto"`` resolved (:func:`axial_force_of`).
    """
    if config.beam.axial_force == "auto":
        config = replace(config, beam=replace(config.beam, axial_force=axial_force_of(config, motion, section)))
    if config.beam.model == "spatial":
        from .spatial_assembly import build_spatial_model

        return build_spatial_model(config, motion, section)
    if motion is not None and not config.drive.prescribed and getattr(motion, "crank", None) is None:
        from .validation import ConfigError

        raise ConfigError([f"drive.law = {config.drive.law!r}: a driven crank makes its own motion; pass no motion, "
                           "or use drive.law = 'speed'"])
    if motion is None and not config.drive.prescribed:
        from .link.drive import driven_motion

        motion = driven_motion(config, section)
    elif motion is None:
        motion = SliderCrank(config.mechanism)
    else:
        from .link.spatial_motion import SpatialPrescribedMotion, SpatialSliderCrank

        if isinstance(motion, (SpatialPrescribedMotion, SpatialSliderCrank)):
            from .validation import ConfigError

            raise ConfigError([f"motion = {type(motion).__name__}: a spatial motion drives beam.model = 'spatial' "
                               "only; set beam.model = 'spatial', or pass a planar motion (lubelink.link.kinematics)"])
    if config.beam.axial_force != "none" and not getattr(motion, "gives_axial_acceleration", False):
        from .validation import ConfigError

        raise ConfigError([f"beam.axial_force = {config.beam.axial_force!r}: needs the axial acceleration of O, "
                           f"which this {type(motion).__name__} does not give; pass A_O1 to the motion, or use "
                           "beam.axial_force = 'none'"])
    compiled, note = _backend(config, motion)
    if config.model.equations in ("double-count", "printed") and not isinstance(motion, SliderCrank):
        raise BackendError(f"model.equations = {config.model.equations!r} needs v_O1, which only the "
                           "slider-crank motion provides")
    return Model(config, motion, make_params(config, motion.table(config.collar.mass), section), compiled, note)
