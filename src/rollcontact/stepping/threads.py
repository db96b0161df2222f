"""One BLAS thread for the stepping model's solves, whatever the host process's thread settings.

The solvers' matrices are small (the polynomial method's slip iteration: at most a few hundred unknowns).  A BLAS
that spreads such a factorisation over threads spends more on waking and joining them than on the arithmetic, and
on a machine whose cores are busy (a host stepping other FMUs, a test suite) it waits for them: a table build is
several times slower with OpenBLAS's default threads than with one (``benchmarks/bench_table.py``, "BLAS threads").
The host's setting cannot be changed by environment variables once numpy is loaded, and changing it for good would
change the host's own linear algebra, so the model limits the BLAS libraries to one thread only while it solves
(threadpoolctl), and restores them after.

The model takes the limit around each exact solve and each part of a build, never
around a closed-form or table step.
"""

from __future__ import annotations

from contextlib import AbstractContextManager

from threadpoolctl import ThreadpoolController

_controller: ThreadpoolController | None = None


def one_blas_thread() -> AbstractContextManager:
    """A context in which the BLAS libraries loaded in the process use one thread.

    The libraries are found once, at the first call (numpy's and scipy's BLAS are loaded by then: the solvers import
    both).
    """
    global _controller
    if _controller is None:
        _controller = ThreadpoolController()
    return _controller.limit(limits=1, user_api="blas")
