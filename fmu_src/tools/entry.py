"""The FMUs' entry modules, written by ``build_fmu.py`` from one template (:data:`TEMPLATE`) and an FMU's manifest.

pythonfmu names the entry module in ``resources/slavemodule.txt`` and runs it to find the slave class.  pythonfmu 0.7
re-executes its source on every instantiation, leaks the MRO of every class bound there and releases one reference
to its namespace it never took: so the FMI 2.0 entry binds one existing class (``rollcontact_fmu.fmi2.fmi2_class`` of
the slave module's ``slave_class``) and balances that reference (``rollcontact_fmu.workarounds.balance_entry_module``).
pythonfmu3 imports it once per process and finds the class by a regular expression over its lines: so the FMI 3.0
entry states the class, naming ``Fmi3Slave`` on one line.  Every entry module is named after its FMU, variant and
FMI version (:func:`module_name`): the FMUs a host loads share one Python process and its ``sys.modules``
(docs/fmu-internals.md, "Entry modules").
"""

from __future__ import annotations

from pathlib import Path

TEMPLATE = '''"""{tool} entry module of the {model} FMU (FMI {fmi}.0), written by build_fmu.py from
fmu_src/{folder}/manifest.toml and the template of fmu_src/tools/entry.py ({why})."""

{imports}
from {slave} import slave_class

{binding}
'''
"""The entry module: its FMI version's imports and binding (:data:`VERSIONS`) around the slave module's class."""

VERSIONS = {
    2: {"tool": "pythonfmu",
        "why": "pythonfmu re-executes it on every instantiation: it binds one existing class",
        "imports": "from rollcontact_fmu.fmi2 import fmi2_class\n"
                   "from rollcontact_fmu.workarounds import balance_entry_module",
        "binding": "{model} = fmi2_class(slave_class({arguments}))\n"
                   "balance_entry_module(globals(), locals())"},
    3: {"tool": "pythonfmu3",
        "why": "pythonfmu3 finds the class statement naming Fmi3Slave by a regular expression",
        "imports": "from pythonfmu3 import Fmi3Slave\n"
                   "from rollcontact_fmu.fmi3 import TableSlave3",
        "binding": "Shared = slave_class({arguments})\n\n\n"
                   "class {model}(TableSlave3, Shared, Fmi3Slave):\n"
                   '    """The {model} FMU\'s slave on pythonfmu3 (FMI 3.0)."""'},
}
"""FMI version -> the parts of :data:`TEMPLATE` that differ."""


def module_name(model: str, fmi: int, integer_codes: bool = False) -> str:
    """The entry module's name for the FMU named ``model`` (a variant's name), FMI version ``fmi``."""
    return f"rollcontact_fmu_entry_{model}_fmi{fmi}" + ("_integer_codes" if integer_codes else "")


def entry_source(model: str, fmi: int, folder: str, slave: str, arguments: dict) -> str:
    """The entry module of the FMU named ``model`` in FMI ``fmi``: the class of ``slave_class(**arguments)`` of the
    slave module ``slave`` (in ``fmu_src/<folder>/``)."""
    parts = VERSIONS[fmi]
    call = ", ".join(f"{key}={value!r}" for key, value in arguments.items())
    return TEMPLATE.format(tool=parts["tool"], model=model, fmi=fmi, folder=folder, why=parts["why"],
                           imports=parts["imports"], slave=slave,
                           binding=parts["binding"].format(model=model, arguments=call))


def write_entry(dest: Path, model: str, fmi: int, folder: str, slave: str, arguments: dict) -> Path:
    """Write :func:`entry_source` into the folder ``dest`` as :func:`module_name`'s file; its path."""
    path = Path(dest) / f"{module_name(model, fmi, bool(arguments.get('integer_codes')))}.py"
    path.write_text(entry_source(model, fmi, folder, slave, arguments))
    return path
