"""Build the project's FMUs from their manifests: FMI 2.0 with pythonfmu 0.7, FMI 3.0 with pythonfmu3 0.3.4.

Usage::

    python build_fmu.py [--only MODEL | --all | --contacts N] [--fmi 2|3|2,3] [--integer-codes] [--if-stale]
                        [--dest DIR] [--docs]

Without a selection it builds RollingContact2D; ``--only MODEL`` one FMU, ``--all`` every FMU (one folder
``fmu_src/<MODEL>/`` with a ``manifest.toml`` each), ``--contacts N`` the contact FMUs with N contacts per instance
(``RollingContact2D_N``, ``RollingContact3D_N``).  FMI 2.0 goes into ``<dest>/`` (default ``models/``), FMI 3.0 into
``<dest>/fmi3/``; ``--fmi 2,3`` builds both.  ``--integer-codes`` declares the enumerations' variables as plain
Integer (FMI 2.0, for hosts without FMI enumerations such as libcosim; an FMU without enumerations is built as it
is).  ``--if-stale`` builds only the FMUs that are missing or older than one of their sources (:func:`sources`).
``--docs`` writes the variable tables of docs/fmu.md from the slaves' declarations and builds nothing.

Python API: :func:`build`, :func:`is_stale` and :func:`ensure` (build when missing or stale) of one FMU into one
folder; :data:`FMUS`, the manifests by model name; :func:`fmi_dest`, the folder of an FMI version under ``--dest``.

An FMU bundles its slave module, the support package ``fmu_src/rollcontact_fmu/``, the manifest's packages and data
folders in ``resources/``, with an entry module written from one template (``fmu_src/tools/entry.py``); its Linux
binary gets the exit fix of ``fmu_src/tools/pythonfmu_exit_fix.py``.  How a build imports, and what a manifest holds:
docs/fmu-internals.md.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import math
import shutil
import sys
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import NamedTuple

try:
    import tomllib
except ImportError:  # Python 3.10
    import tomli as tomllib

ROOT = Path(__file__).resolve().parent
SOURCES = ROOT / "src"
FMU_SOURCES = ROOT / "fmu_src"
SUPPORT = FMU_SOURCES / "rollcontact_fmu"
"""The support package, bundled into every FMU."""
TOOLS = FMU_SOURCES / "tools"
"""The build's own modules (the entry template, the exit fix), bundled into no FMU."""
MODELS = ROOT / "models"
DOCS = ROOT / "docs" / "fmu.md"
DEFAULT_MODEL = "RollingContact2D"
FMI_VERSIONS = (2, 3)
FMI3_FOLDER = "fmi3"
"""Subfolder of ``--dest`` that ``--fmi 3`` builds into."""
MAX_CONTACTS = 64
"""Most contacts of one FMU (``--contacts``)."""
MANIFEST_KEYS = frozenset({"model", "slave", "packages", "resources", "docs", "variants"})
VARIANT_KEYS = frozenset({"contacts", "enumerations", "arrays"})
"""The keys of a manifest and of its ``[variants]`` table."""


class Manifest(NamedTuple):
    """What the build needs to know of one FMU: its ``fmu_src/<model>/manifest.toml`` (docs/fmu-internals.md).

    Attributes
    ----------
    model : str
        The model name (its folder's name): the FMU is ``<model>.fmu``, a variant of n contacts ``<model>_n.fmu``.
    folder : Path
        Its folder, holding the manifest and the slave module.
    slave : str
        The slave module (``<folder>/<slave>.py``), giving ``slave_class(**variant)`` (the shared slave class, no FMI
        binding) and ``declaration(**variant)`` (its variable table and enumerations).
    packages : tuple of Path
        The packages bundled in ``resources/`` besides the slave module and the support package.
    resources : tuple of Path
        Data folders copied into ``resources/`` under their own names (the WheelsetContact FMU's profiles).
    contacts : bool
        Whether it is built with n contacts (``--contacts``; the variant argument ``contacts``).
    enumerations : bool
        Whether it declares FMI enumerations, which ``--integer-codes`` turns into Integer variables (the variant
        argument ``integer_codes``); an FMU without is built as it is.
    arrays : bool
        Whether FMI 3.0 declares its per-contact variables as arrays (the variant argument ``arrays``).
    docs : bool
        Whether docs/fmu.md holds its variable table (``--docs``).
    """

    model: str
    folder: Path
    slave: str
    packages: tuple[Path, ...]
    resources: tuple[Path, ...]
    contacts: bool
    enumerations: bool
    arrays: bool
    docs: bool

    @classmethod
    def read(cls, folder: Path) -> Manifest:
        """The manifest of the FMU folder ``folder``; ValueError naming the file and what is wrong with it."""
        path = folder / "manifest.toml"
        data = tomllib.loads(path.read_text())
        variants = data.get("variants", {})
        problems = []
        if set(data) - MANIFEST_KEYS or set(variants) - VARIANT_KEYS:
            problems.append(f"unknown keys {sorted(set(data) - MANIFEST_KEYS)}, unknown variants "
                            f"{sorted(set(variants) - VARIANT_KEYS)} (keys: {sorted(MANIFEST_KEYS)}; variants: "
                            f"{sorted(VARIANT_KEYS)})")
        if data.get("model") != folder.name:
            problems.append(f"model = {data.get('model')!r} is not the folder's name {folder.name!r}")
        if not (folder / f"{data.get('slave')}.py").is_file():
            problems.append(f"slave = {data.get('slave')!r} names no module of the folder")
        packages = tuple(data.get("packages", ()))
        problems += [f"package {package!r} is no package folder of the repository" for package in packages
                     if not (ROOT / package / "__init__.py").is_file()]
        resources = tuple(data.get("resources", ()))
        problems += [f"resources {folder!r} is no folder of the repository" for folder in resources
                     if not (ROOT / folder).is_dir()]
        flags = {key: variants.get(key, False) for key in VARIANT_KEYS} | {"docs": data.get("docs", False)}
        problems += [f"{key} = {value!r} is not true or false" for key, value in flags.items()
                     if not isinstance(value, bool)]
        if problems:
            raise ValueError(f"{path}: " + "; ".join(problems))
        return cls(folder.name, folder, data["slave"], tuple(ROOT / package for package in packages),
                   tuple(ROOT / folder for folder in resources), **flags)

    def name(self, contacts: int = 1) -> str:
        """The model name of the variant with ``contacts`` contacts."""
        return self.model if contacts == 1 else f"{self.model}_{contacts}"

    def variant(self, fmi: int = 2, contacts: int = 1, integer_codes: bool = False) -> dict:
        """The arguments of ``slave_class`` for the variant (those the manifest makes variants of); ValueError for
        a variant it has not or an FMI version or contact count out of range."""
        if fmi not in FMI_VERSIONS:
            raise ValueError(f"fmi = {fmi!r}: give one of {FMI_VERSIONS}")
        if isinstance(contacts, bool) or not isinstance(contacts, int) or not 1 <= contacts <= MAX_CONTACTS:
            raise ValueError(f"contacts = {contacts!r} must be a whole number from 1 to {MAX_CONTACTS}")
        if contacts != 1 and not self.contacts:
            raise ValueError(f"{self.model} has no n-contact build (--contacts builds "
                             f"{', '.join(m for m, f in FMUS.items() if f.contacts)})")
        if integer_codes and fmi == 3:
            raise ValueError("--integer-codes is an FMI 2.0 build (for libcosim); FMI 3.0 declares enumerations")
        arguments = {"contacts": contacts} if self.contacts else {}
        if self.enumerations:
            arguments["integer_codes"] = bool(integer_codes)
        if self.arrays:
            arguments["arrays"] = fmi == 3
        return arguments


def manifests() -> dict[str, Manifest]:
    """The manifests of ``fmu_src/*/manifest.toml`` by model name, in the folders' order."""
    return {folder.name: Manifest.read(folder) for folder in sorted(FMU_SOURCES.iterdir())
            if (folder / "manifest.toml").is_file()}


FMUS = manifests()
"""Every FMU the project builds: model name -> :class:`Manifest`."""


def manifest(model: str) -> Manifest:
    """The manifest of ``model``; ValueError listing the FMUs for another name."""
    if model not in FMUS:
        raise ValueError(f"no FMU {model!r}: the FMUs are {', '.join(FMUS)} (a folder of fmu_src/ with a manifest)")
    return FMUS[model]


def tool(name: str):
    """The build's module ``fmu_src/tools/<name>.py``, loaded once per process (under ``rollcontact_build_<name>``)."""
    key = f"rollcontact_build_{name}"
    if key not in sys.modules:
        spec = importlib.util.spec_from_file_location(key, TOOLS / f"{name}.py")
        module = sys.modules[key] = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
    return sys.modules[key]


@contextmanager
def source_path(fmu: Manifest):
    """``sys.path`` with the sources of ``fmu`` first (its folder, ``fmu_src/``, ``src/``), restored afterwards."""
    saved = sys.path[:]
    sys.path[:0] = [str(fmu.folder), str(FMU_SOURCES), str(SOURCES)]
    try:
        yield
    finally:
        sys.path[:] = saved


def slave_module(fmu: Manifest, fmi: int = 2):
    """The slave module of ``fmu`` with every module a build of FMI version ``fmi`` imports, imported from the
    source tree (once per process): the support package's binding and workarounds, the slave module (and through it
    what it imports) and the bundled packages.

    pythonfmu's builders run the entry module from a temporary copy of the FMU's files, first on ``sys.path``, and
    delete it afterwards: a module first imported there would stay in ``sys.modules`` with its files gone, and the
    next build in the process would fail to import from it.  Imported here first, every module the entry module
    names is taken from ``sys.modules``, and the submodules of a package from the package's own (source) folder.
    """
    with source_path(fmu):
        for name in (f"rollcontact_fmu.fmi{fmi}", "rollcontact_fmu.workarounds",
                     *(package.name for package in fmu.packages)):
            importlib.import_module(name)
        return importlib.import_module(fmu.slave)


def copies(before: set[str]) -> list[str]:
    """Modules imported since ``before`` (names in ``sys.modules``) whose file no longer exists: imported from a
    builder's deleted temporary copy."""
    return sorted(name for name, module in list(sys.modules.items()) if name not in before
                  and getattr(module, "__file__", None) and not Path(module.__file__).exists())


def build(model: str, dest: Path | str = MODELS, *, fmi: int = 2, contacts: int = 1,
          integer_codes: bool = False) -> Path:
    """Build the FMU ``model`` (a key of :data:`FMUS`) into the folder ``dest`` [created if missing]; its path.

    Parameters
    ----------
    model : str
        The FMU's model name (its folder under ``fmu_src/``).
    dest : Path or str
        The folder the FMU is written to (the CLI's ``<dest>/fmi3/`` for FMI 3.0 is :func:`fmi_dest`'s).
    fmi : int
        2 (pythonfmu 0.7) or 3 (pythonfmu3 0.3.4).
    contacts : int
        Contacts per instance (1 to :data:`MAX_CONTACTS`; more than one only for a manifest with ``contacts``): the
        FMU ``<model>_<contacts>``.
    integer_codes : bool
        Declare the enumerations' variables as plain Integer (FMI 2.0).

    Raises
    ------
    ValueError
        An unknown model or a variant it has not; RuntimeError if the builder imported a module from its temporary
        copy (:func:`slave_module`) or named the FMU otherwise.
    """
    fmu = manifest(model)
    arguments = fmu.variant(fmi, contacts, integer_codes)
    name = fmu.name(contacts)
    entries = tool("entry")
    with tempfile.TemporaryDirectory(prefix="rollcontact_entry_") as tmp:
        entry = entries.write_entry(Path(tmp), name, fmi, fmu.folder.name, fmu.slave, arguments)
        slave_module(fmu, fmi)
        before, saved = set(sys.modules), sys.path[:]
        files = [fmu.folder / f"{fmu.slave}.py", SUPPORT, *fmu.packages, *fmu.resources]
        try:
            built = Path(pack2(entry, files, dest) if fmi == 2 else pack3(entry, files, dest))
        finally:
            sys.path[:] = saved  # pythonfmu 0.7's builder leaves the entry's folder on sys.path
            sys.modules.pop(entry.stem, None)
        stale = copies(before)
        if stale:
            raise RuntimeError(f"building {name} imported {', '.join(stale)} from the builder's temporary copy: "
                               f"import them in {fmu.slave} or list their package in {fmu.folder.name}/manifest.toml")
    if built.name != f"{name}.fmu":
        raise RuntimeError(f"the builder wrote {built.name}, not {name}.fmu: the slave class is named otherwise")
    tool("pythonfmu_exit_fix").patch_fmu(built)
    return built


def pack2(entry: Path, files: list[Path], dest: Path | str) -> Path:
    """pythonfmu 0.7's FMI 2.0 build of the entry module ``entry`` bundling ``files``."""
    from pythonfmu.builder import FmuBuilder

    return FmuBuilder.build_FMU(entry, dest=dest, project_files=files, canGetAndSetFMUstate=True,
                                canSerializeFMUstate=True)


def pack3(entry: Path, files: list[Path], dest: Path | str) -> Path:
    """pythonfmu3's FMI 3.0 build of the entry module ``entry`` bundling ``files`` and pythonfmu's Python files (the
    variable tables are written in its types); state handling and a variable communication step size declared
    explicitly (pythonfmu3 0.3.4 writes the latter from another option's value otherwise)."""
    import pythonfmu
    from pythonfmu3 import FmuBuilder

    with tempfile.TemporaryDirectory(prefix="rollcontact_fmi3_") as tmp:
        framework = Path(tmp, "pythonfmu")
        framework.mkdir()
        for source in Path(pythonfmu.__file__).parent.glob("*.py"):
            shutil.copy2(source, framework)
        return FmuBuilder.build_FMU(entry, dest=dest, project_files=[*files, framework], canGetAndSetFMUState=True,
                                    canSerializeFMUState=True, canHandleVariableCommunicationStepSize=True)


def sources(model: str) -> list[Path]:
    """The files the FMU ``model`` is built from: its folder's manifest and modules, the support package, the
    bundled packages' modules, the data folders' files, the build's tools and this script."""
    fmu = manifest(model)
    return [fmu.folder / "manifest.toml", *sorted(fmu.folder.glob("*.py")), *sorted(SUPPORT.rglob("*.py")),
            *(f for package in fmu.packages for f in sorted(package.rglob("*.py"))),
            *(f for folder in fmu.resources for f in sorted(folder.rglob("*")) if f.is_file()),
            *sorted(TOOLS.glob("*.py")),
            Path(__file__).resolve()]


def is_stale(model: str, dest: Path | str = MODELS, fmi: int = 2, *, contacts: int = 1,
             integer_codes: bool = False) -> bool:
    """True when the FMU :func:`build` would write (``<dest>/<model>[_<contacts>].fmu``) is missing or older than one
    of its :func:`sources`; ValueError for a variant :func:`build` refuses."""
    fmu = manifest(model)
    fmu.variant(fmi, contacts, integer_codes)
    path = Path(dest) / f"{fmu.name(contacts)}.fmu"
    if not path.is_file():
        return True
    built = path.stat().st_mtime
    return any(f.stat().st_mtime > built for f in sources(model))


def ensure(model: str, dest: Path | str = MODELS, *, fmi: int = 2, contacts: int = 1,
           integer_codes: bool = False) -> Path:
    """The path of the FMU ``model`` in ``dest``, built by :func:`build` when missing or stale (:func:`is_stale`)."""
    if is_stale(model, dest, fmi, contacts=contacts, integer_codes=integer_codes):
        return build(model, dest, fmi=fmi, contacts=contacts, integer_codes=integer_codes)
    return Path(dest) / f"{manifest(model).name(contacts)}.fmu"


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


def markers(model: str) -> tuple[str, str]:
    """The lines around the variable table of ``model`` in docs/fmu.md."""
    return (f"<!-- variables of {model}: written by build_fmu.py --docs -->",
            f"<!-- end of variables of {model} -->")


def variables_table(model: str = DEFAULT_MODEL) -> str:
    """The variables and enumerations of the single-contact FMU ``model`` as markdown, from its slave's
    declaration."""
    return variables_markdown(*slave_module(manifest(model)).declaration())


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
    """Replace the variable table between each documented model's :func:`markers` in docs/fmu.md with
    :func:`variables_table`; ValueError if a documented model has no markers there."""
    text = path.read_text()
    for model, fmu in FMUS.items():
        if not fmu.docs:
            continue
        begin, end = markers(model)
        head, found, rest = text.partition(begin)
        if not found or end not in rest:
            raise ValueError(f"{path.name} has no lines {begin!r} ... {end!r} for the variables of {model}")
        text = f"{head}{begin}\n{variables_table(model)}{end}{rest.partition(end)[2]}"
    path.write_text(text)
    return path


def selection(args) -> list[tuple[str, int]]:
    """The (model, contacts) pairs the command line selects."""
    if args.contacts is not None:
        return [(model, args.contacts) for model, fmu in FMUS.items() if fmu.contacts]
    if args.all:
        return [(model, 1) for model in FMUS]
    return [(args.only or DEFAULT_MODEL, 1)]


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    chosen = parser.add_mutually_exclusive_group()
    chosen.add_argument("--only", choices=list(FMUS), help="build this FMU only (default: RollingContact2D)")
    chosen.add_argument("--all", action="store_true", help="build every FMU")
    chosen.add_argument("--contacts", type=int, default=None, metavar="N",
                        help=f"build the contact FMUs with N contacts per instance, <model>_N (1..{MAX_CONTACTS})")
    parser.add_argument("--fmi", type=fmi_versions, default=(2,), metavar="2|3|2,3",
                        help="FMI versions to build (default 2); FMI 3.0 goes into <dest>/fmi3/")
    parser.add_argument("--integer-codes", action="store_true",
                        help="plain Integer variables instead of FMI enumerations (for hosts such as libcosim)")
    parser.add_argument("--if-stale", action="store_true",
                        help="build only FMUs that are missing or older than their sources")
    parser.add_argument("--dest", default=str(MODELS), help="output folder (default: models/)")
    parser.add_argument("--docs", action="store_true", help="write the variable tables of docs/fmu.md (no build)")
    args = parser.parse_args(argv)
    if args.docs:
        print(write_docs())
        return
    if args.integer_codes and 3 in args.fmi:
        parser.error("--integer-codes builds FMI 2.0 only (for libcosim): drop it or use --fmi 2")
    if args.contacts is not None and not 1 <= args.contacts <= MAX_CONTACTS:
        parser.error(f"--contacts {args.contacts}: give 1 to {MAX_CONTACTS}")
    make = ensure if args.if_stale else build
    for fmi in args.fmi:
        for model, contacts in selection(args):
            print(make(model, fmi_dest(args.dest, fmi), fmi=fmi, contacts=contacts, integer_codes=args.integer_codes))


if __name__ == "__main__":
    main()
