# SPDX-License-Identifier: Apache-2.0
"""The benches' small build of rtl/motion_top.v (W = 16, FRAC = 16) and a cocotb run of commands on it.

Used by the motion benchmarks (interp/benchmarks/motion.py), the speed harness
(interp/simulation/harness.py) and tb/motion_top; `interp gcode` uses the
32-bit build through interp/simulation/native.
"""
from __future__ import annotations

import json
import tempfile
from pathlib import Path

PARAMETERS = {"W": 16, "FRAC": 16, "FEED_W": 16, "NW": 16, "PF": 12, "LEN_W": 34, "ZW": 48, "MW": 6,
              "QDEPTH": 4, "QLW": 3, "SDEPTH": 2, "TW": 4}
FRAC, FEED_MAX = 16, (1 << 16) - 1
QUANTUM = 64                # the benches' speed quantum A (path units per clock): 1/1024 step per clock
PF = PARAMETERS["PF"]


def simulate(commands, sim: str, timing: dict, vcd: str | None = None, max_cycles: int = 5_000_000,
             settings: dict | None = None, controls=()) -> dict:
    """Commands (with their profiles: interp.models.profile.profile_for) through the benches'
    motion_top build with cocotb; the driver's result.  settings: speed_quantum, block_shift,
    jerk_shift, override; controls: [(cycle, "hold" | "resume" | "override", value)]."""
    from .jobs import job_env
    from .runner import run_cocotb

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "result.json"
        job = {"commands": [c.ports() for c in commands], "timing": timing, "out": str(out),
               "max_cycles": max_cycles, "settings": settings or {}, "controls": [list(c) for c in controls]}
        run_cocotb(toplevel="motion_top", test_module="interp.simulation.motion_driver", sim=sim,
                   parameters=PARAMETERS, env=job_env("INTERP_JOB", job, tmp), waves=vcd,
                   name="motion_top", test_dir=Path(tmp), quiet=True)
        return json.loads(out.read_text())
