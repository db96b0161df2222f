"""The README's snippets run and print what the README says they print; the README stays short and history-free."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()
SNIPPETS = re.findall(r"```python\n(.*?)```\n+```text\n(.*?)```", README, flags=re.S)


def test_the_readme_has_its_snippets_and_its_two_commands():
    assert len(SNIPPETS) == 3, f"three python snippets, each followed by its output: found {len(SNIPPETS)}"
    commands = re.findall(r"```bash\n(.*?)```", README, flags=re.S)
    assert any("-m rollcontact_cosim" in c for c in commands), "the main job's command"
    ci = (ROOT / ".ci" / "run").read_text()
    test_command = next(c.strip() for c in commands if "pytest" in c)
    assert test_command in ci, ".ci/run runs exactly the README's test command"


@pytest.mark.parametrize("index", range(len(SNIPPETS)))
def test_a_snippet_prints_what_the_readme_says(index, fmu_path, tmp_path):
    code, expected = SNIPPETS[index]
    code = code.replace('"models/RollingContact2D.fmu"', repr(str(fmu_path)))
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == expected.split(), f"printed:\n{done.stdout}\nthe README says:\n{expected}"


def test_the_readme_is_short_and_says_what_is():
    assert len(README) < 7000, f"README.md is {len(README)} characters (aim: under 7,000)"
    history = re.search(r"\b(sess[i]ons?|was|until|earlier runs?)\b", README, flags=re.I)
    assert history is None, f"the README speaks of history ({history and history.group(0)!r})"
    for link in re.findall(r"\]\(([^)#]+)\)", README):
        assert (ROOT / link).exists(), f"the README links {link}, which does not exist"
