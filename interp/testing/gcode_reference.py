# SPDX-License-Identifier: Apache-2.0
"""An independent reading of RS274NGC G-code, written for the tests only.

It shares no code with interp.gcode (and uses no parser library): a small
hand-written tokenizer, a recursive-descent expression evaluator, the O-word
control flow and just enough of the LinuxCNC semantics to know where a program
ends: units (G20/G21), distance modes, G92 and its family, the work coordinate
systems G54-G59.3 with G10 L2/L20, G53, G28/G30, tool length offsets (G43 H,
G49), arcs (end points only; counted), the canned cycles G73/G81-G89 with
G98/G99 and L repeats (XY plane), polar words @ and ^, M2/M30, numbered and
named parameters with expressions and functions, #5420-#5422.

`run(text, g28=..., g30=..., tools=...)` returns a `Result`: the end position in
work coordinates (program units) and in machine millimetres, the number of
straight moves (feed and rapid, canned-cycle moves included) and of arcs, and
the events the program asks for (names of interp.gcode.moves.EVENTS, by
name only).  Anything it does not know raises `Refused(line, text)`.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

INCH = 25.4
CYCLES = {730, 810, 820, 830, 850, 860, 890}          # G73, G81-G83, G85, G86, G89 (x10)
COORDINATE_SYSTEMS = [540, 550, 560, 570, 580, 590, 591, 592, 593]
KNOWN_G = {0, 10, 20, 30, 40, 100, 170, 180, 190, 200, 210, 280, 281, 300, 301, 530, 800, 430,
           490, 900, 910, 920, 921, 922, 923, 980, 990,
           400, 610, 611, 640, 901, 911, 930, 940} | CYCLES | set(COORDINATE_SYSTEMS)
FUNCTIONS = {
    "abs": abs, "acos": lambda v: math.degrees(math.acos(v)),
    "asin": lambda v: math.degrees(math.asin(v)), "cos": lambda v: math.cos(math.radians(v)),
    "sin": lambda v: math.sin(math.radians(v)), "tan": lambda v: math.tan(math.radians(v)),
    "exp": math.exp, "ln": math.log, "sqrt": math.sqrt, "fix": math.floor, "fup": math.ceil,
    "round": lambda v: float(math.floor(v + 0.5)) if v >= 0 else -float(math.floor(-v + 0.5)),
}
BINARY = {"**": 6, "*": 5, "/": 5, "mod": 5, "+": 4, "-": 4, "eq": 3, "ne": 3, "gt": 3,
          "ge": 3, "lt": 3, "le": 3, "and": 2, "or": 2, "xor": 2}
OPERATOR = re.compile("|".join(re.escape(op) for op in sorted(BINARY, key=len, reverse=True)))
NUMBER = re.compile(r"\d*\.?\d*")
NUMBER_START = set("0123456789.")
KEYWORDS = ("sub", "endsub", "call", "return", "if", "elseif", "else", "endif", "while",
            "endwhile", "do", "repeat", "endrepeat", "break", "continue")


class Refused(Exception):
    def __init__(self, line: int, text: str):
        super().__init__(f"line {line}: {text}")
        self.line = line


@dataclass
class Result:
    work: tuple[float, float, float]        # program units, the work coordinate system in force
    machine: tuple[float, float, float]     # millimetres
    units: str                              # "mm" or "inch" at the end
    lines: int = 0                          # straight moves, feed and rapid
    arcs: int = 0
    events: list[tuple[str, float]] = field(default_factory=list)


# ---------------------------------------------------------------------------- reading
def _strip(raw: str, number: int) -> str:
    """The line without comments and blanks, lower case."""
    out, depth = [], 0
    for ch in raw:
        if ch == "(":
            depth += 1
        elif ch == ")":
            if depth == 0:
                raise Refused(number, "')' without '('")
            depth -= 1
        elif depth == 0:
            if ch == ";":
                break
            if not ch.isspace():
                out.append(ch.lower())
    if depth:
        raise Refused(number, "unclosed comment")
    return "".join(out)


class _Reader:
    """Recursive descent over one stripped line; values need the parameters."""

    def __init__(self, text: str, number: int, machine: "_Machine"):
        self.s, self.i, self.n, self.m = text, 0, number, machine

    def fail(self, text: str):
        raise Refused(self.n, f"{text} at column {self.i + 1} of '{self.s}'")

    def peek(self, k: int = 1) -> str:
        return self.s[self.i:self.i + k]

    def eat(self, token: str) -> bool:
        if self.s.startswith(token, self.i):
            self.i += len(token)
            return True
        return False

    def number(self) -> float:
        match = NUMBER.match(self.s, self.i)
        text = match.group(0)
        if not any(c.isdigit() for c in text):
            self.fail("number expected")
        self.i += len(text)
        return float(text)

    def real(self) -> float:
        first = self.s[self.i:self.i + 1]
        if not first:
            self.fail("value expected")
        if first in NUMBER_START:
            return self.number()
        if first in "-+":
            self.i += 1
            return -self.real() if first == "-" else self.real()
        if first == "[":
            self.i += 1
            value = self.expression()
            if not self.eat("]"):
                self.fail("']' expected")
            return value
        if first == "#":
            return self.m.get(self.parameter_key())
        match = re.match(r"[a-z]+", self.s[self.i:])
        if match:
            name = match.group(0)
            self.i += len(name)
            if name == "exists":
                if not (self.eat("[") and self.peek() == "#"):
                    self.fail("EXISTS[#<name>] expected")
                key = self.parameter_key()
                if not self.eat("]"):
                    self.fail("']' expected")
                return float(self.m.exists(key))
            if name not in FUNCTIONS and name != "atan":
                self.fail(f"unknown function {name.upper()}")
            if self.peek() != "[":
                self.fail("'[' expected")
            argument = self.real()
            if name == "atan":
                if not self.eat("/"):
                    self.fail("ATAN[y]/[x] expected")
                return math.degrees(math.atan2(argument, self.real()))
            try:
                return float(FUNCTIONS[name](argument))
            except (ValueError, OverflowError):
                self.fail(f"{name.upper()} of {argument} is undefined")
        return self.number()

    def parameter_key(self) -> int | str:
        self.eat("#")
        if self.eat("<"):
            end = self.s.find(">", self.i)
            if end < 0:
                self.fail("'>' expected")
            name, self.i = self.s[self.i:end], end + 1
            return name
        value = self.real()
        if value != int(value) or not 1 <= value <= 5602:
            self.fail(f"parameter number {value} out of range")
        return int(value)

    def operator(self) -> str | None:
        match = OPERATOR.match(self.s, self.i)
        return match.group(0) if match else None

    def expression(self) -> float:
        """Inside brackets: binary operators by precedence, left to right."""
        values, ops = [self.real()], []

        def reduce():
            b, a, op = values.pop(), values.pop(), ops.pop()
            values.append(_apply(op, a, b, self))
        while (op := self.operator()) is not None:
            self.i += len(op)
            while ops and BINARY[ops[-1]] >= BINARY[op]:
                reduce()
            ops.append(op)
            values.append(self.real())
        while ops:
            reduce()
        return values[0]


def _apply(op: str, a: float, b: float, reader: _Reader) -> float:
    if op == "**":
        return a ** b
    if op == "*":
        return a * b
    if op == "/":
        if b == 0:
            reader.fail("division by zero")
        return a / b
    if op == "mod":
        if b == 0:
            reader.fail("MOD by zero")
        rest = math.fmod(a, b)
        return rest + abs(b) if rest < 0 else rest
    if op == "+":
        return a + b
    if op == "-":
        return a - b
    tests = {"eq": a == b, "ne": a != b, "gt": a > b, "ge": a >= b, "lt": a < b, "le": a <= b,
             "and": bool(a) and bool(b), "or": bool(a) or bool(b), "xor": bool(a) != bool(b)}
    return float(tests[op])


# ---------------------------------------------------------------------------- the machine
class _Machine:
    def __init__(self, g28, g30, tools, fanuc_g80):
        self.fanuc_g80 = fanuc_g80
        self.last_straight = None                        # G0 or G1, while no arc mode came after
        self.numbered: dict[int, float] = {}
        self.frames: list[dict[str, float]] = [{}]       # named locals per call level
        self.globals: dict[str, float] = {}
        self.g28, self.g30 = list(g28), list(g30)
        self.tools = tools
        self.position = [0.0, 0.0, 0.0]                  # machine mm
        self.factor = 1.0                                # mm per program unit
        self.absolute = True
        self.plane = 170
        self.motion = 800
        self.systems = [[0.0, 0.0, 0.0] for _ in COORDINATE_SYSTEMS]
        self.system = 0
        self.g92 = [0.0, 0.0, 0.0]
        self.g92_saved = [0.0, 0.0, 0.0]
        self.tool_z = 0.0
        self.selected_tool = 0
        self.current_tool = 0
        self.r_plane = True                              # G99
        self.cycle_r = self.cycle_z = None
        self.initial_level = None                        # the canned cycles' G98 level
        self.feed = 0.0
        self.spindle = 0                                 # 0 off, 3 cw, 4 ccw
        self.speed = 0.0
        self.lines = self.arcs = 0
        self.events: list[tuple[str, float]] = []
        self.ended = False
        self.polar_words: dict[str, float] = {}          # the block's @ and ^

    # parameters
    def get(self, key):
        if isinstance(key, str):
            table = self.globals if key.startswith("_") else self.frames[-1]
            if key not in table:
                raise KeyError(key)
            return table[key]
        if 5420 <= key <= 5422:
            return self.work()[key - 5420]
        return self.numbered.get(key, 0.0)

    def exists(self, key) -> bool:
        table = self.globals if str(key).startswith("_") else self.frames[-1]
        return key in table

    def set(self, key, value):
        if isinstance(key, str):
            (self.globals if key.startswith("_") else self.frames[-1])[key] = value
        else:
            self.numbered[key] = value

    # coordinates
    def offset(self, axis: int) -> float:
        return (self.systems[self.system][axis] + self.g92[axis]
                + (self.tool_z if axis == 2 else 0.0))

    def work(self) -> list[float]:
        return [(self.position[a] - self.offset(a)) / self.factor for a in range(3)]

    def to_machine(self, work) -> list[float]:
        return [work[a] * self.factor + self.offset(a) for a in range(3)]


# ---------------------------------------------------------------------------- blocks
def _words(reader: _Reader):
    """(letter, value) pairs and parameter assignments of a block."""
    words, assignments = [], []
    while reader.i < len(reader.s):
        ch = reader.s[reader.i]
        if ch == "#":
            key = reader.parameter_key()
            if not reader.eat("="):
                reader.fail("'=' expected after a parameter")
            assignments.append((key, reader.real()))
            continue
        if ch not in "abcdfghijklmnpqrstxyz@^$":
            reader.fail(f"unknown word '{ch}'")
        reader.i += 1
        words.append((ch, reader.real()))
    return words, assignments


def _code(value: float, number: int, letter: str) -> int:
    code = round(value * 10)
    if abs(code - value * 10) > 1e-6:
        raise Refused(number, f"{letter.upper()}{value} is not a code")
    return code


def _execute(m: _Machine, number: int, words: list[tuple[str, float]]):
    def fail(text):
        raise Refused(number, text)
    g = [_code(v, number, "g") for c, v in words if c == "g"]
    mc = [_code(v, number, "m") / 10 for c, v in words if c == "m"]
    other = {}
    for letter, value in words:
        if letter in "gmn":
            continue
        if letter in other:
            fail(f"two {letter.upper()} words")
        other[letter] = value
    has = other.__contains__

    # feed, speed, tool
    if has("f"):
        m.feed = other["f"]
    if has("s"):
        if m.spindle and other["s"] != m.speed and not any(c in (3, 4, 5) for c in mc):
            m.events.append(("spindle_speed", other["s"]))
        m.speed = other["s"]
    if has("t"):
        m.selected_tool = int(other["t"])
    for code in mc:
        if code not in (0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 30, 60, 62, 63, 64, 65):
            fail(f"M{code:g} unknown")
    if 6 in mc:
        m.current_tool = m.selected_tool
        m.events += [("tool_change", m.selected_tool), ("pause", 6)]
    for code in mc:
        if code in (3, 4):
            m.spindle = int(code)
            m.events.append(("spindle_cw" if code == 3 else "spindle_ccw", m.speed))
        elif code == 5:
            m.spindle = 0
            m.events.append(("spindle_off", 0))
    for code in mc:
        if code in (7, 8, 9):
            m.events.append(({7: "mist_on", 8: "flood_on", 9: "coolant_off"}[code], 0))
        elif code in (62, 63, 64, 65):
            m.events.append(("output_on" if code in (62, 64) else "output_off", other.get("p", 0)))

    # modal settings, in the RS274NGC order of execution
    modes = set(g)
    if 40 in modes:
        if not has("p"):
            fail("G4 without P")
    for code in modes:
        if code in (410, 420, 411, 421):
            fail("cutter radius compensation")
        if code not in KNOWN_G:
            fail(f"G{code / 10:g} unknown")
        if code in (170, 180, 190):
            m.plane = code
        elif code in (200, 210):
            m.factor = INCH if code == 200 else 1.0
    if 430 in modes:
        tool = int(other["h"]) if has("h") else m.current_tool
        m.tool_z = float(m.tools.get(tool, {}).get("length_mm", 0.0))
    if 490 in modes:
        m.tool_z = 0.0
    for index, code in enumerate(COORDINATE_SYSTEMS):
        if code in modes:
            m.system = index
    if 900 in modes:
        m.absolute = True
    if 910 in modes:
        m.absolute = False
    if 980 in modes:
        m.r_plane = False
    if 990 in modes:
        m.r_plane = True

    axes = {a: other[c] for a, c in enumerate("xyz") if has(c)}
    polar = has("@") or has("^")
    non_modal = modes & {100, 280, 281, 300, 301, 920, 921, 922, 923}
    motion_codes = modes & ({0, 10, 20, 30, 800} | CYCLES)
    if m.fanuc_g80 and 800 in motion_codes and len(motion_codes & {0, 10, 20, 30}) == 1:
        motion_codes = motion_codes - {800}              # G0 ... G80: the motion word wins
    if len(motion_codes) > 1 or len(non_modal) > 1:
        fail("two G codes of one modal group")
    if motion_codes:
        m.motion = next(iter(motion_codes))
        if m.motion not in CYCLES:
            m.initial_level = None
        if m.motion in (0, 10, 20, 30):
            m.last_straight = m.motion if m.motion in (0, 10) else None
    if non_modal:
        code = non_modal.pop()
        if code == 100:
            _g10(m, other, axes, fail)
        elif code in (280, 300):
            home = m.g28 if code == 280 else m.g30
            if axes:
                _straight(m, axes, polar=False, fail=fail, count=False)
                m.lines += 1
                for a in axes:
                    m.position[a] = home[a]
            else:
                m.position = list(home)
            m.lines += 1
        elif code in (281, 301):
            (m.g28 if code == 281 else m.g30)[:] = m.position
        elif code == 920:
            if not axes:
                fail("G92 without axis words")
            for a, value in axes.items():
                m.g92[a] = m.position[a] - m.systems[m.system][a] - (m.tool_z if a == 2 else 0) \
                    - value * m.factor
            m.g92_saved = list(m.g92)
        elif code in (921, 922):
            m.g92 = [0.0, 0.0, 0.0]
            if code == 921:
                m.g92_saved = [0.0, 0.0, 0.0]
        elif code == 923:
            m.g92 = list(m.g92_saved)
    elif (axes or polar or motion_codes & ({20, 30} | CYCLES)
          or (m.motion in (20, 30) and {"i", "j", "k"} & set(other))):
        if m.motion == 800 and m.fanuc_g80 and m.last_straight is not None:
            m.motion = m.last_straight                   # Fanuc: the mode before the cycle
        if m.motion == 800:
            fail("axis words without a motion mode (G80 in force)")
        if 530 in modes:
            if m.motion not in (0, 10) or not m.absolute:
                fail("G53 needs G0 or G1 and G90")
            for a, value in axes.items():
                m.position[a] = value * m.factor
            m.lines += 1
        elif m.motion in (0, 10):
            _straight(m, axes, polar, fail)
        elif m.motion in (20, 30):
            if polar:
                fail("polar arc")
            if not (has("r") or has("i") or has("j") or has("k")):
                fail("arc without I, J, K or R")
            start = list(m.position)
            _straight(m, axes, False, fail, count=False)
            if has("r") and m.position == start:
                fail("full circle in R format")
            if m.feed <= 0:
                fail("arc with zero feed")
            m.arcs += 1
        else:
            _cycle(m, other, axes, polar, fail)

    for code in mc:
        if code in (0, 1, 60):
            m.events.append(("pause", code))
        elif code in (2, 30):
            m.events.append(("program_end", code))
            m.ended = True


def _straight(m: _Machine, axes, polar, fail, count=True):
    work = m.work()
    target = list(work)
    for a, value in axes.items():
        target[a] = value if m.absolute else work[a] + value
    if polar:
        target[0], target[1] = _polar(m, work, fail)
    if m.motion == 10 and m.feed <= 0 and count:
        fail("G1 with zero feed")
    m.position = m.to_machine(target)
    if count:
        m.lines += 1


def _polar(m: _Machine, work, fail):
    args = m.polar_words
    if m.plane != 170:
        fail("polar words outside G17")
    if m.absolute:
        radius = args.get("@", math.hypot(work[0], work[1]))
        angle = math.radians(args["^"]) if "^" in args else math.atan2(work[1], work[0])
    else:
        if work[0] == 0 and work[1] == 0:
            fail("incremental polar motion at the origin")
        radius = math.hypot(work[0], work[1]) + args.get("@", 0.0)
        angle = math.atan2(work[1], work[0]) + math.radians(args.get("^", 0.0))
    return radius * math.cos(angle), radius * math.sin(angle)


def _g10(m: _Machine, other, axes, fail):
    layer = other.get("l")
    if layer not in (2, 20) or "r" in other:
        fail("G10 other than L2 / L20 without R")
    p = int(other.get("p", 0))
    index = m.system if p == 0 else p - 1
    if not 0 <= index < len(COORDINATE_SYSTEMS):
        fail(f"G10 P{p} out of range")
    for a, value in axes.items():
        if layer == 2:
            m.systems[index][a] = value * m.factor
        else:
            m.systems[index][a] = (m.position[a] - m.g92[a] - (m.tool_z if a == 2 else 0)
                                   - value * m.factor)


def _cycle(m: _Machine, other, axes, polar, fail):
    """A canned cycle in the XY plane: positions only (LinuxCNC's convert_cycle_xy)."""
    if m.plane != 170:
        fail("canned cycle outside G17")
    fresh = m.initial_level is None
    if fresh and 2 not in axes:
        fail("canned cycle without Z")
    if "r" not in other and fresh:
        fail("canned cycle without R")
    work = m.work()
    z = axes.get(2, m.cycle_z)
    r = other.get("r", m.cycle_r)
    m.cycle_z, m.cycle_r = z, r
    if m.motion == 730 and fresh and "q" not in other:
        fail("G73 without Q")
    if m.motion in (820, 860, 890) and fresh and "p" not in other:
        fail("dwell cycle without P")
    if m.feed <= 0:
        fail("canned cycle with zero feed")
    repeats = int(other.get("l", 1))
    if repeats < 1:
        fail("L must be at least 1")
    if fresh:
        m.initial_level = work[2]
    old = m.initial_level
    x, y = work[0], work[1]
    dx = dy = dr = da = 0.0
    if m.absolute:
        if polar:
            x, y = _polar(m, work, fail)
        else:
            x, y = axes.get(0, x), axes.get(1, y)
        bottom = z
    else:
        dx, dy = axes.get(0, 0.0), axes.get(1, 0.0)
        dr, da = m.polar_words.get("@", 0.0), math.radians(m.polar_words.get("^", 0.0))
        r = r + old
        bottom = r + z
    if r < bottom:
        fail("R below the bottom of the canned cycle")
    if old < r:
        m.lines += 1
        old = r
    clear = r if m.r_plane else old
    for _ in range(repeats):
        x, y = x + dx, y + dy
        if dr or da:
            if x == 0 and y == 0:
                fail("incremental polar motion at the origin")
            radius, angle = math.hypot(x, y) + dr, math.atan2(y, x) + da
            x, y = radius * math.cos(angle), radius * math.sin(angle)
        m.lines += 4 if old != r else 3          # to the hole, (down to R,) feed, retract
        old = clear
    m.position = m.to_machine([x, y, clear])


# ---------------------------------------------------------------------------- programs
def _parse(text: str):
    """[(line number, kind, payload)]: kind "block" (stripped text) or an O-word keyword."""
    program = []
    for number, raw in enumerate(text.split("\n"), start=1):       # "\r\r\n" is one line end
        stripped = raw.strip()
        if not stripped or stripped[0] in "%$" or stripped[0] == "?" and _strip(raw, number) == "?":
            continue
        code = _strip(raw, number)
        if code.startswith("/"):
            continue
        code = re.sub(r"^n\d+(\.\d*)?", "", code)
        if not code:
            continue
        match = re.match(r"o(<[^>]*>|\d+)", code)
        if match:
            label, rest = match.group(1), code[match.end():]
            keyword = next((k for k in sorted(KEYWORDS, key=len, reverse=True)
                            if rest.startswith(k)), None)
            if keyword is None:
                if rest == "":
                    continue                    # a program number (O1000) on its own
                raise Refused(number, f"unknown O-word '{code}'")
            program.append((number, keyword, (label, rest[len(keyword):])))
        else:
            program.append((number, "block", code))
    return program


def run(text: str, *, g28=(0.0, 0.0, 0.0), g30=(0.0, 0.0, 0.0), tools=None,
        fanuc_g80: bool = False) -> Result:
    """The end of `text` as LinuxCNC would run it (see the module's docstring).

    g28, g30: the G28 / G30 positions in machine mm; tools: T -> {"length_mm": ...} (a tool
    missing from it has length 0).  fanuc_g80 allows two Fanuc habits LinuxCNC refuses:
    G80 in a block with G0..G3 (the motion word wins), and axis words while G80 is in force
    (they move in the G0 / G1 mode that was in force before the canned cycle).
    """
    m = _Machine(g28, g30, tools or {}, fanuc_g80)
    program = _parse(text)
    subs = {}
    for index, (number, kind, payload) in enumerate(program):
        if kind == "sub":
            end = next((j for j in range(index + 1, len(program))
                        if program[j][1] == "endsub" and program[j][2][0] == payload[0]), None)
            if end is None:
                raise Refused(number, "sub without endsub")
            subs[payload[0]] = (index, end)

    def find(start, label, kinds, step=1):
        j = start + step
        while 0 <= j < len(program):
            if program[j][1] in kinds and program[j][2][0] == label:
                return j
            j += step
        raise Refused(program[start][0], f"no {'/'.join(kinds)} for o{label}")

    def value(number, rest):
        reader = _Reader(rest, number, m)
        if not rest:
            return None
        try:
            result = reader.real()
        except KeyError as error:
            raise Refused(number, f"named parameter #<{error.args[0]}> not defined")
        if reader.i != len(rest):
            reader.fail("trailing text")
        return result

    calls, loops = [], []          # (return index, saved #1-#30); loops: [label, index, count]
    pc, steps = 0, 0
    while pc < len(program) and not m.ended:
        steps += 1
        if steps > 10_000_000:
            raise Refused(program[pc][0], "runs too long")
        number, kind, payload = program[pc]
        if kind == "block":
            reader = _Reader(payload, number, m)
            try:
                words, assignments = _words(reader)
            except KeyError as error:
                raise Refused(number, f"named parameter #<{error.args[0]}> not defined")
            m.polar_words = {c: v for c, v in words if c in "@^"}
            _execute(m, number, words)
            for key, val in assignments:
                m.set(key, val)
            pc += 1
            continue
        label, rest = payload
        if kind == "sub":
            pc = subs[label][1] + 1
        elif kind == "call":
            if label not in subs:
                raise Refused(number, f"o{label} is not defined")
            args = []
            reader = _Reader(rest, number, m)
            try:
                while reader.i < len(rest):
                    if reader.peek() != "[":
                        reader.fail("'[' expected")
                    args.append(reader.real())
            except KeyError as error:
                raise Refused(number, f"named parameter #<{error.args[0]}> not defined")
            if len(calls) > 200:
                raise Refused(number, "subroutine calls nested too deep")
            saved = {k: m.numbered.get(k, 0.0) for k in range(1, 31)}
            calls.append((pc + 1, saved, loops))
            loops = []
            for k in range(1, 31):
                m.numbered[k] = args[k - 1] if k <= len(args) else 0.0
            m.frames.append({})
            pc = subs[label][0] + 1
        elif kind in ("endsub", "return"):
            if not calls:
                if kind == "endsub":
                    pc += 1
                    continue
                raise Refused(number, "return outside a subroutine")
            pc, saved, loops = calls.pop()
            m.numbered.update(saved)
            m.frames.pop()
        elif kind in ("if", "elseif"):
            if kind == "elseif":            # reached from a taken branch
                pc = find(pc, label, ("endif",)) + 1
                continue
            j = pc
            while True:
                number_j, kind_j, (label_j, rest_j) = program[j]
                if kind_j == "else" or value(number_j, rest_j):
                    pc = j + 1
                    break
                j = find(j, label, ("elseif", "else", "endif"))
                if program[j][1] == "endif":
                    pc = j + 1
                    break
        elif kind == "else":
            pc = find(pc, label, ("endif",)) + 1
        elif kind == "endif":
            pc += 1
        elif kind == "do":
            pc += 1
        elif kind == "while":
            is_end_of_do = any(program[j][1] == "do" and program[j][2][0] == label
                               for j in range(pc))
            if is_end_of_do:
                pc = find(pc, label, ("do",), -1) + 1 if value(number, rest) else pc + 1
            elif value(number, rest):
                pc += 1
            else:
                pc = find(pc, label, ("endwhile",)) + 1
        elif kind == "endwhile":
            pc = find(pc, label, ("while",), -1)
        elif kind == "repeat":
            count = int(value(number, rest) or 0)
            if count <= 0:
                pc = find(pc, label, ("endrepeat",)) + 1
            else:
                loops.append([label, pc, count])
                pc += 1
        elif kind == "endrepeat":
            if not loops or loops[-1][0] != label:
                raise Refused(number, "endrepeat without repeat")
            loops[-1][2] -= 1
            if loops[-1][2] > 0:
                pc = loops[-1][1] + 1
            else:
                loops.pop()
                pc += 1
        elif kind in ("break", "continue"):
            j = find(pc, label, ("endwhile", "endrepeat", "while"))
            if program[j][1] == "endrepeat":
                if kind == "break":
                    loops.pop()
                    pc = j + 1
                else:
                    pc = j
            elif program[j][1] == "endwhile":
                pc = j + 1 if kind == "break" else find(j, label, ("while",), -1)
            else:                                        # the while of a do-while
                pc = j + 1 if kind == "break" else j
        else:
            raise Refused(number, f"O-word {kind}")
    return Result(tuple(m.work()), tuple(m.position), "inch" if m.factor == INCH else "mm",
                  m.lines, m.arcs, m.events)
