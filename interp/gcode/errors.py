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
    """

    def __init__(self, line: int, column: int, word: str, text: str):
        self.line = line
        self.column = column
        self.word = word
        self.text = text
        super().__init__(str(self))

    def __str__(self) -> str:
        word = printable(self.word)
        if len(word) > WORD_SHOWN:                  # e.g. a 400-digit number: its start is enough
            word = f"{word[:WORD_SHOWN - 3]}... ({len(self.word)} characters)"
        text = printable(self.text)
        if word:
            return f"line {self.line}, column {self.column}: {word}: {text}"
        return f"line {self.line}, column {self.column}: {text}"

    def __reduce__(self):
        return (type(self), (self.line, self.column, self.word, self.text))
