"""The FMI 2.0 co-simulation binding of the project's slaves (pythonfmu 0.7, bundled in each FMU's resources).

:class:`TableSlave2` puts a slave of this project (a :class:`rollcontact_fmu_base.TableSlave` with its model glue,
e.g. ``rollcontact_fmu_contact.RollingContact2DShared``) on pythonfmu's ``Fmi2Slave``.  The FMI 2.0 slave class
names the shared class first and the binding next, in the module of the shared class (pythonfmu re-executes the
entry module on every instantiation, so no class is defined there)::

    class RollingContact2D(RollingContact2DShared, TableSlave2):

so the shared slave's ``do_step``, ``setup_experiment``, ``exit_initialization_mode`` and FMU state methods answer
pythonfmu, and this binding constructs the slave (``Fmi2Slave.__init__``, then
:meth:`rollcontact_fmu_base.TableSlave.init_table`), answers the typed getters and setters in FMI 2.0's names, gives
the messages FMI 2.0's words and writes the completed model description.  The FMI 3.0 binding,
:class:`fmi3_table_slave.TableSlave3`, puts the same shared class on pythonfmu3: no FMI 3.0 slave inherits this
class or ``Fmi2Slave``.
"""

from __future__ import annotations

import math
from xml.etree.ElementTree import Element

from pythonfmu import Fmi2Slave, Real
from pythonfmu.variables import Boolean, Integer, String
from rollcontact_fmu_base import complete_model_description


class TableSlave2(Fmi2Slave):
    """The FMI 2.0 side of a :class:`rollcontact_fmu_base.TableSlave` (module docstring): put it after the shared
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
