"""Progress bars of the long commands (impactdamper.reporting.progress): drawn on stderr when it
is a terminal, never when it is piped or redirected, never with --quiet; the output is the same."""

import fcntl
import io
import json
import os
import pty
import struct
import subprocess
import sys
import termios
import threading

import pytest

from impactdamper.reporting.progress import progress_bar, _shows_progress

RESPONSE = ["response", "--points", "3", "--json"]


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def _on_a_terminal(*args: str) -> tuple[int, str, str]:
    """Run ``python -m impactdamper *args`` with stderr on a pseudo-terminal (80 columns) and
    stdout piped: (status, stdout, what the terminal received)."""
    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 80, 0, 0))
    received = bytearray()

    def read() -> None:
        while True:
            try:
                chunk = os.read(master, 4096)
            except OSError:  # the terminal's other end closed
                return
            if not chunk:
                return
            received.extend(chunk)

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    with subprocess.Popen([sys.executable, "-m", "impactdamper", *args], stdout=subprocess.PIPE, stderr=slave) as proc:
        os.close(slave)
        out = proc.stdout.read().decode()
        status = proc.wait(timeout=300)
    reader.join(timeout=10)
    os.close(master)
    return status, out, received.decode(errors="replace")


def test_bar_counts_steps_on_a_terminal_only():
    terminal = _Terminal()
    with progress_bar(4, "demo", stream=terminal) as bar:
        assert bar.shown
        for _ in range(4):
            bar.step("any", "arguments")
        bar._bar.refresh()
        assert "demo" in terminal.getvalue() and "4/4" in terminal.getvalue()
    for stream, quiet in ((io.StringIO(), False), (_Terminal(), True)):
        with progress_bar(4, "demo", stream=stream, quiet=quiet) as bar:
            bar.step()
            assert not bar.shown
        assert stream.getvalue() == ""
    assert _shows_progress(stream=_Terminal()) and not _shows_progress(stream=io.StringIO())


@pytest.mark.slow
def test_response_shows_a_bar_on_a_terminal_and_not_with_quiet():
    status, out, terminal = _on_a_terminal(*RESPONSE)
    assert status == 0, terminal
    assert "response:" in terminal and "/6" in terminal  # 2 sweeps x 3 points
    quiet_status, quiet_out, quiet_terminal = _on_a_terminal(*RESPONSE, "--quiet")
    assert quiet_status == 0 and quiet_terminal == ""
    assert out == quiet_out and len(json.loads(out)["points"]) == 3


@pytest.mark.slow
def test_response_piped_writes_nothing_to_stderr():
    proc = subprocess.run(
        [sys.executable, "-m", "impactdamper", *RESPONSE], capture_output=True, text=True, timeout=300
    )
    assert proc.returncode == 0 and proc.stderr == ""
    assert len(json.loads(proc.stdout)["points"]) == 3


@pytest.mark.slow
def test_quiet_is_a_flag_of_response_only():
    proc = subprocess.run(
        [sys.executable, "-m", "impactdamper", "steady", "--quiet"], capture_output=True, text=True, timeout=300
    )
    assert proc.returncode == 2 and "unrecognized arguments: --quiet" in proc.stderr
