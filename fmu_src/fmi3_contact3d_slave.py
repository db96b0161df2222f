"""pythonfmu3 entry module of the RollingContact3D FMU (FMI 3.0 co-simulation).

The slave is the shared class of the variant (:func:`rollcontact_fmu_contact3d.slave_class` with ``fmi=3``, the slave
logic of the FMI 2.0 FMU without its binding) put on pythonfmu3 by :class:`fmi3_table_slave.TableSlave3`; the class
statement names ``Fmi3Slave`` on one line for pythonfmu3's loader (``fmi3_rollcontact_slave.py``'s docstring).
``build_fmu.py --contacts n`` builds from this text with the variant's model name (``RollingContact3D_n``) and
arguments in place of these, in a module of the variant's own name (pythonfmu3 imports an entry module once per
process).
"""

from fmi3_table_slave import TableSlave3
from pythonfmu3 import Fmi3Slave
from rollcontact_fmu_contact3d import slave_class

RollingContact3DShared = slave_class(contacts=1, integer_codes=False, fmi=3)


class RollingContact3D(TableSlave3, RollingContact3DShared, Fmi3Slave):
    """Elliptic rolling contact of rollcontact as an FMI 3.0 co-simulation slave (the shared slave's table)."""


__all__ = ["RollingContact3D"]
