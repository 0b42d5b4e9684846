#!/usr/bin/env python3
"""springpend tests (issue 28): the fifteenth attacker's pass
(doc/notes/2026-11-27/attack15.md), findings 1 and 7:
- #1: a FIFO whose reader opens it and never reads kept a render deaf to
  the first SIGTERM (a PNG sequence's frame, raw frames: the write blocked
  on a writer thread), and a still or CSV said "cannot write: Interrupted
  system call". Written through non-blocking, waited on with poll() and the
  stop flag: one SIGTERM ends each within a few seconds, exit 143, the
  signal named, no .part and no frame of the sequence left; the same for a
  pipe at stdout that nobody reads;
- #7: a baselines' compare.ini that picks `metric = rms` (tol 255) or
  `metric = pixelmatch` (threshold 1) loosened the command line's
  `--max-diff 0 --max-pixels 0`: an image passed with "(0 allowed)" beside
  its ok. A command-line limit the metric in force does not read is now
  checked by its own rule too; the line names it and whether it decided.
usage: test_attack15_fifo_rule.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import fcntl
import os
import signal
import subprocess
import termios
import time

import sptest
from sptest import done, err, ok

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack15-fifo-rule")
default = os.path.join(scenes, "default.ini")
stiff = os.path.join(scenes, "stiff.ini")
F_GETPIPE_SZ = 1032


def queued(fd):
    """Bytes waiting in the pipe whose read end is fd."""
    return int.from_bytes(fcntl.ioctl(fd, termios.FIONREAD, b"\0\0\0\0"), "little")


def stop_stalled(args, read_fd, stdout=subprocess.DEVNULL):
    """Runs springpend args until the pipe read_fd reads from is full (its
    reader never reads), sends one SIGTERM and waits at most 6 s: (exit
    status or a sentence, stderr, seconds from the signal to the end)."""
    p = subprocess.Popen([exe, *args], cwd=work, stdout=stdout, stderr=subprocess.PIPE)
    size = fcntl.fcntl(read_fd, F_GETPIPE_SZ)
    deadline, last, since = time.time() + 60, -1, time.time()
    # full, or (small writes leave part of a pipe's pages unused) no longer filling
    while time.time() < deadline and p.poll() is None and queued(read_fd) < size and \
            (last <= 0 or time.time() - since < 1):
        if queued(read_fd) != last:
            last, since = queued(read_fd), time.time()
        time.sleep(0.05)
    time.sleep(0.3)  # the writer is in its wait
    t0 = time.time()
    p.send_signal(signal.SIGTERM)
    try:
        rc = p.wait(timeout=6)
    except subprocess.TimeoutExpired:
        p.kill()
        rc = f"still running 6 s after one SIGTERM (killed: {p.wait()})"
    return rc, p.stderr.read().decode(errors="replace").strip(), time.time() - t0


# 1: a FIFO whose reader opened it and never reads: one SIGTERM stops each kind
big = ["--size", "1920x1080"]
cases = [
    ("a PNG sequence's frame", "seq", "00002.png",
     ["render", default, "--set", "video.duration=0.2", "--fps", "30", *big, "-q"], "%05d.png"),
    ("a single PNG", "still", "s.png", ["still", default, "--at", "1", *big, "-q"], None),
    ("raw frames", "raw", "r.raw",
     ["render", default, "--set", "video.duration=2", "--size", "320x180", "--format", "raw",
      "-q"], None),
    ("a CSV", "csv", "d.csv", ["data", default, "--set", "video.duration=200", "-q"], None),
    ("an SVG", "svg", "f.svg", ["still", default, "--at", "1", *big, "-q"], None),
]
for what, folder, fifo, args, pattern in cases:
    d = path(folder)
    os.makedirs(d, exist_ok=True)
    os.mkfifo(os.path.join(d, fifo))
    rfd = os.open(os.path.join(d, fifo), os.O_RDONLY | os.O_NONBLOCK)  # opened, never read
    try:
        rc, msg, took = stop_stalled([*args, "-o", os.path.join(d, pattern or fifo)], rfd)
    finally:
        os.close(rfd)
    left = sorted(os.listdir(d))
    ok(rc == 143 and "interrupted by SIGTERM" in msg and "Interrupted system call" not in msg
       and left == [fifo] and took < 4,
       f"1: {what} through a FIFO whose reader does not read stops on one SIGTERM: exit {rc} "
       f"in {took:.1f} s, the signal named, nothing left but the FIFO ({left}; {msg[-160:]})")

# a pipe at stdout that nobody reads: its own non-blocking description
r_fd, w_fd = os.pipe()
try:
    rc, msg, took = stop_stalled(["render", default, "--set", "video.duration=2", "--size",
                                  "320x180", "--format", "raw", "-q", "-o", "-"], r_fd,
                                 stdout=w_fd)
    blocking = not fcntl.fcntl(w_fd, fcntl.F_GETFL) & os.O_NONBLOCK
finally:
    os.close(r_fd)
    os.close(w_fd)
ok(rc == 143 and "interrupted by SIGTERM" in msg and took < 4 and blocking,
   f"1: raw frames to a stdout pipe nobody reads stop on one SIGTERM: exit {rc} in {took:.1f} s, "
   f"the shared pipe left blocking: {blocking} ({msg[-160:]})")

# 7: a command-line limit binds whatever metric compare.ini picks
e, a = path("e"), path("a")
os.makedirs(e)
os.makedirs(a)
for name, scene in [("x.png", default), ("y.png", default)]:
    r1 = run("still", scene, "--at", "1", "--size", "320x180", "-o", os.path.join(e, name), "-q")
    r2 = run("still", stiff, "--at", "1", "--size", "320x180", "-o", os.path.join(a, name), "-q")
    assert r1.returncode == 0 and r2.returncode == 0, (err(r1), err(r2))


def line_of(ini, *opts, name="x.png"):
    """compare.ini's text, the run's options: (exit status, name's line)."""
    with open(os.path.join(e, "compare.ini"), "w") as f:
        f.write(ini)
    r = run("compare", e, a, *opts)
    out = r.stdout.decode(errors="replace").splitlines()
    return r.returncode, next((s for s in out if f" {name}:" in s), f"(no line: {err(r)[:200]})")


ONLY_Y = "[x.png]\nmax_diff = 255\nmax_pixels = 100%\n[y.png]\n"
LOOSE = "[*]\nmax_diff = 255\nmax_pixels = 100%\n"
for ini, opts, rule in [
        ("[*]\nmetric = rms\ntol = 255\n", ["--max-diff", "0", "--max-pixels", "0"], "reftest"),
        ("[*]\nmetric = pixelmatch\nthreshold = 1\n", ["--max-diff", "0", "--max-pixels", "0"],
         "reftest"),
        ("[*]\nmetric = rms\n", ["--tol", "20", "--max-pixels", "0"], "reftest"),
        ("[*]\nmetric = rms\ntol = 255\n", ["--max-pixels", "0"], "reftest"),
        ("[*]\nmetric = pixelmatch\nthreshold = 1\n", ["--max-diff", "0"], "reftest"),
        # the symmetrical ones: compare.ini's reftest is loose, the command line's rms or
        # pixelmatch limit (read by another image's metric) binds x.png too
        (ONLY_Y + "metric = rms\n", ["--tol", "1"], "rms"),
        (ONLY_Y + "metric = pixelmatch\n", ["--threshold", "0.05", "--max-pixels", "0"],
         "pixelmatch")]:
    rc, line = line_of(ini, *opts)
    ok(rc == 1 and line.startswith("FAIL") and f"the command line's {rule} rule" in line
       and "which decided: fail" in line,
       f"7: compare.ini {ini!r} does not loosen {' '.join(opts)}: x.png fails, its line names "
       f"the command line's {rule} rule (exit {rc}: {line[:90]} … {line[-110:]})")

# where the command line's limits are the looser, compare.ini's rule decides as before
rc, line = line_of("[*]\nmetric = rms\ntol = 255\n", "--max-diff", "255", "--max-pixels", "100%")
ok(rc == 0 and line.startswith("ok") and "reftest rule" in line and "passed" in line,
   f"7: a looser command line passes under compare.ini's rms (exit {rc}: {line[-120:]})")
rc, line = line_of(LOOSE, "--metric", "rms", "--tol", "0")
ok(rc == 1 and line.startswith("FAIL") and "> tol 0" in line,
   f"7: --metric rms --tol 0 is the metric over a loose compare.ini (exit {rc}: {line[-80:]})")
done()
