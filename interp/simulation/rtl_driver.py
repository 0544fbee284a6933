# SPDX-License-Identifier: Apache-2.0
"""cocotb test module behind `interp run`: drives one core with its stimulus.

The job (core name, options, output file) comes as JSON in the file named by
$INTERP_JOB_FILE (or in $INTERP_JOB itself); the
per-cycle samples go to the output file as JSON for the CLI to turn into CSV.
"""
import json
from argparse import Namespace

import cocotb

from ..cores import load_all
from ..testing.tbkit import TB, read, run_stimulus
from .jobs import job_from_env


@cocotb.test()
async def run_job(dut):
    job = job_from_env("INTERP_JOB")
    core = load_all()[job["core"]]
    args = Namespace(**job["args"])
    watch = core.model(args).watch
    probes = getattr(core, "probes", {})            # watched names that are signals inside the DUT
    tb = TB(dut)
    stimulus = core.stimulus(args)
    first = next(stimulus)
    await tb.reset({name: 0 for name in first})     # the inputs the stimulus drives, held low

    def sample():
        return {name: read(dut, probes.get(name, name), signed) for name, signed in watch.items()}

    samples = await run_stimulus(tb, stimulus, sample, first=first)
    with open(job["out"], "w") as f:
        json.dump(samples, f)
