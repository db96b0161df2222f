"""Every notice and log message the stepping model emits speaks to its user: one or two sentences of what happens
and what the user can change, at most :data:`LIMIT` characters, naming no benchmark script (the derivations are in
docs/accuracy.md).  The messages are collected by driving each case that emits one."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from rollcontact.stepping import ContactModel, ContactParameters
from rollcontact.stepping.line.table import CorrugationUse

ROOT = Path(__file__).resolve().parents[3]
H = 1e-3
LIMIT = 250
"""Characters of one message at most."""

OSCILLATING = [(1e5, 1e-3 * (1.0 + 0.8 * math.sin(2.0 * math.pi * k / 5.0)), 20.0) for k in range(12)]
CORRUGATION = {"corrugation_amplitude": 20e-6, "corrugation_wavelength": 0.04}
TABLE_ROWS = [(2e4 * (1.0 + 0.05 * math.sin(0.37 * k)), (1.1e-3, 4e-4, 2.1e-3, -8e-4)[k % 4], 30.0) for k in range(30)]

CASES = {  # name: (parameters, input rows, model keywords, a phrase the message says)
    "scene file": ({"scene_file": str(ROOT / "models" / "carter.toml")}, OSCILLATING[:1], {}, "are ignored"),
    "no instationary model": ({"transient": 1, **CORRUGATION}, OSCILLATING[:1], {}, "quasi-steady"),
    "relaxation lag": ({"transient": 1}, OSCILLATING[:1], {}, "relaxation lag"),
    "transient where the lag misses": ({"transient": 1, "tolerance": 1e-3}, OSCILLATING[:1], {}, "relaxation lag"),
    "transient misses": ({"transient": 1, "tolerance": 1e-6}, OSCILLATING[:1], {}, "NOT met"),
    "given elements miss": ({"transient": 2, "method": 3, "tolerance": 1e-3, "elements": 60}, OSCILLATING[:1], {},
                            "NOT met"),
    "memory cut": ({"transient": 2, "method": 3, "tolerance": 1e-3, "step_budget": 2e-3}, OSCILLATING, {},
                   "step_budget"),
    "tolerance over budget": ({"friction_law": 1, "friction_decay": 3.0, "method": 3, "tolerance": 1e-8,
                               "step_budget": 0.02}, OSCILLATING[:1], {}, "is not met within step_budget"),
    "table built": ({**CORRUGATION, "table": 2}, TABLE_ROWS[:2], {}, "ready over"),
    "table starved": ({**CORRUGATION, "table": 0, "step_budget": 2e-4}, TABLE_ROWS, {}, "leaves no room"),
    "table declined": ({**CORRUGATION, "table": 0, "step_budget": 5e-3}, TABLE_ROWS[:3], {"stop_time": 300 * H},
                       "steps remain"),
    "falling friction table": ({"friction_law": 1, "friction_kinetic_ratio": 0.6, "friction_decay": 6.9, "table": 2},
                               [(6.2e4, 1e-3, 45.0), (6.2e4, 4e-4, 45.0)], {}, "ready over"),
    "no table": ({"corrugation_amplitude": 20e-6, "corrugation_wavelength": 0.01, "table": 2}, TABLE_ROWS[:2], {},
                 "no certified table"),
}


def messages(parameters: dict, rows, keywords: dict) -> list[str]:
    """The model's notices and every message its steps queue."""
    model = ContactModel(ContactParameters(**parameters), **keywords)
    said = list(model.notices)
    for k, row in enumerate(rows):
        model.step(k * H, H, *row)
        said += model.take_messages()
    return said


@pytest.mark.parametrize("case", CASES)
def test_each_message_is_short_and_names_no_benchmark_script(case, monkeypatch):
    if case != "table declined":  # a table of 3 solves: built in a few steps (the declined one needs its real cost)
        monkeypatch.setattr(CorrugationUse, "expected_solves", 3)
    parameters, rows, keywords, phrase = CASES[case]
    said = messages(parameters, rows, keywords)
    assert any(phrase in m for m in said), f"{case}: no message says {phrase!r}: {said}"
    for message in said:
        assert len(message) <= LIMIT, f"{case}: {len(message)} characters: {message!r}"
        assert re.search(r"benchmarks/|bench_\w+|\.py\b", message) is None, f"{case}: cites a script: {message!r}"
        assert re.search(r"\b[A-Z]{2,}_[A-Z_]+\b", message) is None, f"{case}: names a constant: {message!r}"
        sentences = [s for s in re.split(r"(?<=[.;])\s+", message.strip()) if s]
        assert len(sentences) <= 3, f"{case}: one or two sentences: {message!r}"
