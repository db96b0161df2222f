"""Build the project's FMUs (FMI 2.0 co-simulation) with PythonFMU.

Usage: ``python build_fmu.py [--dest models]`` writes ``<dest>/RollingContact2D.fmu`` from the slave
``fmu_src/rollcontact_fmu_slave.py`` and bundles the ``src/rollcontact`` package in the FMU's resources, so the
FMU needs only numpy and scipy from the host's Python.  ``--all`` also writes ``<dest>/WheelRig.fmu``, the
co-simulation host (slave ``fmu_src/wheel_rig_slave.py``, bundling ``src/rollcontact_cosim``); ``--if-stale``
builds only the FMUs that are missing or older than one of their sources; ``--integer-codes`` declares the
enumerations' variables as plain Integer, for hosts without FMI enumerations (libcosim); ``--docs`` writes the
variable table of ``docs/fmu.md`` from the slave's.  Both FMUs can get, set and serialise
their state; both bundle the shared slave base and modelDescription helper ``fmu_src/rollcontact_fmu_xml.py``.
The slave files are tiny entry modules that import the slave class from a bundled module
(``fmu_src/rollcontact_fmu_contact.py``, ``fmu_src/rollcontact_fmu_wheel_rig.py``): pythonfmu re-executes the
entry module on every instantiation (``fmu_src/rollcontact_fmu_slave.py``'s docstring).
"""

from __future__ import annotations

import argparse
import os
import subprocess
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


def build_model(model: str, dest: Path | str = ROOT / "models", integer_codes: bool = False) -> Path:
    """Build the FMU ``model`` (a key of :data:`FMUS`) into the folder ``dest`` [created if missing]; its path.

    ``integer_codes``: declare the enumerations' variables as plain Integer (for hosts without FMI enumerations,
    such as libcosim); a build in a fresh process, since the slave module reads it when first imported.
    """
    if integer_codes:
        done = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--dest", str(dest), "--only", model],
                              env={**os.environ, "ROLLCONTACT_FMU_INTEGER_CODES": "1"}, capture_output=True,
                              text=True, timeout=600)
        if done.returncode != 0:
            raise RuntimeError(f"build_fmu.py --integer-codes failed:\n{done.stdout}\n{done.stderr}")
        return Path(dest) / f"{model}.fmu"
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


def build_all(dest: Path | str = ROOT / "models", if_stale: bool = False,
              integer_codes: bool = False) -> dict[str, Path]:
    """Build every FMU of :data:`FMUS` into ``dest`` (only the stale ones with ``if_stale``); model -> path."""
    return {model: build_model(model, dest, integer_codes) if not if_stale or is_stale(model, dest)
            else Path(dest) / f"{model}.fmu" for model in FMUS}


DOCS = ROOT / "docs" / "fmu.md"
BEGIN, END = "<!-- variables: written by build_fmu.py --docs -->", "<!-- end of variables -->"


def variables_table() -> str:
    """The RollingContact2D FMU's variables and enumerations as markdown, from the slave's single table."""
    sys.path[:0] = [str(SOURCES), str(ROOT / "fmu_src")]
    try:
        import rollcontact_fmu_contact as contact
        from rollcontact_fmu_xml import variables_markdown

        return variables_markdown(contact.VARIABLES, contact.ENUMERATIONS)
    finally:
        del sys.path[:2]


def write_docs(path: Path = DOCS) -> Path:
    """Replace the variable table between the markers of docs/fmu.md with :func:`variables_table`."""
    text = path.read_text()
    head, _, rest = text.partition(BEGIN)
    _, _, tail = rest.partition(END)
    path.write_text(f"{head}{BEGIN}\n{variables_table()}{END}{tail}")
    return path


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dest", default=str(ROOT / "models"), help="output folder (default: models/)")
    parser.add_argument("--all", action="store_true", help="also build the WheelRig host FMU")
    parser.add_argument("--if-stale", action="store_true",
                        help="build only FMUs that are missing or older than their sources")
    parser.add_argument("--docs", action="store_true", help="write the variable table of docs/fmu.md (no build)")
    parser.add_argument("--integer-codes", action="store_true",
                        help="plain Integer variables instead of FMI enumerations (for hosts such as libcosim)")
    parser.add_argument("--only", choices=list(FMUS), help=argparse.SUPPRESS)  # one model (the integer-codes build)
    args = parser.parse_args(argv)
    if args.docs:
        print(write_docs())
        return
    if args.only:
        print(build_model(args.only, args.dest))
    elif args.all:
        for path in build_all(args.dest, if_stale=args.if_stale, integer_codes=args.integer_codes).values():
            print(path)
    elif args.integer_codes:
        print(build_model("RollingContact2D", args.dest, integer_codes=True))
    elif not args.if_stale or is_stale("RollingContact2D", args.dest):
        print(build(args.dest))
    else:
        print(Path(args.dest) / "RollingContact2D.fmu")


if __name__ == "__main__":
    main()
