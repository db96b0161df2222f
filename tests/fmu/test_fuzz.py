"""The quick fuzz of ``tests/tools/fuzz_fmu.py`` against the contact FMUs built for the test run: no finding.

``--quick`` runs a few seeded episodes of 12 operations on each target, RollingContact2D (FMI 2.0), RollingContact3D,
RollingContact3D_8 and WheelsetContact (FMI 2.0 and 3.0): random valid, extreme and invalid parameters and inputs,
every level, Jacobian mode and friction law, state save/restore/serialise of valid, corrupted and crafted states, late
parameters, communication points inside a step, resets; then instantiate/free cycles.  Each target runs in a worker
subprocess (a crash is a finding, not the end of the test run).  Step times are reported, never findings here.  A
finding names its target and episode: ``python tests/tools/fuzz_fmu.py --seed 1 --steps 12 --target MODEL/FMI
--episode K --fmu FILE`` replays it.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TOOL = ROOT / "tests" / "tools" / "fuzz_fmu.py"


def test_quick_fuzz_of_every_contact_fmu_has_no_finding(fmu_path, contact_variants, eight_contacts, fmu_folders):
    fmus = [
        fmu_path,
        *(contact_variants[fmi] / "RollingContact3D.fmu" for fmi in (2, 3)),
        *(eight_contacts[fmi] / "RollingContact3D_8.fmu" for fmi in (2, 3)),
        *(fmu_folders[fmi] / "WheelsetContact.fmu" for fmi in (2, 3)),
    ]
    command = [sys.executable, str(TOOL), "--quick", "--seed", "1", *(a for f in fmus for a in ("--fmu", str(f)))]
    done = subprocess.run(command, capture_output=True, text=True, timeout=900)
    assert done.returncode in (0, 1), f"fuzz_fmu.py failed (exit {done.returncode}):\n{done.stderr[-3000:]}"
    summary = json.loads(done.stdout.strip().splitlines()[-1])
    expected = {
        "RollingContact2D/2": 16,
        "RollingContact3D/2": 5,
        "RollingContact3D/3": 5,
        "RollingContact3D_8/2": 4,
        "RollingContact3D_8/3": 4,
        "WheelsetContact/2": 3,
        "WheelsetContact/3": 3,
    }
    assert summary["targets"] == expected, f"the quick fuzz runs every episode of every target: {summary}"
    findings = done.stdout[done.stdout.find("## Findings") :]
    assert summary["findings"] == 0 and done.returncode == 0, f"fuzz findings:\n{findings[:6000]}"
