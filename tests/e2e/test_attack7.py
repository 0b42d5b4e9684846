#!/usr/bin/env python3
"""springpend tests (issue 28): fixes for the attacker's seventh pass
(doc/notes/2026-11-27/attack7.md), each check run as the attacker ran it:
- finding 3: a shard's recorded command (prov:wasGeneratedBy) with spaces
  in a row made sp_command_line_recorded split it into more words than it
  had room for: a heap overflow (40 spaces corrupt the heap, 200 000 crash
  sweep --merge with SIGSEGV). A line springpend never writes is now no
  command at all, and the merge goes on without recording one;
- finding 6: a signal while a CSV and its metadata waited (up to 5 s) for
  their folder's lock was ignored: both were put in place, exit 0. Now
  neither is, and the run exits 128 + signal.
usage: test_attack7.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import fcntl
import json
import os
import signal
import subprocess
import time

import sptest
from sptest import done, err, ok

exe, src, work, _ = sptest.setup("attack7", [])
run = sptest.runner_bytes(exe, work)
chaotic = os.path.join(src, "..", "scenes", "chaotic.ini")


def path(*names):
    return os.path.join(work, *names)


# ---- finding 3: a forged command with spaces in a row --------------------------
grid = ["--vary", "initial.angle=1:179:4", "--measure", "lyapunov", "--time", "2", "-q"]
for i in (1, 2):
    r = run("sweep", chaotic, *grid, "--shard", f"{i}/2", "--csv", f"s{i}.csv")
    assert r.returncode == 0, err(r)
for spaces in (2, 40, 200000):
    for i in (1, 2):
        meta = path(f"s{i}.csv-metadata.json")
        with open(meta) as f:
            m = json.load(f)
        m["prov:wasGeneratedBy"] = "springpend" + " " * spaces + "x"
        with open(meta, "w") as f:
            json.dump(m, f)
    out = f"m{spaces}.png"
    r = run("sweep", "--merge", "s1.csv", "s2.csv", "-o", out)
    cmd = run("scene", out, "--command") if r.returncode == 0 else None
    ok(r.returncode == 0 and os.path.exists(path(out)) and cmd.returncode == 2 and
       b"carries no command" in cmd.stderr,
       f"sweep --merge of shards whose command is 'springpend' + {spaces} spaces + 'x': "
       f"merged, and the figure records no command (a line springpend never writes) "
       f"(exit {r.returncode}: {err(r)[-120:]!r})")

# ---- finding 6: a signal while the pair waits for its folder's lock -------------
default = os.path.join(src, "..", "scenes", "default.ini")
locked = path("locked")
os.makedirs(locked, exist_ok=True)
holder = os.open(locked, os.O_RDONLY)
fcntl.flock(holder, fcntl.LOCK_EX)  # another process keeps the folder locked
cases = [(["data", default, "--set", "video.duration=1", "-o", os.path.join(locked, "d.csv")],
          signal.SIGTERM),
         (["sweep", chaotic, *grid, "--csv", os.path.join(locked, "s.csv"), "-o",
           os.path.join(locked, "s.png")], signal.SIGINT)]
for args, sig in cases:
    p = subprocess.Popen([exe, *args], cwd=work, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    sptest.wait_caught(p, sig)
    time.sleep(1.5)  # the rows are written; the pair polls the lock (for up to 5 s)
    p.send_signal(sig)
    out, errs = p.communicate(timeout=60)
    left = os.listdir(locked)
    ok(p.returncode == 128 + sig and not left,
       f"{args[0]}: {signal.Signals(sig).name} while its CSV waits for the folder's lock: "
       f"exit {p.returncode} (128 + {int(sig)}), nothing left ({left}) {errs.decode()[-120:]!r}")
os.close(holder)

done()
