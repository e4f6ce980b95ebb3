"""Imported once by the pool's forkserver (:data:`lubelink.sweep.local.PRELOAD`): run a sweep's first
point for a moment, so that every worker forked from the server starts with its compiled kernels
loaded (about 0.6 s a worker otherwise, on its first point).

The point comes in the environment variable :data:`ENV` (set by
:func:`lubelink.sweep.local.start_server` while it starts the server): a JSON object with its
configuration (TOML), the stored quantities and a file to create once done (``ready``: the parent
waits for it, interruptible, before starting the workers with Ctrl-C held; a cold cache compiles
here, once for every worker). Nothing here may stop the server: any failure only leaves the workers
to load the kernels themselves.
"""

from __future__ import annotations

import os

#: The environment variable holding the point to warm up with.
ENV = "LUBELINK_SWEEP_WARM"
#: Samples of the shortened run [output steps]: long enough to take compiled steps and an output.
WARM_STEPS = 20


def warm(text):
    """Run the point of ``text`` (:data:`ENV`'s value) to ``WARM_STEPS`` output steps, the way a worker
    computes a point (:func:`lubelink.sweep.compute._compute_points`)."""
    import json
    import tomllib
    from dataclasses import replace

    from ..config import from_stored, validate
    from .compute import _compute_points, _TaskOptions

    spec = json.loads(text)
    config = validate(from_stored(tomllib.loads(spec["config"]), "the warm-up point"))
    s = config.solver
    config = replace(config, solver=replace(s, t_end=min(s.t_end, WARM_STEPS * s.output_step)))
    opts = _TaskOptions(quantities=tuple(spec["quantities"]), time_series=(), max_impacts=int(spec["max_impacts"]),
                        n_time=0, output_step=s.output_step, tag="warm")
    _compute_points([0], [{}], config, opts)


def _main():
    text = os.environ.pop(ENV, None)
    if not text:
        return
    try:
        warm(text)
    except Exception:  # noqa: BLE001 - a warm-up that fails costs the workers their own loading, nothing else
        pass
    finally:  # ready: the parent waits for this file, Ctrl-C free, before it holds Ctrl-C to start the workers
        try:
            import json

            spec = json.loads(text)
            ready = spec.get("ready")
            if ready and os.getppid() == spec.get("parent"):  # (a parent gone no longer waits: no file left behind)
                open(ready, "a").close()
        except Exception:  # noqa: BLE001 - the parent stops waiting after a while
            pass


_main()
