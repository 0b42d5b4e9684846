#!/usr/bin/env python3
"""springpend tests: a camera distance that puts the eye inside or too near
the motion (attacker's pass 3, finding 10; issue 26) is refused with where it
was set (FILE:LINE, or --set view.camera), exit 2 and no output, and the
least distance it suggests is the least: that distance renders, 0.99 times
it is refused (and suggests the same), for three cameras. (Before, each
suggestion was itself refused: 0.366, 0.439, 0.453 and only then 0.456 m.)
usage: test_camera_least.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import re
import shutil
import sys

from sptest import done, ok, runner

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "camera_least"))
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
run = runner(exe, work)
SCENE = os.path.join(src, "..", "scenes", "swinging-spring.ini")


def still(out, *sets):
    args = [a for s in sets for a in ("--set", s)]
    return run("still", SCENE, "--at", "50", "--size", "640x360", "-q", "-o", out, *args)


def least_of(stderr):
    m = re.search(r"here at least ([0-9.e+-]+) m", stderr)
    return float(m.group(1)) if m else None


# ---- set in the scene file: FILE:LINE --------------------------------------
path = os.path.join(work, "near.ini")
with open(SCENE) as fp:
    body = fp.read()
lines = [ln for ln in body.rstrip("\n").split("\n") if not ln.replace(" ", "").startswith("camera=")]
lines += ["[view]", "camera = 35 25 0.01"] if "[view]" not in body else []
if "[view]" in body:
    lines.insert(lines.index("[view]") + 1, "camera = 35 25 0.01")
with open(path, "w") as fp:
    fp.write("\n".join(lines) + "\n")
line = lines.index("camera = 35 25 0.01") + 1
out = os.path.join(work, "near.png")
r = run("still", path, "--at", "50", "--size", "640x360", "-q", "-o", out)
ok(r.returncode == 2 and r.stderr.startswith(f"springpend: {path}:{line}: view.camera") and
   not os.path.exists(out),
   f"an eye inside the motion, set in the file: exit {r.returncode}, FILE:LINE first, no output "
   f"('{r.stderr.strip()[:120]}')")

# ---- set by --set: named so, and the suggestion is the least ----------------
for azel in ("35 25", "-60 12", "140 50"):
    out = os.path.join(work, "c.png")
    r = still(out, f"view.camera={azel} 1e-300")
    least = least_of(r.stderr)
    ok(r.returncode == 2 and "--set view.camera: from" in r.stderr and "view.camera: view.camera" not in r.stderr and least and
       not os.path.exists(out),
       f"camera {azel} 1e-300: refused, named as --set view.camera, suggests {least} m")
    if not least:
        continue
    r1 = still(out, f"view.camera={azel} {least!r}")
    ok(r1.returncode == 0 and os.path.exists(out),
       f"camera {azel} {least}: the suggested distance renders ({r1.stderr.strip()[:100]})")
    if os.path.exists(out):
        os.remove(out)
    r2 = still(out, f"view.camera={azel} {0.99 * least!r}")
    ok(r2.returncode == 2 and not os.path.exists(out) and least_of(r2.stderr) == least,
       f"camera {azel} {0.99 * least:.6g} (0.99 times it): refused, suggesting the same "
       f"{least_of(r2.stderr)} m")
done()
