"""Build the project's FMUs (FMI 2.0 co-simulation) with PythonFMU.

Usage: ``python build_fmu.py [--dest models]`` writes ``<dest>/RollingContact2D.fmu`` from the slave
``fmu_src/rollcontact_fmu_slave.py`` and bundles the ``src/rollcontact`` package in the FMU's resources, so the
FMU needs only numpy and scipy from the host's Python.  ``--all`` also writes ``<dest>/WheelRig.fmu``, the
co-simulation host (slave ``fmu_src/wheel_rig_slave.py``, bundling ``src/rollcontact_cosim``); ``--if-stale``
builds only the FMUs that are missing or older than one of their sources.  Both FMUs can get, set and serialise
their state; both bundle the shared slave base and modelDescription helper ``fmu_src/rollcontact_fmu_xml.py``.
The slave files are tiny entry modules that import the slave class from a bundled module
(``fmu_src/rollcontact_fmu_contact.py``, ``fmu_src/rollcontact_fmu_wheel_rig.py``): pythonfmu re-executes the
entry module on every instantiation (``fmu_src/rollcontact_fmu_slave.py``'s docstring).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent
SOURCES = ROOT / "src"
XML_HELPER = ROOT / "fmu_src" / "rollcontact_fmu_xml.py"
SLAVE = ROOT / "fmu_src" / "rollcontact_fmu_slave.py"
PACKAGE = SOURCES / "rollcontact"
HOST_SLAVE = ROOT / "fmu_src" / "wheel_rig_slave.py"
HOST_PACKAGE = SOURCES / "rollcontact_cosim"

FMUS = {  # model name -> (entry module, bundled packages and modules)
    "RollingContact2D": (SLAVE, (PACKAGE, ROOT / "fmu_src" / "rollcontact_fmu_contact.py")),
    "WheelRig": (HOST_SLAVE, (HOST_PACKAGE, ROOT / "fmu_src" / "rollcontact_fmu_wheel_rig.py")),
}


def build_model(model: str, dest: Path | str = ROOT / "models") -> Path:
    """Build the FMU ``model`` (a key of :data:`FMUS`) into the folder ``dest`` [created if missing]; its path."""
    slave, packages = FMUS[model]
    # the builder imports the slave, which imports the packages: use the copies that get bundled
    sys.path.insert(0, str(SOURCES))
    try:
        from pythonfmu.builder import FmuBuilder

        return Path(FmuBuilder.build_FMU(slave, dest=dest, project_files=[*packages, XML_HELPER],
                                         canGetAndSetFMUstate=True, canSerializeFMUstate=True))
    finally:
        sys.path.remove(str(SOURCES))


def build(dest: Path | str = ROOT / "models") -> Path:
    """Build the RollingContact2D FMU into the folder ``dest`` [created if missing] and return the FMU's path."""
    return build_model("RollingContact2D", dest)


def sources(model: str) -> list[Path]:
    """Files the FMU ``model`` is built from (its slave, the XML helper and the bundled packages' modules)."""
    slave, packages = FMUS[model]
    return [slave, XML_HELPER, *(f for package in packages
                                 for f in ([package] if package.is_file() else package.rglob("*.py")))]


def is_stale(model: str, dest: Path | str = ROOT / "models") -> bool:
    """True when ``<dest>/<model>.fmu`` is missing or older than one of its :func:`sources`."""
    fmu = Path(dest) / f"{model}.fmu"
    if not fmu.is_file():
        return True
    built = fmu.stat().st_mtime
    return any(f.stat().st_mtime > built for f in sources(model))


def build_all(dest: Path | str = ROOT / "models", if_stale: bool = False) -> dict[str, Path]:
    """Build every FMU of :data:`FMUS` into ``dest`` (only the stale ones with ``if_stale``); model -> path."""
    return {model: build_model(model, dest) if not if_stale or is_stale(model, dest) else Path(dest) / f"{model}.fmu"
            for model in FMUS}


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dest", default=str(ROOT / "models"), help="output folder (default: models/)")
    parser.add_argument("--all", action="store_true", help="also build the WheelRig host FMU")
    parser.add_argument("--if-stale", action="store_true",
                        help="build only FMUs that are missing or older than their sources")
    args = parser.parse_args(argv)
    if args.all:
        for path in build_all(args.dest, if_stale=args.if_stale).values():
            print(path)
    elif not args.if_stale or is_stale("RollingContact2D", args.dest):
        print(build(args.dest))
    else:
        print(Path(args.dest) / "RollingContact2D.fmu")


if __name__ == "__main__":
    main()
