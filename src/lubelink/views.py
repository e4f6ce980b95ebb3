"""The compiled code's view of the parameters: each section of :mod:`lubelink.params` as a named tuple.

A view has the dataclass's field names; floats stay floats and integers integers (so every
configuration gives compiled code the same types) and a choice becomes its index in
:data:`lubelink.params.CHOICES`. The view classes live at this module's top level, so that they
pickle by reference (Numba keys its on-disk cache on the parameter types).
"""

from __future__ import annotations

from collections import namedtuple
from dataclasses import fields
from functools import lru_cache

from .params import CHOICES, Beam, Collar, Contact, Film, Mechanism, ModelOptions

__all__ = ["kernel_view", "MechanismView", "BeamView", "FilmView", "CollarView", "ContactView", "ModelOptionsView"]


def _view_type(cls):
    view = namedtuple(f"{cls.__name__}View", [f.name for f in fields(cls) if f.metadata.get("kernel", True)])
    view.__module__ = __name__
    return view


MechanismView = _view_type(Mechanism)
BeamView = _view_type(Beam)
FilmView = _view_type(Film)
CollarView = _view_type(Collar)
ContactView = _view_type(Contact)
ModelOptionsView = _view_type(ModelOptions)
_VIEWS = {Mechanism: ("mechanism", MechanismView), Beam: ("beam", BeamView), Film: ("film", FilmView),
          Collar: ("collar", CollarView), Contact: ("contact", ContactView),
          ModelOptions: ("model", ModelOptionsView)}


def kernel_view(section):
    """The compiled code's view of a parameter section: a named tuple with the same field names.

    Floats stay floats and integers integers (so every configuration gives compiled code the same
    types); a choice becomes its index in :data:`CHOICES`; a pair stays a tuple of floats. A field with
    ``metadata={"kernel": False}`` stays out (its value reaches compiled code through another field).
    """
    view, plan = _view_plan(type(section))
    values = []
    for field_name, choices, integer in plan:
        v = getattr(section, field_name)
        if choices is not None:
            v = choices.index(v)
        elif isinstance(v, tuple):
            v = tuple(float(c) for c in v)
        elif integer or isinstance(v, bool):
            v = int(v)
        else:
            v = float(v)
        values.append(v)
    return view(*values)


@lru_cache(maxsize=None)
def _view_plan(cls):
    """``(view, ((field, choices or None, integer), ...))`` of a section class, for :func:`kernel_view`."""
    name, view = _VIEWS[cls]
    return view, tuple((f.name, CHOICES.get(f"{name}.{f.name}"), f.type in ("int", int)) for f in fields(cls)
                       if f.metadata.get("kernel", True))
