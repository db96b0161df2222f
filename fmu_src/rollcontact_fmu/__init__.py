"""The support layer every FMU of the project bundles around its slave (``resources/rollcontact_fmu/``), by concern:

* :mod:`.slave`: :class:`~.slave.TableSlave`, a slave's variables from one table, its life cycle, ``do_step`` and its
  refusals, in either FMI version;
* :mod:`.state`: the FMU state (what it holds, its serialisation with a checksum, the complete check of a state
  handed back);
* :mod:`.description`: the modelDescription completion (units, bounds, enumerations, ModelStructure);
* :mod:`.enumerations`: the enumerations derived from the solver's tables, and the integer-codes variant;
* :mod:`.contacts`: several contacts in one slave, and a contact FMU's variant classes;
* :mod:`.workarounds`: what pythonfmu's binaries need from a slave (printf-safe messages, the logger object's layout,
  the repeated ``sys.path`` entries, scipy's ``_uarray`` at exit, the entry module's reference balance);
* :mod:`.fmi2`, :mod:`.fmi3`: the bindings on pythonfmu 0.7 (FMI 2.0) and pythonfmu3 0.3.4 (FMI 3.0).

Nothing is imported here: an FMI 2.0 FMU bundles no pythonfmu3, which :mod:`.fmi3` imports.
"""
