# SPDX-License-Identifier: Apache-2.0
"""RS274NGC machine semantics: blocks of words -> moves in machine millimetres.

`interpret(text)` runs the language layer (`iterate_blocks`: lexing, parsing,
expressions, O-word control flow) and gives each block the meaning LinuxCNC's
interpreter gives it: modal groups, the order of execution within a block,
units, distance modes, work offsets (G54..G59.3, G92, G10), tool length offsets,
arcs in any plane, helices, canned cycles, dwells and M-word events.  The
result is a `Program` (moves.py).  Anything it cannot run faithfully is
refused with one `GcodeError` naming the line, column and word.

Internally every position and offset is kept in machine millimetres; the
parameters the program can read (#5420.. the position, #5221.. the
coordinate systems, ...) are written back in program units after each block.
docs/gcode.md ("Machine semantics") describes the accepted words and the differences from
LinuxCNC and Grbl.
"""
from __future__ import annotations

import copy
import math
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Sequence

from . import cycles, spline
from .cutter import CompensationError, Compensator
from .errors import GcodeError, without_controls
from .language import Block, ExpressionError, Parameters, Word, iterate_blocks, read_source, substitute_parameters
from .moves import CONTINUOUS, PLANES, Arc, Dwell, Event, Line, Point, ProbeResult, Program
from .parameter_file import LENGTHS

MM_PER_INCH = 25.4

# Arc tolerances, in program units.  Zero radius and the R form's reach: LinuxCNC's
# RADIUS_TOLERANCE (0.00005 inch).  Centre form: the rule of LinuxCNC's G2/G3 documentation,
# an error if the radii to the start and the end differ by more than 0.05 inch (0.5 mm), or
# by more than 0.0005 inch (0.005 mm) and 0.1 % of the radius.
RADIUS_TOLERANCE = {"inch": 0.00005, "mm": 0.00005 * MM_PER_INCH}
CENTRE_ABSOLUTE_TOLERANCE = {"inch": 0.05, "mm": 0.5}
CENTRE_SMALL_TOLERANCE = {"inch": 0.0005, "mm": 0.005}
CENTRE_RELATIVE_TOLERANCE = 0.001
MAX_CYCLE_MOVES = 1_000_000     # one canned-cycle block expands to at most this many moves
MAX_TURNS = 10_000              # an arc's P (turns): 10,000 compile in about 6 s
MAX_MOVES = 2_000_000           # moves of one program, an arc's turns counted (minutes to compile)
DEBUG_FLAG = 5599                                # #5599 > 0: (DEBUG, ...) comments are shown
WORD_LIMIT = 1e15               # a word's value beyond this is refused (no position overflows)
SAME_POINT_MM = 1e-9            # an arc's end this close to its start is a full circle

AXES = "XYZ"
EXTRA_AXES = "ABCUVW"           # axes this machine does not have
PLANE_OF = {170: "XY", 180: "ZX", 190: "YZ"}
PLANE_CODE = {"XY": "G17", "ZX": "G18", "YZ": "G19"}

# G codes in tenths (G59.1 -> 591) -> modal group
G_GROUPS: dict[int, str] = {}
for _codes, _group in (
        ((0, 10, 20, 30, 50, 51, 382, 383, 384, 385, 800, 730, 810, 820, 830, 850, 860, 890), "motion"),
        ((40, 100, 280, 281, 300, 301, 520, 530, 920, 921, 922, 923), "non-modal"),
        ((170, 180, 190), "plane"), ((900, 910), "distance"), ((901, 911), "arc distance"),
        ((930, 940), "feed mode"), ((200, 210), "units"), ((400, 410, 420, 411, 421), "cutter compensation"),
        ((430, 431, 490), "tool length"), ((980, 990), "return mode"),
        ((540, 550, 560, 570, 580, 590, 591, 592, 593), "coordinate system"),
        ((610, 611, 640), "path control"), ((970,), "spindle speed mode"),
        ((80,), "lathe diameter mode")):
    for _code in _codes:
        G_GROUPS[_code] = _group

G_REFUSED = {
    52: "NURBS moves (G5.2) are not supported",
    53: "NURBS moves (G5.3) are not supported",
    70: "lathe diameter mode is not supported",
    330: "spindle-synchronized motion is not supported",
    331: "rigid tapping is not supported",
    740: "tapping cycles need a spindle encoder: not supported",
    840: "tapping cycles need a spindle encoder: not supported",
    760: "threading cycles are not supported",
    870: "back boring (G87) is not supported",
    880: "G88 (manual retract) is not supported",
    432: "G43.2 (additional tool offset) is not supported",
    171: "UVW planes are not supported", 181: "UVW planes are not supported",
    191: "UVW planes are not supported",
    950: "feed per revolution (G95) is not supported",
    960: "constant surface speed (G96) is not supported",
}

M_GROUPS: dict[int, str] = {}
for _codes, _group in (((0, 1, 2, 30, 60), "stopping"), ((3, 4, 5), "spindle"),
                       ((6, 61), "tool change"), ((7, 8, 9), "coolant"),
                       ((48, 49, 50, 51, 52, 53), "override"), ((70, 71, 72, 73), "modal state"),
                       ((62, 63, 64, 65), "output")):
    for _code in _codes:
        M_GROUPS[_code] = _group

PROBE_CODES = {382: "G38.2", 383: "G38.3", 384: "G38.4", 385: "G38.5"}
PROBE_AWAY = (384, 385)           # the probe trips where it loses contact
PROBE_FAIL = {382: "the probe did not touch before the end of the move",
              384: "the probe did not lose contact before the end of the move"}
MOTION_NAMES = {0: "G0", 10: "G1", 20: "G2", 30: "G3", 50: "G5", 51: "G5.1", 800: "G80", 730: "G73", 810: "G81",
                820: "G82", 830: "G83", 850: "G85", 860: "G86", 890: "G89"}
CYCLE_CODES = {730: 73, 810: 81, 820: 82, 830: 83, 850: 85, 860: 86, 890: 89}
AXIS_USERS = {100: "G10", 280: "G28", 300: "G30", 520: "G52", 920: "G92"}
# what M70 / M73 save and M72 restores: LinuxCNC's modal state, of what this machine has
# (units, plane, distance and feed modes, F, S, spindle, coolant, coordinate system, tool
# length offset, canned-cycle return mode, path control)
MODAL_STATE = ("units", "plane", "absolute", "arc_absolute", "inverse_time", "feed", "speed", "spindle",
               "mist", "flood", "coordinate_system", "tool_length", "tool_offset", "r_plane_retract",
               "path_control", "naive_tolerance")


@dataclass
class _ModalState:
    values: dict
    autorestore: bool           # M73: back at the subroutine's return


VALID_LETTERS = set("ABCDFGHIJKLMNPQRSTUVWXYZ@^")


def interpret(text: str, *, g28: Point = (0.0, 0.0, 0.0), g30: Point = (0.0, 0.0, 0.0),
              tools: dict[int, dict] | None = None, start: Point = (0.0, 0.0, 0.0),
              saved: dict[int, float] | None = None, probes: list[ProbeResult] | None = None,
              folders: Sequence[Path] = ()) -> Program:
    """Run a G-code program: text -> Program of moves in machine mm (see moves.py).

    g28, g30: the G28 / G30 home positions in machine mm (#5161.., #5181..);
    tools: T -> {"length_mm": float, "diameter_mm": float}, the tool table
    (G10 L1/L10 change a copy of it); start: where the machine is when the program
    starts, machine mm (the first move starts there); saved: the persistent parameters
    an earlier program left (parameter_file.py: offsets, G92, coordinate system, G28 /
    G30 positions in machine mm; they override g28 and g30).  The program's own end
    values are `Program.saved` (M2 / M30: G54 selected).  probes: what the program's probe
    moves (G38.2 .. G38.5) did on the machine, in order; the interpretation stops after the first
    probe move beyond them (`Program.probe_pending`).  None: no machine (`interp gcode`), each
    probe move touches at its end.  folders: where `o<name> call` of a subroutine the program
    does not define finds name.ngc, in order (LinuxCNC's single-file subroutines).  Raises
    GcodeError for anything it cannot run.
    """
    params = Parameters()
    params.set(DEBUG_FLAG, 1.0)                       # (DEBUG, ...) shown, as LinuxCNC starts
    machine = _Machine(params, g28, g30, tools or {}, start, saved or {})
    machine.probe_results = probes
    for block in iterate_blocks(text, params, subroutine_finder(folders)):
        if block.delete:
            continue                                  # block delete switch on
        try:
            machine.run_block(block)
        except GcodeError as error:
            if not block.file or error.file or error.line != block.line:
                raise
            raise error.in_file(block.file, block.line, block.file_line) from None
        if machine.ended or machine.program.probe_pending:
            break
    if not machine.program.probe_pending:
        machine.compensation_off(tool_stays=True)   # (the text ended with compensation on)
    program = machine.program
    # the language layer's warnings and ours, in line order
    program.warnings = sorted(list(getattr(params, "warnings", [])) + program.warnings,
                              key=_warning_line)
    program.end_machine = tuple(machine.position)
    program.end_work = machine.work_position()
    program.units = machine.units
    program.saved = machine.saved_parameters()
    program.subroutines = params.subroutines
    return program


@dataclass
class _Words:
    """A block's words sorted out: G and M codes (tenths / integers) and the other letters."""
    block: Block
    g: dict[str, tuple[int, Word]]       # modal group -> (code, word)
    m: dict[str, tuple[int, Word]]
    letters: dict[str, Word]
    used: set[str]
    coolant: list[tuple[int, Word]]     # M7, M8, M9 (M7 and M8 may share a block)

    def has(self, letter: str) -> bool:
        return letter in self.letters

    def value(self, letter: str) -> float:
        self.used.add(letter)
        return self.letters[letter].value

    def get(self, letter: str, default=None):
        return self.value(letter) if letter in self.letters else default

    def word(self, letter: str) -> Word:
        return self.letters[letter]


class _Machine:
    def __init__(self, params: Parameters, g28: Point, g30: Point, tools: dict[int, dict],
                 start: Point = (0.0, 0.0, 0.0), saved: dict[int, float] | None = None):
        self.params = params
        params.on_return = self._returned
        self.program = Program()
        self.moves_made = 0
        self.tools = {int(t): dict(v) for t, v in tools.items()}
        self.position = [float(v) for v in start]   # machine mm
        self.units = "mm"
        self.plane = "XY"
        self.absolute = True                     # G90
        self.arc_absolute = False                # G91.1
        self.inverse_time = False                # G93
        self.feed: float | None = None           # mm/min (G94)
        self.motion = 800                        # G80
        self.motion_before_cycle: int | None = None   # G0 / G1 in force before a canned cycle
        self.spline_tail: tuple[float, float] | None = None  # -P, -Q (mm) of a G5 just run: the next G5's I, J
        self.coordinate_system = 1               # G54
        self.work_offsets = [[0.0, 0.0, 0.0] for _ in range(9)]
        self.g92 = [0.0, 0.0, 0.0]               # applied G92 offset
        self.g92_stored = [0.0, 0.0, 0.0]        # #5211.. (kept while G92.2 suspends)
        self.g92_enabled = False
        self.tool_offset = [0.0, 0.0, 0.0]
        self.tool_length = "G49"                 # its mode: G43, G43.1, G49 (M72 restores the mode)
        self.homes = {280: list(map(float, g28)), 300: list(map(float, g30))}
        self.r_plane_retract = True              # G99 (LinuxCNC's start-up mode)
        self.cycle_initial: float | None = None
        self.cycle_sticky: dict[str, float] = {}
        self.spindle: str | None = None          # "cw", "ccw" or None
        self.speed = 0.0
        self.tool_selected = 0
        self.tool_loaded = 0
        self.ended = False
        self.written: dict[int, float] = {}
        self.settings_changed = True             # the offset parameters need writing
        self.assigned_mm: dict[int, float] = {}  # see _keep_assignments
        self.probe_results: list[ProbeResult] | None = None
        self.mist = self.flood = False           # M7, M8 in force (M9 ends both)
        self.probes_made = 0
        self.touch_assumed = False                # a probe move took its touch at its end (no machine)
        self.comp: Compensator | None = None      # cutter compensation (G41 / G42, until its exit move)
        self.block_top = 0                        # the running block's line outside any subroutine
        self.path_control = CONTINUOUS            # G61 / G61.1 / G64 and its P (mm): stamped on each motion
        self.naive_tolerance = 0.0                # G64's Q (or P without Q), mm; 0: G61, G61.1, G64 alone
        self.chain = 0                            # the naive-CAM chain count: a path-control block or a message ends one
        self._restore(saved or {})
        self._write_parameters()

    # ---- the persistent parameters (parameter_file.py) ------------------------------
    def _restore(self, saved: dict[int, float]) -> None:
        """Start from the parameters an earlier program saved (machine mm)."""
        for a in range(3):
            self.homes[280][a] = saved.get(5161 + a, self.homes[280][a])
            self.homes[300][a] = saved.get(5181 + a, self.homes[300][a])
            self.g92_stored[a] = saved.get(5211 + a, 0.0)
            for n in range(9):
                self.work_offsets[n][a] = saved.get(5221 + 20 * n + a, 0.0)
        self.coordinate_system = int(saved.get(5220, 1))
        self.g92_enabled = bool(saved.get(5210, 0.0))
        self.g92 = list(self.g92_stored) if self.g92_enabled else [0.0, 0.0, 0.0]

    def saved_parameters(self) -> dict[int, float]:
        """The persistent parameters at the program's end, machine mm: the offsets, G92, the
        coordinate system and the G28 / G30 positions; a length parameter the program assigned
        and no G word took over yet is saved as assigned, as LinuxCNC saves its parameter table.
        M2 / M30 select G54; G92 stays as it is, as Grbl and LinuxCNC keep it."""
        values = {5220: float(self.coordinate_system), 5210: 1.0 if self.g92_enabled else 0.0}
        for a in range(3):
            values[5161 + a] = self.homes[280][a]
            values[5181 + a] = self.homes[300][a]
            values[5211 + a] = self.g92_stored[a]
            for n in range(9):
                values[5221 + 20 * n + a] = self.work_offsets[n][a]
        for key in values:
            if key not in (5210, 5220) and self.params.get(key) != self.written.get(key):
                values[key] = self.params.get(key) * self.scale
        if self.ended:
            values[5220] = 1.0
        return values

    # ---- coordinates ----------------------------------------------------------------
    @property
    def scale(self) -> float:
        return MM_PER_INCH if self.units == "inch" else 1.0

    def offset(self, axis: int) -> float:
        return (self.work_offsets[self.coordinate_system - 1][axis] + self.g92[axis]
                + self.tool_offset[axis])

    def work_position(self) -> Point:
        return tuple(_clean((self.position[a] - self.offset(a)) / self.scale) for a in range(3))

    # ---- parameters -----------------------------------------------------------------
    def _parameter_map(self) -> dict[int, float]:
        s = self.scale
        values = {5220: float(self.coordinate_system), 5210: 1.0 if self.g92_enabled else 0.0,
                  5400: float(self.tool_loaded)}
        for a in range(3):
            values[5211 + a] = _clean(self.g92_stored[a] / s)
            values[5161 + a] = _clean(self.homes[280][a] / s)
            values[5181 + a] = _clean(self.homes[300][a] / s)
            values[5401 + a] = _clean(self.tool_offset[a] / s)
            for n in range(9):
                values[5221 + 20 * n + a] = _clean(self.work_offsets[n][a] / s)
        return values

    def _write_parameters(self) -> None:
        """Write the parameters that changed: the position after every block, the offsets,
        homes and tool after a block that changed them (or the units)."""
        values = dict(zip((5420, 5421, 5422), self.work_position()))
        if self.settings_changed:
            values.update(self._parameter_map())
            self.settings_changed = False
        for key, value in values.items():
            if self.written.get(key) != value:
                self._set_parameter(key, value)
                self.written[key] = value
        for key, mm in self.assigned_mm.items():           # still assigned, in the new units
            self._set_parameter(key, _clean(mm / self.scale))
        self.assigned_mm = {}

    def _set_parameter(self, key: int, value: float) -> None:
        try:
            self.params.set(key, value)
        except ExpressionError:                             # an offset or position overflowed
            self._fail(None, "a position or offset is out of range (not a finite number)")

    def _keep_assignments(self) -> None:
        """Before G20 / G21 changes the units: the persistent lengths the program assigned and
        no G word took over yet, in mm, to be written back in the new units."""
        self.assigned_mm = {key: self.params.get(key) * self.scale for key in LENGTHS
                            if self.params.get(key) != self.written.get(key)}

    def _read_offsets(self, system: int) -> None:
        """Select a coordinate system: its offsets from #5221.. (the program may have set them),
        as LinuxCNC reads them when G54..G59.3 is programmed."""
        for a in range(3):
            key = 5221 + 20 * (system - 1) + a
            if self.params.get(key) != self.written.get(key):
                self.work_offsets[system - 1][a] = self.params.get(key) * self.scale

    def _read_vector(self, base: int, vector: list[float]) -> None:
        for a in range(3):
            if self.params.get(base + a) != self.written.get(base + a):
                vector[a] = self.params.get(base + a) * self.scale

    # ---- output ---------------------------------------------------------------------
    def _add(self, move) -> None:
        """Append a move (an arc's turns count as moves towards MAX_MOVES); under cutter
        compensation, the tool's moves the compensator settles with it, each carrying the
        line outside any subroutine that made it (its origin: they settle later).  A motion
        ends a G5 series (the next G5 needs its I and J)."""
        if isinstance(move, (Line, Arc)):
            self.spline_tail = None
        if self.comp is None:
            self._append([move])
            return
        comp = self.comp
        move = replace(move, origin=self.block_top)
        try:
            moves = comp.take(move)
        except CompensationError as error:
            self._fail(None, error.text, line=error.line)
        self._comp_warnings(comp)
        if comp.state == "done":
            self.comp = None
        self._append(moves)

    def _append(self, moves) -> None:
        for move in moves:
            self.moves_made += move.turns if isinstance(move, Arc) else 1
            if self.moves_made > MAX_MOVES:
                self._fail(None, f"the program makes more than {MAX_MOVES} moves (an arc's turns counted): "
                                 "split it")
            marks = {"origin": move.origin or self.block_top}
            if isinstance(move, (Line, Arc)):
                marks["path_control"] = self.path_control
            if isinstance(move, Line) and move.feed is not None and not move.probe and self.naive_tolerance > 0:
                marks["join"] = (self.chain, self.naive_tolerance)
            self.program.moves.append(replace(move, **marks))

    def compensation_off(self, tool_stays: bool = False) -> None:
        """G40: the pending compensated move ends; the next XY move starts where the tool is.
        tool_stays (the program's end): compensation ends where the tool is (no exit move)."""
        if self.comp is None:
            return
        comp = self.comp
        try:
            settled = comp.off()
        except CompensationError as error:
            self._fail(None, error.text, line=error.line)
        self._comp_warnings(comp)
        self._append(settled)
        self.comp = None if tool_stays or comp.state == "done" else comp
        if tool_stays:
            u, v, _ = PLANES[comp.plane]
            self.position[u], self.position[v] = comp.tool

    def _comp_warnings(self, comp: Compensator) -> None:
        for line, text in comp.warnings:
            self._warn(line, text)
        comp.warnings.clear()

    def _compensating(self) -> bool:
        return self.comp is not None and self.comp.state in ("entering", "on")

    def _refuse_in_compensation(self, word: Word, what: str) -> None:
        if self._compensating():
            self._fail(word, f"{what} cannot be used with cutter compensation on (G40 first)")

    def _modal_state(self, m: tuple[int, Word], line: int) -> None:
        """M70 saves the modal state (MODAL_STATE) of this call level, M73 too, to come back when
        the subroutine returns; M71 forgets it; M72 restores it (LinuxCNC's)."""
        code, word = m
        self._refuse_in_compensation(word, f"M{code}")
        slots = self.params.modal_saved
        if code in (70, 73):
            slots[-1] = _ModalState({name: copy.deepcopy(getattr(self, name)) for name in MODAL_STATE}, code == 73)
        elif code == 71:
            slots[-1] = None
        elif slots[-1] is None:
            self._fail(word, "no modal state saved at this call level (M70 or M73 first)")
        else:
            self._restore_modal(slots[-1], line)

    def _returned(self, state: _ModalState, line: int) -> None:
        """A subroutine that saved its caller's modal state with M73 returns (at `line`): the
        state back before the language layer reads the next line (its expressions see it)."""
        if self._compensating():
            self._fail(None, "a subroutine with M73 returned with cutter compensation on: its modal "
                             "state cannot come back (G40 before the return)", line=line)
        self._restore_modal(state, line)
        self._write_parameters()

    def _restore_modal(self, state: _ModalState, line: int) -> None:
        """The saved values back; the spindle and coolant events where they differ."""
        was = {name: getattr(self, name) for name in MODAL_STATE}
        if state.values["units"] != self.units:
            self._keep_assignments()
        self.settings_changed = True                    # (units, offsets: the parameters)
        for name, value in state.values.items():
            setattr(self, name, copy.deepcopy(value))
        if self.coordinate_system != was["coordinate_system"]:
            self._read_offsets(self.coordinate_system)
        # the tool length's mode comes back, not its value: G43 takes the loaded tool's length,
        # G49 none, G43.1 the offsets it had; the same mode keeps the offset in force
        if self.tool_length == was["tool_length"]:
            self.tool_offset = was["tool_offset"]
        elif self.tool_length == "G49":
            self.tool_offset = [0.0, 0.0, 0.0]
        elif self.tool_length == "G43":
            self.tool_offset = [0.0, 0.0, self._tool_length_of(self.tool_loaded)]
        if (self.path_control, self.naive_tolerance) != (was["path_control"], was["naive_tolerance"]):
            self.chain += 1                             # (a naive-CAM chain ends)
        if self.spindle is None and was["spindle"] is not None:
            self._event("spindle_off", 0, line)
        elif self.spindle is not None and self.spindle != was["spindle"]:
            self._event("spindle_cw" if self.spindle == "cw" else "spindle_ccw", self.speed, line)
        elif self.spindle is not None and self.speed != was["speed"]:
            self._event("spindle_speed", self.speed, line)
        if (self.mist, self.flood) != (was["mist"], was["flood"]):
            if was["mist"] or was["flood"]:
                self._event("coolant_off", 0, line)
            for name in ("mist", "flood"):
                if getattr(self, name):
                    self._event(f"{name}_on", 0, line)

    def _cutter(self, words: _Words) -> None:
        """17. G40, G41 / G42 D (tool number; without D the loaded tool), G41.1 / G42.1 D (diameter)."""
        code, word = words.g["cutter compensation"]
        if code == 400:
            self.compensation_off()
            return
        if self._compensating():
            self._fail(word, "cutter compensation is already on: turn it off (G40) first")
        if self.plane == "YZ":
            self._fail(word, "cutter compensation works in the XY (G17) and XZ (G18) planes, not in G19")
        if words.has("L"):
            self._fail(words.word("L"), "a lathe tool orientation (L) is not supported")
        if code in (410, 420):
            tool = self.tool_loaded
            if words.has("D"):
                d = words.value("D")
                if d < 0 or d != int(d):
                    self._fail(words.word("D"), "D must be a tool number (a whole number >= 0)")
                tool = int(d)
            if tool != 0 and tool not in self.tools:
                self._fail(words.word("D") if words.has("D") else word,
                           f"tool {tool} is not in the tool table: its diameter is not known")
            diameter = float(self.tools.get(tool, {}).get("diameter_mm", 0.0))
            if not diameter >= 0 or not math.isfinite(diameter):
                what = "a negative diameter" if diameter < 0 else "a diameter that is not a number"
                self._fail(words.word("D") if words.has("D") else word,
                           f"tool {tool} has {what} ({diameter:g} mm; G10 L1 R sets it)")
        else:
            if not words.has("D"):
                self._fail(word, "needs a D word (the tool's diameter)")
            diameter = words.value("D") * self.scale
            if diameter < 0:
                self._fail(words.word("D"), "the tool's diameter cannot be negative")
        words.used.add("D")
        if diameter == 0:                       # (LinuxCNC: a radius of 0 compensates nothing)
            return
        u, v, _ = PLANES[self.plane]
        tool = self.comp.tool if self.comp is not None else (self.position[u], self.position[v])
        self.comp = Compensator("left" if code in (410, 411) else "right", diameter / 2, tool, self.plane)

    def _event(self, name: str, value: float, line: int) -> None:
        self._add(Event(name, float(value), line))

    def _warn(self, line: int, text: str) -> None:
        self.program.warnings.append(f"line {line}: {text}")

    def _line_to(self, target: list[float], feed: float | None, line: int) -> None:
        start = tuple(self.position)
        end = tuple(target)
        if start != end:
            self._add(Line(start, end, feed, line))
        self.position = list(target)

    # ---- one block ------------------------------------------------------------------
    def _message(self, block: Block, text: str) -> None:
        self.program.messages.append(f"line {block.line}: {text}")
        self.chain += 1
        held = self.comp.held() if self.comp is not None else 0     # (moves made before it, not settled yet)
        self.program.message_origins.append((len(self.program.moves) + held, block.top))

    def run_block(self, block: Block) -> None:
        self.block_top = block.top
        for comment in block.comments:
            text = comment.lstrip()
            head, comma, rest = text.partition(",")
            kind = head.lower() if comma else ""           # (LinuxCNC: "msg," etc. at the start)
            if kind == "msg":
                self._message(block, without_controls(rest.strip()))
            elif kind in ("debug", "print") and (kind == "print" or self.params.get(DEBUG_FLAG) > 0.0):
                shown = substitute_parameters(rest, self.params).strip()
                self._message(block, without_controls(shown))
            elif kind == "abort":
                shown = without_controls(substitute_parameters(rest, self.params).strip())
                if self.touch_assumed:          # (it may depend on a touch only the machine knows)
                    said = f"(ABORT) {shown}".rstrip()
                    self._warn(block.line, f"{said}: not taken, since a probe move before it took its touch at "
                                           "the end of the move")
                else:
                    error = GcodeError(block.line, 1, "", f"(ABORT) {shown}".rstrip())
                    error.messages = list(self.program.messages)      # what the program said before
                    raise error
        words = self._sort_words(block)
        line = block.line
        if words.g.keys() & {"non-modal", "units", "tool length", "coordinate system"} or \
                words.m.keys() & {"tool change", "modal state"}:
            self.settings_changed = True
        if words.g.keys() & {"tool length", "coordinate system"} or \
                words.g.get("non-modal", (0,))[0] in (100, 520, 920, 921, 922, 923):
            self.chain += 1                 # (an offset change ends a naive-CAM chain, as in LinuxCNC)

        # 3. feed rate mode, 4. feed rate
        feed_mode = words.g.get("feed mode")
        if feed_mode is not None:
            inverse = feed_mode[0] == 930
            if inverse != self.inverse_time:
                self.feed = None
            self.inverse_time = inverse
        units = words.g.get("units")
        block_units = self.units if units is None else ("inch" if units[0] == 200 else "mm")
        block_scale = MM_PER_INCH if block_units == "inch" else 1.0
        inverse_f = None
        if words.has("F"):
            f = words.value("F")
            if f <= 0:
                self._fail(words.word("F"), "the feed rate must be positive")
            if self.inverse_time:
                inverse_f = f
            else:
                self.feed = f * block_scale
        # 5. spindle speed
        if words.has("S"):
            s = words.value("S")
            if s < 0:
                self._fail(words.word("S"), "the spindle speed cannot be negative")
            if self.spindle is not None and s != self.speed and "spindle" not in words.m:
                self._event("spindle_speed", s, line)
            self.speed = s
        # 6. select tool
        if words.has("T"):
            t = words.value("T")
            if t < 0 or t != int(t):
                self._fail(words.word("T"), "the tool number must be a whole number >= 0")
            self.tool_selected = int(t)
        # 7. outputs
        if "output" in words.m:
            code, word = words.m["output"]
            if not words.has("P"):
                self._fail(word, "needs a P word (the output number)")
            number = words.value("P")
            if number < 0 or number != int(number):
                self._fail(words.word("P"), "the output number must be a whole number >= 0")
            self._event("output_on" if code in (62, 64) else "output_off", number, line)
        # 8. tool change
        if "tool change" in words.m:
            code, word = words.m["tool change"]
            if code == 6:
                self._refuse_in_compensation(word, "a tool change")
                self._event("tool_change", self.tool_selected, line)
                self._event("pause", 6, line)
                self.tool_loaded = self.tool_selected
            else:                                            # M61 Q: set the loaded tool
                if not words.has("Q"):
                    self._fail(word, "needs a Q word (the tool number)")
                q = words.value("Q")
                if q < 0 or q != int(q):
                    self._fail(words.word("Q"), "the tool number must be a whole number >= 0")
                self.tool_loaded = int(q)
        # 9. spindle
        if "spindle" in words.m:
            code = words.m["spindle"][0]
            if code == 5:
                self.spindle = None
                self._event("spindle_off", 0, line)
            else:
                self.spindle = "cw" if code == 3 else "ccw"
                self._event("spindle_cw" if code == 3 else "spindle_ccw", self.speed, line)
        # 10. save, forget, restore the modal state
        if "modal state" in words.m:
            self._modal_state(words.m["modal state"], line)
            if self.inverse_time and words.has("F"):    # (M72 back to G93: the block's F times its move)
                inverse_f = words.value("F")
        # 11. coolant
        for code, _word in words.coolant:
            self._event({7: "mist_on", 8: "flood_on", 9: "coolant_off"}[code], 0, line)
            self.mist = code == 7 or (code == 8 and self.mist)
            self.flood = code == 8 or (code == 7 and self.flood)
        # 12. overrides
        if "override" in words.m:
            code, word = words.m["override"]
            if code in (50, 51, 52, 53) and words.has("P"):
                words.value("P")
            self._warn(line, f"{word.text}: overrides are not modelled; ignored")
        # 14. dwell
        nonmodal = words.g.get("non-modal")
        if nonmodal is not None and nonmodal[0] == 40:
            if not words.has("P"):
                self._fail(nonmodal[1], "needs a P word (seconds)")
            p = words.value("P")
            if p < 0:
                self._fail(words.word("P"), "the dwell time cannot be negative")
            self._add(Dwell(p, line))
        # 15. plane, 16. units
        if "plane" in words.g:
            if PLANE_OF[words.g["plane"][0]] != self.plane:
                self._refuse_in_compensation(words.g["plane"][1], "a change of plane")
            self.plane = PLANE_OF[words.g["plane"][0]]
        if units is not None:               # (no G20 / G21: the units in force, as M72 may have restored them)
            if block_units != self.units:
                self._keep_assignments()
            self.units = block_units
        # 17. cutter radius compensation
        if "cutter compensation" in words.g:
            self._cutter(words)
        # 18. tool length offset
        axes_taken = False
        if "tool length" in words.g:
            axes_taken = self._tool_length(words)
        # 19. coordinate system
        if "coordinate system" in words.g:
            code = words.g["coordinate system"][0]
            self.coordinate_system = {540: 1, 550: 2, 560: 3, 570: 4, 580: 5, 590: 6,
                                      591: 7, 592: 8, 593: 9}[code]
            self._read_offsets(self.coordinate_system)
        # 20. path control
        if "path control" in words.g:
            code, word = words.g["path control"]
            if self._compensating():        # (LinuxCNC refuses it too: the comp's moves lag a block)
                self._fail(word, "the path-control mode cannot change with cutter compensation on (G40 first)")
            p = q = None
            if code == 640:
                p = words.get("P")
                q = words.get("Q")
                for letter, value in (("P", p), ("Q", q)):
                    if value is not None and not value >= 0:
                        self._fail(words.word(letter), "the G64 tolerance cannot be negative")
                p = None if p is None else p * self.scale
                q = None if q is None else q * self.scale
            self.path_control = ({610: "G61", 611: "G61.1", 640: "G64"}[code], p)
            self.naive_tolerance = (q if q is not None else p if p is not None else 0.0) if code == 640 else 0.0
            self.chain += 1
        # 21. distance modes, 22. return mode
        if "distance" in words.g:
            self.absolute = words.g["distance"][0] == 900
        if "arc distance" in words.g:
            self.arc_absolute = words.g["arc distance"][0] == 901
        if "return mode" in words.g:
            self.r_plane_retract = words.g["return mode"][0] == 990
        # 23. home, G10, G92
        axis_letters = [c for c in AXES + EXTRA_AXES + "@^" if words.has(c)]
        if nonmodal is not None and nonmodal[0] != 40 and nonmodal[0] != 530:
            axes_taken = self._non_modal(words, nonmodal) or axes_taken
        # 24. motion
        motion = words.g.get("motion")
        if motion is not None:
            if motion[0] in CYCLE_CODES and self.motion not in CYCLE_CODES:
                self.cycle_initial = None
            new_mode = motion[0]
        else:
            new_mode = self.motion
        g53 = nonmodal is not None and nonmodal[0] == 530
        if g53 and new_mode not in (0, 10):
            self._fail(nonmodal[1], "G53 needs G0 or G1")
        if g53 and not self.absolute:
            self._fail(nonmodal[1], "G53 cannot be used in incremental mode (G91)")
        if g53:
            self._refuse_in_compensation(nonmodal[1], "G53")
        if new_mode == 800:
            if motion is not None and axis_letters and not axes_taken:
                self._fail(motion[1], "axis words cannot be used with G80")
            if axis_letters and not axes_taken:
                word = words.word(axis_letters[0])
                if self.motion_before_cycle is None:
                    self._fail(word, "axis word without a motion mode (G0, G1, G2, G3 or a "
                                     "cycle) in force")
                # Fanuc and Mach3 keep the motion mode from before the canned cycle in force
                # after G80 (LinuxCNC and Grbl refuse the block): run it, with a warning.
                new_mode = self.motion_before_cycle
                self._warn(line, f"{word.text.strip()}: axis word after G80: moved in "
                                 f"{MOTION_NAMES[new_mode]}, the motion mode in force before "
                                 "the canned cycle (as Fanuc and Mach3 do; LinuxCNC refuses it)")
                self._straight(words, new_mode, g53, inverse_f)
            self.cycle_initial = None
        elif not axes_taken and (axis_letters or (motion is not None and new_mode in (20, 30)
                                                  and any(words.has(c) for c in "IJKR"))
                                 or (motion is not None and new_mode in (50, 51)
                                     and any(words.has(c) for c in "IJPQ"))):
            if new_mode in (0, 10):
                self._straight(words, new_mode, g53, inverse_f)
            elif new_mode in (20, 30):
                self._arc(words, new_mode, motion, inverse_f)
            elif new_mode in (50, 51):
                self._spline(words, new_mode, motion, inverse_f)
            elif new_mode in PROBE_CODES:
                self._probe(words, new_mode, inverse_f)
            else:
                self._cycle(words, new_mode, motion)
        if new_mode not in CYCLE_CODES:
            self.cycle_initial = None
        if new_mode in (0, 10):
            self.motion_before_cycle = new_mode
        elif new_mode in (20, 30, 50, 51):
            self.motion_before_cycle = None
        self.motion = new_mode
        self._check_unused(words)
        if self.program.probe_pending:      # the rest of the block runs when the result is known
            return
        # 25. stop
        if "stopping" in words.m:
            code = words.m["stopping"][0]
            if code in (2, 30):
                self.compensation_off(tool_stays=True)      # (LinuxCNC's M2 / M30 end it)
                self._event("program_end", code, line)
                self.ended = True
            else:
                self._event("pause", code, line)
        self._write_parameters()

    # ---- words ----------------------------------------------------------------------
    def _fail(self, word: Word | None, text: str, line: int | None = None):
        if word is None:
            raise GcodeError(line if line is not None else self._line, 1, "", text)
        raise GcodeError(self._line, word.column, word.text.strip(), text)

    def _claim(self, taken: dict[str, tuple[int, Word]], group: str, code: int, word: Word) -> None:
        """The block's G or M code of a modal group: one each."""
        if group in taken:
            self._fail(word, f"two {word.letter.upper()} codes of the {group} group in one block "
                             f"({taken[group][1].text.strip()} and {word.text.strip()})")
        taken[group] = (code, word)

    def _sort_words(self, block: Block) -> _Words:
        self._line = block.line
        g: dict[str, tuple[int, Word]] = {}
        m: dict[str, tuple[int, Word]] = {}
        letters: dict[str, Word] = {}
        coolant: list[tuple[int, Word]] = []
        for word in block.words:
            if not abs(word.value) <= WORD_LIMIT:
                self._fail(word, f"the value is out of range (beyond {WORD_LIMIT:g})")
            letter = word.letter.upper()
            if letter == "G":
                code = round(word.value * 10)
                if abs(word.value * 10 - code) > 1e-6 or word.value < 0:
                    self._fail(word, "unknown G code")
                if code in G_REFUSED:
                    self._fail(word, G_REFUSED[code])
                group = G_GROUPS.get(code)
                if group is None:
                    self._fail(word, "unknown or unsupported G code")
                if group == "motion" and group in g and 800 in (code, g[group][0]) and \
                        {code, g[group][0]} & {0, 10, 20, 30}:
                    # Fanuc's safe-start idiom "G0 G17 G40 G80 G90": there G80 (cycle cancel)
                    # has a group of its own; here G0..G3 end any cycle anyway.
                    if code != 800:
                        g[group] = (code, word)
                    continue
                self._claim(g, group, code, word)
            elif letter == "M":
                code = round(word.value)
                if abs(word.value - code) > 1e-6 or word.value < 0:
                    self._fail(word, "unknown M code")
                group = M_GROUPS.get(code)
                if group is None:
                    self._fail(word, "unsupported M code")
                if group == "coolant":
                    if any(c == 9 or code == 9 or c == code for c, _ in coolant):
                        self._fail(word, "two M codes of the coolant group in one block")
                    coolant.append((code, word))
                    m[group] = (code, word)
                    continue
                self._claim(m, group, code, word)
            elif letter == "N":
                continue
            elif letter == "$":         # LinuxCNC's spindle select: this machine has spindle 0 only
                if word.value != 0:
                    self._fail(word, "this machine has one spindle, $0")
                continue
            else:
                if letter not in VALID_LETTERS:
                    self._fail(word, f"{letter} is not an RS274NGC word")
                if letter in letters:
                    self._fail(word, f"two {letter} words in one block")
                letters[letter] = word
        if ("non-modal" in g and g["non-modal"][0] in AXIS_USERS and "motion" in g
                and g["motion"][0] != 800
                and any(c in letters for c in AXES + EXTRA_AXES + "@^")):
            self._fail(g["motion"][1], f"{g['non-modal'][1].text.strip()} and "
                                       f"{g['motion'][1].text.strip()} both use the axis words")
        return _Words(block, g, m, letters, set(), coolant)

    def _check_unused(self, words: _Words) -> None:
        for letter, word in words.letters.items():
            if letter not in words.used and letter not in "FST":
                if letter == "D":
                    self._fail(word, "D word without G41, G42, G41.1 or G42.1")
                if letter == "H":
                    self._fail(word, "H word without G43")
                self._fail(word, "word not used by any command in this block")

    def _axis_value(self, words: _Words, letter: str) -> float:
        return words.value(letter)

    def _extra_axes(self, words: _Words) -> None:
        """A/B/C/U/V/W: accepted only if they do not move (the machine has X, Y and Z)."""
        for letter in EXTRA_AXES:
            if words.has(letter):
                if words.value(letter) != 0:
                    self._fail(words.word(letter), f"this machine has no {letter} axis")

    def _target(self, words: _Words, g53: bool = False) -> list[float]:
        """The end point of a straight or arc move (machine mm) from the axis words."""
        s = self.scale
        target = list(self.position)
        self._extra_axes(words)
        polar = words.has("@") or words.has("^")
        if polar:
            for letter in "XY":
                if words.has(letter):
                    self._fail(words.word(letter), "X or Y cannot be used with polar "
                                                   "coordinates (@ ^)")
            if self.plane != "XY":
                self._fail(words.word("@" if words.has("@") else "^"),
                           "polar coordinates need the XY plane (G17)")
            work = [(self.position[a] - self.offset(a)) / s for a in range(2)]
            radius, theta = self._polar(words, work)
            target[0] = radius * math.cos(theta) * s + self.offset(0)
            target[1] = radius * math.sin(theta) * s + self.offset(1)
        for axis, letter in enumerate(AXES):
            if not words.has(letter):
                continue
            v = words.value(letter) * s
            if g53:
                target[axis] = v
            elif self.absolute:
                target[axis] = v + self.offset(axis)
            else:
                target[axis] = self.position[axis] + v
        return target

    def _polar(self, words: _Words, work: list[float]) -> tuple[float, float]:
        radius, theta = math.hypot(work[0], work[1]), math.atan2(work[1], work[0])
        if self.absolute:
            if words.has("@"):
                radius = words.value("@")
            if words.has("^"):
                theta = math.radians(words.value("^"))
        else:
            if work[0] == 0 and work[1] == 0:
                word = words.word("@" if words.has("@") else "^")
                self._fail(word, "incremental polar motion is undefined at the origin")
            if words.has("@"):
                radius += words.value("@")
            if words.has("^"):
                theta += math.radians(words.value("^"))
        return radius, theta

    def _feed_for(self, length_mm: float, inverse_f: float | None, word: Word | None) -> float:
        if self.inverse_time:
            if inverse_f is None:
                self._fail(word, "inverse time mode (G93) needs an F word on every feed move")
            return length_mm * inverse_f
        if self.feed is None:
            self._fail(word, "feed move without a feed rate (no F word yet)")
        return self.feed

    # ---- motion ---------------------------------------------------------------------
    def _straight(self, words: _Words, mode: int, g53: bool, inverse_f: float | None) -> None:
        target = self._target(words, g53)
        if mode == 0:
            self._line_to(target, None, self._line)
            return
        length = math.dist(self.position, target)
        feed = self._feed_for(length, inverse_f, self._motion_word(words))
        self._line_to(target, feed, self._line)

    def _probe(self, words: _Words, mode: int, inverse_f: float | None) -> None:
        """G38.2 / G38.3: a feed move towards the target that stops where the probe touches;
        G38.4 / G38.5: one away from the work that stops where the probe loses contact.
        #5070 = 1 if the probe tripped (touched, or lost contact), #5061..#5063 = where
        (work coordinates, program units).  G38.2 and G38.4 fail without the trip."""
        name, word = PROBE_CODES[mode], self._motion_word(words)
        if self._compensating():
            self._fail(word, f"{name} cannot be used with cutter compensation on (G40 first)")
        if words.has("@") or words.has("^"):
            self._fail(words.word("@" if words.has("@") else "^"), f"polar coordinates cannot be used with {name}")
        target = self._target(words)
        length = math.dist(self.position, target)
        if length < SAME_POINT_MM:
            self._fail(word, "the probe move has no length: its end is where the machine is")
        feed = self._feed_for(length, inverse_f, word)
        if self.spindle is not None or self.mist or self.flood:
            # (a controller ends a probe move with an abort, which stops the spindle and coolant)
            self._fail(word, f"{name} with the spindle or coolant on: stop them (M5, M9) before probing")
        self._add(Line(tuple(self.position), tuple(target), feed, self._line, probe=mode))
        index, self.probes_made = self.probes_made, self.probes_made + 1
        if self.probe_results is None:
            self.touch_assumed = True
            result = ProbeResult(True, tuple(target), tuple(target))
            trip = "loss of contact" if mode in PROBE_AWAY else "touch"
            self._warn(self._line, f"{name}: the probe's {trip} is taken at the end of the move (only the machine "
                                   "knows where it is)")
        elif index < len(self.probe_results):
            result = self.probe_results[index]
            if not result.touched and mode in PROBE_FAIL:
                self._fail(word, PROBE_FAIL[mode])
        else:
            self.program.probe_pending = True
            return
        self.position = [float(v) for v in result.stop]
        at = result.trip if result.touched else result.stop
        for a in range(3):
            self._set_parameter(5061 + a, _clean((at[a] - self.offset(a)) / self.scale))
        self._set_parameter(5070, 1.0 if result.touched else 0.0)

    def _motion_word(self, words: _Words) -> Word:
        if "motion" in words.g:
            return words.g["motion"][1]
        for letter in AXES + EXTRA_AXES + "@^":
            if words.has(letter):
                return words.word(letter)
        return words.block.words[0]

    def _arc(self, words: _Words, mode: int, motion, inverse_f: float | None) -> None:
        s = self.scale
        units = self.units
        iu, iv, iw = PLANES[self.plane]
        ou, ov, ow = "IJK"[iu], "IJK"[iv], "IJK"[iw]
        mword = motion[1] if motion is not None else self._motion_word(words)
        if words.has("@") or words.has("^"):
            self._fail(words.word("@" if words.has("@") else "^"),
                       "polar coordinates cannot be used with arcs")
        target = self._target(words)
        start = list(self.position)
        if words.has(ow):
            if words.value(ow) != 0:
                self._fail(words.word(ow), f"{ow} is not an offset of the "
                                           f"{PLANE_CODE[self.plane]} plane")
        turns = 1
        if words.has("P"):
            p = words.value("P")
            if p != int(p) or not 1 <= p <= MAX_TURNS:
                self._fail(words.word("P"), f"the number of turns must be a whole number 1 .. {MAX_TURNS}")
            turns = int(p)
        su, sv = start[iu], start[iv]
        eu, ev = target[iu], target[iv]
        if words.has("R"):
            for letter in (ou, ov):
                if words.has(letter):
                    self._fail(words.word(letter), "an arc takes either R or I/J/K, not both")
            r_word = words.word("R")
            radius = words.value("R")
            if su == eu and sv == ev:
                self._fail(r_word, "an R arc needs an end point different from its start")
            abs_r = abs(radius) * s
            half = math.hypot(eu - su, ev - sv) / 2
            if half - abs_r > RADIUS_TOLERANCE[units] * s:
                self._fail(r_word, f"the radius is too small to reach the end point "
                                   f"(half the chord is {half / s:.4f})")
            if abs_r == 0:
                self._fail(r_word, "zero-radius arc")
            if half / abs_r > 1 - 1e-12:
                half = abs_r
            ccw = mode == 30
            theta = math.atan2(ev - sv, eu - su)
            theta += -math.pi / 2 if (not ccw) == (radius > 0) else math.pi / 2
            offset = abs_r * math.cos(math.asin(half / abs_r))
            cu = (su + eu) / 2 + offset * math.cos(theta)
            cv = (sv + ev) / 2 + offset * math.sin(theta)
        else:
            if not (words.has(ou) or words.has(ov)):
                self._fail(mword, f"an arc in the {PLANE_CODE[self.plane]} plane needs "
                                  f"{ou} or {ov} (the centre) or R")
            if self.arc_absolute:
                for letter in (ou, ov):
                    if not words.has(letter):
                        self._fail(mword, f"G90.1 (absolute centre) needs both {ou} and {ov}")
                cu = words.value(ou) * s + self.offset(iu)
                cv = words.value(ov) * s + self.offset(iv)
            else:
                cu = su + words.get(ou, 0.0) * s
                cv = sv + words.get(ov, 0.0) * s
            r1 = math.hypot(su - cu, sv - cv) / s
            r2 = math.hypot(eu - cu, ev - cv) / s
            word = words.word(ou) if words.has(ou) else words.word(ov)
            if r1 < RADIUS_TOLERANCE[units] or r2 < RADIUS_TOLERANCE[units]:
                self._fail(word, f"zero-radius arc (radius {r1:.4f} at the start, "
                                 f"{r2:.4f} at the end)")
            error = abs(r1 - r2)
            if error > CENTRE_ABSOLUTE_TOLERANCE[units] or (
                    error > CENTRE_SMALL_TOLERANCE[units]
                    and error / max(r1, r2) > CENTRE_RELATIVE_TOLERANCE):
                self._fail(word, f"the radius to the end ({r2:.4f}) differs from the radius "
                                 f"to the start ({r1:.4f}) by {error:.4g} {units}, more than "
                                 f"{CENTRE_ABSOLUTE_TOLERANCE[units]:g}, or more than "
                                 f"{CENTRE_SMALL_TOLERANCE[units]:g} and 0.1 %")
        if math.hypot(eu - su, ev - sv) < SAME_POINT_MM:
            target[iu], target[iv] = su, sv
            eu, ev = su, sv
        centre = list(start)
        centre[iu], centre[iv] = cu, cv
        ccw = mode == 30
        a0 = math.atan2(sv - cv, su - cu)
        a1 = math.atan2(ev - cv, eu - cu)
        sweep = (a1 - a0) if ccw else (a0 - a1)
        sweep %= 2 * math.pi
        if sweep == 0:
            sweep = 2 * math.pi
        sweep += 2 * math.pi * (turns - 1)
        radius_mm = math.hypot(su - cu, sv - cv)
        length = math.hypot(radius_mm * sweep, target[iw] - start[iw])
        feed = self._feed_for(length, inverse_f, mword)
        self._add(Arc(tuple(start), tuple(target), tuple(centre), self.plane, ccw, turns, feed, self._line))
        self.position = target

    def _spline(self, words: _Words, mode: int, motion, inverse_f: float | None) -> None:
        """G5 (cubic: I J P Q) and G5.1 (quadratic: I J) in the XY plane, as LinuxCNC runs them:
        the control points are offsets (program units) from the start (I, J) and from the end
        (P, Q); a G5 right after a G5 may leave out I and J (the last one's -P, -Q).  The
        curve runs as arcs and lines within spline.TOLERANCE_MM of it (interp.gcode.spline)."""
        name, s = MOTION_NAMES[mode], self.scale
        mword = motion[1] if motion is not None else self._motion_word(words)
        self._refuse_in_compensation(mword, name)
        if self.comp is not None:                       # (G40 given, its straight exit move not yet)
            self._fail(mword, f"{name} cannot be the exit move after G40: a straight move (G0 or G1) first")
        if self.plane != "XY":
            self._fail(mword, f"{name} splines must be in the XY plane (G17)")
        for letter in "Z@^":
            if words.has(letter):
                self._fail(words.word(letter), f"{name} moves only X and Y")
        has_i, has_j = words.has("I"), words.has("J")
        if mode == 51 and not (has_i and has_j):
            self._fail(mword, "G5.1 needs both I and J")
        if has_i != has_j:
            self._fail(words.word("I" if has_i else "J"), f"{name} needs both I and J, or neither")
        if mode == 50 and not (words.has("P") and words.has("Q")):
            self._fail(mword, "G5 needs both P and Q")
        tail = self.spline_tail
        if not has_i and tail is None:
            self._fail(mword, "G5 needs I and J (they may be left out only right after another G5)")
        first = (words.value("I") * s, words.value("J") * s) if has_i else tail
        target = self._target(words)
        start = tuple(self.position)
        control = [start[:2], (start[0] + first[0], start[1] + first[1])]
        if mode == 50:
            p, q = words.value("P") * s, words.value("Q") * s
            control.append((target[0] + p, target[1] + q))
        control.append((target[0], target[1]))
        try:
            parts = spline.pieces(control)
        except spline.SplineError as error:
            self._fail(mword, str(error))
        feed = self._feed_for(spline.length(parts), inverse_f, mword)
        z = start[2]
        for n, part in enumerate(parts):
            a, b = (*part[1], z), (*part[2], z)
            if part[0] == "line":
                self._add(Line(a, b, feed, self._line, continues=n > 0))
            else:
                self._add(Arc(a, b, (*part[3], z), "XY", part[4], 1, feed, self._line, continues=n > 0))
        self.position = [target[0], target[1], z]
        self.spline_tail = (-p, -q) if mode == 50 else None       # (after the pieces: _add clears it)

    def _cycle(self, words: _Words, mode: int, motion) -> None:
        line = self._line
        code = CYCLE_CODES[mode]
        mword = motion[1] if motion is not None else self._motion_word(words)
        self._refuse_in_compensation(mword, "a canned cycle")
        s = self.scale
        ia, ib, ic = PLANES[self.plane]
        la, lb, lc = AXES[ia], AXES[ib], AXES[ic]
        same_mode = self.motion == mode
        if self.inverse_time:
            self._fail(mword, "canned cycles cannot be used in inverse time mode (G93)")
        if self.feed is None:
            self._fail(mword, "canned cycle without a feed rate (no F word yet)")
        self._extra_axes(words)
        sticky = self.cycle_sticky
        if words.has("R"):
            sticky["R"] = words.value("R")
        elif not same_mode or "R" not in sticky:
            self._fail(mword, "canned cycle without an R word (the retract plane)")
        if words.has(lc):
            sticky["depth"] = words.value(lc)
        elif not same_mode or "depth" not in sticky:
            self._fail(mword, f"canned cycle without a {lc} word (the bottom of the hole)")
        q = p = 0.0
        if code in (73, 83):
            if words.has("Q"):
                sticky["Q"] = words.value("Q")
            elif not same_mode or "Q" not in sticky:
                self._fail(mword, "needs a Q word (the peck depth)")
            q = sticky["Q"]
            if q <= 0:
                self._fail(words.word("Q") if words.has("Q") else mword,
                           "the peck depth Q must be positive")
        if code == 86 and self.spindle is None:
            self._fail(mword, "G86 needs the spindle turning (M3 or M4): it stops it in the hole")
        if code in (82, 86, 89):
            if words.has("P"):
                sticky["P"] = words.value("P")
            elif not same_mode or "P" not in sticky:
                self._fail(mword, "needs a P word (the dwell in seconds)")
            p = sticky["P"]
            if p < 0:
                self._fail(words.word("P") if words.has("P") else mword,
                           "the dwell time cannot be negative")
        repeats = 1
        if words.has("L"):
            value = words.value("L")
            if value != int(value) or value < 1:
                self._fail(words.word("L"), "the number of repeats L must be a whole number "
                                            ">= 1")
            repeats = int(value)
        pecks = 1
        if code in (73, 83):
            depth = (sticky["R"] - (sticky["depth"] if self.absolute else sticky["R"] +
                                    sticky["depth"]))
            pecks = max(1, math.ceil(depth / q)) if depth > 0 else 1
        if repeats * (pecks * (3 if code == 83 else 2) + 3) > MAX_CYCLE_MOVES:
            word = words.word("L") if words.has("L") and pecks < MAX_CYCLE_MOVES / 4 else (
                words.word("Q") if words.has("Q") else mword)
            self._fail(word, f"this canned cycle would make more than {MAX_CYCLE_MOVES} moves "
                             f"({repeats} holes of {pecks} pecks)")
        current = self.position[ic]
        if self.cycle_initial is None:
            self.cycle_initial = current
        old = self.cycle_initial
        polar = words.has("@") or words.has("^")
        if polar and self.plane != "XY":
            self._fail(words.word("@" if words.has("@") else "^"),
                       "polar coordinates need the XY plane (G17)")
        if polar:
            for letter in "XY":
                if words.has(letter):
                    self._fail(words.word(letter), "X or Y cannot be used with polar "
                                                   "coordinates (@ ^)")
        holes: list[tuple[float, float]] = []
        if self.absolute:
            r = sticky["R"] * s + self.offset(ic)
            bottom = sticky["depth"] * s + self.offset(ic)
            a, b = self.position[ia], self.position[ib]
            if polar:
                work = [(self.position[k] - self.offset(k)) / s for k in range(2)]
                radius, theta = self._polar(words, work)
                a = radius * math.cos(theta) * s + self.offset(0)
                b = radius * math.sin(theta) * s + self.offset(1)
            if words.has(la):
                a = words.value(la) * s + self.offset(ia)
            if words.has(lb):
                b = words.value(lb) * s + self.offset(ib)
            holes = [(a, b)] * repeats
        else:
            r = sticky["R"] * s + old
            bottom = r + sticky["depth"] * s
            da = words.value(la) * s if words.has(la) else 0.0
            db = words.value(lb) * s if words.has(lb) else 0.0
            a, b = self.position[ia], self.position[ib]
            d_radius = words.value("@") if words.has("@") else 0.0
            d_theta = math.radians(words.value("^")) if words.has("^") else 0.0
            for _ in range(repeats):
                a, b = a + da, b + db
                if polar:
                    wa, wb = (a - self.offset(0)) / s, (b - self.offset(1)) / s
                    if wa == 0 and wb == 0:
                        self._fail(words.word("@" if words.has("@") else "^"),
                                   "incremental polar motion is undefined at the origin")
                    radius = math.hypot(wa, wb) + d_radius
                    theta = math.atan2(wb, wa) + d_theta
                    a = radius * math.cos(theta) * s + self.offset(0)
                    b = radius * math.sin(theta) * s + self.offset(1)
                holes.append((a, b))
        if r < bottom:
            self._fail(mword, f"the R plane is below the bottom of the hole ({lc})")
        if old < r:
            raised = list(self.position)
            raised[ic] = r
            self._line_to(raised, None, line)
            old = r
        clear = r if self.r_plane_retract else old
        for kind, value in cycles.expand(code, axes=(ia, ib, ic), start=tuple(self.position),
                                         holes=holes, r=r, bottom=bottom, clear=clear, q=q * s,
                                         p=p):
            if kind == "dwell":
                self._add(Dwell(value, line))
            elif kind == "spindle":
                if value:
                    self._event("spindle_cw" if self.spindle == "cw" else "spindle_ccw", self.speed, line)
                else:
                    self._event("spindle_off", 0, line)
            else:
                self._line_to(list(value), None if kind == "rapid" else self.feed, line)

    # ---- G4 excepted non-modal codes --------------------------------------------------
    def _non_modal(self, words: _Words, nonmodal: tuple[int, Word]) -> bool:
        """G10, G28, G28.1, G30, G30.1, G52, G92, G92.1, G92.2, G92.3; True if it used the axis words."""
        code, word = nonmodal
        s = self.scale
        line = self._line
        if code == 100:
            self._g10(words, word)
            return True
        if code in (280, 300):
            self._refuse_in_compensation(word, "G28 / G30")
            self._extra_axes(words)
            named = [a for a in range(3) if words.has(AXES[a])]
            if words.has("@") or words.has("^"):
                self._fail(words.word("@" if words.has("@") else "^"),
                           "polar coordinates cannot be used with G28/G30")
            home = self.homes[code]
            self._read_vector(5161 if code == 280 else 5181, home)
            if named:
                self._line_to(self._target(words), None, line)
                final = list(self.position)
                for a in named:
                    final[a] = home[a]
            else:
                final = list(home)
            self._line_to(final, None, line)
            return True
        if code in (281, 301):
            self.homes[code - 1] = list(self.position)
            return False
        if code in (520, 920):
            # G92: the offset that gives the current point the words' coordinates; G52 (LinuxCNC,
            # Fanuc, Mach3): the words are the offset itself, from the coordinate system's
            # origin (G52 X0 Y0 Z0 ends it); both set the same offsets (#5210..#5213)
            for letter in EXTRA_AXES:                 # offsets of absent axes: no effect
                if words.has(letter):
                    words.value(letter)
            named = [a for a in range(3) if words.has(AXES[a])]
            if not named and not any(words.has(c) for c in EXTRA_AXES):
                self._fail(word, f"{AXIS_USERS[code]} needs at least one axis word")
            for a in named:
                if code == 520:
                    self.g92[a] = words.value(AXES[a]) * s
                else:
                    self.g92[a] = (self.position[a] - self.work_offsets[self.coordinate_system - 1][a]
                                   - self.tool_offset[a] - words.value(AXES[a]) * s)
            self.g92_stored = list(self.g92)
            self.g92_enabled = True
            return True
        if code == 921:
            self.g92 = [0.0, 0.0, 0.0]
            self.g92_stored = [0.0, 0.0, 0.0]
            self.g92_enabled = False
            return False
        if code == 922:
            self.g92 = [0.0, 0.0, 0.0]
            self.g92_enabled = False
            return False
        if code == 923:
            self._read_vector(5211, self.g92_stored)
            self.g92 = list(self.g92_stored)
            self.g92_enabled = True
            return False
        raise AssertionError(code)

    def _g10(self, words: _Words, word: Word) -> None:
        s = self.scale
        if not words.has("L"):
            self._fail(word, "G10 needs an L word (L1, L2, L10, L11 or L20)")
        l_word = words.word("L")
        level = words.value("L")
        if not words.has("P"):
            self._fail(word, "G10 needs a P word")
        p_word = words.word("P")
        p = words.value("P")
        if p != int(p):
            self._fail(p_word, "P must be a whole number")
        p = int(p)
        if level in (2, 20):
            if not 0 <= p <= 9:
                self._fail(p_word, "the coordinate system P must be 0 (the current one) to 9")
            system = self.coordinate_system if p == 0 else p
            if words.has("R") and words.value("R") != 0:
                self._fail(words.word("R"), "rotated coordinate systems are not supported")
            for letter in EXTRA_AXES:
                if words.has(letter):
                    words.value(letter)
            offsets = self.work_offsets[system - 1]
            for a in range(3):
                if words.has(AXES[a]):
                    v = words.value(AXES[a]) * s
                    if level == 2:
                        offsets[a] = v
                    else:
                        offsets[a] = self.position[a] - self.g92[a] - self.tool_offset[a] - v
            return
        if level in (1, 10, 11):
            if p < 1:
                self._fail(p_word, "the tool number P must be 1 or more")
            entry = self.tools.setdefault(p, {"length_mm": 0.0, "diameter_mm": 0.0})
            for letter in "XY" + EXTRA_AXES:
                if words.has(letter):
                    words.value(letter)
            if words.has("R"):
                entry["diameter_mm"] = 2 * words.value("R") * s
            if words.has("Q"):
                words.value("Q")
            if words.has("Z"):
                z = words.value("Z") * s
                if level == 1:
                    entry["length_mm"] = z
                elif level == 10:
                    entry["length_mm"] = (self.position[2] - self.g92[2]
                                          - self.work_offsets[self.coordinate_system - 1][2] - z)
                else:
                    entry["length_mm"] = self.position[2] - self.work_offsets[8][2] - z
            return
        self._fail(l_word, "unsupported G10 form (L1, L2, L10, L11 and L20 are supported)")

    def _tool_length_of(self, tool: int, line: int | None = None) -> float:
        """Tool `tool`'s length from the tool table (0: none; a tool not in it: 0, with a warning
        on `line`)."""
        if tool == 0:
            return 0.0
        if tool not in self.tools:
            self._warn(line if line is not None else self._line,
                       f"G43: tool {tool} is not in the tool table; its length is taken as 0")
            return 0.0
        return float(self.tools[tool].get("length_mm", 0.0))

    def _tool_length(self, words: _Words) -> bool:
        code, word = words.g["tool length"]
        line = self._line
        self.tool_length = {490: "G49", 430: "G43", 431: "G43.1"}[code]
        if code == 490:
            self.tool_offset = [0.0, 0.0, 0.0]
            return False
        elif code == 430:
            tool = self.tool_loaded
            if words.has("H"):
                h = words.value("H")
                if h < 0 or h != int(h):
                    self._fail(words.word("H"), "H must be a whole number >= 0")
                tool = int(h)
            self.tool_offset = [0.0, 0.0, self._tool_length_of(tool, line)]
            return False
        else:                                       # G43.1: dynamic offsets from axis words
            self._extra_axes(words)
            offset = [0.0, 0.0, 0.0]
            for a in range(3):
                if words.has(AXES[a]):
                    offset[a] = words.value(AXES[a]) * self.scale
            self.tool_offset = offset
            return True


MAX_SUBROUTINE_BYTES = 1 << 24


def subroutine_finder(folders: Sequence[Path]):
    """find_file for iterate_blocks: name -> (path shown, text) of the first folder's
    name.ngc, or None."""
    def find(name: str):
        for folder in folders:
            path = Path(folder) / f"{name}.ngc"
            if path.is_file():
                return str(path), read_source(path, MAX_SUBROUTINE_BYTES, "a subroutine file")
        return None
    return find


def _warning_line(text: str) -> int:
    head = text.split(":", 1)[0]
    return int(head[5:]) if head.startswith("line ") and head[5:].isdigit() else 0


def _clean(value: float) -> float:
    """Round off the binary noise of unit conversions (1e-12 of a unit) for the parameters."""
    rounded = round(value, 9)
    return 0.0 if rounded == 0 else rounded
