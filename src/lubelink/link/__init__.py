"""The flexible link's model layer: what compiled code runs for the planar and the spatial link.

``kinematics`` and ``spatial_motion`` the rigid motion (one layout: ``RigidMotion``,
``SpatialRigidMotion``); ``section`` and ``spatial_section`` a variable cross-section's eigenbases;
``faces`` the collar on one pair of faces, which both links call on their blocks of modes;
``model`` the planar link's right-hand side, Jacobian and gap; ``spatial`` and ``spatial_model``
the spatial link's equations, right-hand side and gap. The Python side (parameters from a
configuration, the backend, one-state helpers) is :mod:`lubelink.assembly` and
:mod:`lubelink.spatial_assembly`.
"""

import importlib as _importlib


def __getattr__(name):
    """The submodules on first use (``lubelink.link.kinematics`` after ``import lubelink``)."""
    try:
        return _importlib.import_module(f".{name}", __name__)
    except ModuleNotFoundError as exc:
        if exc.name != f"{__name__}.{name}":
            raise
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None
