# SPDX-License-Identifier: Apache-2.0
"""cocotb test module behind `interp curve-error`: many curve moves in one simulation.

$INTERP_JOBS_FILE names a JSON file (or $INTERP_JOBS holds the JSON) with a list of CLI argument dicts for the `curve` core; the
visited nodes of each move go to $INTERP_OUT as JSON (one list per job).
"""
import json
import os
from argparse import Namespace

import cocotb

from ..cores import load_all
from ..testing.tbkit import TB, run_stimulus
from .jobs import job_from_env


@cocotb.test()
async def run_jobs(dut):
    core = load_all()["curve"]
    tb = TB(dut)
    results = []
    first = True
    for job in job_from_env("INTERP_JOBS"):
        args = Namespace(**job)
        watch = core.model(args).watch
        stimulus = core.stimulus(args)
        inputs = next(stimulus)
        if first:
            await tb.reset({k: 0 for k in inputs})
            first = False
        prog = core.program(args)
        points = [(prog.x0, prog.y0)]
        samples = await run_stimulus(tb, stimulus, lambda: tb.sample(watch), first=inputs)
        for s in samples[1:]:
            if s["step_x"] or s["step_y"]:
                points.append((s["x_q"], s["y_q"]))
        results.append(points)
    with open(os.environ["INTERP_OUT"], "w") as f:
        json.dump(results, f)
