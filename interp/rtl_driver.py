"""cocotb test module behind `interp run`: drives one core with its stimulus.

The job (core name, options, output file) comes in $INTERP_JOB as JSON; the
per-cycle samples go to the output file as JSON for the CLI to turn into CSV.
"""
import json
import os
from argparse import Namespace

import cocotb

from .cores import load_all
from .tbkit import TB


@cocotb.test()
async def run_job(dut):
    job = json.loads(os.environ["INTERP_JOB"])
    core = load_all()[job["core"]]
    args = Namespace(**job["args"])
    watch = core.model(args).watch
    tb = TB(dut)
    stimulus = core.stimulus(args)
    await tb.reset({name: 0 for name in next_inputs_names(core, args)})
    samples = [tb.sample(watch)]
    inputs = next(stimulus)
    while True:
        await tb.tick(inputs)
        samples.append(tb.sample(watch))
        try:
            inputs = stimulus.send(samples[-1])
        except StopIteration:
            break
    with open(job["out"], "w") as f:
        json.dump(samples, f)


def next_inputs_names(core, args):
    """Input names to hold at 0 during reset: those the stimulus drives."""
    return list(core.stimulus(args).__next__().keys())
