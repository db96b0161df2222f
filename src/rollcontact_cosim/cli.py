"""What the command-line entry points share: a one-line error with exit code 2 instead of a traceback, and a
progress bar for long work that shows on a terminal and stays quiet otherwise."""

from __future__ import annotations

import sys
import time
from collections.abc import Callable

OPTIONAL = {"libcosimpy": "the libcosim master (--master libcosim) needs libcosimpy: pip install -e '.[cosim]' "
                          "(Python >= 3.11), or use --master fmpy",
            "dask": "sweeps and regression suites run on dask.distributed: pip install -e '.[dist]'",
            "distributed": "sweeps and regression suites run on dask.distributed: pip install -e '.[dist]'",
            "matplotlib": "the plot needs matplotlib: pip install -e '.[fmu]'",
            "fmpy": "the co-simulation masters drive the FMUs through fmpy: pip install -e '.[fmu]'",
            "pythonfmu": "building the FMUs needs pythonfmu: pip install -e '.[fmu]'"}
"""Optional dependency (top-level module name) -> what needs it and how to install it."""


def run(prog: str, main: Callable[[], int], expected: tuple[type[Exception], ...] = (ValueError, OSError)) -> int:
    """``main()``, with a missing optional dependency or an ``expected`` error (a bad scene name or value, a file
    that cannot be read) reported as one line ``prog: error: ...`` on stderr and exit code 2."""
    try:
        return main()
    except ModuleNotFoundError as exc:
        root = (exc.name or "").split(".")[0]
        if root not in OPTIONAL:
            raise
        print(f"{prog}: error: {root} is not installed: {OPTIONAL[root]}", file=sys.stderr)
        return 2
    except expected as exc:
        print(f"{prog}: error: {exc}", file=sys.stderr)
        return 2


class Progress:
    """A progress bar ``[#####.....] k/n label (elapsed)`` on stderr when it is a terminal; nothing otherwise.

    Parameters
    ----------
    total : int
        Units of work.
    label : str
        What is counted.
    stream : file, optional
        Where to draw (default stderr); drawn only when it is a terminal.
    """

    WIDTH = 30

    def __init__(self, total: int, label: str = "", stream=None):
        self.total = max(int(total), 1)
        self.label = label
        self.stream = sys.stderr if stream is None else stream
        self.active = bool(getattr(self.stream, "isatty", lambda: False)())
        self.done = 0
        self.start = time.perf_counter()

    def advance(self, units: int = 1, label: str | None = None) -> None:
        """Count ``units`` more done (and change the label)."""
        self.done = min(self.total, self.done + units)
        if label is not None:
            self.label = label
        if self.active:
            filled = round(self.WIDTH * self.done / self.total)
            self.stream.write(f"\r[{'#' * filled}{'.' * (self.WIDTH - filled)}] {self.done}/{self.total} "
                              f"{self.label} ({time.perf_counter() - self.start:.0f} s)\033[K")
            self.stream.flush()

    def close(self) -> None:
        """End the bar's line."""
        if self.active:
            self.stream.write("\n")
            self.stream.flush()

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
