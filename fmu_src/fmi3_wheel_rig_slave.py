"""pythonfmu3 entry module of the WheelRig FMU (FMI 3.0 co-simulation).

The slave is :class:`rollcontact_fmu_wheel_rig.WheelRigShared` (the FMI 2.0 FMU's slave logic) put on pythonfmu3 by
:class:`fmi3_table_slave.TableSlave3`; the class statement names ``Fmi3Slave`` on one line for pythonfmu3's loader
(``fmi3_rollcontact_slave.py``'s docstring).
"""

from fmi3_table_slave import TableSlave3
from pythonfmu3 import Fmi3Slave
from rollcontact_fmu_wheel_rig import VARIABLES, WheelRigShared


class WheelRig(TableSlave3, WheelRigShared, Fmi3Slave):
    """Driven wheel on a rail with longitudinal vehicle dynamics as an FMI 3.0 co-simulation slave."""


__all__ = ["VARIABLES", "WheelRig"]
