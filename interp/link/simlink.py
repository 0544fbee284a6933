# SPDX-License-Identifier: Apache-2.0
"""A simulated serial port: the Verilator model of rtl/uart_controller.v behind a
pyserial-like object, for `interp send --sim` and the tests.

    link = SimLink(steps="out/steps.csv", line_noise=0.01, seed=1, baud=3_000_000,
                   machine="my.toml")
    link.write(frame)                 # bytes queued onto the model's uart_rx pin
    reply = link.read(8)              # waits in SIMULATED time for link.timeout seconds
    link.now()                        # simulated seconds since reset
    result = link.close()             # {"cycles", "steps", "position", ...}

The harness (interp/simulation/native/board_main.cpp) runs in lockstep with this
object: simulated time advances only inside read() (and in_waiting / sleep()), so a
run is the same for the same seed whatever the host's speed, and every timeout of a
driver that takes its clock from `now` runs in simulated time.  write() only queues
the bytes; they are shifted onto uart_rx bit by bit at CLK_HZ / BAUD from the current
simulated time while later reads run the model.

The model is built once per source and parameter set (cached like the motion harness):
uart_controller with CLK_HZ = the machine file's controller.clock_hz and BAUD = baud,
its other parameters at the design's defaults.
"""
from __future__ import annotations

import json
import math
import subprocess
from pathlib import Path

from ..simulation.runner import RTL

__all__ = ["SimLink", "SimLinkError", "DEFAULT_BAUD", "baud_problem", "default_baud"]

DEFAULT_BAUD = 3_000_000
MIN_BAUD, MAX_BAUD = 115_200, 3_000_000     # uart_link's BAUD range
BLOCK_SECONDS = 60.0        # a read with timeout None gives up after this much simulated time


class SimLinkError(RuntimeError):
    """The simulator refused its input or stopped."""


def _clock_hz(machine) -> int:
    if machine is None:
        from ..gcode.machine import load_machine

        machine = load_machine()
    elif isinstance(machine, (str, Path)):
        from ..gcode.machine import load_machine

        machine = load_machine(str(machine))
    clock = float(getattr(machine, "clock_hz"))
    if clock != int(clock) or clock < 1:
        raise SimLinkError(f"the simulator needs a whole number of Hz for controller.clock_hz (got {clock:g})")
    return int(clock)


def baud_problem(baud: int, clock_hz: int) -> str | None:
    """Why uart_link cannot run at `baud` with this clock (its parameter checks, and the
    rate its whole clocks a bit make: within 3 % of `baud` at 7 or more clocks a bit, 2 %
    below, docs/link-protocol.md), or None."""
    if not MIN_BAUD <= baud <= MAX_BAUD:
        return f"baud {baud}: the link runs at {MIN_BAUD} .. {MAX_BAUD} baud"
    clocks = (clock_hz + baud // 2) // baud
    if clocks < 4:
        return (f"baud {baud}: the link needs 4 clocks a bit, so at most {clock_hz // 4} baud at "
                f"controller.clock_hz = {clock_hz}")
    off = abs(clock_hz / clocks / baud - 1.0)
    if off > (0.03 if clocks >= 7 else 0.02):
        return (f"baud {baud}: {clocks} clocks a bit at controller.clock_hz = {clock_hz} make "
                f"{clock_hz / clocks:.0f} baud, {100 * off:.1f} % off (the link takes 3 %, 2 % below 7 "
                f"clocks a bit): choose a baud near {clock_hz // clocks}")
    return None


def default_baud(clock_hz: int) -> int:
    """The fastest baud the clock makes well enough (baud_problem): 3 Mbaud from 12 MHz on,
    else a whole 115200-multiple or a whole fraction of the clock (at least 4 clocks a bit)."""
    candidates = sorted({DEFAULT_BAUD, *(k * MIN_BAUD for k in range(1, MAX_BAUD // MIN_BAUD + 1)),
                         *(clock_hz // n for n in range(4, clock_hz // MIN_BAUD + 1))}, reverse=True)
    return next((b for b in candidates if baud_problem(b, clock_hz) is None), MIN_BAUD)


class SimLink:
    """pyserial-like transport to the simulated controller (see the module text)."""

    def __init__(self, steps=None, line_noise: float = 0.0, seed: int = 1, baud: int = DEFAULT_BAUD,
                 machine=None, timeout: float | None = 1.0, rtl: Path = RTL, exact: bool = False,
                 parameters: dict | None = None, announce=None):
        from ..simulation.native.build import board_executable

        if not 0.0 <= float(line_noise) <= 1.0:
            raise SimLinkError(f"line noise {line_noise} is out of 0 .. 1")
        self.clock_hz = _clock_hz(machine)
        self.baud = int(baud)
        problem = baud_problem(self.baud, self.clock_hz)
        if problem:
            raise SimLinkError(problem)
        self.timeout = timeout
        self.line_noise = float(line_noise)
        self.seed = int(seed)
        params = {"CLK_HZ": self.clock_hz, "BAUD": self.baud, **(parameters or {})}
        kwargs = {"announce": announce} if announce else {}
        exe = board_executable(params, rtl=rtl, **kwargs)
        cmd = [str(exe), "--clock-hz", str(self.clock_hz), "--baud", str(self.baud),
               "--line-noise", repr(self.line_noise), "--seed", str(self.seed), "--exact", "1" if exact else "0"]
        if steps is not None:
            cmd += ["--steps", str(steps)]
        self._proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                      stderr=subprocess.PIPE, text=True, bufsize=1)
        self._cycle = 0
        self._buffer = bytearray()
        self._result: dict | None = None
        self.bytes_written = 0
        self.bytes_read = 0

    # -- the bridge ------------------------------------------------------------------------
    def _ask(self, line: str) -> str:
        if self._proc is None:
            raise SimLinkError("the simulated link is closed")
        try:
            self._proc.stdin.write(line + "\n")
            self._proc.stdin.flush()
            answer = self._proc.stdout.readline()
        except (BrokenPipeError, OSError):
            answer = ""
        if not answer:
            status = self._proc.wait()
            message = self._proc.stderr.read().strip().splitlines()
            self._proc = None
            raise SimLinkError(f"the simulator stopped (status {status})" + (f": {message[-1]}" if message else ""))
        return answer.rstrip("\n")

    def _run(self, size: int, cycles: int) -> None:
        words = self._ask(f"r {max(0, int(size))} {max(0, int(cycles))}").split(" ")
        self._cycle = int(words[1])
        if len(words) > 2 and words[2]:
            self._buffer += bytes.fromhex(words[2])

    def _cycles(self, seconds: float) -> int:
        return max(0, math.ceil(seconds * self.clock_hz - 1e-9))

    # -- pyserial-like ---------------------------------------------------------------------
    def write(self, data) -> int:
        data = bytes(data)
        if data:
            words = self._ask("w " + data.hex()).split(" ")
            self._cycle = int(words[1])
        self.bytes_written += len(data)
        return len(data)

    def read(self, size: int = 1) -> bytes:
        """Up to `size` bytes: waits (simulated) until there are `size` or `timeout` seconds
        have passed (timeout 0: one character time at most; None: up to BLOCK_SECONDS)."""
        if len(self._buffer) < size:
            if self.timeout is None:
                seconds = BLOCK_SECONDS
            elif self.timeout <= 0:
                seconds = 10.0 / self.baud
            else:
                seconds = self.timeout
            self._run(size - len(self._buffer), self._cycles(seconds))
        out = bytes(self._buffer[:size])
        del self._buffer[:size]
        self.bytes_read += len(out)
        return out

    @property
    def in_waiting(self) -> int:
        """Bytes received; if none, the model first runs one character time (so that a
        polling loop advances simulated time)."""
        if not self._buffer:
            self._run(1, self._cycles(10.0 / self.baud))
        return len(self._buffer)

    def reset_input_buffer(self) -> None:
        self._buffer.clear()

    def flush(self) -> None:
        pass

    def now(self) -> float:
        """Simulated seconds since the controller's reset."""
        return self._cycle / self.clock_hz

    @property
    def cycle(self) -> int:
        return self._cycle

    def sleep(self, seconds: float) -> None:
        """Let `seconds` of simulated time pass (bytes that arrive are kept for read())."""
        self._run(1 << 62, self._cycles(seconds))

    def set_pin(self, name: str, value: int) -> None:
        """Drive an input pin of the model: estop, limit (3 bits: x, y, z), probe, rst (the reset)."""
        words = self._ask(f"p {name} {int(value)}").split(" ")
        self._cycle = int(words[1])

    def set_switch(self, axis: int, side: str, at: int) -> None:
        """A limit switch on axis 0..2 at harness position `at` (the pulses counted at the step
        pins since the reset, which a POS write does not move): active at or below it for
        side "min", at or above for "max"; that limit pin then follows the position."""
        words = self._ask(f"s {int(axis)} {int(side == 'max')} {int(at)}").split(" ")
        self._cycle = int(words[1])

    def set_touch(self, axis: int, side: str, at: int) -> None:
        """A probe touch on axis 0..2 at harness position `at`, side as for set_switch: the probe
        pin then follows the position, high while any touch is reached (a plate, an edge)."""
        words = self._ask(f"t {int(axis)} {int(side == 'max')} {int(at)}").split(" ")
        self._cycle = int(words[1])

    def close(self) -> dict:
        """Stop the simulator; the run's figures: cycles, first_push, steps, position [x, y, z]
        (pulses counted at the pins), bits / flipped bits each way, chars dropped, skipped
        cycles, wall_seconds, plus seconds (simulated) and cycles_per_second (simulation speed)."""
        if self._result is not None:
            return self._result
        if self._proc is None:             # the simulator stopped (its error was raised then)
            self._result = {"cycles": self._cycle, "seconds": self._cycle / self.clock_hz, "stopped": True}
            return self._result
        line = self._ask("q")
        self._proc.wait()
        self._proc = None
        result = json.loads(line)
        result["seconds"] = result["cycles"] / self.clock_hz
        simulated = result["cycles"] - result["skipped"]
        result["cycles_per_second"] = simulated / result["wall_seconds"] if result["wall_seconds"] > 0 else 0.0
        result["bytes_written"] = self.bytes_written
        result["bytes_read"] = self.bytes_read
        self._result = result
        return result

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self._proc is not None:
            try:
                self.close()
            except SimLinkError:
                pass
        return False

    def __del__(self):
        proc = getattr(self, "_proc", None)
        if proc is not None and proc.poll() is None:
            proc.kill()
            proc.wait()
