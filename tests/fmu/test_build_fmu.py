"""``build_fmu.py``: the commands the docs give, each run in a fresh process, build FMUs that load; ``--if-stale``
builds only what is missing or older than its sources, for every selection; the manifests, the entry modules and the
enumerations derived from the solver's tables.

The builds are the test run's (``tests/conftest.py``: ``--all`` and ``--fmi 3 --all``, ``--contacts 8`` and ``--fmi 3
--contacts 8``, ``--integer-codes``, each its own process) and two more here (``--fmi 3 --only RollingContact3D``,
``--only Wheelset``); each command's FMUs are loaded and stepped in one fresh process, from folders that stay
extracted while it runs.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from fmu_checks import run_build

import build_fmu
from rollcontact.stepping.parameters import FRICTION_LAW_CODES, RAIL_CONDITION_SETS, Level

ROOT = Path(__file__).resolve().parents[2]

LOAD_PROBE = """
import sys, tempfile
from fmpy import extract, simulate_fmu
folder = tempfile.mkdtemp()
for k, path in enumerate(sys.argv[1:]):
    result = simulate_fmu(extract(path, unzipdir=f"{folder}/{k}"), validate=False, stop_time=0.005,
                          output_interval=1e-3, output=[])
    print(path, len(result))
"""


@pytest.fixture(scope="module")
def only(tmp_path_factory) -> Path:
    """``build_fmu.py --fmi 3 --only RollingContact3D`` and ``--only Wheelset`` into a folder of their own (the folder
    of ``--dest``)."""
    dest = tmp_path_factory.mktemp("only")
    run_build("--fmi", "3", "--only", "RollingContact3D", dest=dest)
    run_build("--only", "Wheelset", dest=dest)
    return dest


@pytest.fixture
def commands(fmu_path, fmu_folders, eight_contacts, integer_codes, only) -> dict[str, list[Path]]:
    """Build command -> the FMUs it wrote (the test run's builds and :func:`only`, each command in a fresh process)."""
    every = ("RollingContact2D", "RollingContact3D", "WheelRig", "Wheelset", "WheelsetContact")
    return {"": [fmu_path],
            "--all": [fmu_folders[2] / f"{m}.fmu" for m in every],
            "--fmi 3 --all": [fmu_folders[3] / f"{m}.fmu" for m in every],
            "--contacts 8": [eight_contacts[2] / f"{m}_8.fmu" for m in every[:2]],
            "--fmi 3 --contacts 8": [eight_contacts[3] / f"{m}_8.fmu" for m in every[:2]],
            "--fmi 3 --only RollingContact3D": [only / "fmi3" / "RollingContact3D.fmu"],
            "--only Wheelset": [only / "Wheelset.fmu"],
            "--integer-codes": [integer_codes / "RollingContact2D.fmu"],
            "--contacts 2 --integer-codes": [integer_codes / f"{m}_2.fmu" for m in every[:2]]}


def shapes(command: str) -> set[tuple[str, int, bool]]:
    """What a build command selects, for each FMI version it builds: (``--only``, ``--all``, ``--contacts`` or "",
    FMI version, integer codes)."""
    words = command.split()
    selector = next((word for word in words if word in ("--only", "--all", "--contacts")), "")
    versions = words[words.index("--fmi") + 1].split(",") if "--fmi" in words else ["2"]
    return {(selector, int(fmi), "--integer-codes" in words) for fmi in versions}


def documented() -> dict[str, tuple[str, int, bool]]:
    """The build commands of README.md and docs/*.md (but ``--docs``): command -> its shapes."""
    found = {}
    for page in (ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))):
        for args in re.findall(r"python build_fmu\.py((?: --[a-z-]+(?: (?!--)[^\s`]+)?)*)", page.read_text()):
            if "--docs" not in args:
                found[f"{page.name}: python build_fmu.py{args}"] = shapes(args)
    return found


def test_every_documented_build_command_is_run_here_and_its_fmus_load_in_a_fresh_process(commands):
    """Each kind of command the docs give (its selection, FMI version and integer codes) ran in a fresh process
    (exit 0, ``run_build``); its FMUs load and step in a fresh process of their own (the bundled packages, not the
    test process's modules)."""
    tested = set().union(*map(shapes, commands))
    untested = {command: sorted(kinds - tested) for command, kinds in documented().items() if kinds - tested}
    assert not untested, f"documented build commands of a kind no test runs: {untested}"
    for command, paths in commands.items():
        done = subprocess.run([sys.executable, "-c", LOAD_PROBE, *map(str, paths)], capture_output=True, text=True,
                              timeout=300)
        assert done.returncode == 0, f"build_fmu.py {command}: the FMUs do not load:\n{done.stderr[-3000:]}"
        assert done.stdout.split() == [word for path in paths for word in (str(path), "6")], done.stdout


def test_each_fmu_bundles_its_slave_the_support_package_and_its_packages_but_no_build_tool(fmu_folders):
    for fmi, folder in fmu_folders.items():
        for model, fmu in build_fmu.FMUS.items():
            with zipfile.ZipFile(folder / f"{model}.fmu") as archive:
                names = set(archive.namelist())
                entry = archive.read("resources/slavemodule.txt").decode().strip()
            expected = {f"resources/{fmu.slave}.py", f"resources/{entry}.py",
                        *(f"resources/{p.relative_to(build_fmu.FMU_SOURCES).as_posix()}"
                          for p in build_fmu.SUPPORT.rglob("*.py")),
                        *(f"resources/{p.relative_to(package.parent).as_posix()}" for package in fmu.packages
                          for p in package.rglob("*.py"))}
            assert expected <= names, f"FMI {fmi} {model} lacks {sorted(expected - names)[:5]}"
            assert entry == build_fmu.tool("entry").module_name(model, fmi), f"FMI {fmi} {model}: entry {entry}"
            assert not any("pythonfmu_exit_fix" in name or "manifest.toml" in name for name in names), \
                f"FMI {fmi} {model} bundles build tooling"


def test_if_stale_builds_nothing_that_is_up_to_date_for_every_selection(fmu_folders, eight_contacts, integer_codes,
                                                                        only):
    """``--if-stale`` with ``--all``, ``--contacts 8``, ``--only``, ``--integer-codes`` and ``--fmi 3``, each in a fresh
    process, on the test run's fresh builds: every FMU is reported where it is, none is written again."""
    runs = [(["--all", "--fmi", "2,3"], fmu_folders[2]), (["--contacts", "8", "--fmi", "2,3"], eight_contacts[2]),
            (["--only", "RollingContact3D", "--fmi", "3"], only), (["--only", "Wheelset"], only),
            (["--integer-codes"], integer_codes), (["--contacts", "2", "--integer-codes"], integer_codes)]
    for args, dest in runs:
        before = {p: p.stat().st_mtime_ns for p in dest.rglob("*.fmu")}
        printed = [Path(line) for line in run_build(*args, "--if-stale", dest=dest).split()]
        assert printed and set(printed) <= set(before), f"{args}: {printed}"
        assert {p: p.stat().st_mtime_ns for p in dest.rglob("*.fmu")} == before, f"{args}: an FMU was rebuilt"


@pytest.mark.parametrize(("model", "fmi", "contacts", "integer_codes"), [
    ("RollingContact2D", 2, 1, False), ("RollingContact3D", 3, 8, False), ("RollingContact2D", 2, 2, True),
    ("Wheelset", 3, 1, False)])
def test_an_fmu_is_stale_when_missing_or_older_than_a_source(tmp_path, model, fmi, contacts, integer_codes):
    name = build_fmu.FMUS[model].name(contacts)
    kwargs = {"contacts": contacts, "integer_codes": integer_codes}
    assert build_fmu.is_stale(model, tmp_path, fmi, **kwargs), "missing"
    path = tmp_path / f"{name}.fmu"
    path.write_bytes(b"")
    newest = max(f.stat().st_mtime for f in build_fmu.sources(model))
    os.utime(path, (newest + 1, newest + 1))
    assert not build_fmu.is_stale(model, tmp_path, fmi=fmi, **kwargs), "newer than every source"
    os.utime(path, (newest - 1, newest - 1))
    assert build_fmu.is_stale(model, tmp_path, fmi=fmi, **kwargs), "older than a source"
    assert any(f.name == "manifest.toml" for f in build_fmu.sources(model)), "the manifest is a source"


def test_if_stale_rebuilds_a_stale_fmu_in_a_fresh_process(fmu_path, tmp_path):
    stale = tmp_path / "RollingContact2D.fmu"
    stale.write_bytes(fmu_path.read_bytes())
    os.utime(stale, (0, 0))
    out = run_build("--only", "RollingContact2D", "--if-stale", dest=tmp_path)
    assert Path(out.strip()) == stale and stale.stat().st_mtime > 0, out
    with zipfile.ZipFile(stale) as archive:
        assert archive.testzip() is None and "modelDescription.xml" in archive.namelist()


def test_a_variant_an_fmu_has_not_is_refused_before_anything_is_built(tmp_path):
    for call, match in ((lambda: build_fmu.build("WheelRig", tmp_path, contacts=2), "WheelRig has no n-contact"),
                        (lambda: build_fmu.build("NoSuchModel", tmp_path), "no FMU 'NoSuchModel'"),
                        (lambda: build_fmu.is_stale("RollingContact2D", tmp_path, 3, integer_codes=True),
                         "FMI 2.0 build"),
                        (lambda: build_fmu.build("RollingContact2D", tmp_path, fmi=4), "fmi = 4")):
        with pytest.raises(ValueError, match=match):
            call()
    assert not any(tmp_path.iterdir()), "nothing written"
    with pytest.raises(SystemExit):
        build_fmu.main(["--all", "--only", "WheelRig", "--dest", str(tmp_path)])


def test_a_manifest_with_unknown_keys_another_model_or_no_slave_is_refused(tmp_path):
    folder = tmp_path / "Toy"
    folder.mkdir()
    (folder / "manifest.toml").write_text('model = "Other"\nslave = "missing"\npackages = ["src/nothing"]\n'
                                          'colour = "red"\n[variants]\ncontacts = "yes"\n')
    with pytest.raises(ValueError) as refused:
        build_fmu.Manifest.read(folder)
    for part in ("unknown keys ['colour']", "model = 'Other' is not the folder's name 'Toy'", "slave = 'missing'",
                 "package 'src/nothing'", "contacts = 'yes' is not true or false"):
        assert part in str(refused.value), str(refused.value)


def test_the_entry_modules_are_written_from_one_template_for_every_fmu_and_version():
    """Every FMU's entry module compiles, binds or states the class of its variant's name, and is named after the
    model, variant and version (FMUs share ``sys.modules``)."""
    entry = build_fmu.tool("entry")
    names = set()
    for fmu in build_fmu.FMUS.values():
        for fmi in (2, 3):
            for contacts in ((1, 8) if fmu.contacts else (1,)):
                name = fmu.name(contacts)
                source = entry.entry_source(name, fmi, fmu.folder.name, fmu.slave, fmu.variant(fmi, contacts))
                compile(source, name, "exec")
                statement = f"class {name}(TableSlave3, Shared, Fmi3Slave):" if fmi == 3 else \
                    f"{name} = fmi2_class(slave_class("
                assert statement in source and f"from {fmu.slave} import slave_class" in source, source
                names.add(entry.module_name(name, fmi, False))
    assert len(names) == sum(2 * (2 if fmu.contacts else 1) for fmu in build_fmu.FMUS.values()), names


def test_a_module_the_builder_imported_from_its_deleted_copy_is_found(tmp_path):
    gone = type(sys)("rollcontact_build_test_gone")
    gone.__file__ = str(tmp_path / "deleted" / "gone.py")
    before = set(sys.modules)
    sys.modules[gone.__name__] = gone
    try:
        assert build_fmu.copies(before) == [gone.__name__]
    finally:
        del sys.modules[gone.__name__]


# the enumerations, derived from the solver's tables ----------------------------------------------------------------
@pytest.mark.parametrize(("model", "levels", "method", "used"), [
    ("RollingContact2D", "rollcontact.stepping.line.parameters", "Method", "MethodUsed"),
    ("RollingContact3D", "rollcontact.stepping.elliptic.parameters", "Method3D", "MethodUsed3D")])
def test_a_level_appended_to_a_geometry_reaches_its_fmus_enumerations_and_bounds(monkeypatch, model, levels, method,
                                                                                 used):
    """One line in ``METHOD_LEVELS`` (a toy level, the next free code) is a ``method`` item, a ``method_used`` item
    and the new upper bound of both, in the single-contact table and in the n-contact and integer-codes tables."""
    import importlib

    table = importlib.import_module(levels)
    code = max(level.code for level in table.METHOD_LEVELS) + 1
    monkeypatch.setattr(table, "METHOD_LEVELS", (*table.METHOD_LEVELS, Level(code, "toy", "a toy level", "the toy")))
    slave = build_fmu.slave_module(build_fmu.FMUS[model])
    variables, enumerations = slave.declaration()
    rows = {row[0]: row for row in variables}
    assert enumerations["method"][0] == method and (code, "toy", "a toy level") in enumerations["method"][1]
    assert enumerations["method_used"][0] == used and (code, "toy", "the toy") in enumerations["method_used"][1]
    assert rows["method"][7] == rows["method_used"][7] == code, "the bounds follow the levels"
    several, _ = slave.declaration(contacts=2)
    assert [row[7] for row in several if row[0].startswith("method")] == [code] * 3
    coded, _ = slave.declaration(integer_codes=True)
    assert f"{code} toy" in {row[0]: row for row in coded}["method"][8]


@pytest.mark.parametrize("model", ["RollingContact2D", "RollingContact3D"])
def test_friction_law_and_rail_condition_items_are_the_solvers_tables(model):
    _, enumerations = build_fmu.slave_module(build_fmu.FMUS[model]).declaration()
    assert enumerations["friction_law"] == ("FrictionLaw", tuple((r.code, r.item, r.formula)
                                                                 for r in FRICTION_LAW_CODES))
    type_name, items = enumerations["rail_condition"]
    assert type_name == "RailCondition" and [code for code, *_ in items] == [0, *RAIL_CONDITION_SETS]
    for code, name, text in items[1:]:
        condition = RAIL_CONDITION_SETS[code]
        assert name == condition.name and f"mu {condition.mu_static:g}, A {condition.kinetic_ratio:g}, " \
                                          f"B {condition.decay:g} s/m" in text and "Polach 2005" in text, text


@pytest.mark.parametrize("model", sorted(m for m, fmu in build_fmu.FMUS.items() if fmu.docs))
def test_the_documented_variable_table_of_every_fmu_is_its_declaration(model):
    assert build_fmu.variables_table(model) in (ROOT / "docs" / "fmu.md").read_text(), \
        f"docs/fmu.md's table of {model} differs from its slave's: run python build_fmu.py --docs"
