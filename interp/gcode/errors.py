# SPDX-License-Identifier: Apache-2.0
"""The one error type of the G-code front end: a line, a column, the word, what is wrong."""
from __future__ import annotations

from interp.cores import UsageError


def printable(text: str) -> str:
    """`text` safe to print on any terminal: control and non-ASCII characters escaped.

    A byte that was not valid UTF-8 (decoded with errors="surrogateescape") shows as
    its byte value, e.g. \\xff; any other non-printable character as \\uXXXX.
    """
    if text.isascii() and text.isprintable():
        return text
    out = []
    for ch in text:
        code = ord(ch)
        if 0x20 <= code < 0x7F:
            out.append(ch)
        elif 0xDC80 <= code <= 0xDCFF:              # surrogateescape: the original byte
            out.append(f"\\x{code - 0xDC00:02x}")
        elif code < 0x100:
            out.append(f"\\x{code:02x}")
        else:
            out.append(f"\\u{code:04x}" if code < 0x10000 else f"\\U{code:08x}")
    return "".join(out)


def without_controls(text: str) -> str:
    """`text` with its control characters (and any other non-printable one) escaped as
    printable() does; printable non-ASCII text (a message in Russian) is kept."""
    return "".join(ch if ch.isprintable() else printable(ch) for ch in text)


WORD_SHOWN = 40         # a longer word is shortened in the message


class GcodeError(UsageError):
    """Bad G-code: str() is "line L, column C: WORD: text" ("line L, column C: text" with no word).

    line and column are 1-based; word is the offending word as written (e.g. "G41"), or "".
    In a subroutine file (`o<name> call` of name.ngc), file names it, line and column are
    in it and called_at is the program's line of the call: "line N: FILE: line L, ...".
    """

    def __init__(self, line: int, column: int, word: str, text: str, file: str = "", called_at: int = 0):
        self.line = line
        self.column = column
        self.word = word
        self.text = text
        self.file = file
        self.called_at = called_at
        super().__init__(str(self))

    def __str__(self) -> str:
        word = printable(self.word)
        if len(word) > WORD_SHOWN:                  # e.g. a 400-digit number: its start is enough
            word = f"{word[:WORD_SHOWN - 3]}... ({len(self.word)} characters)"
        text = printable(self.text)
        where = f"line {self.line}, column {self.column}"
        if self.file:
            where = f"line {self.called_at}: {printable(self.file)}: {where}"
        return f"{where}: {word}: {text}" if word else f"{where}: {text}"

    def in_file(self, file: str, called_at: int, line: int | None = None) -> "GcodeError":
        """This error, placed in subroutine file `file` (at its `line`, default the error's)
        called at program line `called_at` (unchanged if it already names a file)."""
        if self.file:
            return self
        error = GcodeError(self.line if line is None else line, self.column, self.word, self.text, file, called_at)
        error.__dict__.update({k: v for k, v in self.__dict__.items() if k not in error.__dict__})
        return error

    def __reduce__(self):
        return (type(self), (self.line, self.column, self.word, self.text, self.file, self.called_at))
