"""The FMI 2.0 co-simulation binding of the project's slaves (pythonfmu 0.7).

:func:`fmi2_class` puts a shared slave class (a :class:`rollcontact_fmu.slave.TableSlave` with its model glue, e.g.
a variant of ``rollcontact_fmu_contact2d.RollingContact2DShared``) on pythonfmu's ``Fmi2Slave``: a class of the same
name that names the shared class first and :class:`TableSlave2` next::

    class RollingContact2D(RollingContact2D, TableSlave2):  # what fmi2_class(slave_class()) makes

so the shared slave's ``do_step``, ``setup_experiment``, ``exit_initialization_mode`` and FMU state methods answer
pythonfmu, and this binding constructs the slave (``Fmi2Slave.__init__``, then
:meth:`rollcontact_fmu.slave.TableSlave.init_table`), answers the typed getters and setters in FMI 2.0's names, gives
the messages FMI 2.0's words and writes the completed model description.  The entry module binds that class only
(pythonfmu re-executes the entry module on every instantiation: no class is defined there).  The FMI 3.0 binding,
:class:`rollcontact_fmu.fmi3.TableSlave3`, puts the same shared class on pythonfmu3: no FMI 3.0 slave inherits this
class or ``Fmi2Slave``.
"""

from __future__ import annotations

import math
from functools import cache
from xml.etree.ElementTree import Element

from pythonfmu import Fmi2Slave, Real
from pythonfmu.variables import Boolean, Integer, String

from rollcontact_fmu.description import complete_model_description


class TableSlave2(Fmi2Slave):
    """The FMI 2.0 side of a :class:`rollcontact_fmu.slave.TableSlave` (module docstring): put it after the shared
    class in the bases."""

    WORDS = {"error": "fmi2Error", "ok": "fmi2OK", "fmi": "FMI 2", "binding": "pythonfmu", "set_state": "setFMUstate"}
    """FMI 2.0's words in the shared slave's messages."""

    def __init__(self, **kwargs):
        Fmi2Slave.__init__(self, **kwargs)  # pythonfmu's attributes (vars, instance_name, resources, ...)
        self.init_table(**kwargs)  # the shared slave's table, registered through Fmi2Slave.register_variable

    def set_real(self, vrs, values):
        self.write_values(vrs, values, Real, "setReal")

    def set_integer(self, vrs, values):
        self.write_values(vrs, values, Integer, "setInteger")

    def set_boolean(self, vrs, values):
        self.write_values(vrs, values, Boolean, "setBoolean")

    def set_string(self, vrs, values):
        self.write_values(vrs, values, String, "setString")

    def get_real(self, vrs):
        return self.read_values(vrs, Real, float, math.nan, "getReal")

    def get_integer(self, vrs):
        return self.read_values(vrs, Integer, int, 0, "getInteger")

    def get_boolean(self, vrs):
        return self.read_values(vrs, Boolean, bool, False, "getBoolean")

    def get_string(self, vrs):
        return self.read_values(vrs, String, str, "", "getString")

    def to_xml(self, model_options=None) -> Element:
        """pythonfmu's model description plus units, bounds, UnitDefinitions and a complete ModelStructure."""
        root = Fmi2Slave.to_xml(self, {} if model_options is None else model_options)
        return complete_model_description(root, self.VARIABLES, self.INITIAL_DEPENDENCIES, self.ENUMERATIONS)


@cache
def fmi2_class(shared: type) -> type:
    """The FMI 2.0 slave class of the shared slave class ``shared``: ``shared`` on :class:`TableSlave2`, of the same
    name (pythonfmu names the model after the class), one per shared class and process (pythonfmu 0.7 re-executes
    the entry module per instantiation: it must bind the same class every time)."""
    return type(shared.__name__, (shared, TableSlave2), {"__doc__": f"{shared.__doc__} On pythonfmu (FMI 2.0).",
                                                         "__module__": shared.__module__})
