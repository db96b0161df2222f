"""Build the project's FMUs (FMI 2.0 co-simulation) with PythonFMU.

Usage: ``python build_fmu.py [--dest models]`` writes ``<dest>/RollingContact2D.fmu`` from the slave
``fmu_src/rollcontact_fmu_slave.py`` and bundles the ``src/rollcontact`` package in the FMU's resources, so the
FMU needs only numpy and scipy from the host's Python.  ``--all`` also writes ``<dest>/WheelRig.fmu``, the
co-simulation host (slave ``fmu_src/wheel_rig_slave.py``, bundling ``src/rollcontact_cosim``), and
``<dest>/Wheelset.fmu``, the host of the wheelset hunting scene with two contacts (slave
``fmu_src/wheelset_slave.py``, class in ``fmu_src/rollcontact_fmu_wheelset.py``); ``--if-stale``
builds only the FMUs that are missing or older than one of their sources; ``--integer-codes`` declares the
enumerations' variables as plain Integer, for hosts without FMI enumerations (libcosim); ``--docs`` writes the
variable table of ``docs/fmu.md`` from the slave's.  Every FMU can get, set and serialise
their state; all bundle the shared slave base and modelDescription helper ``fmu_src/rollcontact_fmu_xml.py``.
The slave files are tiny entry modules that import the slave class from a bundled module
(``fmu_src/rollcontact_fmu_contact.py``, ``fmu_src/rollcontact_fmu_wheel_rig.py``): pythonfmu re-executes the
entry module on every instantiation (``fmu_src/rollcontact_fmu_slave.py``'s docstring).

``--fmi 3`` builds the FMI 3.0 co-simulation variants into ``<dest>/fmi3/`` with pythonfmu3 instead (``--fmi 2,3``
both): the same slave classes, put on pythonfmu3 by ``fmu_src/fmi3_table_slave.py`` (entry modules
``fmu_src/fmi3_rollcontact_slave.py``, ``fmu_src/fmi3_wheel_rig_slave.py``, ``fmu_src/fmi3_wheelset_slave.py``);
they also bundle pythonfmu's Python
files, in whose types the shared slave's variable table is written.  The default builds FMI 2.0 only.
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent
SOURCES = ROOT / "src"
XML_HELPER = ROOT / "fmu_src" / "rollcontact_fmu_xml.py"
EXIT_FIX = ROOT / "fmu_src" / "pythonfmu_exit_fix.py"
"""The build's fix of pythonfmu's export library (not bundled into the FMUs)."""
SLAVE = ROOT / "fmu_src" / "rollcontact_fmu_slave.py"
PACKAGE = SOURCES / "rollcontact"
HOST_SLAVE = ROOT / "fmu_src" / "wheel_rig_slave.py"
HOST_PACKAGE = SOURCES / "rollcontact_cosim"

FMUS = {  # model name -> (entry module, bundled packages and modules)
    "RollingContact2D": (SLAVE, (PACKAGE, ROOT / "fmu_src" / "rollcontact_fmu_contact.py")),
    "WheelRig": (HOST_SLAVE, (HOST_PACKAGE, ROOT / "fmu_src" / "rollcontact_fmu_wheel_rig.py")),
    "Wheelset": (ROOT / "fmu_src" / "wheelset_slave.py",
                 (HOST_PACKAGE, ROOT / "fmu_src" / "rollcontact_fmu_wheelset.py")),
}

FMI3_HELPER = ROOT / "fmu_src" / "fmi3_table_slave.py"
FMUS3 = {  # model name -> (FMI 3.0 entry module, bundled packages and modules besides the FMI 2.0 ones)
    "RollingContact2D": (ROOT / "fmu_src" / "fmi3_rollcontact_slave.py", (FMI3_HELPER,)),
    "WheelRig": (ROOT / "fmu_src" / "fmi3_wheel_rig_slave.py", (FMI3_HELPER,)),
    "Wheelset": (ROOT / "fmu_src" / "fmi3_wheelset_slave.py", (FMI3_HELPER,)),
}
FMI_VERSIONS = (2, 3)
FMI3_FOLDER = "fmi3"
"""Subfolder of ``--dest`` that ``--fmi 3`` builds into."""


def build_model(model: str, dest: Path | str = ROOT / "models", integer_codes: bool = False, fmi: int = 2) -> Path:
    """Build the FMU ``model`` (a key of :data:`FMUS`) into the folder ``dest`` [created if missing]; its path.

    ``integer_codes``: declare the enumerations' variables as plain Integer (for hosts without FMI enumerations,
    such as libcosim); a build in a fresh process, since the slave module reads it when first imported.
    ``fmi``: 2 (pythonfmu) or 3 (pythonfmu3, :func:`build_model3`).
    """
    if fmi == 3:
        if integer_codes:
            raise ValueError("--integer-codes is an FMI 2.0 build (for libcosim); FMI 3.0 declares enumerations")
        return build_model3(model, dest)
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

        return exit_fixed(FmuBuilder.build_FMU(slave, dest=dest, project_files=[*packages, XML_HELPER],
                                               canGetAndSetFMUstate=True, canSerializeFMUstate=True))
    finally:
        sys.path.remove(str(SOURCES))


def build_model3(model: str, dest: Path | str) -> Path:
    """Build the FMI 3.0 FMU ``model`` (a key of :data:`FMUS3`) with pythonfmu3 into ``dest``; its path.

    Besides the FMI 2.0 build's files it bundles the FMI 3.0 entry module and binding and pythonfmu's Python files
    (the slave's variable table is written in its types); state handling and a variable communication step size
    are declared explicitly (pythonfmu3 0.3.4 writes the latter from another option's value otherwise).
    """
    import pythonfmu
    from pythonfmu3 import FmuBuilder

    slave, extra = FMUS3[model]
    packages = FMUS[model][1]
    sys.path.insert(0, str(SOURCES))
    try:
        with tempfile.TemporaryDirectory(prefix="rollcontact_fmi3_") as tmp:
            framework = Path(tmp, "pythonfmu")
            framework.mkdir()
            for source in Path(pythonfmu.__file__).parent.glob("*.py"):
                shutil.copy2(source, framework)
            return exit_fixed(FmuBuilder.build_FMU(slave, dest=dest,
                                                   project_files=[*packages, *extra, XML_HELPER, framework],
                                                   canGetAndSetFMUState=True, canSerializeFMUState=True,
                                                   canHandleVariableCommunicationStepSize=True))
    finally:
        sys.path.remove(str(SOURCES))


def exit_fixed(fmu: Path | str) -> Path:
    """The built FMU ``fmu`` with pythonfmu's exit-time double release fixed in its Linux binary
    (``fmu_src/pythonfmu_exit_fix.py``, docs/fmu.md "Exit"); RuntimeError if the binary is not a pinned release's."""
    fix = sys.modules.get("pythonfmu_exit_fix")
    if fix is None:
        spec = importlib.util.spec_from_file_location("pythonfmu_exit_fix", EXIT_FIX)
        fix = sys.modules[spec.name] = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(fix)
    fix.patch_fmu(fmu)
    return Path(fmu)


def build(dest: Path | str = ROOT / "models") -> Path:
    """Build the RollingContact2D FMU into the folder ``dest`` [created if missing] and return the FMU's path."""
    return build_model("RollingContact2D", dest)


def sources(model: str, fmi: int = 2) -> list[Path]:
    """Files the FMU ``model`` is built from (its slave, the XML helper and the bundled packages' modules; for FMI
    3.0 also its entry module and the FMI 3.0 binding)."""
    slave, packages = FMUS[model]
    files = [slave, XML_HELPER, *(f for package in packages
                                  for f in ([package] if package.is_file() else package.rglob("*.py")))]
    return files if fmi == 2 else [FMUS3[model][0], *FMUS3[model][1], *files]


def is_stale(model: str, dest: Path | str = ROOT / "models", fmi: int = 2) -> bool:
    """True when ``<dest>/<model>.fmu`` is missing or older than one of its :func:`sources`."""
    fmu = Path(dest) / f"{model}.fmu"
    if not fmu.is_file():
        return True
    built = fmu.stat().st_mtime
    return any(f.stat().st_mtime > built for f in sources(model, fmi))


def build_all(dest: Path | str = ROOT / "models", if_stale: bool = False,
              integer_codes: bool = False, fmi: int = 2) -> dict[str, Path]:
    """Build every FMU of :data:`FMUS` into ``dest`` (only the stale ones with ``if_stale``); model -> path."""
    return {model: build_model(model, dest, integer_codes, fmi) if not if_stale or is_stale(model, dest, fmi)
            else Path(dest) / f"{model}.fmu" for model in FMUS}


def fmi_versions(text: str) -> tuple[int, ...]:
    """The FMI versions of ``--fmi`` (``"2"``, ``"3"`` or ``"2,3"``)."""
    try:
        versions = tuple(sorted({int(part) for part in text.split(",")}))
    except ValueError:
        versions = ()
    if not versions or not set(versions) <= set(FMI_VERSIONS):
        raise argparse.ArgumentTypeError(f"{text!r}: give 2, 3 or 2,3")
    return versions


def fmi_dest(dest: Path | str, fmi: int) -> Path:
    """Where ``--fmi`` ``fmi`` builds into: ``dest`` for FMI 2.0, ``dest/fmi3`` for FMI 3.0."""
    return Path(dest) if fmi == 2 else Path(dest) / FMI3_FOLDER


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
    parser.add_argument("--all", action="store_true", help="also build the host FMUs (WheelRig, Wheelset)")
    parser.add_argument("--if-stale", action="store_true",
                        help="build only FMUs that are missing or older than their sources")
    parser.add_argument("--docs", action="store_true", help="write the variable table of docs/fmu.md (no build)")
    parser.add_argument("--integer-codes", action="store_true",
                        help="plain Integer variables instead of FMI enumerations (for hosts such as libcosim)")
    parser.add_argument("--fmi", type=fmi_versions, default=(2,), metavar="2|3|2,3",
                        help="FMI versions to build (default 2); FMI 3.0 goes into <dest>/fmi3/")
    parser.add_argument("--only", choices=list(FMUS), help=argparse.SUPPRESS)  # one model (the integer-codes build)
    args = parser.parse_args(argv)
    if args.docs:
        print(write_docs())
        return
    if args.integer_codes and 3 in args.fmi:
        parser.error("--integer-codes builds FMI 2.0 only (for libcosim): drop it or use --fmi 2")
    for fmi in args.fmi:
        dest = fmi_dest(args.dest, fmi)
        if args.only:
            print(build_model(args.only, dest, fmi=fmi))
        elif args.all:
            for path in build_all(dest, if_stale=args.if_stale, integer_codes=args.integer_codes, fmi=fmi).values():
                print(path)
        elif args.integer_codes:
            print(build_model("RollingContact2D", dest, integer_codes=True))
        elif not args.if_stale or is_stale("RollingContact2D", dest, fmi):
            print(build_model("RollingContact2D", dest, fmi=fmi))
        else:
            print(dest / "RollingContact2D.fmu")


if __name__ == "__main__":
    main()
