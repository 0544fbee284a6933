# SPDX-License-Identifier: Apache-2.0
"""Shared pieces of the golden models: the cycle-model protocol and move stimulus.

A cycle model mirrors a core's registers.  `clock(inputs)` is one rising edge;
`sample(watch)` returns the registered outputs (and the internal registers a
bench compares) as integers, exactly as the RTL shows them between edges.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Generator, Iterable, Mapping

Stimulus = Generator[Mapping[str, int], dict, None]

# Step/dir/busy/done: every interpolator core shows these.
MOTION_OUTPUTS = {"step_x": False, "step_y": False, "dir_x": False, "dir_y": False,
                  "busy": False, "done": False}


class CycleModel:
    """Base class: subclasses set `watch` (name -> signed) and implement clock()."""

    watch: Mapping[str, bool] = MOTION_OUTPUTS

    def clock(self, inputs: Mapping[str, int]) -> None:
        raise NotImplementedError

    def sample(self, names: Iterable[str] | None = None) -> dict[str, int]:
        names = self.watch if names is None else names
        return {name: int(getattr(self, name)) for name in names}


def drive(model: CycleModel, stimulus: Stimulus) -> list[dict[str, int]]:
    """Run a model alone with the same protocol as tbkit.scoreboard."""
    samples = [model.sample()]
    inputs = next(stimulus)
    while True:
        model.clock(inputs)
        samples.append(model.sample())
        try:
            inputs = stimulus.send(samples[-1])
        except StopIteration:
            return samples


def move(load: Mapping[str, int], tick: Callable[[int], int] = lambda c: 1,
         max_cycles: int = 1_000_000, idle_after: int = 2,
         end: str = "done") -> Stimulus:
    """Pulse `start` with the `load` inputs, tick by `tick(cycle)`, stop after `end`.

    Cycle 0 is the cycle in which `start` is high.  The move ends when `end`
    (default: `done`) or, for cores that have one, `error` is seen; then
    `idle_after` more cycles run to show nothing else moves.  A move that
    never ends raises after `max_cycles`.
    """
    sample = yield {**load, "start": 1, "tick": tick(0)}
    cycle = 1
    while not (sample[end] or sample.get("error")):
        if cycle > max_cycles:
            raise RuntimeError(f"no {end} after {max_cycles} cycles")
        sample = yield {**load, "start": 0, "tick": tick(cycle)}
        cycle += 1
    for _ in range(idle_after):
        sample = yield {**load, "start": 0, "tick": tick(cycle)}
        cycle += 1


@dataclass
class Run:
    """What `interp run`/`interp model` write: steps and (patent cores) the trace."""

    steps: list[tuple[int, int, int]] = field(default_factory=list)
    trace: list[dict] = field(default_factory=list)
    samples: list[dict[str, int]] = field(default_factory=list)


def steps_of(samples: list[dict[str, int]], axes: str = "xy") -> list[tuple[int, ...]]:
    """(cycle, dx, dy[, dz]) for every sampled cycle with at least one step strobe.

    Sample i is the state after i rising edges, i.e. during cycle i, where
    cycle 0 is the one in which `start` was high.
    """
    rows = []
    for cycle, s in enumerate(samples):
        deltas = [(-1 if s[f"dir_{a}"] else 1) if s[f"step_{a}"] else 0 for a in axes]
        if any(deltas):
            rows.append((cycle, *deltas))
    return rows


def sequence(inputs: Iterable[Mapping[str, int]]) -> Stimulus:
    """A fixed list of per-cycle inputs as a stimulus (samples are not looked at)."""
    for item in inputs:
        yield item
