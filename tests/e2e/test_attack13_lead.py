#!/usr/bin/env python3
"""springpend tests (issue 28): the thirteenth attacker's pass
(doc/notes/2026-11-27/attack13.md), the lead's findings:
- #5: data and still took --set keys they never read (data's view.title,
  video.crf; a still's video.crf and preset) and wrote the same bytes:
  refused, exit 2, nothing written; a key they read is still taken;
- #6: the bash completion split file names at blanks and globbed them, and
  offered sweep (and data) --set keys they refuse;
- #7: with an [ensemble], view.vectors, strobe, trail and colorbar (the one
  bob's) were taken and not drawn: refused where given with the ensemble or
  after it; an ensemble added by --set to a scene with its own trail is
  still drawn;
- #8: still --scale N (supersampling) was taken for an SVG or PDF: refused;
- #11: a whole PNG-sequence render over an earlier, longer one left the old
  run's frames after its own: removed and said; a part (--frames) keeps
  them; what is not a regular file is left and named;
- #14: a FIFO at a sequence frame's name made the writer thread wait in a
  blocking open() that no signal interrupts: one SIGTERM now stops it (exit
  143, said, the frames written removed);
- #15: still --size 8cm --size 640x360 drew the 8 cm figure: the later
  --size wins, whatever its form;
- #21: two `still -o s.png --state s.json` at once left one run's PNG
  beside the other's state: the two are put in place together under their
  folder's lock, as a CSV and its metadata are (60 pairs, none mixed);
- #25: `springpend version --verbose` was in no --help, man page or
  completion: the command list names it, `version --help` answers, and the
  completion and man page (made from --help) follow.
usage: test_attack13_lead.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import re
import signal
import time
import shlex
import struct
import json
import subprocess

import sptest
from sptest import done, err, ok, skip

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack13-lead")
default = os.path.join(scenes, "default.ini")
stiff = os.path.join(scenes, "stiff.ini")
short = ["--set", "video.duration=0.2"]

# 5: data and still refuse --set keys they do not read
for args, key in [(["data", default, *short, "--set", "view.title=x"], "view.title"),
                  (["data", default, *short, "--set", "video.crf=20"], "video.crf"),
                  (["data", default, *short, "--set", "video.width=640"], "video.width"),
                  (["still", default, "--at", "0.1", "--set", "video.crf=20"], "video.crf"),
                  (["still", default, "--at", "0.1", "--set", "video.preset=slow"], "video.preset")]:
    out = path(f"unread-{args[0]}-{key}.{'csv' if args[0] == 'data' else 'png'}")
    r = run(*args, "-o", out)
    ok(r.returncode == 2 and f"does not read {key}" in err(r) and not os.path.exists(out),
       f"5: {args[0]} --set {key}= (not read) refused, exit 2, nothing written "
       f"(exit {r.returncode}: {err(r)[:160]})")
# the keys they read still change what they write
a, b = path("mass1.csv"), path("mass2.csv")
r1 = run("data", default, *short, "-o", a, "-q")
r2 = run("data", default, *short, "--set", "pendulum.mass=2", "--set", "video.fps=10",
         "--quality", "low", "-o", b, "-q")
ok(r1.returncode == 0 and r2.returncode == 0 and open(a).read() != open(b).read(),
   f"5: data takes pendulum.mass, video.fps and --quality, and its rows change "
   f"(exit {r1.returncode}, {r2.returncode}: {err(r2)[:120]})")
r = run("still", default, "--at", "0.1", "--size", "320x180", "--set", "video.png_level=9",
        "-o", path("level9.png"), "-q")
ok(r.returncode == 0, f"5: still takes video.png_level (exit {r.returncode}: {err(r)[:120]})")

# 6: the completion: names with blanks and glob characters, keys per command
completion = os.path.join(os.path.dirname(exe), "doc", "springpend")
if not os.path.exists(completion):
    skip("6: the bash completion", "not built here")
else:
    names = ["my scene.ini", "[ab].ini", "a.ini", "other.ini"]
    folder = path("completion")
    os.makedirs(folder, exist_ok=True)
    for n in names:
        open(os.path.join(folder, n), "w").close()

    def complete(*words):
        script = (f"source {shlex.quote(completion)}\n"
                  f"COMP_WORDS=({' '.join(shlex.quote(w) for w in words)}); "
                  f"COMP_CWORD={len(words) - 1}; _springpend; printf '%s\\n' \"${{COMPREPLY[@]}}\"")
        r = subprocess.run(["bash", "-c", script], cwd=folder, capture_output=True, text=True)
        return [w for w in r.stdout.split("\n") if w]
    got = complete("springpend", "still", "my")
    ok(got == ["my scene.ini"], f"6: 'still my<TAB>' offers the one name with a blank ({got})")
    got = complete("springpend", "still", "[")
    ok(got == ["[ab].ini"], f"6: 'still [<TAB>' offers the name [ab].ini, not the file its glob "
       f"matches ({got})")
    # what sweep and data refuse (doc/sweeps.md: sweep reads the physics and its
    # figure's look; data the physics, the ensemble and the frame times)
    for command, refused in [("sweep", ("video.", "view.panels=", "view.trail=", "ensemble.")),
                             ("data", ("view.", "video.crf=", "video.width=", "video.png_level="))]:
        keys = complete("springpend", command, "x.ini", "--set", "")
        bad = [k for k in keys if k.startswith(refused)]
        ok(keys and not bad and "pendulum.stiffness=" in keys,
           f"6: {command} --set <TAB> offers {len(keys)} keys, none it refuses ({bad[:4]})")

# 7: an ensemble draws its members, not the one bob's arrows, strobe, trail, bar
ens = ["still", default, "--at", "1", "--size", "320x180", "--set", "ensemble.count=5"]
for key in ["view.vectors=forces,velocity", "view.strobe=0.1", "view.trail=all",
            "view.colorbar=true"]:
    out = path(f"ens-{key.split('=')[0]}.png")
    r = run(*ens, "--set", key, "-o", out)
    ok(r.returncode == 2 and "[ensemble]" in err(r) and not os.path.exists(out),
       f"7: --set {key} with an ensemble refused, exit 2, nothing written "
       f"(exit {r.returncode}: {err(r)[:120]})")
r = run(*ens, "-o", path("ens.png"), "-q")
ok(r.returncode == 0, f"7: --set ensemble.count=5 on a scene with its own trail and colour bar "
   f"still draws (exit {r.returncode}: {err(r)[:160]})")
with open(default) as f:
    text = f.read()
ens_scene = path("ens-scene.ini")
with open(ens_scene, "w") as f:
    f.write(text + "\n[ensemble]\ncount = 4\n")
line = next(i + 1 for i, l in enumerate(text.split("\n")) if l.replace(" ", "").startswith("trail="))
r = run("still", ens_scene, "--at", "1", "--size", "320x180", "-o", path("ens-scene.png"))
ok(r.returncode == 2 and f"ens-scene.ini:{line}: view.trail" in err(r),
   f"7: a scene with [ensemble] and its own trail: refused at the trail's line {line} "
   f"(exit {r.returncode}: {err(r)[:140]})")

# 8: --scale is for a PNG
for ext in ("svg", "pdf"):
    out = path(f"scaled.{ext}")
    r = run("still", default, "--at", "1", "--size", "320x180", "--scale", "3", "-o", out)
    ok(r.returncode == 2 and "--scale" in err(r) and not os.path.exists(out),
       f"8: still --scale 3 -o x.{ext} refused, exit 2, nothing written "
       f"(exit {r.returncode}: {err(r)[:120]})")
r = run("still", default, "--at", "1", "--size", "320x180", "--scale", "2", "-o", path("scaled.png"),
        "-q")
ok(r.returncode == 0, f"8: still --scale 2 -o x.png taken (exit {r.returncode})")

# 11: a whole sequence over a longer one
seq = path("seq")
os.makedirs(seq, exist_ok=True)
pattern = os.path.join(seq, "s_%03d.png")
base = ["--fps", "10", "--size", "160x90", "-o", pattern]
r1 = run("render", stiff, "--set", "video.duration=1", *base, "-q")
before = sorted(os.listdir(seq))
r2 = run("render", default, "--set", "video.duration=0.4", *base, "--frames", "0:1")
kept = sorted(os.listdir(seq))
r3 = run("render", default, "--set", "video.duration=0.4", *base)
after = sorted(os.listdir(seq))
n_long, n_short = len(before), len(after)
ok(r1.returncode == 0 and n_long == 10 and kept == before,
   f"11: a part (--frames 0:1) keeps the other frames ({n_long} before, {len(kept)} after)")
ok(r3.returncode == 0 and after == [f"s_{k:03d}.png" for k in range(n_short)] and n_short < n_long
   and f"removed {n_long - n_short} frames" in err(r3),
   f"11: a whole render of {n_short} frames over {n_long} leaves only its own, said "
   f"({after[-2:]}; {err(r3)[:120]})")
# every frame left is the new scene's: its record holds default.ini's
# stiffness, not stiff.ini's (read from the two scene files here)
def stiffness(text):
    return float(re.search(r"^stiffness\s*=\s*([0-9.]+)", text, re.M).group(1))
want = stiffness(open(default).read())
assert want != stiffness(open(stiff).read())
stale = [n for n in after if stiffness(subprocess.run([exe, "scene", os.path.join(seq, n)],
                                                      capture_output=True, text=True).stdout) != want]
ok(not stale, f"11: no frame of the earlier run is left ({stale})")
os.mkfifo(os.path.join(seq, f"s_{n_short:03d}.png"))
r = run("render", default, "--set", "video.duration=0.4", *base)
ok(r.returncode == 0 and f"s_{n_short:03d}.png is numbered past" in err(r) and
   os.path.exists(os.path.join(seq, f"s_{n_short:03d}.png")),
   f"11: a FIFO numbered past the end is named, not opened or removed "
   f"(exit {r.returncode}: {err(r)[:140]})")

# 14: one SIGTERM stops a sequence waiting on a FIFO frame
fifo_seq = path("fifo-seq")
os.makedirs(fifo_seq, exist_ok=True)
os.mkfifo(os.path.join(fifo_seq, "00002.png"))
p = subprocess.Popen([exe, "render", default, "--set", "video.duration=0.2", "--fps", "30",
                      "--size", "160x90", "-o", os.path.join(fifo_seq, "%05d.png")],
                     stderr=subprocess.PIPE, cwd=work)
deadline = time.time() + 30
while time.time() < deadline and not os.path.exists(os.path.join(fifo_seq, "00001.png")):
    time.sleep(0.1)
time.sleep(1)  # the writer is in its wait
p.send_signal(signal.SIGTERM)
try:
    rc = p.wait(timeout=10)
except subprocess.TimeoutExpired:
    p.kill()
    rc = p.wait()
    rc = f"still running 10 s after SIGTERM (killed: {rc})"
msg = p.stderr.read().decode(errors="replace")
left = sorted(os.listdir(fifo_seq))
ok(rc == 143 and "interrupted by SIGTERM" in msg and left == ["00002.png"],
   f"14: a sequence waiting on a FIFO frame stops on one SIGTERM: exit {rc}, frames removed, "
   f"the FIFO left ({left}; {msg.strip()[-120:]})")

# 15: the later --size wins, whatever its form (13 cm: default.ini's panels
# fit a printed still from about 12.7 cm, test attack13-print)
W13 = round(13 / 2.54 * 300)  # px at the default 300 dpi; the height from 1280:720
H13 = round(13 / 2.54 * 300 * 720 / 1280)
for sizes, want in [(["13cm", "640x360"], (640, 360)), (["640x360", "13cm"], (W13, H13))]:
    out = path(f"size-{'-'.join(sizes)}.png")
    r = run("still", default, "--at", "1", "--size", sizes[0], "--size", sizes[1], "-o", out, "-q")
    got = None
    if r.returncode == 0:
        with open(out, "rb") as f:
            head = f.read(24)
        got = (int.from_bytes(head[16:20], "big"), int.from_bytes(head[20:24], "big"))
    ok(got == want, f"15: --size {sizes[0]} --size {sizes[1]}: {got} px, want {want} "
       f"({err(r)[-100:]})")


# 21: a PNG and its --state, two runs at once: never one's image beside the
# other's state (the PNG's springpend.time against the JSON's t)
def png_time(name):
    d = open(name, "rb").read()
    p = 8
    while p < len(d):
        n, kind = struct.unpack(">I", d[p:p + 4])[0], d[p + 4:p + 8]
        body = d[p + 8:p + 8 + n]
        if kind == b"tEXt" and body.startswith(b"springpend.time\0"):
            return float(body.split(b"\0")[-1])
        p += 12 + n
    return None


pair = path("pair")
os.makedirs(pair, exist_ok=True)
png, state = os.path.join(pair, "s.png"), os.path.join(pair, "s.json")
mixed, failed = 0, 0
for k in range(60):
    procs = [subprocess.Popen([exe, "still", default, "--at", str(at), "--size", "64x36", "-o", png,
                               "--state", state, "-q"], stderr=subprocess.DEVNULL, cwd=work)
             for at in (1, 2)]
    failed += sum(p.wait() != 0 for p in procs)
    t_png, t_state = png_time(png), json.load(open(state))["t"]
    mixed += t_png is None or abs(t_png - t_state) > 1e-9
ok(mixed == 0 and failed == 0, f"21: 60 pairs of stills at once: {mixed} left one's PNG beside the "
   f"other's state, {failed} failed")

# 25: the version command is listed, answers --help, and is completed
top = run("--help").stdout.decode()
vh = run("version", "--help")
ok(re.search(r"^  version\s+springpend's version", top, re.M) is not None and vh.returncode == 0
   and b"--verbose" in vh.stdout,
   f"25: --help lists 'version'; 'version --help' exits {vh.returncode} naming --verbose")
if os.path.exists(completion):
    got = complete("springpend", "ver")
    ok(got == ["version"], f"25: 'springpend ver<TAB>' offers version ({got})")
    man = os.path.join(os.path.dirname(completion), "springpend-version.1")
    ok(os.path.exists(man) and "\\-\\-verbose" in open(man).read(),
       "25: springpend-version(1) is made and names --verbose")
done()
