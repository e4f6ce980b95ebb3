"""lubelink.warmup: after ``compile_all`` (which the session's conftest runs first), no built-in scenario and
no command compiles anything.

The check is Numba's own: its ``numba:compile`` event fires when a function is compiled, not when it is
loaded from the on-disk cache. A fresh process runs every scenario (and the steady-state commands) briefly
and records the events.
"""

import json
import os
import subprocess
import sys

import pytest

from lubelink import _jit

SCRIPT = r"""
import json, sys
from numba.core import event

compiled = []

class Record(event.Listener):
    def on_start(self, ev):
        compiled.append(f"{getattr(ev.data.get('dispatcher'), '__qualname__', ev.data.get('dispatcher'))}"
                        f"{ev.data.get('args')}")

    def on_end(self, ev):
        pass

event.register("numba:compile", Record())

import lubelink
from lubelink.scenarios import SCENARIOS

done = {}
for name in SCENARIOS:
    before = len(compiled)
    lubelink.simulate(name, {"solver.t_end": 0.01, "solver.output_step": 1e-3})
    done[name] = compiled[before:]
before = len(compiled)
lubelink.periodic("paper-dry", {"beam.modes": 1})
done["periodic"] = compiled[before:]
print(json.dumps(done))
"""


@pytest.mark.skipif(not _jit.ENABLED, reason="Numba is off (LUBELINK_JIT=0)")
def test_nothing_compiles_after_compile_all():
    env = dict(os.environ, LUBELINK_FIRST_RUN="compile")
    out = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True, env=env, timeout=900)
    assert out.returncode == 0, out.stderr[-3000:]
    done = json.loads(out.stdout.strip().splitlines()[-1])
    compiled = {name: kernels for name, kernels in done.items() if kernels}
    assert not compiled, f"compiled after compile_all: {compiled}"
