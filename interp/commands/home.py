# SPDX-License-Identifier: Apache-2.0
"""`interp home`: the homing cycle, as Grbl's $H runs it (docs/host-driver.md, "Homing").

  interp home (--port DEVICE [--baud B] | --sim) [--machine FILE.toml] [--axes XYZ]

Each axis with a home end in the machine file (`axis.X.home = "min"` or "max"), in
`homing.order`: a seek towards its limit switch at `homing.seek_mm_min` (the switch
stops the steps in the clock it shows, ERROR 17), a pull-off of `homing.pull_off_mm`,
a slow approach at `homing.locate_mm_min`, a pull-off again, then POS_<axis> is set so
that the axis stands at that travel end (`axis.X.min_mm` or `max_mm`): the switch is a
pull-off beyond it.  An axis resting on its switch pulls off first; a switch that
bounces while it lets go is ridden over.  The moves are compiled as `interp gcode` compiles a G91 G1
move, without the travel limits (the position is not known yet).  Exit status: 0 homed,
1 a switch not found, still active after a pull-off, another error or a link error, 2
usage (no axis to home).  --sim homes the simulated controller (as `interp send --sim`),
whose machine powers up SIM_PULL_OFFS pull-offs from each home switch.
"""
from __future__ import annotations

import sys

from ..cores import UsageError
from ..gcode.machine import AXES, Machine, load_machine
from ..link import protocol as p
from ..link.driver import Driver, LinkError, MismatchError, read_position
from . import send
from .jog import relative_move, unlimited
from .send import add_link_options, check_link_args, mm_text

SEEK_TRAVELS = 1.5          # the seek goes at most 1.5 travels (and a pull-off) towards the switch
BOUNCES = 5                 # a pull-off tripped again by a bouncing switch is run again this often
SIM_PULL_OFFS = 2           # --sim: the simulated machine powers up this many pull-offs from each switch


class HomingError(Exception):
    """The cycle cannot go on: one line."""


def move(driver: Driver, machine: Machine, free: Machine, axis: int, distance_mm: float, rate: float):
    """One G91 G1 move of `axis` by distance_mm at `rate` mm/min: the run's Outcome."""
    return relative_move(driver, machine, free, [distance_mm if a == axis else 0.0 for a in range(3)], rate)


def switch_active(driver: Driver, axis: int) -> bool:
    return bool(driver.read_register("INPUTS") >> (1 + axis) & 1)


def expect_switch(outcome, axis: int, what: str) -> None:
    """The move must have ended on this axis's limit switch."""
    name = AXES[axis].upper()
    if outcome.status == "error" and outcome.error == 17 and outcome.limits == 1 << axis:
        return
    if outcome.status == "error" and outcome.error == 17:
        others = " ".join(AXES[a].upper() for a in range(3) if outcome.limits >> a & 1)
        raise HomingError(f"{name}: the {others} limit switch tripped during the {what}")
    if outcome.status == "error":
        raise HomingError(f"{name}: {what_stopped(outcome)} during the {what}")
    raise HomingError(f"{name}: no limit switch was found during the {what}")


def pull_off(driver: Driver, machine: Machine, free: Machine, axis: int, away: float) -> None:
    """Move `away` (+1 / -1) by homing.pull_off_mm at the seek speed until the switch lets go.
    A switch that bounces as it lets go trips the limit again (ERROR 17 on this axis): the
    rest of the distance is run again, up to BOUNCES times."""
    name, spm = AXES[axis].upper(), machine.steps_per_mm[axis]
    distance = machine.homing["pull_off_mm"]
    target = read_position(driver)[axis] + round(away * distance * spm)
    for _ in range(BOUNCES + 1):
        rest = (target - read_position(driver)[axis]) / spm
        if abs(rest) * spm < 0.5:
            break
        outcome = move(driver, machine, free, axis, rest, machine.homing["seek_mm_min"])
        if outcome.status == "done":
            break
        if not (outcome.status == "error" and outcome.error == 17 and outcome.limits == 1 << axis):
            raise HomingError(f"{name}: {what_stopped(outcome)} during the pull-off")
    else:
        raise HomingError(f"{name}: the limit switch tripped again {BOUNCES} times during the pull-off")
    if switch_active(driver, axis):
        raise HomingError(f"{name}: the limit switch is still active after the pull-off of {distance:g} mm: "
                          "raise homing.pull_off_mm")


def what_stopped(outcome) -> str:
    if outcome.status != "error":
        return f"the move did not end ({outcome.status})"
    names = " ".join(AXES[a].upper() for a in range(3) if outcome.limits >> a & 1)
    return f"controller error {outcome.error} ({p.error_text(outcome.error)}{', ' + names if names else ''})"


def home_axis(driver: Driver, machine: Machine, axis: int) -> tuple[float, float]:
    """Home one axis: (the switch's machine coordinate, where the axis ends), mm.  The switch is
    a pull-off outside the travel, so the axis ends at its travel end (min_mm or max_mm), as
    Grbl places its home: a move to the soft limit stops short of the switch."""
    name, settings = AXES[axis].upper(), machine.values[f"axis.{AXES[axis]}"]
    homing, free, spm = machine.homing, unlimited(machine), machine.steps_per_mm[axis]
    toward = -1.0 if settings["home"] == "min" else 1.0
    pull = homing["pull_off_mm"]
    if switch_active(driver, axis):                    # resting on it: off it first
        pull_off(driver, machine, free, axis, -toward)
    seek = SEEK_TRAVELS * (settings["max_mm"] - settings["min_mm"]) + pull
    expect_switch(move(driver, machine, free, axis, toward * seek, homing["seek_mm_min"]), axis,
                  f"seek ({seek:g} mm towards {settings['home']})")
    pull_off(driver, machine, free, axis, -toward)
    expect_switch(move(driver, machine, free, axis, toward * 2 * pull, homing["locate_mm_min"]), axis,
                  f"slow approach ({2 * pull:g} mm)")
    trip = read_position(driver)[axis]
    pull_off(driver, machine, free, axis, -toward)
    switch_mm = settings["min_mm"] - pull if toward < 0 else settings["max_mm"] + pull
    steps = round(switch_mm * spm) + read_position(driver)[axis] - trip
    driver.write_register("CONTROL", p.CONTROL_CLEAR | p.CONTROL_ENABLE)
    driver.write_register(f"POS_{name}", steps & 0xFFFFFFFF)
    if read_position(driver)[axis] != steps:
        raise HomingError(f"{name}: the controller did not take the position {steps} steps (busy, or beyond its "
                          "position counter)")
    return switch_mm, steps / spm


def axes_to_home(args, machine: Machine) -> list[int]:
    axes = machine.homed_axes()
    if args.axes is not None:
        chosen = args.axes.lower()
        if not chosen or any(a not in AXES for a in chosen):
            raise UsageError(f"--axes {args.axes}: give axes of XYZ, e.g. --axes Z or --axes XY")
        if len(set(chosen)) != len(chosen):
            raise UsageError(f"--axes {args.axes}: an axis given twice")
        missing = [a.upper() for a in chosen if AXES.index(a) not in axes]
        if missing:
            raise UsageError(f"--axes {args.axes}: {' '.join(missing)} has no home end in the machine file "
                             f"(axis.{missing[0].lower()}.home) or is not in homing.order")
        axes = [a for a in axes if AXES[a] in chosen]
    if not axes:
        raise UsageError(f"{machine.source}: no axis to home: set axis.X.home = \"min\" or \"max\" (and homing.order)")
    return axes


def place_sim_switches(link, machine: Machine, axes: list[int]) -> float:
    """--sim: a limit switch for each axis at its home end, SIM_PULL_OFFS pull-offs from where
    the simulated machine powers up (it follows the pulses counted at the step pins); the
    distance in mm."""
    distance = SIM_PULL_OFFS * machine.homing["pull_off_mm"]
    for axis in axes:
        side = machine.values[f"axis.{AXES[axis]}"]["home"]
        link.set_switch(axis, side, round((-1 if side == "min" else 1) * distance * machine.steps_per_mm[axis]))
    return distance


def cmd_home(args) -> int:
    args.steps = args.line_noise = None
    if not (args.port or args.sim or args.sim_model):
        raise UsageError("interp home: give --port DEVICE or --sim")
    check_link_args(args)
    machine = load_machine(args.machine, [], None)
    axes = axes_to_home(args, machine)
    opened = send.open_or_report(args, machine)
    if opened is None:
        return 1
    transport, baud = opened
    driver = None
    try:
        if args.sim:
            distance = place_sim_switches(transport, machine, axes)
            print(f"interp home: --sim: the simulated machine powers up {distance:.3f} mm from each limit switch",
                  file=sys.stderr)
        driver = Driver(transport, baud=baud)
        send.make_ready(driver, machine, sim=bool(args.sim), homing_lock=False)
        start = driver.clock()
        for axis in axes:
            switch_mm, end_mm = home_axis(driver, machine, axis)
            print(f"homed {AXES[axis].upper()}: switch at {switch_mm:.3f} mm, now at {end_mm:.3f} mm")
        print(f"machine position {mm_text(machine, read_position(driver))} mm "
              f"({driver.clock() - start:.3f} s)")
    except MismatchError as err:
        raise UsageError(str(err)) from None
    except HomingError as err:
        print(f"interp: error: homing {err}", file=sys.stderr)
        return 1
    except LinkError as err:
        print(f"interp: error: link: {err}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return send.interrupted(driver)
    finally:
        transport.close()
    return 0


def add_parser(sub) -> None:
    p_ = sub.add_parser("home", help="the homing cycle: each axis to its limit switch, which sets its position")
    add_link_options(p_, "the Verilator model of the controller instead of a port, with a limit switch "
                         f"{SIM_PULL_OFFS} pull-offs from where each axis powers up")
    p_.add_argument("--axes", metavar="XYZ", help="home only these axes (default: every axis with a home end)")
    p_.set_defaults(func=cmd_home)
