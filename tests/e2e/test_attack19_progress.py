#!/usr/bin/env python3
"""springpend tests (issue 28): the nineteenth attacker's pass
(doc/notes/2026-11-28/attack19.md), finding 8: under the estimate's 3e8-step
note nothing was said, yet a still's camera pre-pass runs at under 1e6 steps
a second here, so a still ran 10 minutes with no line where stderr was not a
terminal (a CI log, a pipe). The integration's progress now goes to such a
stderr too: a line of its own after 10 s, then once a minute; -q says
nothing.

What is checked, reading stderr through a pipe as a CI log does:
- a still of about 1e7 steps (under the note) says "camera pre-pass: t = …
  of … s (…%), ETA … s" within 20 s, then stops on SIGTERM, exit 143;
- the same with -q says nothing in 15 s;
- data to a file says "data: t = …" the same way;
- attack20 #2: with stderr closed (2>&-) the progress never lands in the
  CSV (springpend fills a closed fd 0-2 so no output file takes it), and
  with `-o - 2>&1` the CSV stream holds no progress line.
usage: test_attack19_progress.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import re
import signal
import subprocess
import threading
import time

import sptest
from sptest import done, ok

exe, src, work, _ = sptest.setup("attack19-progress", [])
driven = os.path.abspath(os.path.join(src, "..", "scenes", "driven.ini"))
SLOW = ["--set", "integrator.dt=1e-7"]  # 4e8 steps of pre-pass: minutes here (killed after its line)


def first_line(args, pattern, limit):
    """Starts springpend with stderr on a pipe; the first stderr line matching
    pattern within `limit` s (or ""), then SIGTERM; (line, exit status)."""
    p = subprocess.Popen([exe, *args], cwd=work, stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE, text=True)
    lines = []
    reader = threading.Thread(target=lambda: lines.extend(p.stderr), daemon=True)
    reader.start()
    t0, found = time.time(), ""
    while time.time() - t0 < limit and not found and p.poll() is None:
        found = next((l for l in list(lines) if re.search(pattern, l)), "")
        time.sleep(0.2)
    took = time.time() - t0
    if p.poll() is None:
        p.send_signal(signal.SIGTERM)
    try:
        p.wait(timeout=30)
    except subprocess.TimeoutExpired:
        p.kill()
        p.wait()
    reader.join(timeout=5)
    sptest.diag(f"after {took:.1f} s: {found.strip() or '(nothing)'}; exit {p.returncode}; "
                f"stderr {''.join(lines).strip()[-200:]!r}")
    return found, p.returncode


line, code = first_line(["still", driven, "--at", "1", "--size", "160x90", *SLOW, "-o", "s.png"],
                        r"camera pre-pass: t = [0-9.e+]+ of [0-9.e+]+ s \([0-9.]+%\), ETA [0-9]+ s", 20)
ok(line != "", "a still's pre-pass says its progress on a pipe within 20 s")
ok(code == 143 and not os.path.exists(os.path.join(work, "s.png")),
   "then SIGTERM stops it, exit 143, nothing written")

line, code = first_line(["still", driven, "--at", "1", "--size", "160x90", *SLOW, "-q", "-o",
                         "q.png"], r".", 15)
ok(line == "" and code == 143, "with -q nothing is said in 15 s")

line, code = first_line(["data", driven, "--set", "video.duration=200", *SLOW, "--set",
                         "integrator.method=rk4", "--every", "1",
                         "-o", "d.csv"], r"data: t = [0-9.e+]+ of [0-9.e+]+ s .*ETA", 20)
ok(line != "" and code == 143 and not os.path.exists(os.path.join(work, "d.csv")),
   "data to a file says its progress on a pipe within 20 s, and stops on SIGTERM")

# attack20 #2: a closed stderr, and stdout and stderr one pipe (about 20 s each
# here; a progress line is due at 10 s)
LONG = ["data", driven, "--set", "integrator.method=rk4", "--set", "integrator.dt=2e-7", "--set",
        "video.duration=24"]
r = subprocess.run([exe, *LONG, "--every", "0.01", "-o", "closed.csv"], cwd=work,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=600,
                   preexec_fn=lambda: os.close(2))
csv = open(os.path.join(work, "closed.csv"), errors="replace").read() if r.returncode == 0 else ""
sptest.diag(f"2>&-: exit {r.returncode}, {len(csv)} bytes of CSV")
ok(r.returncode == 0 and csv.count("\n") > 2000 and "springpend" not in csv,
   "data with stderr closed: the CSV holds rows only (no message took the closed fd 2)")
r = subprocess.run([exe, *LONG, "--every", "0.001", "-o", "-"], cwd=work, stdout=subprocess.PIPE,
                   stderr=subprocess.STDOUT, timeout=600)
text = r.stdout.decode(errors="replace")
sptest.diag(f"-o - 2>&1: exit {r.returncode}, {len(text)} bytes")
ok(r.returncode == 0 and text.count("\n") > 20000 and "springpend" not in text,
   "data -o - with stderr on the same pipe: no progress line inside the CSV stream")
done()
