"""A dependency-free progress bar on standard error."""

from __future__ import annotations

import sys
import time
from typing import TextIO


class Progress:
    """Call once per finished item, with a note on what it was. On a terminal the bar redraws in
    place; in a log (CI) it prints a line at every tenth of the way."""

    def __init__(self, total: int, label: str, stream: TextIO | None = None, width: int = 30) -> None:
        self.total, self.label, self.width = max(total, 1), label, width
        self.stream = stream if stream is not None else sys.stderr
        self.done, self.start, self._last_tenth = 0, time.perf_counter(), -1

    def __call__(self, note: str = "") -> None:
        self.done += 1
        fraction = min(self.done / self.total, 1.0)
        bar = "#" * round(fraction * self.width)
        elapsed = time.perf_counter() - self.start
        line = f"{self.label} [{bar:<{self.width}}] {self.done}/{self.total} {elapsed:5.1f} s {note}"
        if self.stream.isatty():
            end = "\n" if self.done >= self.total else ""
            self.stream.write("\r" + line[:120].ljust(120) + end)
        elif int(fraction * 10) > self._last_tenth or self.done >= self.total:
            self._last_tenth = int(fraction * 10)
            self.stream.write(line + "\n")
        self.stream.flush()
