"""The command-line entry points: one line and exit code 2 for a bad name or a missing optional dependency, no
traceback; a progress bar on a terminal and nothing otherwise."""

from __future__ import annotations

import io
import subprocess
import sys

import pytest

from rollcontact_cosim.cli import Progress

MISSING = "import sys; sys.modules[{module!r}] = None; from {entry} import main; sys.exit(main({argv!r}))"


@pytest.mark.parametrize(("command", "says"), [
    (["-m", "rollcontact_cosim", "no_such_scene"], "no co-simulation scene 'no_such_scene'"),
    (["-m", "rollcontact_cosim.reference", "--check", "no_such_scene"], "no co-simulation scene 'no_such_scene'"),
    (["-m", "rollcontact_cosim.sweep", "--host", "mass"], "expected name=value"),
    (["-c", MISSING.format(module="libcosimpy", entry="rollcontact_cosim.__main__", argv=["--master", "libcosim"])],
     "libcosimpy is not installed"),
    (["-c", MISSING.format(module="dask", entry="rollcontact_cosim.sweep", argv=["--regression"])],
     "dask is not installed"),
])
def test_a_bad_name_or_a_missing_dependency_is_one_line_and_exit_code_2(command, says):
    done = subprocess.run([sys.executable, *command], capture_output=True, text=True, timeout=120)
    assert done.returncode == 2, f"exit code {done.returncode}: {done.stderr}"
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and says in lines[0] and "Traceback" not in done.stderr, done.stderr


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_progress_draws_on_a_terminal_and_is_quiet_otherwise():
    quiet, terminal = io.StringIO(), Terminal()
    for stream in (quiet, terminal):
        with Progress(4, "runs", stream=stream) as progress:
            for _ in range(4):
                progress.advance()
    assert quiet.getvalue() == "", "nothing when the output is not a terminal"
    drawn = terminal.getvalue()
    assert drawn.count("\r") == 4 and "4/4 runs" in drawn and drawn.endswith("\n"), repr(drawn)
