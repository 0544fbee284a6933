# SPDX-License-Identifier: Apache-2.0
"""The machine file: a TOML description of the controller, axes, output timing and tools.

    machine = load_machine("my.toml", sets=["axis.x.steps_per_mm=80"], clock_hz=1e6)

Every key, its unit, default and range is in SCHEMA (docs/machine.md is the
user's page).  A missing file means the shipped default machine
(default_machine.toml next to this module, equal to the defaults below).  An
unknown section or key, a wrong type or a value out of range is a
MachineError (a UsageError: one line, exit status 2) that names the file and
the key, e.g. "machine.toml: unknown key axis.x.steps_per_inch".
"""
from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from ..cores import UsageError

AXES = "xyz"
TIMING_MAX = (1 << 16) - 1      # output-stage timing registers (TW = 16 bits), clock cycles
# the pins of INPUT_INVERT and OUTPUT_INVERT, bit 0 first (regs/controller.rdl)
INPUT_NAMES = ("estop", "limit_x", "limit_y", "limit_z", "probe")
OUTPUT_NAMES = ("step_x", "step_y", "step_z", "dir_x", "dir_y", "dir_z", "enable", "spindle_on", "spindle_ccw",
                "spindle_pwm", "mist", "flood", "dout0", "dout1", "dout2", "dout3")
POSITION_MAX = (1 << 31) - 1    # motion_top's position counters (POS_W = 32, signed)


class MachineError(UsageError):
    """A bad machine file or --set override."""


# (type, default, low, high, unit, meaning); low/high None = unbounded; low inclusive unless
# the type is "float>" / "int>" (strictly above).
def _axis():
    return {
        "steps_per_mm": ("float>", 100.0, 0, 1e7, "steps/mm", "steps per millimetre"),
        "max_rate_mm_min": ("float>", 6000.0, 0, 1e7, "mm/min", "fastest speed of the axis (rapids; feeds are capped to it)"),
        "accel_mm_s2": ("float>", 500.0, 0, 1e9, "mm/s^2", "acceleration of the axis (the planner's path acceleration of each move)"),
        "min_mm": ("float", -1000.0, -1e7, 1e7, "mm", "soft limit: the lowest machine coordinate"),
        "max_mm": ("float", 1000.0, -1e7, 1e7, "mm", "soft limit: the highest machine coordinate"),
        "home": ("choice", "none", ("none", "min", "max"), None, "", "the travel end its limit switch homes it to (interp home)"),
    }


SCHEMA: dict[str, dict[str, tuple]] = {
    "controller": {
        "clock_hz": ("float>", 50e6, 0, 1e10, "Hz", "clock frequency of motion_top"),
    },
    **{f"axis.{a}": _axis() for a in AXES},
    "motion": {
        "junction_deviation_mm": ("float>", 0.01, 0, 1e3, "mm", "cornering tolerance (the planner's junction speeds)"),
        "profile": ("choice", "trapezoid", ("trapezoid", "scurve"), None, "", "speed profile of the hardware (--profile overrides it)"),
        "jerk_mm_s3": ("float>", 20000.0, 0, 1e12, "mm/s^3", "jerk limit of the S-curve profile (its filter window >= 2 accel / jerk)"),
        "naive_cam": ("bool", False, None, None, "", "LinuxCNC's naive CAM detector: in G64 with a tolerance (Q, or P without Q), runs of G1 moves at one F that stay within it of a straight line run as that line (fewer records, sharper corners: usually a longer machine time); off: every move as programmed"),
    },
    "output": {
        "pulse_ns": ("float>", 1000.0, 0, 1e9, "ns", "step pulse width"),
        "dir_setup_ns": ("float", 1000.0, 0, 1e9, "ns", "direction set-up before a step pulse"),
        "dir_hold_ns": ("float", 1000.0, 0, 1e9, "ns", "direction hold after a step pulse"),
        "invert": ("names", (), OUTPUT_NAMES, None, "", "output pins that are active low (the controller's OUTPUT_INVERT)"),
    },
    "input": {
        "invert": ("names", (), INPUT_NAMES, None, "", "input pins that are active low (the controller's INPUT_INVERT)"),
        "filter_us": ("float", 0.0, 0, 1e6, "us", "debounce: an input change counts once it has lasted this long (the controller's INPUT_FILTER; 0: no filter)"),
        "unfiltered": ("names", (), INPUT_NAMES, None, "", "inputs the filter leaves out (they count at once), e.g. [\"probe\"]"),
    },
    "spindle": {
        "max_s": ("float>", 24000.0, 0, 1e9, "rpm", "the S value of 100 % PWM duty"),
        "pwm_hz": ("float>", 1000.0, 0, 1e9, "Hz", "spindle PWM frequency (the controller's SPINDLE_PERIOD)"),
        "laser": ("bool", False, None, None, "", "laser mode, as Grbl's $32: S changes along G1 / G2 / G3 without a stop, the beam off during G0 and while a feed hold has stopped the machine"),
    },
    "gcode": {
        "parameter_file": ("text", "", None, None, "", "file of the settings that outlive a program (work offsets, G92, the coordinate system, G28 / G30 positions); empty: none"),
        "subroutine_path": ("folders", (), None, None, "", "folders where `o<name> call` finds name.ngc, after the program's own folder"),
    },
    "homing": {
        "order": ("text", "zxy", None, None, "", "the axes `interp home` homes, one after another (those with a home end)"),
        "seek_mm_min": ("float>", 500.0, 0, 1e7, "mm/min", "speed towards the switch, and of the pull-offs"),
        "locate_mm_min": ("float>", 50.0, 0, 1e7, "mm/min", "speed of the second, slow approach that sets the position"),
        "pull_off_mm": ("float>", 1.0, 0, 1e3, "mm", "distance back off the switch"),
        "required": ("bool", False, None, None, "", "interp send refuses a controller not homed since its reset"),
    },
    "home": {
        "g28": ("point", (0.0, 0.0, 0.0), -1e7, 1e7, "mm", "the G28 position, machine coordinates"),
        "g30": ("point", (0.0, 0.0, 0.0), -1e7, 1e7, "mm", "the G30 position, machine coordinates"),
    },
}
TOOL_SCHEMA = {
    "length_mm": ("float", 0.0, -1e5, 1e5, "mm", "tool length offset (G43)"),
    "diameter_mm": ("float", 0.0, 0, 1e5, "mm", "tool diameter (cutter compensation)"),
}
TOOL_MAX = 99999


@dataclass(frozen=True)
class Axis:
    steps_per_mm: float
    max_rate_mm_min: float
    accel_mm_s2: float
    min_mm: float
    max_mm: float
    home: str = "none"


@dataclass
class Machine:
    values: dict[str, dict]                      # every section's keys, defaults filled in
    tools: dict[int, dict] = field(default_factory=dict)
    source: str = "default machine"
    source_is_file: bool = False

    @property
    def clock_hz(self) -> float:
        return self.values["controller"]["clock_hz"]

    @property
    def axes(self) -> tuple[Axis, Axis, Axis]:
        return tuple(Axis(**self.values[f"axis.{a}"]) for a in AXES)

    @property
    def steps_per_mm(self) -> tuple[float, float, float]:
        return tuple(self.values[f"axis.{a}"]["steps_per_mm"] for a in AXES)

    @property
    def g28(self):
        return tuple(self.values["home"]["g28"])

    @property
    def g30(self):
        return tuple(self.values["home"]["g30"])

    @property
    def parameter_file(self) -> Path | None:
        """The parameter file (gcode.parameter_file, relative to the machine file's folder), or None."""
        name = self.values["gcode"]["parameter_file"]
        return self._path(name) if name else None

    def subroutine_folders(self, program: str | None = None) -> list[Path]:
        """Where `o<name> call` looks for name.ngc: the folder of the program file (None: none;
        "-", standard input: the current folder), then gcode.subroutine_path (relative to the
        machine file's folder)."""
        first = [] if program is None else [Path(".") if program == "-" else Path(program).parent]
        return first + [self._path(name) for name in self.values["gcode"]["subroutine_path"]]

    def _path(self, name: str) -> Path:
        """A file or folder named in the machine file: relative to its folder."""
        folder = Path(self.source).parent if self.source_is_file else Path(".")
        try:
            return folder / Path(name).expanduser()
        except RuntimeError:                        # ~user that does not exist
            return folder / name

    @property
    def homing(self) -> dict:
        return self.values["homing"]

    def homed_axes(self) -> list[int]:
        """The axes `interp home` homes, in its order (0 = x)."""
        return [AXES.index(a) for a in self.homing["order"] if self.values[f"axis.{a}"]["home"] != "none"]

    def pin_settings(self) -> dict[str, int]:
        """The controller's INPUT_INVERT and OUTPUT_INVERT (input.invert, output.invert),
        INPUT_FILTER (input.filter_us, input.unfiltered) and SPINDLE_PERIOD (spindle.pwm_hz, in
        clocks); MachineError when a period does not fit its register (checked here, where a
        board is driven: `interp gcode` runs any clock)."""
        return {"INPUT_INVERT": pin_bits(self.values["input"]["invert"], INPUT_NAMES),
                "INPUT_FILTER": self.input_filter(),
                "OUTPUT_INVERT": pin_bits(self.values["output"]["invert"], OUTPUT_NAMES),
                "SPINDLE_PERIOD": self.checked_spindle_period()}

    def input_filter(self) -> int:
        """INPUT_FILTER: the filter samples every `period` clocks and takes a new level at the
        4th sample in a row, so a change of 4 x period clocks always counts: period =
        input.filter_us / 4 in clocks (0: no filter); bits 20:16 the inputs filtered."""
        inputs = self.values["input"]
        period = 0
        if inputs["filter_us"] > 0:
            period = max(1, round(inputs["filter_us"] * self.clock_hz / 4e6))
            if period > TIMING_MAX:
                longest = math.floor(4 * TIMING_MAX / self.clock_hz * 1e7) / 10     # (rounded down)
                raise MachineError(f"{self.source}: input.filter_us ({inputs['filter_us']:g} us) is a sample "
                                   f"period of {period} clocks at controller.clock_hz = {self.clock_hz:g}; "
                                   f"INPUT_FILTER takes at most {TIMING_MAX}: at most {longest:g} us")
        mask = 0x1F & ~pin_bits(inputs["unfiltered"], INPUT_NAMES)
        return mask << 16 | period

    def checked_spindle_period(self) -> int:
        """spindle_period(), or MachineError when it does not fit SPINDLE_PERIOD."""
        period = self.spindle_period()
        if not 2 <= period <= TIMING_MAX:
            hz, clock = self.values["spindle"]["pwm_hz"], self.clock_hz
            raise MachineError(f"{self.source}: spindle.pwm_hz ({hz:g} Hz) is a period of {period} clocks at "
                               f"controller.clock_hz = {clock:g}; the controller's SPINDLE_PERIOD takes 2 .. "
                               f"{TIMING_MAX}: {clock / TIMING_MAX:.4g} .. {clock / 2:.4g} Hz")
        return period

    def spindle_period(self) -> int:
        """Clocks of one spindle PWM period (spindle.pwm_hz at the clock)."""
        return max(1, round(self.clock_hz / self.values["spindle"]["pwm_hz"]))

    @property
    def max_s(self) -> float:
        return self.values["spindle"]["max_s"]

    def timing(self) -> dict[str, int]:
        """Output-stage timing in clock cycles (rounded up): pulse_width, setup, hold."""
        out = {}
        for name, key in (("pulse_width", "pulse_ns"), ("setup", "dir_setup_ns"), ("hold", "dir_hold_ns")):
            out[name] = _cycles(self.values["output"][key], self.clock_hz)
        out["pulse_width"] = max(out["pulse_width"], 1)
        return out


def pin_bits(names, table: tuple[str, ...]) -> int:
    """The register bits of pin names (bit n: table[n])."""
    return sum(1 << table.index(name) for name in names)


def _cycles(ns: float, clock_hz: float) -> int:
    return math.ceil(ns * clock_hz / 1e9 - 1e-9)


def default_machine_text() -> str:
    return (Path(__file__).parent / "default_machine.toml").read_text()


def _check(where: str, key: str, spec: tuple, value):
    kind, _, low, high = spec[:4]
    name = f"{where}: {key}"
    if kind == "choice":
        if value not in low:
            raise MachineError(f"{name} must be one of {', '.join(map(repr, low))} (got {value!r})")
        return value
    if kind == "bool":
        if not isinstance(value, bool):
            raise MachineError(f"{name} must be true or false (got {value!r})")
        return value
    if kind == "text":
        if not isinstance(value, str):
            raise MachineError(f"{name} must be a string (got {value!r})")
        return value
    if kind == "folders":
        if not isinstance(value, list) or not all(isinstance(v, str) and v for v in value):
            raise MachineError(f"{name} must be a list of folder names (got {value!r})")
        return tuple(value)
    if kind == "names":
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            raise MachineError(f"{name} must be a list of names of {', '.join(low)} (got {value!r})")
        for v in value:
            if v not in low:
                raise MachineError(f"{name}: {v!r} is not one of {', '.join(low)}")
        if len(set(value)) != len(value):
            raise MachineError(f"{name}: a name given twice")
        return tuple(value)
    if kind == "point":
        if not isinstance(value, list) or len(value) != 3:
            raise MachineError(f"{name} must be a list of three numbers [x, y, z] in mm (got {value!r})")
        return tuple(_check(where, f"{key}[{n}]", ("float", None, low, high), v) for n, v in enumerate(value))
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise MachineError(f"{name} must be a number (got {value!r})")
    value = float(value)
    if not math.isfinite(value):
        raise MachineError(f"{name} must be a finite number (got {value!r})")
    strict = kind.endswith(">")
    if (value <= low if strict else value < low) or value > high:
        rel = ">" if strict else ">="
        raise MachineError(f"{name} must be {rel} {low:g} and <= {high:g} (got {value:g})")
    return value


def _tool_number(where: str, section: str) -> int:
    number = section.split(".", 1)[1]
    if not number.isdigit() or int(number) > TOOL_MAX:
        raise MachineError(f"{where}: unknown section [{section}] (tools are [tool.N], N = 0 .. {TOOL_MAX})")
    return int(number)


def _flatten(where: str, data: dict) -> dict[str, dict]:
    """{"axis": {"x": {...}}, "tool": {"3": {...}}} -> {"axis.x": {...}, "tool.3": {...}}."""
    out: dict[str, dict] = {}
    for name, body in data.items():
        if name in ("axis", "tool") and isinstance(body, dict):
            for sub, inner in body.items():
                if not isinstance(inner, dict):
                    raise MachineError(f"{where}: unknown key {name}.{sub}")
                out[f"{name}.{sub}"] = inner
        elif name in SCHEMA and isinstance(body, dict):
            out[name] = body
        elif name in SCHEMA:
            raise MachineError(f"{where}: {name} must be a section [{name}]")
        elif not isinstance(body, dict):
            raise MachineError(f"{where}: unknown key {name}")
        else:
            raise MachineError(f"{where}: unknown section [{name}]")
    return out


def _schema_of(where: str, section: str) -> dict:
    if section in SCHEMA:
        return SCHEMA[section]
    if section.startswith("tool."):
        _tool_number(where, section)
        return TOOL_SCHEMA
    raise MachineError(f"{where}: unknown section [{section}]")


def _apply(where: str, values: dict[str, dict], sections: dict[str, dict]) -> None:
    for section, body in sections.items():
        schema = _schema_of(where, section)
        target = values.setdefault(section, {k: spec[1] for k, spec in schema.items()})
        for key, value in body.items():
            if key not in schema:
                raise MachineError(f"{where}: unknown key {section}.{key}")
            target[key] = _check(where, f"{section}.{key}", schema[key], value)


def parse_set(text: str) -> tuple[str, str, object]:
    """'axis.x.steps_per_mm=80' -> ("axis.x", "steps_per_mm", 80); the value is read as TOML
    (numbers like 1e6 or 50_000_000, lists, quoted strings), else taken as a plain string."""
    where = f"--set {text}"
    if "=" not in text:
        raise MachineError(f"{where}: want KEY=VALUE, e.g. axis.x.steps_per_mm=80")
    key, raw = (s.strip() for s in text.split("=", 1))
    if "." not in key:
        raise MachineError(f"{where}: want SECTION.KEY=VALUE, e.g. controller.clock_hz=1e6")
    section, name = key.rsplit(".", 1)
    try:
        value = tomllib.loads(f"v = {raw}")["v"]
    except tomllib.TOMLDecodeError:
        value = raw
    return section, name, value


def load_machine(path: str | None = None, sets: list[str] = (), clock_hz: float | None = None) -> Machine:
    """The machine: the defaults, then the file (if any), then each --set, then --clock-hz."""
    if path is None:
        where, text = "default machine", default_machine_text()
    else:
        where = str(path)
        try:
            text = Path(path).read_bytes().decode("utf-8")
        except OSError as err:
            raise MachineError(f"cannot read machine file {path}: {err.strerror or err}") from None
        except UnicodeDecodeError as err:
            raise MachineError(f"{where}: not UTF-8 text (byte {err.start})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise MachineError(f"{where}: not valid TOML: {err}") from None
    values = {section: {k: spec[1] for k, spec in schema.items()} for section, schema in SCHEMA.items()}
    _apply(where, values, _flatten(where, data))
    for item in sets:
        section, name, value = parse_set(item)
        _apply(f"--set {item}", values, {section: {name: value}})
    if clock_hz is not None:
        _apply("--clock-hz", values, {"controller": {"clock_hz": clock_hz}})
    tools = {_tool_number(where, s): dict(v) for s, v in values.items() if s.startswith("tool.")}
    machine = Machine({s: v for s, v in values.items() if not s.startswith("tool.")}, tools, where, path is not None)
    _consistent(machine)
    return machine


def _consistent(machine: Machine) -> None:
    """Checks between keys: travel order, positions and rates the hardware can hold."""
    where = machine.source
    order = machine.homing["order"]
    if any(a not in AXES for a in order) or len(set(order)) != len(order):
        raise MachineError(f"{where}: homing.order must name axes of xyz, each at most once (got {order!r})")
    if machine.homing["required"] and not machine.homed_axes():
        raise MachineError(f"{where}: homing.required needs an axis to home: set axis.X.home = \"min\" or \"max\" "
                           "for an axis of homing.order")
    clock = machine.clock_hz
    for a, axis in zip(AXES, machine.axes):
        if axis.min_mm >= axis.max_mm:
            raise MachineError(f"{where}: axis.{a}.min_mm ({axis.min_mm:g}) must be below axis.{a}.max_mm "
                               f"({axis.max_mm:g})")
        for key in ("min_mm", "max_mm"):
            if abs(getattr(axis, key)) * axis.steps_per_mm > POSITION_MAX:
                raise MachineError(f"{where}: axis.{a}.{key} x steps_per_mm is beyond the 32-bit position "
                                   f"counter (+-{POSITION_MAX} steps)")
        rate = axis.max_rate_mm_min * axis.steps_per_mm / 60
        if rate > clock:
            raise MachineError(f"{where}: axis.{a}.max_rate_mm_min ({axis.max_rate_mm_min:g} mm/min = {rate:.6g} "
                               f"steps/s) is more than one step per clock at controller.clock_hz = {clock:g}")
    for name, key in (("pulse_width", "pulse_ns"), ("setup", "dir_setup_ns"), ("hold", "dir_hold_ns")):
        if _cycles(machine.values["output"][key], clock) > TIMING_MAX:
            raise MachineError(f"{where}: output.{key} is more than {TIMING_MAX} clock cycles at "
                               f"controller.clock_hz = {clock:g}")

