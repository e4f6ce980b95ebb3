"""The sweep definition: :class:`Sweep` (the grid, what is stored, its hash) and :class:`Axis`.

A :class:`Sweep` is made by :func:`lubelink.sweep.read_sweep` (:mod:`.parse`), which validates
the sweep file; here are its shape, the overrides and label of each point, its identity (the
definition as TOML, the SHA-256 hash a store is checked against) and the validation of every
point's configuration.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from ..config import ConfigError
from .schema import SWEEP_FORMAT, _fmt

__all__ = ["Axis", "Sweep"]


@dataclass(frozen=True)
class Axis:
    """One swept parameter: a dimension of the results.

    Attributes
    ----------
    name : str
        ``"section.key"``; also the name of the dimension and its coordinate.
    values : tuple
        The values in order, in the parameter's type.
    scale : str
        ``"list"``, ``"linear"`` or ``"log"`` (how the values were given).
    """

    name: str
    values: tuple
    scale: str = "list"


@dataclass(frozen=True)
class Sweep:
    """A parsed, validated sweep definition (see :func:`read_sweep`).

    The results have one dimension per :class:`Axis` (in file order) and, when
    explicit points are given, a last dimension ``point``. ``hash`` identifies
    everything that decides the stored values and their layout.
    """

    base: str
    base_config: object
    fixed: dict
    axes: tuple
    point_names: tuple
    point_rows: tuple
    quantities: tuple
    time_series: tuple
    max_impacts: int
    invalid_points: str
    origin: str

    # ------------------------------------------------------------ shape
    @property
    def dims(self) -> tuple:
        return tuple(a.name for a in self.axes) + (("point",) if self.point_rows else ())

    @property
    def shape(self) -> tuple:
        return tuple(len(a.values) for a in self.axes) + ((len(self.point_rows),) if self.point_rows else ())

    @property
    def size(self) -> int:
        return int(np.prod(self.shape))

    def overrides(self, flat: int) -> dict:
        """``{"section.key": value}`` of point ``flat`` (C order over :attr:`shape`)."""
        index = np.unravel_index(flat, self.shape)
        out = {a.name: a.values[i] for a, i in zip(self.axes, index)}
        if self.point_rows:
            out.update(zip(self.point_names, self.point_rows[index[-1]]))
        return out

    def label(self, flat: int) -> str:
        return ", ".join(f"{k}={_fmt(v)}" for k, v in self.overrides(flat).items())

    # ------------------------------------------------------------ identity
    def definition(self) -> dict:
        """The sweep as a TOML-ready dict, with the base configuration resolved in full."""
        from ..config import to_dict

        store = {"quantities": list(self.quantities), "time_series": list(self.time_series)}
        if "impact_times" in self.quantities:
            store["max_impacts"] = self.max_impacts
        data = {"base": self.base, "vary": {a.name: list(a.values) for a in self.axes}, "store": store}
        if self.fixed:
            data["set"] = {k: list(v) if isinstance(v, tuple) else v for k, v in self.fixed.items()}
        if self.point_rows:
            data["points"] = [dict(zip(self.point_names, row)) for row in self.point_rows]
        data["base_config"] = to_dict(self.base_config)
        return data

    @cached_property
    def hash(self) -> str:
        """SHA-256 of the resolved base configuration, the grid and the stored quantities."""
        data = self.definition()
        data.pop("base")  # the resolved configuration counts, not how it was named
        data.pop("set", None)  # already folded into base_config
        data["format"] = SWEEP_FORMAT.split(".")[0]
        text = json.dumps(data, sort_keys=True, default=list)
        return hashlib.sha256(text.encode()).hexdigest()

    def to_toml(self) -> str:
        import tomli_w

        data = self.definition()
        data.pop("base_config")
        return tomli_w.dumps(data)

    # ------------------------------------------------------------ points
    def point_configs(self, progress=None):
        """Validate every point: ``(configs, invalid)`` keyed by flat index.

        ``configs[flat]`` is the validated :class:`~lubelink.params.Config`;
        ``invalid[flat]`` the list of problems of a point that fails
        :func:`lubelink.config.validate`. ``progress`` is called with the count
        of points checked.
        """
        from ..config import validate

        configs, invalid = {}, {}
        for flat in range(self.size):
            over = self.overrides(flat)
            by_section = {}
            for name, value in over.items():
                section, key = name.split(".", 1)
                by_section.setdefault(section, {})[key] = value
            cfg = replace(self.base_config, **{s: replace(getattr(self.base_config, s), **kv)
                                               for s, kv in by_section.items()})
            try:
                configs[flat] = validate(cfg)
            except ConfigError as exc:
                invalid[flat] = exc.problems
            if progress is not None:
                progress(flat + 1)
        return configs, invalid

    def invalid_report(self, invalid: dict) -> list:
        """One line per distinct problem, naming the first point it occurs at and how many more."""
        groups = {}
        for flat, problems in invalid.items():
            for p in problems:
                groups.setdefault(p, []).append(flat)
        lines = []
        for problem, flats in list(groups.items())[:20]:
            more = f" and {len(flats) - 1} more point(s)" if len(flats) > 1 else ""
            lines.append(f"{self.origin}: invalid point ({self.label(flats[0])}{more}): {problem}")
        if len(groups) > 20:
            lines.append(f"{self.origin}: ... and {len(groups) - 20} more distinct problems")
        lines.append(f"{self.origin}: {len(invalid)} of {self.size} points are invalid; fix the "
                     "ranges, or set invalid_points = \"record\" to store them as failed points")
        return lines
