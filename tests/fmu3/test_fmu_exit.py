"""The exit fix of pythonfmu's Linux export library in the built FMUs (``fmu_src/tools/pythonfmu_exit_fix.py``,
docs/fmu-internals.md "Exit").

pythonfmu 0.7.0 and pythonfmu3 0.3.4 release their static ``std::shared_ptr<PyState>`` twice at process exit; the
build redirects the static destructor's registration to ``finalizePythonInterpreter``, a 7-byte instruction.  The
expected instructions below were read with ``objdump -d`` from the pinned releases' libraries, an oracle
independent of the module's ELF reader; every other byte must be the installed library's.
"""

from __future__ import annotations

import copy
import hashlib
import importlib.metadata
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT / "fmu_src" / "tools") not in sys.path:
    sys.path.append(str(ROOT / "fmu_src" / "tools"))  # the build's fix of the export library (build_fmu.tool)
import pythonfmu_exit_fix as fix  # noqa: E402

# version -> (package, folder in the FMU, file offset, instruction before, instruction after), from objdump -d:
#   pythonfmu 0.7.0:  16f73: 48 8b 3d 1e dc 02 00  mov 0x2dc1e(%rip),%rdi  # GOT slot of ~shared_ptr<PyState>
#                     16f73: 48 8d 3d 66 88 01 00  lea 0x18866(%rip),%rdi  # 2f7e0 <finalizePythonInterpreter>
#   pythonfmu3 0.3.4: 16b90: 48 8b 3d 79 d1 02 00  mov 0x2d179(%rip),%rdi  # GOT slot of ~shared_ptr<PyState>
#                     16b90: 48 8d 3d 29 4c 00 00  lea 0x4c29(%rip),%rdi   # 1b7c0 <finalizePythonInterpreter>
REDIRECTION = {
    2: ("pythonfmu", "binaries/linux64/", 0x16F73, "488b3d1edc0200", "488d3d66880100"),
    3: ("pythonfmu3", "binaries/x86_64-linux/", 0x16B90, "488b3d79d10200", "488d3d294c0000"),
}


def installed(package: str, *parts: str) -> Path:
    """A file of the installed distribution ``package`` (not of a copy an FMU put on ``sys.path``: the FMI 3.0
    FMUs bundle pythonfmu's Python files, and pythonfmu puts an instance's resources first on ``sys.path``)."""
    return Path(importlib.metadata.distribution(package).locate_file(Path(package, *parts)))


def installed_library(package: str) -> bytes:
    folder = "linux64" if package == "pythonfmu" else "x86_64-linux"
    return installed(package, "resources", "binaries", folder, "libpythonfmu-export.so").read_bytes()


@pytest.mark.parametrize("model", ["RollingContact2D", "WheelRig"])
def test_the_linux_binary_differs_from_the_release_by_the_redirection_only(fmu_folders, fmi, model):
    package, folder, offset, before, after = REDIRECTION[fmi]
    original = installed_library(package)
    with zipfile.ZipFile(fmu_folders[fmi] / f"{model}.fmu") as fmu:
        binary = fmu.read(f"{folder}{model}.so")
        windows = [name for name in fmu.namelist() if name.endswith(".dll")]
        assert windows, f"{model} FMI {fmi}: no Windows binary in {fmu.namelist()}"
        dll = fmu.read(windows[0])
    assert original[offset:offset + 7].hex() == before, f"{package}: the installed library is not the pinned one"
    assert len(binary) == len(original), f"{model} FMI {fmi}: {len(binary)} bytes, the release has {len(original)}"
    changed = [i for i, (a, b) in enumerate(zip(binary, original, strict=True)) if a != b]
    assert changed and offset <= changed[0] and changed[-1] < offset + 7, \
        f"{model} FMI {fmi}: bytes changed at {[hex(i) for i in changed]}, expected within {offset:#x} + 7"
    assert binary[offset:offset + 7].hex() == after, \
        f"{model} FMI {fmi}: {binary[offset:offset + 7].hex()} at {offset:#x}, expected {after} (lea to the finaliser)"
    windows_original = installed(package, "resources", "binaries")
    assert any(dll == path.read_bytes() for path in windows_original.rglob("*.dll")), \
        f"{model} FMI {fmi}: the Windows binary must be the release's, unchanged"


def test_the_fix_finds_the_instruction_through_the_elf_tables():
    """The module's reader locates the same instruction and target objdump shows, in both releases."""
    for package, _, offset, _, _ in REDIRECTION.values():
        tables = fix.ElfTables(installed_library(package))
        address = fix.registration(tables)
        assert tables.file_offset(address) == offset, f"{package}: registration at {address:#x}"
        target = address + 7 + int.from_bytes(bytes.fromhex(REDIRECTION[2 if package == "pythonfmu" else 3][4])[3:],
                                              "little", signed=True)
        assert tables.symbol(fix.FINALIZER)[0] == target, f"{package}: {fix.FINALIZER} at {target:#x} expected"


def test_the_fix_refuses_other_bytes_and_keeps_fixed_ones():
    original = installed_library("pythonfmu")
    fixed = fix.patch_library(original)
    assert fix.patch_library(fixed) == fixed, "a fixed library comes back unchanged"
    other = bytearray(original)
    other[0x100] ^= 1
    with pytest.raises(RuntimeError, match=hashlib.sha256(other).hexdigest()) as refused:
        fix.patch_library(bytes(other), "other.so")
    assert "pinned pythonfmu release" in str(refused.value) and "other.so" in str(refused.value), str(refused.value)
    with pytest.raises(ValueError, match="not an ELF64"):
        fix.ElfTables(b"MZ" + bytes(100))


def test_an_fmu_with_another_library_is_left_as_it_was(fmu_folders, tmp_path):
    """``patch_fmu`` of an FMU whose Linux binary is no pinned release's: RuntimeError, the file unchanged, no
    temporary file left; an FMU without a Linux binary is refused too."""
    source = fmu_folders[2] / "RollingContact2D.fmu"
    altered, bare = tmp_path / "altered.fmu", tmp_path / "bare.fmu"
    with zipfile.ZipFile(source) as fmu, zipfile.ZipFile(altered, "w") as out, zipfile.ZipFile(bare, "w") as empty:
        for info in fmu.infolist():
            data = fmu.read(info)
            if info.filename.endswith(".so"):
                out.writestr(info, data[:-1] + bytes([data[-1] ^ 1]))
                continue
            out.writestr(info, data)
            empty.writestr(copy.copy(info), data)  # writestr records offsets in the ZipInfo: one per archive
    before = {path: path.read_bytes() for path in (altered, bare)}
    for path, reason in ((altered, "not that of a pinned pythonfmu release"), (bare, "holds no Linux export")):
        with pytest.raises(RuntimeError, match=reason):
            fix.patch_fmu(path)
        assert path.read_bytes() == before[path], f"{path.name} must be left as it was"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["altered.fmu", "bare.fmu"], list(tmp_path.iterdir())


HOST = """
import sys
from pathlib import Path
from rollcontact_cosim.master import Slave

slaves = [Slave(Path(sys.argv[1]), f"exit_{i}") for i in range(int(sys.argv[2]))]
for k, slave in enumerate(slaves):
    slave.set_start_values({"friction_law": 1, "friction_kinetic_ratio": 0.5, "friction_decay": 2.0, "table": 1})
    slave.initialise()
    inputs = [slave.reference(name, "input") for name in ("normal_load", "creep", "velocity")]
    for n in range(3):
        slave.fmu.setReal(inputs, [1e5, 1e-3 * (n + k + 1), 20.0])
        slave.fmu.doStep(currentCommunicationPoint=n * 1e-3, communicationStepSize=1e-3)
    state = slave.fmu.getFMUstate()
    slave.fmu.setFMUstate(state)
    slave.fmu.freeFMUstate(state)
print("results", *(s.fmu.getReal([s.reference("tangential_force")])[0] for s in slaves), flush=True)
for slave in slaves:
    slave.free()
"""


def test_host_processes_that_exit_normally_exit_with_0(fmu_folders):
    """Five fresh Python hosts (FMI 2.0 and 3.0, 1-3 instances, falling friction, a state round trip) end with
    the normal path (interpreter finalisation, ``exit()``'s handlers, the libraries' destructors): every one exits
    with 0.  Whether the double release aborts a process depends on its heap layout, so this can only catch a
    regression by chance; the byte test above is the exact one, ``benchmarks/bench_exit.py`` counts many more."""
    jobs = [(2, 1), (3, 1), (2, 3), (3, 2), (2, 2)]
    processes = [subprocess.Popen([sys.executable, "-c", HOST, str(fmu_folders[v] / "RollingContact2D.fmu"), str(n)],
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                  env={**os.environ, "PYTHONPATH": str(ROOT / "src")})
                 for v, n in jobs]
    for (version, count), process in zip(jobs, processes, strict=True):
        out, err = process.communicate(timeout=180)
        assert process.returncode == 0, f"FMI {version}, {count} instances: exit {process.returncode}\n{err[-2000:]}"
        assert out.startswith("results") and len(out.split()) == 1 + count, f"FMI {version}: printed {out!r}"
