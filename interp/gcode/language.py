# SPDX-License-Identifier: Apache-2.0
"""The G-code language: text -> blocks of evaluated words (LinuxCNC RS274NGC dialect).

Everything below the machine semantics lives here: lines, comments, block delete,
line numbers, "%" and Grbl "$" lines, numbers, parameters (#1, #<name>, #<_global>,
##2, #[expr]), expressions, assignments and the O-word control flow (subroutines,
loops, conditionals).  The interpreter (interpreter.py) gives the words their meaning.

    params = Parameters()
    for block in iterate_blocks(text, params):
        ...             # block.words: [Word("G", 1.0, 1, "G1"), Word("X", 10.0, 4, "X10")]

Every line is read with the lark grammar grammar.lark (LALR); plain lines of
letter-number words take a regular-expression fast path that yields the same words.
Expressions are evaluated when their block is yielded, so the interpreter may
update parameters (the current position, offsets) between blocks.
Anything unreadable raises GcodeError with the line, column and word.
"""
from __future__ import annotations

import bisect
import math
import os
import re
import stat
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterator

import lark

from interp.cores import UsageError
from interp.gcode.errors import GcodeError, printable

NUMBERED = 5602                 # numbered parameters #1 .. #5602
CALL_ARGUMENTS = 30             # #1 .. #30 are a subroutine's arguments, local to the call
MAX_DIGITS = 60                 # digits in one number
MAX_LOOP_ITERATIONS = 10**5     # all loops of one run together (a few seconds with moves inside)
MAX_CALLS = 10**5               # subroutine calls in one run
MAX_CALL_DEPTH = 100            # nested subroutine calls
MAX_NESTING = 200               # brackets / operators nested in one expression
EQUAL_TOLERANCE = 1e-4          # EQ and NE compare with this tolerance, as LinuxCNC does


class ExpressionError(ValueError):
    """An expression or parameter access that cannot be evaluated (wrapped in a GcodeError)."""


@dataclass
class Word:
    letter: str                 # upper case: "G", "X", ... also "@", "^", "$"
    value: float
    column: int                 # 1-based column of the letter
    text: str                   # as written, e.g. "x 1 0.5" or "X[#1*2]"


@dataclass
class Block:
    line: int                   # 1-based line number in the text (in a subroutine file: of the call)
    words: list[Word]
    delete: bool = False        # "/" at the start of the line
    comments: list[str] = field(default_factory=list)   # ( ) and ; texts, without delimiters
    file: str = ""              # the subroutine file it is in ("": the program)
    file_line: int = 0          # ... and its line there
    top: int = 0                # the program's line outside any subroutine that runs it (run from a line)


def _name(key: str) -> str:
    """A named parameter's key: without #< >, lower case, no spaces."""
    key = key.strip()
    if key.startswith("#"):
        key = key[1:]
    if key.startswith("<") and key.endswith(">"):
        key = key[1:-1]
    return key.lower().replace(" ", "").replace("\t", "")


_COMMENT_PARAMETER = re.compile(r"#(\d+|<[^>)]*>)")


def substitute_parameters(text: str, params: "Parameters") -> str:
    """A (DEBUG, ...), (PRINT, ...) or (ABORT, ...) comment's text with each #N and #<name>
    replaced by its value as LinuxCNC writes it (printf's %lf: 5.000000), "######" for an
    undefined name, a number out of range or a value of 30 characters or more (#0 is 0, as
    LinuxCNC's parameter 0); a '#' followed by neither stays."""
    def value(m) -> str:
        key = m.group(1)
        try:
            v = (0.0 if int(key) == 0 else params.get(int(key))) if key.isdigit() else params.get(key)
        except ExpressionError:
            return "######"
        shown = f"{0.0 if abs(v) < 1e-4 else v:f}"     # (LinuxCNC's equal(): |v| < 0.0001 is 0)
        return shown if len(shown) < 30 else "######"   # (and its 30-character buffer)
    return _COMMENT_PARAMETER.sub(value, text)


class Parameters:
    """The parameter store: numbered #1..#5602, global #<_name>, local #<name> per call level.

    Keys: an int (numbered) or a str name ("_global", "local"; "#<...>", case and spaces
    ignored).  Reading an unset numbered parameter gives 0; reading an undefined named
    parameter raises ExpressionError, as does a number out of range.
    `warnings` collects the language layer's warnings, "line L: text" each;
    `subroutines` the program's own subroutines as (label, first line, last line), set
    when its blocks are iterated.
    """

    def __init__(self):
        self.numbered = [0.0] * (NUMBERED + 1)
        self.globals: dict[str, float] = {"_value": 0.0, "_value_returned": 0.0}
        self.frames: list[dict[str, float]] = [{}]          # named locals per call level
        # the interpreter's modal state saved per call level (M70, M73); on_return(state, line)
        # restores one M73 saved when its subroutine returns (at the endsub or return itself)
        self.modal_saved: list[object] = [None]
        self.on_return = None
        self.saved: list[list[float]] = []                  # callers' #1..#30
        self.warnings: list[str] = []
        self.subroutines: list[tuple[str, int, int]] = []

    @staticmethod
    def _index(key) -> int:
        if isinstance(key, bool) or not isinstance(key, (int, float)):
            raise ExpressionError(f"parameter key {key!r} is neither a number nor a name")
        if isinstance(key, float):
            if not math.isfinite(key) or abs(key - round(key)) > 1e-4:
                raise ExpressionError(f"parameter number {key:g} is not an integer")
            key = int(round(key))
        if not 1 <= key <= NUMBERED:
            raise ExpressionError(f"parameter number {key} out of range 1..{NUMBERED}")
        return key

    def _scope(self, name: str) -> dict[str, float]:
        return self.globals if name.startswith("_") else self.frames[-1]

    def get(self, key) -> float:
        if isinstance(key, str):
            name = _name(key)
            try:
                return self._scope(name)[name]
            except KeyError:
                raise ExpressionError(f"#<{name}> is not defined") from None
        return self.numbered[self._index(key)]

    def set(self, key, value: float) -> None:
        value = float(value)
        if not math.isfinite(value):
            raise ExpressionError(f"parameter value {value} is not a finite number")
        if isinstance(key, str):
            name = _name(key)
            if not name:
                raise ExpressionError("empty parameter name")
            self._scope(name)[name] = value
        else:
            self.numbered[self._index(key)] = value

    def exists(self, key) -> bool:
        if isinstance(key, str):
            name = _name(key)
            return name in self._scope(name)
        try:
            self._index(key)
        except ExpressionError:
            return False
        return True

    @property
    def depth(self) -> int:
        """Subroutine call level: 0 in the main program."""
        return len(self.saved)

    def push_call(self, args: list[float]) -> None:
        """Enter a subroutine: #1..#30 saved, #1..#N set from the N args (#N+1..#30 keep
        the caller's values, as LinuxCNC does), new named locals."""
        if len(args) > CALL_ARGUMENTS:
            raise ExpressionError(f"more than {CALL_ARGUMENTS} arguments")
        self.saved.append(self.numbered[1:CALL_ARGUMENTS + 1])
        self.numbered[1:len(args) + 1] = [float(a) for a in args]
        self.frames.append({})
        self.modal_saved.append(None)

    def pop_call(self, line: int = 0) -> None:
        """Leave a subroutine (at `line`): the caller's #1..#30 and locals back, and the modal
        state its M73 saved."""
        self.numbered[1:CALL_ARGUMENTS + 1] = self.saved.pop()
        self.frames.pop()
        state = self.modal_saved.pop()
        if state is not None and state.autorestore and self.on_return is not None:
            self.on_return(state, line)


# --- reading one line -------------------------------------------------------------------

GRAMMAR = (Path(__file__).with_name("grammar.lark")).read_text()
_PARSER = lark.Lark(GRAMMAR, parser="lalr", lexer="contextual")

_WORD_LETTERS = "abcdefghijklmpqrstuvwxyz$@^"          # n and o only at the start
_NUM = r"(?:[0-9]+\.?[0-9]*|\.[0-9]+)"
_PLAIN = re.compile(rf"(?:n[0-9]+)?(?:[{re.escape(_WORD_LETTERS)}][+-]?{_NUM})*")
_PLAIN_WORD = re.compile(rf"([{re.escape(_WORD_LETTERS)}])([+-]?{_NUM})")
_CONTROL = re.compile(r"[\x00-\x08\x0a-\x1f\x7f]")
_GRBL = re.compile(r"\$(?![0-9.+-])|\$[0-9]+=|[?!~]")
_ALLOWED = set("abcdefghijklmnopqrstuvwxyz0123456789.+-*/[]#<>=_$@^")
_MESSAGE = re.compile(r"[ \t]*(/?[ \t]*(?:[nN][ \t0-9]*[0-9][ \t]*)?[mM][ \t]*0*11[78])(?![ \t]*[0-9.])")
_SURROGATE = re.compile("[\ud800-\udfff]")
_FUNCTIONS = ("abs", "acos", "asin", "atan", "cos", "exists", "exp", "fix", "fup", "ln",
              "round", "sin", "sqrt", "tan")


class _LineError(Exception):
    """A problem at compact position `pos` of a line (turned into a GcodeError)."""

    def __init__(self, pos: int, text: str, end: int | None = None):
        self.pos, self.text, self.end = pos, text, end


@dataclass(slots=True)
class _Item:
    target: object              # letter (str, upper case) of a word, or a parameter node
    expr: object                # float or expression node
    column: int
    text: str


@dataclass(slots=True)
class _Line:
    line: int
    kind: str                   # "block" or an O-word keyword
    items: list = field(default_factory=list)
    delete: bool = False
    comments: list = field(default_factory=list)
    label: str = ""             # O-word: "o100" or "o<name>"
    args: list = field(default_factory=list)
    column: int = 1
    text: str = ""
    # jump targets, filled in by _structure
    end: int = -1               # sub -> endsub, while/do/repeat -> their end, if -> endif
    start: int = -1             # end of a loop -> its opening line
    branches: list = field(default_factory=list)    # if: the elseif / else lines
    loop: int = -1              # break / continue: the loop's opening line


def _comment(text: str) -> str:
    """A comment's text, printable: a byte that was not UTF-8 becomes U+FFFD."""
    return text if text.isascii() else _SURROGATE.sub("\ufffd", text)


def _strip_comments(raw: str, number: int, warnings: list[str]):
    """(code, columns, comments): the line without comments, and each code character's column.

    Raises GcodeError for an unterminated comment, a stray ")" or a bad character
    outside the comments.  Balanced parentheses inside a comment are accepted with a
    warning (LinuxCNC refuses them; CAM headers contain them).
    """
    comments: list[str] = []
    if "(" not in raw and ")" not in raw and ";" not in raw:
        code, columns = raw, None
    else:
        chars: list[str] = []
        columns = []
        i, n = 0, len(raw)
        while i < n:
            ch = raw[i]
            if ch == ";":
                comments.append(_comment(raw[i + 1:]))
                break
            if ch == ")":
                raise GcodeError(number, i + 1, ")", "')' without '('")
            if ch == "(":
                depth, j = 1, i + 1
                while j < n and depth:
                    if raw[j] == "(":
                        depth += 1
                    elif raw[j] == ")":
                        depth -= 1
                    j += 1
                if depth:
                    raise GcodeError(number, i + 1, "", "comment not closed: '(' without ')'")
                text = raw[i + 1:j - 1]
                if "(" in text:
                    warnings.append(f"line {number}: parentheses nested in a comment "
                                    "(read as one comment)")
                comments.append(_comment(text))
                i = j
                continue
            chars.append(ch)
            columns.append(i + 1)
            i += 1
        code = "".join(chars)
    if not code.isascii() or _CONTROL.search(code):
        for k, ch in enumerate(code):
            if not ch.isascii() or _CONTROL.match(ch):
                column = columns[k] if columns is not None else k + 1
                what = "control" if ch.isascii() else "non-ASCII"
                raise GcodeError(number, column, ch, f"{what} character outside a comment")
    if columns is None:
        if " " not in code and "\t" not in code:
            return code.lower(), None, comments
        columns = [k + 1 for k, ch in enumerate(code) if ch not in " \t"]
    else:
        columns = [c for c, ch in zip(columns, code) if ch not in " \t"]
    compact = code.replace(" ", "").replace("\t", "").lower()
    return compact, columns, comments


def _digits_ok(text: str) -> bool:
    return len(text) - ("." in text) <= MAX_DIGITS


# --- lark tree -> items -------------------------------------------------------------------

_TEMPLATE = re.compile(r"<[^<>]*>|([0-9]+\.?[0-9]*|\.[0-9]+)")
_TREES: dict[str, lark.Tree] = {}


class _Source:
    """A line and its template, the line with every number written as 1.

    Lines that differ only in their numbers (CAM output with expressions) share one
    template, so the grammar parses each template once.  The tokens of the template's
    tree are mapped back to the line: their text and positions.
    """

    __slots__ = ("compact", "template", "starts", "numbers", "extra")

    def __init__(self, compact: str):
        self.compact = compact
        self.starts: list[int] = []                 # template position of each number
        self.numbers: list[tuple[int, int]] = []    # its span in the line
        self.extra: list[int] = []                  # characters saved up to and with it
        parts = []
        last = shift = 0
        n = len(compact)
        for m in _TEMPLATE.finditer(compact):
            if m.group(1) is None:
                continue
            start, end = m.span()
            if (start and compact[start - 1] in "0123456789.") or (end < n and compact[end] == "."):
                self.template = compact             # "1.2.3", "..5": read as written
                self.starts, self.numbers, self.extra = [], [], []
                return
            parts.append(compact[last:start])
            parts.append("1")
            self.starts.append(start - shift)
            self.numbers.append((start, end))
            shift += end - start - 1
            self.extra.append(shift)
            last = end
        parts.append(compact[last:])
        self.template = "".join(parts)

    def pos(self, tok) -> int:
        p = tok.start_pos
        k = bisect.bisect_right(self.starts, p)
        if k and self.starts[k - 1] == p:
            return self.numbers[k - 1][0]
        return p + (self.extra[k - 1] if k else 0)

    def text(self, tok) -> str:
        if tok.type == "NUMBER":
            k = bisect.bisect_left(self.starts, tok.start_pos)
            if k < len(self.starts) and self.starts[k] == tok.start_pos:
                start, end = self.numbers[k]
                return self.compact[start:end]
        return str(tok)

    def end(self, tok) -> int:
        return self.pos(tok) + len(self.text(tok))

    def first_pos(self, node) -> int:
        while isinstance(node, lark.Tree):
            node = node.children[0]
        return self.pos(node)

    def number(self, tok) -> str:
        text = self.text(tok)
        if not _digits_ok(text):
            raise _LineError(self.pos(tok), f"number with more than {MAX_DIGITS} digits",
                             self.end(tok))
        return text

    def convert(self, node, depth: int = 0):
        """An expression node: float, or a tuple ("p", index) ("n", name) ("b", op, a, b)
        ("f", name, arg) ("atan", y, x) ("exists", param) ("neg", x)."""
        if depth > MAX_NESTING:
            raise _LineError(self.first_pos(node),
                             f"expression nested deeper than {MAX_NESTING} levels")
        d = depth + 1
        data = node.data
        ch = node.children
        convert = self.convert
        if data == "number":
            return float(self.number(ch[0]))
        if data == "pnum":
            return ("p", float(self.number(ch[1])))
        if data == "pname":
            return ("n", _name(str(ch[1])))
        if data == "pexpr":
            return ("p", convert(ch[2], d))
        if data == "pind":
            return ("p", convert(ch[1], d))
        if data == "group":
            return convert(ch[1], d)
        if data == "func":
            return ("f", str(ch[0]), convert(ch[2], d))
        if data == "atan":
            return ("atan", convert(ch[2], d), convert(ch[6], d))
        if data == "exists":
            return ("exists", convert(ch[2], d))
        if data == "neg":
            inner = convert(ch[1], d)
            return -inner if type(inner) is float else ("neg", inner)
        if data == "pos":
            return convert(ch[1], d)
        if data == "binary":
            return ("b", str(ch[1]), convert(ch[0], d), convert(ch[2], d))
        raise AssertionError(data)      # pragma: no cover - the grammar has no other rule


def _parse_tree(text: str) -> lark.Tree:
    try:
        return _PARSER.parse(text)
    except lark.exceptions.UnexpectedInput as e:
        pos = getattr(e, "pos_in_stream", None)
        token = getattr(e, "token", None)
        if token is not None:
            pos = len(text) if token.type == "$END" else token.start_pos
        if pos is None:
            pos = len(text)
        raise _LineError(pos, "") from None


def _parse_compact(compact: str):
    """("block", delete, [(start, target, expr)]) or ("o", delete, start, label, keyword, args).

    start = compact position; raises _LineError."""
    src = _Source(compact)
    tree = _TREES.get(src.template)
    if tree is None:
        try:
            tree = _parse_tree(src.template)
        except _LineError:
            src = _Source.__new__(_Source)          # the error's position in the line itself
            src.compact = src.template = compact
            src.starts, src.numbers, src.extra = [], [], []
            tree = _parse_tree(compact)
        if len(_TREES) < 10_000:
            _TREES[src.template] = tree
    delete = False
    items = []
    for child in tree.children:
        if child.data == "delete":
            delete = True
        elif child.data == "lineno":
            src.number(child.children[1])
        elif child.data == "word":
            letter = child.children[0]
            if letter in "no":
                raise _LineError(src.pos(letter),
                                 "N (line number) must be the first word of the line"
                                 if letter == "n" else
                                 "an O-word must be the first word of the line",
                                 src.pos(letter) + 1)
            items.append((src.pos(letter), letter.upper(), src.convert(child.children[1])))
        elif child.data == "assign":
            items.append((src.first_pos(child), src.convert(child.children[0]),
                          src.convert(child.children[2])))
        elif child.data == "oline":
            o, label, command = child.children
            tok = label.children[0]
            if tok.type == "NUMBER":
                text = src.text(tok)
                if "." in text or not _digits_ok(text):
                    raise _LineError(src.pos(tok), "an O-word number must be an integer")
                name = f"o{int(text)}"
            else:
                name = f"o<{_name(str(tok))}>"
            if command.data == "onone":
                keyword = ""
                args = []
            else:
                keyword = str(command.children[0])
                args = [src.convert(a) for a in command.children[1:]]
            return ("o", delete, src.pos(o), name, keyword, args)
    return ("block", delete, items)


_CACHE: dict[str, object] = {}


def _read_line(raw: str, number: int, warnings: list[str]) -> _Line | None:
    """One line of text -> a _Line, or None for a line that yields nothing."""
    message = _MESSAGE.match(raw)
    if message:                     # Marlin M117 / M118: the rest of the line is a text
        rec = _read_code(message.group(0), number, warnings)
        text = _comment(raw[message.end():].strip(" \t"))
        if text:
            rec.comments.append(text)
        return rec
    return _read_code(raw, number, warnings)


def _read_code(raw: str, number: int, warnings: list[str]) -> _Line | None:
    compact, columns, comments = _strip_comments(raw, number, warnings)
    if not compact:
        return _Line(number, "block", comments=comments) if comments else None
    if _GRBL.match(compact):
        warnings.append(f"line {number}: Grbl command {printable(raw.strip())!r} skipped")
        return None

    def column(pos: int) -> int:
        if columns is None:
            return pos + 1
        return columns[pos] if pos < len(columns) else (columns[-1] + 1 if columns else 1)

    def written(start: int, end: int) -> str:
        if end <= start:
            return ""
        return raw[column(start) - 1:column(end - 1)].strip()

    delete = compact.startswith("/")
    body = compact[1:] if delete else compact
    if _PLAIN.fullmatch(body):
        offset = 1 if delete else 0
        items = []
        matches = list(_PLAIN_WORD.finditer(body))
        for k, m in enumerate(matches):
            start = m.start() + offset
            end = matches[k + 1].start() + offset if k + 1 < len(matches) else len(compact)
            if len(m.group(2)) > MAX_DIGITS and not _digits_ok(m.group(2).lstrip("+-")):
                raise GcodeError(number, column(start), written(start, end),
                                 f"number with more than {MAX_DIGITS} digits")
            items.append(_Item(m.group(1).upper(), float(m.group(2)), column(start),
                               written(start, end)))
        if body.startswith("n") and not _digits_ok(re.match(r"n([0-9]+)", body).group(1)):
            raise GcodeError(number, column(offset), written(offset, len(compact)),
                             f"number with more than {MAX_DIGITS} digits")
        return _Line(number, "block", items, delete, comments)

    parsed = _CACHE.get(compact)
    if parsed is None:
        try:
            parsed = _parse_compact(compact)
        except _LineError as e:
            raise _diagnose(compact, e, number, column, written) from None
        except RecursionError:
            raise GcodeError(number, column(0), written(0, len(compact)),
                             "expression nested too deeply") from None
        if len(_CACHE) < 10_000:
            _CACHE[compact] = parsed
    if parsed[0] == "o":
        _, delete, start, label, keyword, args = parsed
        if delete:
            raise GcodeError(number, column(0), "/", "block delete is not allowed on an O-word line")
        return _Line(number, keyword, comments=comments, label=label, args=args,
                     column=column(start), text=written(start, len(compact)))
    _, delete, found = parsed
    items = []
    for k, (start, target, expr) in enumerate(found):
        end = found[k + 1][0] if k + 1 < len(found) else len(compact)
        items.append(_Item(target, expr, column(start), written(start, end)))
    return _Line(number, "block", items, delete, comments)


def _item_starts(compact: str) -> list[int]:
    """Where the words and assignments of a line start (a heuristic, for error messages)."""
    starts: list[int] = []
    depth = 0
    name = False
    for i, ch in enumerate(compact):
        prev = compact[i - 1] if i else ""
        if name:
            name = ch != ">"
            continue
        if ch == "<":
            name = True
        elif ch == "[":
            depth += 1
        elif ch == "]":
            depth = max(0, depth - 1)
        elif depth == 0 and (ch.isalpha() or ch in "$@^#"):
            if i == 0 or prev in "0123456789.]>/":
                if not (ch == "#" and prev == "/" and i > 1):
                    starts.append(i)
            elif ch != "#" and prev.isalpha() and starts and starts[-1] == i - 1 \
                    and not compact.startswith(_FUNCTIONS, i):
                starts.append(i)
    return starts


def _diagnose(compact: str, error: _LineError, number: int, column, written) -> GcodeError:
    """The GcodeError for a line the grammar refused, naming the offending word."""
    pos = min(error.pos, len(compact))
    body = compact.lstrip("/")
    if body.startswith("o") or re.match(r"n[0-9.]*o", body):
        start = compact.index("o")
        return GcodeError(number, column(start), written(start, len(compact)),
                          error.text or "malformed O-word line (o<number or name> then sub, "
                          "endsub, call, return, do, while, endwhile, if, elseif, else, endif, "
                          "repeat, endrepeat, break or continue, and bracketed arguments)")
    if pos < len(compact) and compact[pos] not in _ALLOWED:
        ch = compact[pos]
        return GcodeError(number, column(pos), ch,
                          "unknown letter" if ch.isalpha() else "unknown character")
    if compact[pos:pos + 1] == "/" and compact[:pos].count("[") == compact[:pos].count("]"):
        return GcodeError(number, column(pos), "/",
                          "block delete '/' must be the first character of the line")
    starts = _item_starts(compact)
    if error.text and error.end is not None:
        return GcodeError(number, column(pos), written(pos, error.end), error.text)
    if pos in starts and pos > 0 and compact[pos - 1] not in "]":
        start = max(s for s in starts if s < pos)    # the word before ended too early
    else:
        start = max([s for s in starts if s <= pos] or [0])
    later = [s for s in starts if s > start]
    end = later[0] if later else len(compact)
    word = written(start, end)
    item = compact[start:end]
    if error.text:
        return GcodeError(number, column(start), word, error.text)
    if len(item) == 1 and (item.isalpha() or item in "$@^"):
        text = "letter without a value"
        if end < len(compact) and compact[end].isalpha():
            text += " (text outside a comment?)"
    elif re.fullmatch(r"[a-z$@^][+-]?[0-9.+-]*", item):
        text = "malformed number"
    elif item.count("[") > item.count("]"):
        text = "missing ']'"
    elif item.count("]") > item.count("["):
        text = "']' without '['"
    elif pos >= len(compact):
        text = "incomplete expression"
    else:
        bad = compact[pos:pos + 1]
        text = f"unexpected {bad!r}"
        if bad == "=" :
            text = "unexpected '=' (an assignment is #<parameter> = value)"
    return GcodeError(number, column(start), word, text)


# --- evaluation -----------------------------------------------------------------------------

def _finite(value: float) -> float:
    if math.isfinite(value):
        return value
    raise ExpressionError("result out of range")


def _function(name: str, x: float) -> float:
    try:
        if name == "abs":
            return abs(x)
        if name == "acos":
            if not -1.0 <= x <= 1.0:
                raise ExpressionError(f"ACOS of {x:g}: argument outside -1..1")
            return math.degrees(math.acos(x))
        if name == "asin":
            if not -1.0 <= x <= 1.0:
                raise ExpressionError(f"ASIN of {x:g}: argument outside -1..1")
            return math.degrees(math.asin(x))
        if name == "cos":
            return math.cos(math.radians(x))
        if name == "sin":
            return math.sin(math.radians(x))
        if name == "tan":
            return _finite(math.tan(math.radians(x)))
        if name == "exp":
            return _finite(math.exp(x))
        if name == "ln":
            if x <= 0.0:
                raise ExpressionError(f"LN of {x:g}: argument not positive")
            return math.log(x)
        if name == "sqrt":
            if x < 0.0:
                raise ExpressionError(f"SQRT of a negative number ({x:g})")
            return math.sqrt(x)
        if name == "fix":
            return float(math.floor(x))
        if name == "fup":
            return float(math.ceil(x))
        if name == "round":                     # half away from zero, as LinuxCNC
            return float(math.floor(x + 0.5)) if x >= 0 else -float(math.floor(-x + 0.5))
    except OverflowError:
        raise ExpressionError(f"{name.upper()} of {x:g}: result out of range") from None
    raise AssertionError(name)      # pragma: no cover


def _binary(op: str, a: float, b: float) -> float:
    try:
        return _operate(op, a, b)
    except OverflowError:
        raise ExpressionError("result out of range") from None


def _operate(op: str, a: float, b: float) -> float:
    if op == "+":
        return _finite(a + b)
    if op == "-":
        return _finite(a - b)
    if op == "*":
        return _finite(a * b)
    if op == "/":
        if b == 0.0:
            raise ExpressionError("division by zero")
        return _finite(a / b)
    if op == "mod":
        if b == 0.0:
            raise ExpressionError("MOD by zero")
        r = math.fmod(a, b)
        return r + abs(b) if r < 0.0 else r
    if op == "**":
        if a == 0.0 and b < 0.0:
            raise ExpressionError("division by zero (0 to a negative power)")
        if a < 0.0 and b != math.floor(b):
            raise ExpressionError(f"negative number to a non-integer power ({a:g} ** {b:g})")
        try:
            return _finite(math.pow(a, b))
        except OverflowError:
            raise ExpressionError("result out of range") from None
    if op == "eq":
        return 1.0 if abs(a - b) < EQUAL_TOLERANCE else 0.0
    if op == "ne":
        return 0.0 if abs(a - b) < EQUAL_TOLERANCE else 1.0
    if op == "gt":
        return 1.0 if a > b else 0.0
    if op == "ge":
        return 1.0 if a >= b else 0.0
    if op == "lt":
        return 1.0 if a < b else 0.0
    if op == "le":
        return 1.0 if a <= b else 0.0
    if op == "and":
        return 1.0 if (a != 0.0 and b != 0.0) else 0.0
    if op == "or":
        return 1.0 if (a != 0.0 or b != 0.0) else 0.0
    if op == "xor":
        return 1.0 if ((a != 0.0) != (b != 0.0)) else 0.0
    raise AssertionError(op)        # pragma: no cover


class _Evaluator:
    def __init__(self, params: Parameters):
        self.params = params
        self.line = 0

    def value(self, node) -> float:
        if type(node) is float:
            return node
        tag = node[0]
        if tag == "b":
            return _binary(node[1], self.value(node[2]), self.value(node[3]))
        if tag == "p":
            return self.params.get(self.index(node))
        if tag == "n":
            return self.named(node[1])
        if tag == "neg":
            return -self.value(node[1])
        if tag == "f":
            return _function(node[1], self.value(node[2]))
        if tag == "atan":
            return math.degrees(math.atan2(self.value(node[1]), self.value(node[2])))
        if tag == "exists":
            target = node[1]
            if target[0] == "n":
                return 1.0 if self.params.exists(target[1]) else 0.0
            return 1.0 if self.params.exists(self.value(target[1])) else 0.0
        raise AssertionError(tag)   # pragma: no cover

    def index(self, node) -> int:
        """The number of a numbered parameter node ("p", expr), checked."""
        return Parameters._index(self.value(node[1]))

    def named(self, name: str) -> float:
        try:
            return self.params.get(name)
        except ExpressionError:
            if name.startswith("_hal["):
                self.params.warnings.append(
                    f"line {self.line}: #<{name}> (a HAL pin) is not available here: read as 0")
                return 0.0
            raise

    def key(self, target) -> int | str:
        """The key an assignment's target parameter node names."""
        return target[1] if target[0] == "n" else self.index(target)


# --- the program: structure and control flow ------------------------------------------------

_OPENERS = {"sub", "while", "do", "if", "repeat"}


def _structure(prog: list[_Line]) -> dict[str, int]:
    """Match every O-word with its partner; returns the subroutines (label -> index)."""
    subs: dict[str, int] = {}
    stack: list[int] = []           # indices of open sub / while / do / if / repeat lines

    def fail(rec: _Line, text: str):
        raise GcodeError(rec.line, rec.column, rec.text, text)

    def where(k: int) -> str:
        return f"{prog[k].label} {prog[k].kind} (line {prog[k].line})"

    def close(rec: _Line, kind: str, opener: str) -> int:
        if not stack or prog[stack[-1]].kind != opener or prog[stack[-1]].label != rec.label:
            if not stack:
                fail(rec, f"{kind} without {opener}")
            fail(rec, f"{kind} does not close {where(stack[-1])}")
        return stack.pop()

    for i, rec in enumerate(prog):
        kind = rec.kind
        if kind == "block":
            continue
        if kind == "sub":
            if stack:
                fail(rec, f"sub inside {where(stack[0])}: subroutines cannot be nested")
            if rec.label in subs:
                fail(rec, f"{rec.label} is defined twice (first on line {prog[subs[rec.label]].line})")
            subs[rec.label] = i
            stack.append(i)
        elif kind == "endsub":
            k = close(rec, "endsub", "sub")
            prog[k].end, rec.start = i, k
        elif kind == "return":
            if not stack or prog[stack[0]].kind != "sub":
                fail(rec, "return outside a subroutine")
            if prog[stack[0]].label != rec.label:
                fail(rec, f"return does not match {where(stack[0])}")
        elif kind == "while":
            if stack and prog[stack[-1]].kind == "do" and prog[stack[-1]].label == rec.label:
                k = stack.pop()
                prog[k].end, rec.start = i, k
                rec.kind = "dowhile"
            else:
                stack.append(i)
        elif kind == "endwhile":
            k = close(rec, "endwhile", "while")
            prog[k].end, rec.start = i, k
        elif kind in ("do", "repeat", "if"):
            stack.append(i)
        elif kind in ("elseif", "else"):
            if not stack or prog[stack[-1]].kind != "if" or prog[stack[-1]].label != rec.label:
                fail(rec, f"{kind} without if" if not stack else
                     f"{kind} does not belong to {where(stack[-1])}")
            opener = prog[stack[-1]]
            if opener.branches and prog[opener.branches[-1]].kind == "else":
                fail(rec, f"{kind} after else (line {prog[opener.branches[-1]].line})")
            opener.branches.append(i)
        elif kind == "endif":
            k = close(rec, "endif", "if")
            prog[k].end = i
            for b in prog[k].branches:
                prog[b].end = i
        elif kind == "endrepeat":
            k = close(rec, "endrepeat", "repeat")
            prog[k].end, rec.start = i, k
        elif kind in ("break", "continue"):
            for k in reversed(stack):
                if prog[k].kind == "sub":
                    break
                if prog[k].kind in ("while", "do", "repeat") and prog[k].label == rec.label:
                    rec.loop = k
                    break
            if rec.loop < 0:
                fail(rec, f"{kind} outside a {rec.label} loop")
        elif kind == "call":
            if len(rec.args) > CALL_ARGUMENTS:
                fail(rec, f"more than {CALL_ARGUMENTS} arguments")
        elif kind == "":
            pass                        # program number, handled by _read_program
        else:                           # pragma: no cover - the grammar has no other keyword
            fail(rec, f"unknown O-word command {kind}")
    if stack:
        rec = prog[stack[-1]]
        partner = {"sub": "endsub", "while": "endwhile", "do": "while", "if": "endif",
                   "repeat": "endrepeat"}[rec.kind]
        fail(rec, f"{rec.kind} without {partner}")
    return subs


def _read_program(text: str, warnings: list[str]) -> list[_Line]:
    if text.startswith("\ufeff"):
        text = text[1:]
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    prog: list[_Line] = []
    opened = content = False
    for number, raw in enumerate(lines, 1):
        stripped = raw.strip(" \t")
        if stripped.startswith("%"):
            if not content and not opened:
                opened = True
            elif opened and stripped == "%":
                rest = next((k for k in range(number, len(lines)) if lines[k].strip()), None)
                if rest is not None:
                    warnings.append(f"line {rest + 1}: text after the closing '%' ignored")
                break
            continue
        if not stripped:
            continue
        content = True
        rec = _read_line(raw, number, warnings)
        if rec is None:
            continue
        if rec.kind == "" and rec.label:
            if rec.label.startswith("o<"):
                raise GcodeError(number, rec.column, rec.text, "O-word without a command")
            warnings.append(f"line {number}: {rec.text} read as a program number and skipped")
            continue
        prog.append(rec)
    return prog


def read_source(path, limit: int, what: str = "a program") -> str:
    """A G-code file's text (bytes that are not UTF-8 kept as surrogate escapes); a folder, a
    device or a file of more than `limit` bytes is refused with one line (UsageError)."""
    try:
        mode = os.stat(path).st_mode
        if stat.S_ISDIR(mode):
            raise UsageError(f"cannot read {path}: is a folder")
        if not (stat.S_ISREG(mode) or stat.S_ISFIFO(mode)):
            raise UsageError(f"cannot read {path}: not a file (a device?)")
        with open(path, "rb") as f:
            data = f.read(limit + 1)
    except OSError as err:
        raise UsageError(f"cannot read {path}: {err.strerror or err}") from None
    if len(data) > limit:
        raise UsageError(f"{path}: {what} of more than {limit >> 20} MiB")
    return data.decode("utf-8", errors="surrogateescape")


@dataclass
class _Unit:
    """The program, or a subroutine file: its lines and where its subroutines start."""
    prog: list[_Line]
    subs: dict[str, int]
    file: str = ""              # "": the program


def iterate_blocks(text: str, params: Parameters, find_file=None) -> Iterator[Block]:
    """The blocks the program executes, in order, with every value evaluated.

    The whole text is read and its O-word structure checked before the first block
    (subroutines may be called before their definition).  Each block's expressions are
    evaluated when it is yielded, then its parameter assignments are made.

    `o<name> call` of a subroutine the program does not define reads it from a file, as
    LinuxCNC does: find_file(name) -> (the file's name as shown, its text) or None.  The
    file is read and checked at the first such call; its subroutines (and those of the
    files it calls) are then defined for the rest of the run, and its lines outside them
    are not run.  Its blocks carry the program's line of the call.  Every block's `top` is
    the program's line outside any subroutine that runs it (a call's line inside one).
    """
    main = _Unit(_read_program(text, params.warnings), {})
    main.subs = _structure(main.prog)
    params.subroutines = [(label, main.prog[k].line, main.prog[main.prog[k].end].line)
                          for label, k in main.subs.items()]
    top = 0                                     # inside a call: the program's line of the outermost call
    defined = {label: main for label in main.subs}      # label -> the unit defining it
    unit, prog = main, main.prog
    called_at = 0                               # in a subroutine file: the program's line of the call
    ev = _Evaluator(params)
    returns: list[tuple] = []                   # (unit, return index, the caller's repeat counts, called_at)
    repeats: dict[int, int] = {}                # repeat line -> iterations left, this level
    iterations = calls = 0
    pc, n = 0, len(prog)

    def fail(rec: _Line, item, text: str):
        column, word = (rec.column, rec.text) if item is None else (item.column, item.text)
        raise GcodeError(rec.line, column, word, text, unit.file, called_at)

    def load(rec: _Line) -> None:
        """The subroutine file of a call the program does not define."""
        label = rec.label
        name = label[2:-1] if label.startswith("o<") else ""
        found = find_file(name) if name and find_file is not None else None
        if found is None:
            where = f" and no {name}.ngc in the subroutine folders" if name and find_file is not None else ""
            fail(rec, None, f"{label} is not defined: no '{label} sub' in the program{where}")
        shown, body = found
        at, warnings = called_at if unit.file else rec.line, []
        try:
            loaded = _Unit(_read_program(body, warnings), {}, shown)
            loaded.subs = _structure(loaded.prog)
        except GcodeError as error:
            raise error.in_file(shown, at) from None
        params.warnings.extend(f"line {at}: {shown}: {w}" for w in warnings)
        if label not in loaded.subs:
            fail(rec, None, f"{label} is not defined: {shown} has no '{label} sub'")
        for other in loaded.subs:
            defined.setdefault(other, loaded)

    def condition(rec: _Line) -> float:
        try:
            return ev.value(rec.args[0])
        except ExpressionError as e:
            fail(rec, None, str(e))

    def loop_again(rec: _Line):
        nonlocal iterations
        iterations += 1
        if iterations > MAX_LOOP_ITERATIONS:
            fail(rec, None, f"more than {MAX_LOOP_ITERATIONS} loop iterations: "
                 "a loop that never ends?")

    while pc < n:
        rec = prog[pc]
        ev.line = rec.line
        kind = rec.kind
        if kind == "block":
            words = []
            item = None
            try:
                assignments = []
                for item in rec.items:
                    target = item.target
                    expr = item.expr
                    value = expr if type(expr) is float else ev.value(expr)
                    if type(target) is str:
                        words.append(Word(target, value, item.column, item.text))
                    else:
                        assignments.append((item, ev.key(target), value))
                for item, key, value in assignments:
                    params.set(key, value)
            except ExpressionError as e:
                fail(rec, item, str(e))
            yield Block(called_at if unit.file else rec.line, words, rec.delete, rec.comments, unit.file, rec.line,
                        top if returns else rec.line)
            pc += 1
        elif kind == "sub":
            pc = rec.end + 1
        elif kind in ("endsub", "return"):
            value = None
            if rec.args:
                value = condition(rec)
            if not returns:                             # pragma: no cover - structure forbids
                fail(rec, None, f"{kind} outside a subroutine call")
            params.pop_call(called_at if unit.file else rec.line)
            params.set("_value", 0.0 if value is None else value)
            params.set("_value_returned", 0.0 if value is None else 1.0)
            unit, pc, repeats, called_at = returns.pop()
            prog, n = unit.prog, len(unit.prog)
        elif kind == "call":
            if rec.label not in defined:
                load(rec)
            try:
                args = [ev.value(a) for a in rec.args]
            except ExpressionError as e:
                fail(rec, None, str(e))
            if params.depth >= MAX_CALL_DEPTH:
                fail(rec, None, f"subroutine calls nested deeper than {MAX_CALL_DEPTH}: "
                     "a recursion that never ends?")
            calls += 1
            if calls > MAX_CALLS:
                fail(rec, None, f"more than {MAX_CALLS} subroutine calls: a runaway program?")
            params.push_call(args)
            top = top if returns else rec.line
            returns.append((unit, pc + 1, repeats, called_at))
            repeats = {}
            called_at = called_at if unit.file else rec.line   # the program's line that leads there
            unit = defined[rec.label]
            prog, n = unit.prog, len(unit.prog)
            pc = unit.subs[rec.label] + 1
        elif kind == "while":
            pc = pc + 1 if condition(rec) != 0.0 else rec.end + 1
        elif kind == "endwhile":
            loop_again(rec)
            pc = rec.start
        elif kind == "do":
            pc += 1
        elif kind == "dowhile":
            if condition(rec) != 0.0:
                loop_again(rec)
                pc = rec.start + 1
            else:
                pc += 1
        elif kind == "if":
            if condition(rec) != 0.0:
                pc += 1
            else:
                pc = rec.end + 1
                for b in rec.branches:
                    branch = prog[b]
                    ev.line = branch.line
                    if branch.kind == "else" or condition(branch) != 0.0:
                        pc = b + 1
                        break
        elif kind in ("elseif", "else"):
            pc = rec.end + 1
        elif kind == "endif":
            pc += 1
        elif kind == "repeat":
            count = condition(rec)
            times = int(math.floor(count + 0.5)) if count > 0 else 0
            if times > 0:
                repeats[pc] = times
                pc += 1
            else:
                pc = rec.end + 1
        elif kind == "endrepeat":
            left = repeats.get(rec.start, 1) - 1
            if left > 0:
                loop_again(rec)
                repeats[rec.start] = left
                pc = rec.start + 1
            else:
                repeats.pop(rec.start, None)
                pc += 1
        elif kind == "break":
            repeats.pop(rec.loop, None)
            pc = prog[rec.loop].end + 1
        elif kind == "continue":
            opener = prog[rec.loop]
            if opener.kind == "while":
                loop_again(rec)
                pc = rec.loop
            else:
                pc = opener.end
        else:                                           # pragma: no cover
            fail(rec, None, f"unknown O-word command {kind}")
