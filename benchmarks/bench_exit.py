"""Exit codes of host processes that drive the FMUs and exit normally: ``tests/tools/exit_study.py``'s study, written
to ``benchmarks/results/exit.md`` (docs/fmu.md, "Exit").

Usage::

    python benchmarks/bench_exit.py [--processes 200] [--unfixed 40] [--c-host 40] [--valgrind 2] [--workers 2]
    python benchmarks/bench_exit.py --quick        # 8 processes, stdout only

The options are the study's (``python tests/tools/exit_study.py --help``); its docstring says what each process does
and when it counts as clean.
"""

from __future__ import annotations

import argparse
import os
import sys

import common  # the benchmarks' first import: one BLAS thread, the checkout on sys.path

sys.path.insert(0, str(common.ROOT / "tests" / "tools"))
import exit_study  # noqa: E402  (the test tool: after its folder is on the path)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0], parents=[exit_study.parser()])
    args = parser.parse_args(argv)
    lines, status = exit_study.run(args, common.machine(os.getloadavg()[0]))
    common.publish(lines, "exit.md", args.quick)
    return status


if __name__ == "__main__":
    sys.exit(main())
