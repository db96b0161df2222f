"""The quick fuzz campaign of ``benchmarks/fuzz_fmu.py`` against the FMU built for the test run: no finding.

``--quick`` runs 150 seeded episodes of 12 operations (random valid, extreme and invalid inputs and parameters,
state save/restore/serialise of valid, corrupted and crafted states, late parameters, communication points inside
a step) and 60 instantiate/free cycles, in a worker subprocess (a crash is a finding, not the end of the test
run).  A finding names its episode: ``python benchmarks/fuzz_fmu.py --seed 1 --steps 12 --episode K`` replays
it.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_quick_fuzz_campaign_has_no_finding(fmu_path):
    done = subprocess.run([sys.executable, str(ROOT / "benchmarks" / "fuzz_fmu.py"), "--quick", "--seed", "1",
                           "--fmu", str(fmu_path)], capture_output=True, text=True, timeout=300)
    assert done.returncode in (0, 1), f"fuzz_fmu.py failed (exit {done.returncode}):\n{done.stderr[-3000:]}"
    summary = json.loads(done.stdout.strip().splitlines()[-1])
    assert summary["episodes"] == 150, f"the quick campaign must run all its episodes: {summary}"
    findings = done.stdout[done.stdout.find("## Findings"):]
    assert summary["findings"] == 0 and done.returncode == 0, f"fuzz findings:\n{findings[:6000]}"
