"""Shared test configuration.

One BLAS thread: the discretised solver's small dense solves are 10-100x slower with OpenBLAS threads on the
2-core machines here (it must be set before numpy is imported).
"""

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
