"""The time-stepping kernels' spring law bound at compile time (bounce.methods._stepping.with_physics): one
kernel per template and law, cached on disk, so a fresh process loads it instead of compiling it (issue 22)."""

from __future__ import annotations

import json
import os
import subprocess
import sys

from bounce.methods import _stepping, moreau_jean, penalty
from bounce.springs import SPRING_LAWS

LOAD_KERNELS = """
import json
from bounce.methods import _stepping, moreau_jean, penalty
from bounce.springs import SPRING_LAWS
stats = {}
for module in (penalty, moreau_jean):
    for law in (SPRING_LAWS["linear"](), SPRING_LAWS["power"](rho=1.0, a=0.5, b=0.5)):
        module._warm(law)
        kernel = _stepping.with_physics(module._advance, type(law))
        stats[module.__name__ + "." + kernel.__qualname__] = [sum(kernel.stats.cache_hits.values()), sum(kernel.stats.cache_misses.values())]
print(json.dumps(stats))
"""


def test_a_fresh_process_loads_each_kernel_from_the_disk_cache():
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    runs = [json.loads(subprocess.run([sys.executable, "-c", LOAD_KERNELS], env=env, capture_output=True, text=True,
                                      check=True).stdout) for _ in range(2)]
    assert len(runs[1]) == 4
    assert all(hits == 1 and misses == 0 for hits, misses in runs[1].values()), runs[1]


def test_one_kernel_per_template_and_law_named_by_both():
    linear, power = SPRING_LAWS["linear"], SPRING_LAWS["power"]
    kernels = {(t, law): _stepping.with_physics(t, law) for t in (penalty._advance, moreau_jean._advance)
               for law in (linear, power)}
    assert len({id(k) for k in kernels.values()}) == 4
    assert _stepping.with_physics(penalty._advance, linear) is kernels[penalty._advance, linear]
    for (template, law), kernel in kernels.items():
        assert kernel.__qualname__.startswith(f"{template.__qualname__}[{law.name}-")
        assert kernel.py_func.__globals__["force"] is law.physics.force
    # the template itself stays unbound: only with_physics gives it a law
    assert penalty._advance.__globals__["force"] is None
