"""Every FMU the project builds has the recorded modelDescription: variables, types, units, structure, capabilities.

``tests/fmu/data/model_descriptions.json`` holds, for each FMU of the test run's builds (RollingContact2D,
RollingContact3D, their 3- and 8-contact variants, WheelRig, Wheelset and WheelsetContact in FMI 2.0 and FMI 3.0; the
``--integer-codes`` builds of RollingContact2D, RollingContact2D_2 and RollingContact3D_2 in FMI 2.0), what its
``modelDescription.xml`` declares, written by ``python tests/fmu/test_model_descriptions.py --record``:

* ``variables``: each model variable in document order with every attribute (name, value reference, causality,
  variability, initial, declared type, unit, start, min, max, ...), its type (``Real``, ``Integer``, ``Enumeration``,
  ``String`` in FMI 2.0; ``Float64``, ``Int32``, ``Enumeration``, ... in FMI 3.0) and its dimensions;
* ``types``: the type definitions, an enumeration's items with their values;
* ``model``: every other element in document order with its attributes (the root's, ``CoSimulation``'s
  capabilities, units, log categories, default experiment, the model structure's outputs, initial unknowns and
  dependencies), except what changes with every build (``guid``, ``instantiationToken``,
  ``generationDateAndTime``);
* ``descriptions``: the description texts (the model's, each variable's, each item's), compared by a separate assert,
  so that a change of wording is told apart from a change of the variables.

The FMUs are the test run's fixtures' builds (``tests/conftest.py``), shared with the other FMU tests.
"""

from __future__ import annotations

import json
import sys
import zipfile
from pathlib import Path
from xml.etree import ElementTree

import pytest

DATA = Path(__file__).resolve().parent / "data" / "model_descriptions.json"
VOLATILE = {"guid", "instantiationToken", "generationDateAndTime"}
"""Root attributes that change with every build."""

FMUS = {  # key -> (fixture of the test run, FMI version, FMU file)
    **{f"FMI {fmi}.0 {model}": ("fmu_folders", fmi, model)
       for fmi in (2, 3) for model in ("RollingContact2D", "RollingContact3D", "WheelRig", "Wheelset",
                                       "WheelsetContact")},
    **{f"FMI {fmi}.0 {model}_{n}": (fixture, fmi, f"{model}_{n}")
       for fmi in (2, 3) for fixture, n in (("contact_variants", 3), ("eight_contacts", 8))
       for model in ("RollingContact2D", "RollingContact3D")},
    **{f"FMI 2.0 integer codes {model}": ("integer_codes", 2, model)
       for model in ("RollingContact2D", "RollingContact2D_2", "RollingContact3D_2")},
}
BUILDS = {  # fixture of the test run -> build_fmu.py arguments (tests/conftest.py), for --record
    "fmu_folders": (["--fmi", "2,3", "--all"],),
    "contact_variants": (["--fmi", "2,3", "--contacts", "3"],),
    "eight_contacts": (["--fmi", "2,3", "--contacts", "8"],),
    "integer_codes": (["--integer-codes"], ["--contacts", "2", "--integer-codes"]),
}


def local(tag: str) -> str:
    return tag.rpartition("}")[2]


def snapshot(fmu: Path) -> dict:
    """What the FMU's modelDescription.xml declares, as the record holds it (module docstring)."""
    with zipfile.ZipFile(fmu) as archive:
        root = ElementTree.fromstring(archive.read("modelDescription.xml"))
    descriptions: dict[str, str] = {}

    def attributes(element, key: str) -> dict:
        values = dict(element.attrib)
        if "description" in values:
            descriptions[key] = values.pop("description")
        return values

    variables, types, model = [], {}, []
    for element in root:
        tag = local(element.tag)
        if tag == "ModelVariables":
            for variable in element:
                entry = attributes(variable, variable.get("name"))
                if local(variable.tag) == "ScalarVariable":  # FMI 2.0: the type is the child element
                    kind = variable[0]
                    entry = {**entry, "type": local(kind.tag), **attributes(kind, variable.get("name") + ".type")}
                else:  # FMI 3.0: the type is the element, dimensions and start values its children
                    entry["type"] = local(variable.tag)
                    for child in variable:
                        entry.setdefault(local(child.tag), []).append(dict(child.attrib))
                variables.append(dict(sorted(entry.items())))
        elif tag == "TypeDefinitions":
            for definition in element:
                name = definition.get("name")
                entry = {"kind": local(definition.tag), **attributes(definition, name)}
                for part in definition.iter():
                    if part is definition:
                        continue
                    if local(part.tag) == "Item":
                        entry.setdefault("items", []).append([part.get("name"), int(part.get("value"))])
                        descriptions[f"{name}.{part.get('name')}"] = part.get("description", "")
                    else:  # FMI 2.0's Enumeration, Real... below SimpleType
                        entry[local(part.tag)] = attributes(part, f"{name}.{local(part.tag)}")
                types[name] = entry
        else:
            for depth, part in walk(element, tag):
                key = depth if local(part.tag) != "Category" else f"{depth}[{part.get('name')}]"
                model.append([depth, attributes(part, key)])
    head = attributes(root, "model")
    model.insert(0, ["fmiModelDescription", {k: v for k, v in head.items() if k not in VOLATILE}])
    return {"model": model, "types": types, "variables": variables, "descriptions": descriptions}


def walk(element, path: str):
    """``(path, element)`` of ``element`` and everything below it, in document order."""
    yield path, element
    for child in element:
        yield from walk(child, f"{path}/{local(child.tag)}")


def differences(key: str, recorded: dict, built: dict) -> list[str]:
    """What differs between the recorded and the built snapshot outside the descriptions, named."""
    found = []
    was = {v["name"]: v for v in recorded["variables"]}
    now = {v["name"]: v for v in built["variables"]}
    found += [f"{key}: variable {name} is new" for name in now if name not in was]
    found += [f"{key}: variable {name} is gone" for name in was if name not in now]
    for name in now.keys() & was.keys():
        for field in sorted(now[name].keys() | was[name].keys()):
            if now[name].get(field) != was[name].get(field):
                found.append(f"{key}: variable {name}: {field} {now[name].get(field)!r}, recorded "
                             f"{was[name].get(field)!r}")
    if not found and [v["name"] for v in built["variables"]] != [v["name"] for v in recorded["variables"]]:
        found.append(f"{key}: the variables' order changed")
    for name in sorted(built["types"].keys() | recorded["types"].keys()):
        if built["types"].get(name) != recorded["types"].get(name):
            found.append(f"{key}: type {name}: {built['types'].get(name)!r}, recorded {recorded['types'].get(name)!r}")
    if built["model"] != recorded["model"]:
        first = next((i for i, (a, b) in enumerate(zip(built["model"], recorded["model"], strict=False)) if a != b),
                     min(len(built["model"]), len(recorded["model"])))
        found.append(f"{key}: model element {first} of {len(built['model'])} (recorded {len(recorded['model'])}): "
                     f"{built['model'][first] if first < len(built['model']) else None!r}, recorded "
                     f"{recorded['model'][first] if first < len(recorded['model']) else None!r}")
    return found


@pytest.fixture(scope="module")
def record() -> dict:
    return json.loads(DATA.read_text())


def test_the_record_holds_every_fmu(record):
    assert sorted(record) == sorted(FMUS), \
        f"record and FMUs differ: {sorted(set(record) ^ set(FMUS))} (python {DATA.name} --record)"


@pytest.mark.parametrize("key", list(FMUS))
def test_the_model_description_is_the_recorded_one(key, record, request):
    fixture, fmi, model = FMUS[key]
    folders = request.getfixturevalue(fixture)
    folder = folders if isinstance(folders, Path) else folders[fmi]
    built = snapshot(folder / f"{model}.fmu")
    found = differences(key, record[key], built)
    assert not found, "\n".join(found[:12]) + (f"\n... {len(found) - 12} more" if len(found) > 12 else "")
    changed = sorted(k for k in built["descriptions"].keys() | record[key]["descriptions"].keys()
                     if built["descriptions"].get(k) != record[key]["descriptions"].get(k))
    assert not changed, "\n".join(f"{key}: the description of {k} is {built['descriptions'].get(k)!r}, recorded "
                                  f"{record[key]['descriptions'].get(k)!r}" for k in changed[:12])


def recorded_json(data: dict) -> str:
    """The record as JSON with one variable, type, model element or description per line."""
    def block(items, open_, close) -> str:
        return open_ + "\n" + ",\n".join(items) + "\n" + close

    fmus = []
    for key, shot in data.items():
        parts = [
            '"model": ' + block([json.dumps(entry) for entry in shot["model"]], "[", "]"),
            '"types": ' + block([f"{json.dumps(k)}: {json.dumps(v)}" for k, v in shot["types"].items()], "{", "}"),
            '"variables": ' + block([json.dumps(v) for v in shot["variables"]], "[", "]"),
            '"descriptions": ' + block([f"{json.dumps(k)}: {json.dumps(v)}" for k, v in shot["descriptions"].items()],
                                       "{", "}"),
        ]
        fmus.append(f"{json.dumps(key)}: " + block(parts, "{", "}"))
    return block(fmus, "{", "}") + "\n"


def main() -> dict:
    """Build every FMU of :data:`FMUS` as the test run's fixtures do, into a temporary folder; key -> snapshot."""
    import subprocess
    import tempfile

    root = Path(__file__).resolve().parents[2]
    base = Path(tempfile.mkdtemp())
    folders = {}
    for fixture, runs in BUILDS.items():
        dest = base / fixture
        for args in runs:
            subprocess.run([sys.executable, str(root / "build_fmu.py"), *args, "--dest", str(dest)], check=True,
                           capture_output=True)
        folders[fixture] = dest
    return {key: snapshot((folders[fixture] if fixture == "integer_codes" else
                           folders[fixture] / ("fmi3" if fmi == 3 else "")) / f"{model}.fmu")
            for key, (fixture, fmi, model) in FMUS.items()}


if __name__ == "__main__" and sys.argv[1:] == ["--record"]:
    DATA.write_text(recorded_json(main()))
    print(f"wrote {DATA}")
