"""Build the RollingContact2D FMU (FMI 2.0 co-simulation) with PythonFMU.

Usage: ``python build_fmu.py [--dest models]`` writes ``<dest>/RollingContact2D.fmu`` from the slave
``fmu_src/rollcontact_fmu_slave.py`` and bundles the ``src/rollcontact`` package in the FMU's resources, so the
FMU needs only numpy and scipy from the host's Python.  The FMU can get, set and serialise its state.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent
SLAVE = ROOT / "fmu_src" / "rollcontact_fmu_slave.py"
PACKAGE = ROOT / "src" / "rollcontact"


def build(dest: Path | str = ROOT / "models") -> Path:
    """Build the FMU into the folder ``dest`` [created if missing] and return the FMU's path."""
    # the builder imports the slave, which imports rollcontact: use the copy that gets bundled
    sys.path.insert(0, str(PACKAGE.parent))
    try:
        from pythonfmu.builder import FmuBuilder

        return Path(FmuBuilder.build_FMU(SLAVE, dest=dest, project_files=[PACKAGE], canGetAndSetFMUstate=True,
                                         canSerializeFMUstate=True))
    finally:
        sys.path.remove(str(PACKAGE.parent))


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dest", default=str(ROOT / "models"), help="output folder (default: models/)")
    args = parser.parse_args(argv)
    print(build(args.dest))


if __name__ == "__main__":
    main()
