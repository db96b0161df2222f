"""pythonfmu3 entry module of the RollingContact2D FMU (FMI 3.0 co-simulation).

The slave is :class:`rollcontact_fmu_contact.RollingContact2DShared` (variable table, enumerations, model glue,
shared ``TableSlave`` logic: the FMI 2.0 FMU's slave without its binding) put on pythonfmu3 by
:class:`fmi3_table_slave.TableSlave3`.  pythonfmu3's builder and binary find the slave class by a regular expression
over this file's lines: the class statement must name ``Fmi3Slave`` on one line.  The module is imported once per
process (pythonfmu3 does not re-execute it per instance, unlike pythonfmu 0.7), so the class can be defined here.
"""

from fmi3_table_slave import TableSlave3
from pythonfmu3 import Fmi3Slave
from rollcontact_fmu_contact import VARIABLES, RollingContact2DShared


class RollingContact2D(TableSlave3, RollingContact2DShared, Fmi3Slave):
    """2D rolling contact of rollcontact as an FMI 3.0 co-simulation slave (the shared slave's table and logic)."""


__all__ = ["VARIABLES", "RollingContact2D"]
