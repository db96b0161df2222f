"""pythonfmu3 entry module of the Wheelset FMU (FMI 3.0 co-simulation).

The slave is :class:`rollcontact_fmu_wheelset.WheelsetShared` (the FMI 2.0 FMU's slave logic) put on pythonfmu3 by
:class:`fmi3_table_slave.TableSlave3`; the class statement names ``Fmi3Slave`` on one line for pythonfmu3's loader
(``fmi3_rollcontact_slave.py``'s docstring).
"""

from fmi3_table_slave import TableSlave3
from pythonfmu3 import Fmi3Slave
from rollcontact_fmu_wheelset import VARIABLES, WheelsetShared


class Wheelset(TableSlave3, WheelsetShared, Fmi3Slave):
    """Suspended wheelset on straight track as an FMI 3.0 co-simulation slave."""


__all__ = ["VARIABLES", "Wheelset"]
