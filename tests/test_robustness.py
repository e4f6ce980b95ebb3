"""Robustness: any configuration gives finite results or a validation error naming a key.

The fuzz test draws configurations the way users write them by hand:
valid values, out-of-range and extreme magnitudes, NaN and infinities,
wrong types, unknown keys and missing sections. Each must either be
rejected by validation with a message naming ``section.key`` or simulate
to finite values (possibly ending early with a status and a message).
``HYPOTHESIS_PROFILE=long`` runs many more examples.
"""

import math
import re

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import lubelink
from lubelink.config import RULES, ConfigError
from lubelink.params import SECTION_TYPES

numbers = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=-1e3, max_value=1e3),
    st.integers(min_value=-10**6, max_value=10**6),
    st.sampled_from([0, 0.0, -0.0, 1e-300, 1e300, -1.0, 1.0, 2.0]),
)
junk = st.one_of(st.text(max_size=5), st.booleans(), st.lists(st.integers(), max_size=3),
                 st.dictionaries(st.text(max_size=3), st.integers(), max_size=2))
choices = {k: list(rule_text.split("one of ")[1].replace('"', "").split(", "))
           for sec in RULES.values() for k, (_, rule_text) in sec.items() if rule_text.startswith("one of")}


def value_for(section, key):
    default = getattr(SECTION_TYPES[section](), key)
    options = [st.just(default), numbers, junk]
    if key in choices:
        options.append(st.sampled_from(choices[key]))
    if isinstance(default, tuple):
        options.append(st.lists(numbers, min_size=1, max_size=3))
    elif isinstance(default, float) and default != 0 and math.isfinite(default):
        options.append(st.floats(0.5, 2.0).map(lambda f, d=default: d * f))  # plausible neighbours
    return st.one_of(*options)


@st.composite
def configurations(draw):
    data = {}
    for section, rules in RULES.items():
        if draw(st.booleans()):
            continue  # missing section: defaults
        keys = draw(st.lists(st.sampled_from(sorted(rules)), unique=True, max_size=3))
        data[section] = {k: draw(value_for(section, k)) for k in keys}
    if draw(st.integers(0, 9)) == 0:
        data.setdefault("beam", {})[draw(st.sampled_from(["mode", "densty", "x"]))] = 1
    if draw(st.integers(0, 9)) == 0:
        data["scenario"] = draw(st.sampled_from(["paper", "paper-dry", "paper-impact", "nope", 3]))
    return data


KEY = re.compile(r"(scenario|\[?[a-z_]+\]?[.][a-z_]+|unknown section \[[^\]]+\]|\[[a-z_]+\])")


@settings(deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(configurations())
def test_fuzzed_configurations_give_results_or_named_errors(data):
    try:
        config = lubelink.resolve_config(data)
    except ConfigError as exc:
        assert exc.problems
        for problem in exc.problems:
            assert KEY.search(problem), problem
            assert "\n" not in problem
        return
    # keep each simulation short: the fuzz is about inputs, not long runs
    short = {"solver.t_end": min(config.solver.t_end, 0.01), "solver.output_step": 1e-3,
             "solver.max_wall_time": 5.0, "output.x_points": 5, "output.pad_points": 5}
    try:
        config = lubelink.resolve_config(config, short)
    except ConfigError as exc:  # e.g. the shortened run no longer fits the output step
        assert all(KEY.search(p) for p in exc.problems)
        return
    ds = lubelink.simulate(config)
    for name, var in ds.data_vars.items():
        if var.dtype.kind == "f" and not name.startswith("impact"):
            assert np.all(np.isfinite(var.values)), name
    assert ds.attrs["status"] in {"complete", "film_breakdown", "chatter", "solver_failure", "timeout"}
    assert ds.attrs["message"]
