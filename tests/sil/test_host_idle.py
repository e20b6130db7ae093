"""The SIL's lockstep asks whether the daemon sleeps in its event loop
(`hil_sim.boards.host._asleep`): a thread waiting for the GIL sleeps too (state S, in
futex) and is mid-pass, which the wait channel tells where the kernel shows it and the
syscall where it hides it."""

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from hil_sim.boards.host import _IDLE_SYSCALLS, ProcFile, _asleep


class _Fixed:
    def __init__(self, data):
        self.data = data

    def read(self):
        return self.data


def _stat(state: str) -> bytes:
    return f"123 (python3 (x)) {state} 1 2 3".encode()


@pytest.mark.skipif(not _IDLE_SYSCALLS, reason="no syscall table for this machine")
def test_the_syscall_decides_where_the_wait_channel_is_hidden():
    idle = next(iter(_IDLE_SYSCALLS))
    hidden = _Fixed(b"0")
    assert _asleep(_stat("S"), hidden, _Fixed(f"{idle} 0x3 0x0".encode()))
    busy = {"aarch64": 98}.get(os.uname().machine, 202)  # futex (202 on x86_64)
    assert not _asleep(_stat("S"), hidden, _Fixed(f"{busy} 0x7f 0x80".encode()))  # the GIL
    assert not _asleep(_stat("S"), hidden, _Fixed(b"running"))
    assert _asleep(_stat("S"), hidden, _Fixed(None))  # unreadable: any sleep counts
    assert _asleep(_stat("S"), hidden, None)
    # a visible wait channel decides by itself
    assert _asleep(_stat("S"), _Fixed(b"ep_poll"), _Fixed(b"202 0x0"))
    assert not _asleep(_stat("S"), _Fixed(b"futex_wait_queue"), _Fixed(f"{idle}".encode()))
    assert not _asleep(_stat("R"), hidden, _Fixed(f"{idle}".encode()))
    assert _asleep(_stat("Z"), hidden, None) and _asleep(None, hidden, None)


_GIL = """
import threading, time
def spin():
    x = 0
    while True:
        x += 1
threading.Thread(target=spin, daemon=True).start()
print("ready", flush=True)
t0 = time.monotonic()
while time.monotonic() - t0 < 5:
    pass
"""
_LOOP = """
import os, selectors
r, w = os.pipe()
s = selectors.DefaultSelector()
s.register(r, selectors.EVENT_READ)
print("ready", flush=True)
s.select(5)
"""


@pytest.mark.skipif(not _IDLE_SYSCALLS or not Path("/proc/self/syscall").exists(),
                    reason="no /proc/PID/syscall or no syscall table here")
def test_a_real_process_waiting_for_the_gil_is_busy_one_in_its_selector_asleep():
    def sample(code):
        p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
        try:
            assert p.stdout.readline().strip() == "ready"  # past its imports, in its loop
            time.sleep(0.2)
            files = [ProcFile(f"/proc/{p.pid}/{n}") for n in ("stat", "wchan", "syscall")]
            if files[2].read() is None:
                pytest.skip("/proc/PID/syscall is not readable here")
            seen = [_asleep(files[0].read(), files[1], files[2]) for _ in range(300)]
            for f in files:
                f.close()
            return seen
        finally:
            p.kill()
            p.wait()

    assert not any(sample(_GIL))
    assert all(sample(_LOOP))


class _Daemon:
    """What the lockstep reads of the daemon: its rchar (port bytes it has read plus
    `other`, bytes read from elsewhere)."""

    killed = False

    def __init__(self):
        self.port_bytes = 0
        self.other = 0

    def read_chars(self):
        return self.port_bytes + self.other

    def wait_read(self, target, queues_empty, settle_s):
        assert self.read_chars() >= target  # the daemon below reads each step at once
        return 0

    def wait_idle(self):
        pass


class _Pty:
    plugged, replugs = True, 0

    def __init__(self):
        self.bytes_written = 0
        self.queued = 0

    def unread(self):
        return self.queued


def _lockstep(daemon, pty):
    from hil_sim.boards.sil import SilRun

    run = SilRun.__new__(SilRun)  # only what _wait_host_idle reads
    run.daemon, run.ptys, run.timing = daemon, {"base": pty}, {}
    run._rchar0 = daemon.read_chars()
    run._ports_seen = ((True, 0),)
    run.other_reads = {"bytes": 0, "times": 0}
    return run


def test_a_read_from_elsewhere_is_taken_out_of_the_lockstep_byte_count():
    # a daemon that imports a module in mid-pass reads more than the ports gave it: without
    # a re-base the byte count is met early at every later step (the lockstep then rests
    # on the idle check alone); with it the count stays exact and the read is counted
    daemon, pty = _Daemon(), _Pty()
    daemon.other = 5000  # its start-up reads, before the flight
    run = _lockstep(daemon, pty)
    for step in range(6):
        pty.bytes_written += 100
        daemon.port_bytes += 100
        if step == 2:
            daemon.other += 413_688  # np.median's lazy `import numpy.ma`
        run._wait_host_idle()
        assert run._rchar0 + pty.bytes_written == daemon.read_chars(), step
    assert run.other_reads == {"bytes": 413_688, "times": 1}
    # bytes still queued for the daemon when it is noticed are not counted as read
    daemon2, pty2 = _Daemon(), _Pty()
    run2 = _lockstep(daemon2, pty2)
    pty2.bytes_written += 300
    daemon2.port_bytes += 200
    pty2.queued = 100
    daemon2.other += 1000
    run2._wait_host_idle()
    assert run2.other_reads == {"bytes": 1000, "times": 1}
    assert run2._rchar0 + pty2.bytes_written - daemon2.read_chars() == 100  # still to read
