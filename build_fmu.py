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
their state; all bundle the shared slave base and modelDescription helper ``fmu_src/rollcontact_fmu_base.py`` and
the FMI 2.0 binding ``fmu_src/fmi2_table_slave.py``.
The slave files are tiny entry modules that import the slave class from a bundled module
(``fmu_src/rollcontact_fmu_contact.py``, ``fmu_src/rollcontact_fmu_wheel_rig.py``): pythonfmu re-executes the
entry module on every instantiation (``fmu_src/rollcontact_fmu_slave.py``'s docstring).

``--fmi 3`` builds the FMI 3.0 co-simulation variants into ``<dest>/fmi3/`` with pythonfmu3 instead (``--fmi 2,3``
both): the same shared slave classes, without the FMI 2.0 binding, put on pythonfmu3 by
``fmu_src/fmi3_table_slave.py`` (entry modules
``fmu_src/fmi3_rollcontact_slave.py``, ``fmu_src/fmi3_wheel_rig_slave.py``, ``fmu_src/fmi3_wheelset_slave.py``);
they also bundle pythonfmu's Python
files, in whose types the shared slave's variable table is written.  The default builds FMI 2.0 only.
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import shutil
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent
SOURCES = ROOT / "src"
SLAVE_BASE = ROOT / "fmu_src" / "rollcontact_fmu_base.py"
FMI2_BINDING = ROOT / "fmu_src" / "fmi2_table_slave.py"
"""The shared slave base and the FMI 2.0 binding (the slave modules define their FMI 2.0 classes with it), bundled
into every FMU."""
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
    "RollingContact3D": (ROOT / "fmu_src" / "contact3d_slave.py",
                         (PACKAGE, ROOT / "fmu_src" / "rollcontact_fmu_contact3d.py")),
}

FMI3_HELPER = ROOT / "fmu_src" / "fmi3_table_slave.py"
FMUS3 = {  # model name -> (FMI 3.0 entry module, bundled packages and modules besides the FMI 2.0 ones)
    "RollingContact2D": (ROOT / "fmu_src" / "fmi3_rollcontact_slave.py", (FMI3_HELPER,)),
    "WheelRig": (ROOT / "fmu_src" / "fmi3_wheel_rig_slave.py", (FMI3_HELPER,)),
    "Wheelset": (ROOT / "fmu_src" / "fmi3_wheelset_slave.py", (FMI3_HELPER,)),
    "RollingContact3D": (ROOT / "fmu_src" / "fmi3_contact3d_slave.py", (FMI3_HELPER,)),
}
CONTACT3D = "RollingContact3D"
"""The FMU built in variants (:func:`build_variant`): n contacts, enumerations or integer codes."""
VARIANT_SLAVES = {"RollingContact2D": "rollcontact_fmu_contact", CONTACT3D: "rollcontact_fmu_contact3d"}
"""The contact FMUs built in variants (``--contacts``) -> their slave module (with ``declaration`` and
``slave_class``)."""
DEFAULT_VARIANT = "contacts=1, integer_codes=False"
"""The arguments of ``slave_class`` in the elliptic contact FMU's entry modules, which a variant build replaces."""
FMI_VERSIONS = (2, 3)
MAX_CONTACTS = 64
"""Most contacts of one FMU (``--contacts``)."""
FMI3_FOLDER = "fmi3"
"""Subfolder of ``--dest`` that ``--fmi 3`` builds into."""


def build_model(model: str, dest: Path | str = ROOT / "models", integer_codes: bool = False, fmi: int = 2,
                contacts: int = 1) -> Path:
    """Build the FMU ``model`` (a key of :data:`FMUS`) into the folder ``dest`` [created if missing]; its path.

    ``integer_codes``: declare the enumerations' variables as plain Integer (for hosts without FMI enumerations,
    such as libcosim): a variant of the contact FMUs (:func:`build_variant`); the hosts declare no enumerations and
    are built as they are.  ``fmi``: 2 (pythonfmu) or 3 (pythonfmu3, :func:`build_model3`).  ``contacts``: the
    contacts of the contact FMUs (:func:`build_variant`).
    """
    if model in VARIANT_SLAVES and (model == CONTACT3D or contacts != 1 or integer_codes):
        return build_variant(dest, contacts, integer_codes, fmi, model)
    if contacts != 1:
        raise ValueError(f"{model} has no n-contact build (--contacts builds {', '.join(VARIANT_SLAVES)})")
    if fmi == 3:
        return build_model3(model, dest)
    slave, packages = FMUS[model]
    # the builder imports the slave, which imports the packages: use the copies that get bundled
    return pack(slave, packages, dest)


def variant_name(contacts: int, model: str = CONTACT3D) -> str:
    """Model name of the contact FMU ``model`` with ``contacts`` contacts: ``model``, else ``model_n``."""
    return model if contacts == 1 else f"{model}_{contacts}"


def build_variant(dest: Path | str, contacts: int = 1, integer_codes: bool = False, fmi: int = 2,
                  model: str = CONTACT3D) -> Path:
    """Build the contact FMU ``model`` (a key of :data:`VARIANT_SLAVES`) with ``contacts`` contacts into ``dest``;
    its path.

    The entry module is the elliptic contact's (``fmu_src/contact3d_slave.py``, ``fmu_src/fmi3_contact3d_slave.py``)
    with the variant's slave module, model name and ``slave_class`` arguments in place of the elliptic
    single-contact FMU's (FMI 3.0: ``arrays``, each per-contact variable one array), in a module named after the
    variant (a host may load several variants: pythonfmu3 imports
    an entry module once per process).  The single-contact RollingContact2D is its own build (:func:`build_model`).
    Integer codes are an FMI 2.0 build (for libcosim).
    """
    if isinstance(contacts, bool) or not isinstance(contacts, int) or not 1 <= contacts <= MAX_CONTACTS:
        raise ValueError(f"contacts = {contacts!r} must be a whole number from 1 to {MAX_CONTACTS}")
    if integer_codes and fmi == 3:
        raise ValueError("--integer-codes is an FMI 2.0 build (for libcosim); FMI 3.0 declares enumerations")
    if model != CONTACT3D and contacts == 1 and not integer_codes:
        return build_model(model, dest, integer_codes, fmi)
    name = variant_name(contacts, model)
    template = FMUS[CONTACT3D][0] if fmi == 2 else FMUS3[CONTACT3D][0]
    text = template.read_text()
    if DEFAULT_VARIANT not in text:
        raise RuntimeError(f"{template} does not call slave_class({DEFAULT_VARIANT}): cannot write the variant")
    text = text.replace(DEFAULT_VARIANT, f"contacts={contacts}, integer_codes={integer_codes}, arrays={fmi == 3}")
    text = text.replace(VARIANT_SLAVES[CONTACT3D], VARIANT_SLAVES[model]).replace(CONTACT3D, name)
    stem = template.stem.replace("contact3d", f"contact{model[-2:].lower()}" + (f"_{contacts}" if contacts > 1 else ""))
    with tempfile.TemporaryDirectory(prefix="rollcontact_variant_") as tmp:
        entry = Path(tmp, f"{stem}.py")
        entry.write_text(text)
        forgotten = (VARIANT_SLAVES[model], template.stem, stem)
        forget(forgotten)
        sys.path[:0] = [tmp, str(ROOT / "fmu_src")]
        try:
            if fmi == 3:
                return build_model3(model, dest, slave=entry)
            return pack(entry, FMUS[model][1], dest)
        finally:
            del sys.path[:2]
            forget(forgotten)


def forget(modules) -> None:
    """Drop ``modules`` from the import cache (the builder imports a variant's entry and slave modules by name)."""
    for module in modules:
        sys.modules.pop(module, None)


def pack(slave: Path, packages, dest: Path | str) -> Path:
    """pythonfmu's FMI 2.0 build of the entry module ``slave`` with the bundled ``packages`` and the shared slave
    base."""
    sys.path.insert(0, str(SOURCES))
    try:
        from pythonfmu.builder import FmuBuilder

        return exit_fixed(FmuBuilder.build_FMU(slave, dest=dest, project_files=[*packages, SLAVE_BASE, FMI2_BINDING],
                                               canGetAndSetFMUstate=True, canSerializeFMUstate=True))
    finally:
        sys.path.remove(str(SOURCES))


def build_model3(model: str, dest: Path | str, slave: Path | None = None, extra: tuple = ()) -> Path:
    """Build the FMI 3.0 FMU ``model`` (a key of :data:`FMUS3`) with pythonfmu3 into ``dest``; its path.

    Besides the FMI 2.0 build's files it bundles the FMI 3.0 entry module and binding and pythonfmu's Python files
    (the slave's variable table is written in its types); state handling and a variable communication step size
    are declared explicitly (pythonfmu3 0.3.4 writes the latter from another option's value otherwise).  ``slave``
    replaces the entry module and ``extra`` adds bundled files (a variant build, :func:`build_variant`).
    """
    import pythonfmu
    from pythonfmu3 import FmuBuilder

    slave = FMUS3[model][0] if slave is None else slave
    extra = (*FMUS3[model][1], *extra)
    packages = FMUS[model][1]
    sys.path.insert(0, str(SOURCES))
    try:
        with tempfile.TemporaryDirectory(prefix="rollcontact_fmi3_") as tmp:
            framework = Path(tmp, "pythonfmu")
            framework.mkdir()
            for source in Path(pythonfmu.__file__).parent.glob("*.py"):
                shutil.copy2(source, framework)
            return exit_fixed(FmuBuilder.build_FMU(slave, dest=dest,
                                                   project_files=[*packages, *extra, SLAVE_BASE, FMI2_BINDING,
                                                                  framework],
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
    """Files the FMU ``model`` is built from (its slave, the shared slave base and the bundled packages' modules;
    for FMI 3.0 also its entry module and the FMI 3.0 binding)."""
    slave, packages = FMUS[model]
    files = [slave, SLAVE_BASE, FMI2_BINDING, *(f for package in packages
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
DOCUMENTED = {"RollingContact2D": ("rollcontact_fmu_contact", (BEGIN, END)),
              CONTACT3D: ("rollcontact_fmu_contact3d", (BEGIN.replace("variables", f"variables of {CONTACT3D}"),
                                                        END.replace("variables", f"variables of {CONTACT3D}")))}
"""Model -> (slave module, markers of its variable table in docs/fmu.md)."""


def variables_table(model: str = "RollingContact2D") -> str:
    """The variables and enumerations of ``model`` (a key of :data:`DOCUMENTED`; the single-contact FMU) as
    markdown, from the slave's single table."""
    sys.path[:0] = [str(SOURCES), str(ROOT / "fmu_src")]
    try:
        import importlib

        slave = importlib.import_module(DOCUMENTED[model][0])
        if model == CONTACT3D:
            return variables_markdown(*slave.declaration())
        return variables_markdown(slave.VARIABLES, slave.ENUMERATIONS)
    finally:
        del sys.path[:2]


def variables_markdown(variables, enumerations: dict | None = None) -> str:
    """The variable table of a slave as markdown (name, causality, type, unit, range, start, description), then its
    enumerations: what ``build_fmu.py --docs`` writes into docs/fmu.md, so the documentation is the table."""
    enumerations = enumerations or {}

    def number(value, kind) -> str:
        if value is None:
            return ""
        if kind.__name__ == "Real":
            below = float(f"{value:.12g}")  # a bound just below a round value excludes it
            if value == math.nextafter(0.0, 1.0):
                return "> 0"
            return f"< {below:g}" if value != below and math.nextafter(below, 0.0) == value else f"{value:.16g}"
        return str(value)

    lines = ["| variable | causality | type | unit | min | max | start | description |",
             "|---|---|---|---|---|---|---|---|"]
    for name, kind, causality, _variability, unit, start, lower, upper, description in variables:
        type_name = enumerations[name][0] if name in enumerations else kind.__name__
        low, high = number(lower, kind), number(upper, kind)
        shown = repr(start) if isinstance(start, str) else number(start, kind)
        lines.append(f"| `{name}` | {causality.name} | {type_name} | {unit or ''} | {low} | {high} | {shown} | "
                     f"{description.replace('|', chr(92) + '|')} |")
    for type_name, items in dict(enumerations.values()).items():
        lines += ["", f"{type_name}: " + "; ".join(f"{value} `{item}` ({text})" for value, item, text in items) + "."]
    return "\n".join(lines) + "\n"


def write_docs(path: Path = DOCS) -> Path:
    """Replace the variable table between each model's markers in docs/fmu.md with :func:`variables_table`."""
    text = path.read_text()
    for model, (_, (begin, end)) in DOCUMENTED.items():
        head, _, rest = text.partition(begin)
        _, _, tail = rest.partition(end)
        text = f"{head}{begin}\n{variables_table(model)}{end}{tail}"
    path.write_text(text)
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
    parser.add_argument("--contacts", type=int, default=None, metavar="N",
                        help=f"build RollingContact2D_N and {CONTACT3D}_N: N contacts per instance (1..{MAX_CONTACTS})")
    parser.add_argument("--only", choices=list(FMUS), help="build this FMU only")
    args = parser.parse_args(argv)
    if args.docs:
        print(write_docs())
        return
    if args.integer_codes and 3 in args.fmi:
        parser.error("--integer-codes builds FMI 2.0 only (for libcosim): drop it or use --fmi 2")
    if args.contacts is not None and not 1 <= args.contacts <= MAX_CONTACTS:
        parser.error(f"--contacts {args.contacts}: give 1 to {MAX_CONTACTS}")
    for fmi in args.fmi:
        dest = fmi_dest(args.dest, fmi)
        if args.contacts is not None:
            for model in VARIANT_SLAVES:
                print(build_variant(dest, args.contacts, args.integer_codes, fmi, model))
        elif args.only:
            print(build_model(args.only, dest, args.integer_codes, fmi))
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
