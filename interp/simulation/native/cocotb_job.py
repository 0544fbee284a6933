# SPDX-License-Identifier: Apache-2.0
"""A native-harness job under cocotb (interp/simulation/motion_driver.py), for cross-checks.

The job goes to the driver as a JSON file whose path is in $INTERP_JOB_FILE (no
size limit); the driver writes the steps CSV and a result JSON like the native
harness's.
"""
from __future__ import annotations

import json
import tempfile
from pathlib import Path

from ..jobs import job_env
from ..runner import run_cocotb


def run(rows, sim: str, timing: tuple[int, int, int], steps_path, max_cycles: int, vcd, parameters: dict,
        progress=None, settings: dict | None = None, controls=(), push_interval: int = 1) -> dict:
    with tempfile.TemporaryDirectory(prefix="interp-cocotb-") as tmp:
        out = Path(tmp) / "result.json"
        pulse_width, setup, hold = timing
        env = job_env("INTERP_JOB", {
            "commands": [list(r) for r in rows], "max_cycles": int(max_cycles),
            "timing": {"pulse_width": pulse_width, "setup": setup, "hold_time": hold},
            "steps": str(Path(steps_path).resolve()), "out": str(out), "settings": settings or {},
            "controls": [list(c) for c in controls], "push_interval": int(push_interval)}, tmp)
        run_cocotb(toplevel="motion_top", test_module="interp.simulation.motion_driver", sim=sim,
                   parameters=parameters, env=env,
                   waves=str(vcd) if vcd is not None else None, name="motion_top_job", test_dir=Path(tmp),
                   quiet=True)
        result = json.loads(out.read_text())
    if progress:
        progress(result["cycles"], result["steps"], result["dispatched"])
    return result
