"""The long fuzz campaign of the contact FMUs: ``tests/tools/fuzz_fmu.py``'s episodes over RollingContact2D (FMI
2.0), RollingContact3D, RollingContact3D_8 and WheelsetContact (FMI 2.0 and 3.0), written to
``benchmarks/results/fuzz.md``.

Usage::

    python benchmarks/fuzz_campaign.py [--seed 1] [--episodes N] [--steps S] [--strict-time] [--quick]

The options are the tool's (``python tests/tools/fuzz_fmu.py --help``); by default 100 episodes of RollingContact2D
and of each WheelsetContact target, 130 of each 3D target, 20 operations each, the FMUs built by ``build_fmu.py``
into a temporary folder.  What an episode does and what counts as a finding: the tool's docstring.  ``--quick``, a
replayed ``--episode`` or a single ``--target`` write nothing.  The exit status is 1 when there is a finding.
"""

from __future__ import annotations

import argparse
import os
import sys

import common  # the benchmarks' first import: one BLAS thread, the checkout on sys.path

sys.path.insert(0, str(common.ROOT / "tests" / "tools"))
import fuzz_fmu  # noqa: E402  (the test tool: after its folder is on the path)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0], parents=[fuzz_fmu.parser()])
    args = fuzz_fmu.defaults(parser.parse_args(argv), parser.error)
    load = os.getloadavg()[0]
    text, summary = fuzz_fmu.run(args)
    command = " ".join(["python benchmarks/fuzz_campaign.py", *(sys.argv[1:] if argv is None else argv)])
    lines = [*text.rstrip().splitlines(), "", f"Run by `{command}` on:", "", *common.machine(load)]
    partial = args.quick or args.episode is not None or args.target is not None
    common.publish(lines, "fuzz.md", partial)
    print(summary)
    return 1 if summary["findings"] else 0


if __name__ == "__main__":
    sys.exit(main())
