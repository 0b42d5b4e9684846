#!/usr/bin/env python3
"""springpend tests (issue 28): the sixteenth attacker's pass
(doc/notes/2026-11-27/attack16.md), the lead's findings:
- #4: still -o /dev/stdout --state - (and the other spellings of stdout
  against each other) wrote the PNG and the JSON into one stdout: refused;
- #5: a [timeline] refused for the frame times its pauses make was told to
  raise its slowest speed: it is told to shorten the pauses, at the longest;
- #8: side by side, --at 10.000001 was refused as "--at 10 ... up to 10":
  the times are printed whole.
usage: test_attack16_lead.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import re
import subprocess

import sptest
from sptest import done, err, ok

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack16-lead")
default = os.path.join(scenes, "default.ini")
stiff = os.path.join(scenes, "stiff.ini")
lesson = os.path.join(scenes, "lesson-exchange.ini")

# ---- 4: two outputs on one stdout ------------------------------------------------------------
for o_, st in (("/dev/stdout", "-"), ("-", "/dev/stdout"), ("/dev/fd/1", "-"), ("-", "/proc/self/fd/1")):
    with open(path("stdout.bin"), "wb") as f:
        r = subprocess.run([exe, "still", default, "--at", "1", "--size", "320x180", "-o", o_, "--state", st,
                            "-q"], stdout=f, stderr=subprocess.PIPE, text=True, cwd=work)
    ok(r.returncode == 2 and "would overwrite the scene or the image" in r.stderr
       and os.path.getsize(path("stdout.bin")) == 0,
       f"4: still -o {o_} --state {st}: refused, nothing on stdout (exit {r.returncode}: {r.stderr[:120]})")
with open(path("stdout.bin"), "wb") as f:
    r = subprocess.run([exe, "still", default, "--at", "1", "--size", "320x180", "-o", "-", "--state",
                        "s.json", "-q"], stdout=f, stderr=subprocess.PIPE, text=True, cwd=work)
ok(r.returncode == 0 and open(path("stdout.bin"), "rb").read(8) == b"\x89PNG\r\n\x1a\n"
   and os.path.exists(path("s.json")),
   f"4: still -o - --state s.json: the PNG on stdout, the state in its file (exit {r.returncode})")

# ---- 5: a video of pauses is told to shorten them --------------------------------------------
head = re.split(r"^\[timeline\]", open(lesson).read(), flags=re.M)[0]
first = head.count("\n") + 2
with open(path("pauses.ini"), "w") as f:
    f.write(head + "[timeline]\n" + "".join(f"{0.05 * i:.2f} = pause 3600\n" for i in range(1, 701)))
r = run("info", path("pauses.ini"), "--set", "video.fps=1000")
said = err(r)
ok(r.returncode == 2 and f"pauses.ini:{first}:" in said and "the pauses hold 2.52e+06 s of it; shorten them" in said
   and "raise it" not in said,
   f"5: 700 pauses of an hour at 1000 fps: refused, told to shorten the pauses (exit {r.returncode}: "
   f"{said[:220]})")

# ---- 8: the refused --at is printed as given --------------------------------------------------
r = run("still", default, stiff, "--at", "10.000001", "--size", "320x180", "-o", "two.png")
ok(r.returncode == 2 and "--at 10.000001:" in err(r) and "up to 10," in err(r)
   and not os.path.exists(path("two.png")),
   f"8: side by side --at 10.000001 (both 10 s long): refused, naming 10.000001 (exit "
   f"{r.returncode}: {err(r)[:160]})")

done()
