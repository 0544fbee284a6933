# SPDX-License-Identifier: Apache-2.0
"""The generated speed harness (interp/simulation/harness.py) builds and runs natively, and counts
what the cycle model predicts: lin_std at WIDTH 8, a short move restarted whenever
the core is idle."""
from interp.simulation import harness, speed
from interp.cores import load_all


def model_count(core, argv, width, cycles):
    """Steps the harness must print: start <= !busy && !start at every edge, as in the harness."""
    inputs = harness.core_inputs(core, argv, width)
    model = core.model(harness.core_args(core, argv, width))
    start, steps = 0, 0
    for _ in range(cycles):
        before = model.sample()
        steps += any(before[f"step_{a}"] for a in core.axes)
        model.clock({**inputs, "start": start, "tick": 1})
        start = int(not before["busy"] and not start)
    return steps


def test_harness_counts_like_the_model(sim, tmp_path):
    core, argv, width, cycles = load_all()["lin-std"], ["--x", "5", "--y", "-3"], 8, 300
    module = f"speed_selftest_{sim}"
    src = harness.generate(module, core.toplevel, {"WIDTH": width}, harness.core_inputs(core, argv, width),
                           core.axes, cycles=100, out=tmp_path)
    got, seconds = speed.run_harness(module, sim, plusargs=[f"+cycles={cycles}"], src=src)
    assert got == {"cycles": cycles, "steps": model_count(core, argv, width, cycles)}
    assert 0 < got["steps"] < cycles and seconds < 10


def test_every_cli_core_gets_a_harness():
    for name, core in load_all().items():
        module, src = harness.for_row(name)
        text = src.read_text()
        assert f"module {module};" in text and f"{core.toplevel} #(" in text and ".tick(1'b1)" in text
    assert ".cmd_valid(start)" in harness.for_row("motion_top")[1].read_text()
    assert harness.for_row("feed_rate") is None
