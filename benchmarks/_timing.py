"""Median wall time of a call, shared by the benchmark scripts (run as ``python benchmarks/<script>.py``)."""

from __future__ import annotations

import statistics
import time


def median_time(function, min_repeats: int = 5, min_seconds: float = 0.3, warmups: int = 1) -> float:
    """Median wall time [s] of ``function()`` over at least ``min_repeats`` calls and ``min_seconds``.

    ``warmups`` calls come first and are not timed (imports, size-keyed caches).
    """
    for _ in range(warmups):
        function()
    times = []
    start = time.perf_counter()
    while len(times) < min_repeats or time.perf_counter() - start < min_seconds:
        t0 = time.perf_counter()
        function()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)
