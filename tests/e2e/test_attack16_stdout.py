#!/usr/bin/env python3
"""springpend tests (issue 28): the sixteenth attacker's pass
(doc/notes/2026-11-27/attack16.md), finding 1: a standard output that is a
socket (systemd's StandardOutput=socket, inetd, socat) or a terminal (a
hung terminal emulator, `script` that stopped reading) whose reader does not
read kept `still -o -`, `data -o -` and raw frames deaf to the first signal:
the blocking write sat on a thread the signal does not interrupt. A socket
is now written with send(MSG_DONTWAIT), a terminal through a non-blocking
description of its own, each waited on with poll() and the stop flag, as a
pipe is (attack15 #1). One SIGTERM ends each within a few seconds, exit 143,
the signal named; a reader that does read gets every byte.
usage: test_attack16_stdout.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import fcntl
import os
import pty
import signal
import socket
import subprocess
import termios
import threading
import time
import tty

import sptest
from sptest import done, ok

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack16-stdout")
default = os.path.join(scenes, "default.ini")
chaotic = os.path.join(scenes, "chaotic.ini")


def queued(fd):
    """Bytes waiting to be read at fd (the reader's end)."""
    return int.from_bytes(fcntl.ioctl(fd, termios.FIONREAD, b"\0\0\0\0"), "little")


def stop_stalled(args, write_fd, read_fd):
    """Runs springpend args with stdout write_fd until what waits at read_fd
    (never read) stops growing for a second, sends one SIGTERM and waits at
    most 6 s: (exit status or a sentence, stderr)."""
    p = subprocess.Popen([exe, *args], cwd=work, stdout=write_fd, stderr=subprocess.PIPE)
    deadline, last, since = time.time() + 90, -1, time.time()
    while time.time() < deadline and p.poll() is None and (last <= 0 or time.time() - since < 1):
        if queued(read_fd) != last:
            last, since = queued(read_fd), time.time()
        time.sleep(0.05)
    time.sleep(0.3)  # the writer is in its wait
    p.send_signal(signal.SIGTERM)
    try:
        rc = p.wait(timeout=6)
    except subprocess.TimeoutExpired:
        p.kill()
        rc = f"still running 6 s after one SIGTERM (killed: {p.wait()})"
    return rc, p.stderr.read().decode(errors="replace").strip()


def socket_pair():
    a, b = socket.socketpair()
    for s in (a, b):
        s.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 4096)
        s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    return a, b


def terminal():
    """(the terminal springpend writes to, the master its reader reads)"""
    m, s = pty.openpty()
    tty.setraw(s)  # bytes as written (no \n -> \r\n), as a binary reader of a pty sets it
    return s, m


cases = [
    ("still -o - (a 1920x1080 PNG)", ["still", chaotic, "--at", "200", "--size", "1920x1080", "-o", "-", "-q"]),
    ("data -o - (300 s of CSV)", ["data", chaotic, "--set", "video.duration=300", "-o", "-", "-q"]),
    ("raw frames -o -", ["render", default, "--set", "video.duration=2", "--size", "640x360",
                         "--format", "raw", "-o", "-", "-q"]),
]
for kind, make in (("a socket", socket_pair), ("a terminal", terminal)):
    # a terminal's buffer holds a whole PNG still: its case is the other two
    for what, args in cases[kind == "a terminal":]:
        w, r = make()
        wfd = w.fileno() if hasattr(w, "fileno") else w
        rfd = r.fileno() if hasattr(r, "fileno") else r
        rc, msg = stop_stalled(args, wfd, rfd)
        for end in (w, r):
            end.close() if hasattr(end, "close") else os.close(end)
        ok(rc == 143 and "SIGTERM" in msg,
           f"1: {what} to {kind} whose reader never reads: one SIGTERM ends it, exit 143 "
           f"({rc}: {msg[-160:]})")


def read_all(fd, into, size):
    """Reads fd into `into` until size bytes, the end, or 60 s without data."""
    import select
    while sum(map(len, into)) < size:
        if not select.select([fd], [], [], 60)[0]:
            return
        try:
            chunk = os.read(fd, 65536)
        except OSError:  # a pty's master reads EIO once the last writer closed
            return
        if not chunk:
            return
        into.append(chunk)


def terminal_master():
    """(a pseudo-terminal's master, its terminal): the master is not opened
    again by name, which would make a new pseudo-terminal"""
    s, m = terminal()
    return m, s


# a reader that reads (slowly at first) gets every byte, as a file does
ref = path("ref.csv")
r0 = run("data", default, "--set", "video.duration=30", "-o", ref, "-q")
want = open(ref, "rb").read() if r0.returncode == 0 else None
for kind, make in (("a socket", socket_pair), ("a terminal", terminal),
                   ("a pseudo-terminal's master", terminal_master)):
    w, r = make()
    wfd = w.fileno() if hasattr(w, "fileno") else w
    rfd = r.fileno() if hasattr(r, "fileno") else r
    got = []
    t0 = time.time()
    p = subprocess.Popen([exe, "data", default, "--set", "video.duration=30", "-o", "-", "-q"], cwd=work,
                         stdout=wfd, stderr=subprocess.PIPE)
    # The test keeps its own copy of the written end open until the reader
    # has read: a pseudo-terminal whose last master closes is hung up, and
    # the kernel drops what its terminal side had not yet handed to the
    # reader (a loss of the test's making, seen once in 20 runs).
    time.sleep(0.5)  # the buffer fills and the writer waits on it
    reader = threading.Thread(target=read_all, args=(rfd, got, len(want or b"")))
    reader.start()
    rc = p.wait(timeout=120)
    reader.join(timeout=90)
    w.close() if hasattr(w, "close") else os.close(w)
    r.close() if hasattr(r, "close") else os.close(r)
    data = b"".join(got)
    print(f"# {kind}: read in {time.time() - t0:.1f} s")
    ok(rc == 0 and want is not None and data == want,
       f"1: data -o - to {kind} that is read: exit 0, the {len(want or b'')} bytes a file gets "
       f"(exit {rc}, {len(data)} bytes read)")

done()
