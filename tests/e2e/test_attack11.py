#!/usr/bin/env python3
"""springpend tests (issue 28): what the tenth attacker's pass left open
(doc/notes/2026-11-27/attack10.md; fix10's notes), and the eleventh pass:
- attack10 #7: a raw H.264 stream named .mp4 (or a Matroska file named
  .mp4, an MP4 named .gif) was read by compare, and failed on times it does
  not have: a file whose format FFmpeg finds is not the one its name says
  is refused, naming the format, exit 2; a raw stream named .h264 and a
  MOV named .mov are read as before;
- attack10 #6: under ulimit -v a cut MP4 was "out of memory ... allow
  more memory" (exit 1) at limits where a valid pair passes, the verdict
  flipping from run to run (a guess by how near the limit the process
  was): each file is decoded again alone, and a file that does not decode
  is damaged, exit 2, the same every run;
- attack10 #15: signal 32 (the kernel's first real-time signal, glibc's
  SIGCANCEL) killed a render and left its .part: caught as the others are
  (exit 160, nothing partial left) in render, compare and sweep; signal 33
  (glibc's SIGSETXID, whose handler glibc installs) changes nothing;
- attack11 #2 (MEDIUM): `scene X.csv --command` printed a forged CSV
  record whatever it held (`still ... --state FILE`), and the CSV recipe
  then overwrote FILE: a CSV's record may hold only what springpend writes
  there (`data ... -o FILE`, `sweep ... --csv FILE [-o FIGURE]`, a merge's
  --merge), read with the command's own option table;
- attack11 #3: with POSIXLY_CORRECT set, that check stopped at the scene
  file, so a forged --state after it was printed: every word is read;
- attack11 #11 (MEDIUM): an actual image named like an alternative
  (x.llvm.png beside x.png, llvm declared) was a new image, which
  --update=missing or --candidates/--approve installed as x.png's llvm
  alternative, letting a broken x.png pass: an error naming it, never
  compared, added or made a candidate;
- attack11 #7: the merge's muted look at a forged command's scene still
  quoted its [timeline] lines (a secret's keys): muted too;
- attack11 #9: a sweep stopped by a signal did not name it: it does;
- attack11 #13: folder-mode compare wrote a report over a baseline video
  (only *.png counted as an input): every name the walk reads counts, in
  the folders and under them;
- attack11 #12: sweep --merge ... --csv SHARD.csv-metadata.json wrote the
  rows over a shard's metadata (an input): refused;
- attack11 #8: a video a player shows turned (a display matrix) or
  stretched (a sample aspect ratio) passed as its baseline: refused;
- attack11 #4: two outputs at one file through a folder not made yet
  (--csv nd/../s.png -o s.png), and a report inside compare's --candidates
  or --diff folder (replacing a candidate or a diff): refused;
- attack11 #19: a tab in a timeline caption or pause note was drawn as a
  box: refused, as [view] text refuses it;
- attack11 #20: the "--approve C E" hint was not quoted: a folder with a
  space or a leading '-' pasted to an error; quoted as the baseline hint;
- attack11 #21: an animated PNG (APNG) or one whose gamma makes viewers
  draw other colours passed as "identical pixels": refused;
- attack11 #22: a --diff or --candidates folder inside the actual folder
  was taken, and the next run took its files for snapshots: refused;
- attack11 #23: side by side, a second scene's crf, preset or png_level
  was used or ignored by the scenes' order, without a word: refused;
- attack11 #24: data's scene column took a file name that starts with '='
  (a formula in every row of a spreadsheet): refused;
- attack11 #17: a compare.ini another user planted beside the baseline (in
  a shared folder) decided the verdict: one that anyone may write, or
  another user's in a folder others may write, is not read (exit 2);
- attack11 #15: doc/ci.md's recipe appended -o NAME after a record's
  "-- -c.ini", where it is a scene: the recipe puts it after the command
  word;
- attack11 #1 (in part): a ZWNJ after a virama that follows no letter of
  its script (at the start, after a space or a Latin letter) was written
  raw though it draws nothing: escaped;
- attack11 #25: the default output name cut the scene file's name at its
  first dot (chaotic.v2.ini and chaotic.v3.ini both wrote out/chaotic.png):
  the name less its last extension.
usage: test_attack11.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import resource
import shutil
import signal
import subprocess
import time

import sptest
from sptest import done, err, ok, skip

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack11")
chaotic = os.path.join(scenes, "chaotic.ini")
default = os.path.join(scenes, "default.ini")


def ff(*a):
    subprocess.run(["ffmpeg", "-v", "error", "-y", *a], cwd=work, check=True, timeout=120)


# ---- attack10 #7: a container that is not what the file's name says is refused -----------
r = run("render", default, "--size", "160x90", "--fps", "10", "--set", "video.duration=0.5",
        "-o", "a.mp4", "-q")
assert r.returncode == 0, err(r)
if shutil.which("ffmpeg"):
    ff("-i", "a.mp4", "-c:v", "copy", "-f", "h264", "raw.mp4")
    ff("-i", "a.mp4", "-c:v", "copy", "-f", "matroska", "mkv.mp4")
    ff("-i", "a.mp4", "-c:v", "copy", "-f", "h264", "raw.mkv")
    ff("-i", "a.mp4", "-c:v", "copy", "-f", "h264", "raw.h264")
    shutil.copy(path("a.mp4"), path("mp4.gif"))
    for name, found, said in (("raw.mp4", "'h264'", "not MP4 as its name says"),
                              ("mkv.mp4", "'matroska,webm'", "not MP4 as its name says"),
                              ("raw.mkv", "'h264'", "not Matroska as its name says"),
                              ("mp4.gif", "'mov,mp4", "not GIF as its name says")):
        for cmd in (["compare", "a.mp4", name], ["compare", "a.mp4", name, "--json"]):
            r = run(*cmd)
            ok(r.returncode == 2 and f"{name}: a file of format {found}" in err(r)
               and said in err(r) and ".h264 and .264 as raw H.264" in err(r),
               f"{' '.join(cmd)}: refused (exit 2), naming the format FFmpeg found and what "
               f"the name allows (exit {r.returncode}: {err(r)[-220:]!r})")
    shutil.copy(path("a.mp4"), path("a.MOV"))
    r = run("compare", "a.mp4", "a.MOV")
    ok(r.returncode == 0, f"an MP4 named .MOV (the same demuxer) still compares "
       f"(exit {r.returncode}: {err(r)[-160:]!r})")
    r = run("compare", "raw.h264", "raw.h264")
    ok(r.returncode == 0, f"a raw H.264 stream named .h264 still compares "
       f"(exit {r.returncode}: {err(r)[-160:]!r})")
else:
    skip("containers that are not what their names say", "ffmpeg is not installed")

# ---- attack11 #8: a video shown turned or stretched is not what springpend writes ----------
if shutil.which("ffmpeg"):
    ff("-i", "a.mp4", "-c", "copy", "-metadata:s:v:0", "rotate=90", "turned.mp4")
    ff("-i", "a.mp4", "-c", "copy", "-bsf:v", "h264_metadata=sample_aspect_ratio=4/3", "wide.mp4")
    ff("-i", "a.mp4", "-c", "copy", "-aspect", "16:3", "wide2.mp4")
    for name, said in (("turned.mp4", "shown turned by 90 degrees"),
                       ("wide.mp4", "pixels are shown 4:3"), ("wide2.mp4", "pixels are shown 3:1")):
        r = run("compare", "a.mp4", name)
        ok(r.returncode == 2 and said in err(r),
           f"compare a.mp4 {name} (the same coded pixels, shown otherwise): refused, exit 2 "
           f"(exit {r.returncode}: {err(r)[-160:]!r})")
else:
    skip("videos shown turned or stretched", "ffmpeg is not installed")

# ---- attack10 #6: a cut video under ulimit -v is damaged, every run -----------------------
r = run("render", default, "--size", "1280x720", "--fps", "10", "--set", "video.duration=2",
        "-o", "big.mp4", "-q", timeout=120)
assert r.returncode == 0, err(r)
shutil.copy(path("big.mp4"), path("big2.mp4"))
with open(path("big.mp4"), "rb") as f:
    whole = f.read()
with open(path("cut.mp4"), "wb") as f:
    f.write(whole[:len(whole) * 80 // 100])
r = run("compare", "big.mp4", "cut.mp4")
assert r.returncode == 2 and b"cannot decode cut.mp4" in r.stdout, (r.returncode, r.stdout)
if sanitized:
    skip("a cut video under ulimit -v", "ulimit -v and a sanitizer's shadow memory")
else:
    seen = {}
    for mb in range(300, 460, 20):
        def limit(mb=mb):
            resource.setrlimit(resource.RLIMIT_AS, (mb << 20, mb << 20))
        # 127: the dynamic loader itself could not map a library, before springpend ran
        rcs = [x.returncode for x in (run("compare", "big.mp4", "cut.mp4", preexec_fn=limit,
                                          timeout=120) for _ in range(3))
               if x.returncode != 127]
        valid = run("compare", "big.mp4", "big2.mp4", preexec_fn=limit, timeout=120).returncode
        seen[mb] = (rcs, valid)
    flips = {mb: v for mb, v in seen.items() if len(set(v[0])) > 1}
    # where the valid pair passes, memory is no excuse: the cut file is damaged
    wrong = {mb: v for mb, v in seen.items() if v[1] == 0 and set(v[0]) != {2}}
    ok(not flips and not wrong and any(v[1] == 0 for v in seen.values()),
       f"compare big.mp4 cut.mp4 (1280x720, cut at 80 %) three times under ulimit -v 300..440 "
       f"MB: the same verdict each run, and 'cannot decode' (exit 2) wherever the valid pair "
       f"passes (MB: [cut's exits], valid pair's exit: {seen})")

# ---- attack10 #15: signal 32 stops a run as the others do; 33 changes nothing -------------
SIG32 = 32


def send(p, sig):
    """Sends sig to p, unless it has ended (an old build killed by the last one)."""
    try:
        os.kill(p.pid, sig)
    except ProcessLookupError:
        pass


def writing(p, d, limit=60.0):
    """Waits until p has written frames to a .part file in folder d."""
    end = time.time() + limit
    while time.time() < end and p.poll() is None:
        if any(os.path.getsize(os.path.join(d, n)) > 4096 for n in sptest.part_files(d)):
            return
        time.sleep(0.02)


def stopped_by(sig, args, folder, stop_first=False, settle=0.5):
    """Runs springpend args in folder (made fresh), sends sig once the
    handlers are set (stop_first: while the process is stopped, so that it
    is seen at the next check; settle None: once it writes a .part); (exit
    status, what it printed, the folder's names)."""
    d = path(folder)
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    p = subprocess.Popen([exe, *args], cwd=d, stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True)
    sptest.wait_caught(p, signal.SIGTERM)
    sptest.wait_caught(p, SIG32, limit=5)
    if stop_first:
        send(p, signal.SIGSTOP)
    elif settle is None:
        writing(p, d)
    else:
        time.sleep(settle)
    send(p, sig)
    if stop_first:
        time.sleep(0.05)
        send(p, signal.SIGCONT)
    said = p.communicate(timeout=120)[0]
    return p.returncode, said, sorted(os.listdir(d))


long_render = ["render", default, "--size", "320x180", "--fps", "30", "--set",
               "video.duration=120", "-o", "v.mp4", "-q"]
rc, said, names = stopped_by(SIG32, long_render, "s32r", settle=None)
ok(rc == 128 + SIG32 and names == ["v.mp4"] and "interrupted by signal 32" in said,
   f"render stopped by signal 32: exit 160, the frames so far kept in v.mp4, no .part "
   f"(exit {rc}: {said[-160:]!r}; {names})")
if rc == 128 + SIG32:
    r = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-show_entries",
                        "stream=nb_read_frames", "-of", "csv=p=0", path("s32r", "v.mp4")],
                       capture_output=True, text=True) if shutil.which("ffprobe") else None
    ok(r is None or (r.returncode == 0 and int(r.stdout.strip() or 0) > 0),
       f"the kept v.mp4 plays ({r.stdout.strip() if r else 'no ffprobe'} frames)")

# a second signal 32 (both sent while the render is stopped): stops at once, nothing partial left
d = path("s32x2")
shutil.rmtree(d, ignore_errors=True)
os.makedirs(d)
p = subprocess.Popen([exe, *long_render], cwd=d, stdout=subprocess.DEVNULL,
                     stderr=subprocess.PIPE, text=True)
sptest.wait_caught(p, SIG32, limit=20)
writing(p, d)
send(p, signal.SIGSTOP)
send(p, SIG32)
send(p, SIG32)  # a real-time signal: queued, both delivered
send(p, signal.SIGCONT)
said = p.communicate(timeout=120)[1]
ok(p.returncode == 128 + SIG32 and not sptest.part_files(d) and "second signal" in said,
   f"render given signal 32 twice: exit 160, no .part left (exit {p.returncode}: "
   f"{said.strip()[-160:]!r}; {sorted(os.listdir(d))})")

# compare of two videos: every frame pair is a check of the flag
r = run("render", default, "--size", "320x180", "--fps", "30", "--set", "video.duration=30",
        "-o", "c.mp4", "-q", timeout=120)
assert r.returncode == 0, err(r)
rc, said, names = stopped_by(SIG32, ["compare", path("c.mp4"), path("c.mp4"), "--junit",
                                     "j.xml", "--report", "r.html"], "s32c", stop_first=True)
ok(rc == 128 + SIG32 and not [n for n in names if n.endswith(".part")]
   and "signal 32" in said,
   f"compare stopped by signal 32: exit 160, names it, no .part (exit {rc}: {said[-200:]!r}; "
   f"{names})")

sweep = ["sweep", chaotic, "--vary", "initial.angle=1:179:2000", "--measure", "lyapunov",
         "--time", "50", "--csv", "s.csv", "-o", "s.png"]
rc, said, names = stopped_by(SIG32, sweep, "s32s", stop_first=True)
ok(rc == 128 + SIG32 and names == [] and "interrupted by signal 32: nothing written" in said,
   f"sweep stopped by signal 32: exit 160, nothing written, no .part (exit {rc}: "
   f"{said[-160:]!r}; {names})")

# attack11 #9: a sweep stopped by SIGTERM names it, as merge and data do
rc, said, names = stopped_by(signal.SIGTERM, sweep, "s15s", stop_first=True)
ok(rc == 143 and names == [] and "interrupted by SIGTERM: nothing written" in said,
   f"sweep stopped by SIGTERM: names it (exit {rc}: {said[-160:]!r}; {names})")

# 33: glibc's own handler takes it (setuid's broadcast to threads) and ignores it from outside
short_render = ["render", default, "--size", "320x180", "--fps", "30", "--set",
                "video.duration=20", "-o", "w.mp4", "-q"]
rc, said, names = stopped_by(33, short_render, "s33r", settle=0.2)
ok(rc == 0 and names == ["w.mp4"],
   f"render sent signal 33 (glibc's SIGSETXID): runs on to its end, exit 0, no .part "
   f"(exit {rc}: {said[-160:]!r}; {names})")

# ---- attack11 #2 (MEDIUM): a CSV's record holds only what springpend writes there ---------
import json  # noqa: E402

r = run("data", chaotic, "--set", "video.duration=1", "-o", "d.csv", "-q")
assert r.returncode == 0, err(r)
grid = ["--vary", "initial.angle=1:179:4", "--measure", "lyapunov", "--time", "2"]
for i in (1, 2):
    r = run("sweep", chaotic, *grid, "--shard", f"{i}/2", "--csv", f"sh{i}.csv", "-q")
    assert r.returncode == 0, err(r)
r = run("sweep", "--merge", "sh1.csv", "sh2.csv", "--csv", "m.csv", "-o", "m.png", "-q")
assert r.returncode == 0, err(r)
victim = path("victim.txt")
with open(path("d.csv-metadata.json")) as f:
    meta = json.load(f)


def csv_record(line):
    """f.csv, a copy of d.csv whose metadata's prov:wasGeneratedBy is line."""
    shutil.copy(path("d.csv"), path("f.csv"))
    with open(path("f.csv-metadata.json"), "w") as f:
        json.dump(dict(meta, **{"prov:wasGeneratedBy": line}), f)


data = f"springpend data {chaotic} --set video.duration=1"
sweep_line = f"springpend sweep {chaotic} {' '.join(grid)}"
for forged, said in ((f"springpend still {chaotic} --at 1 --size 64x36 --state {victim} -o d.csv",
                      "a 'still' command, which writes no CSV"),
                     (f"{data} --state {victim} -o d.csv", "holds --state"),
                     (f"{data} -o d.csv --sta={victim}", "holds --state"),
                     (f"{data} -o d.csv -o{victim}", "holds --output"),
                     (f"{sweep_line} --csv d.csv --csv {victim}", "holds --csv"),
                     (f"{sweep_line} --csv d.csv -o a.png --output {victim}.png", "holds --output"),
                     (f"{data} -o d.csv --bogus {victim}", "holds --bogus"),
                     (f"{data}", "names no CSV")):
    with open(victim, "w") as f:
        f.write("keep me\n")
    csv_record(forged)
    r = run("scene", "f.csv", "--command")
    line = r.stdout.decode().strip()
    again = None
    if r.returncode == 0:  # doc/ci.md's CSV recipe: change the CSV's own FILE to NAME
        again = subprocess.run(["sh", "-c", "'" + exe + "'" + line[len("springpend"):]
                                .replace("-o d.csv", "-o again.csv")
                                .replace("--csv d.csv", "--csv again.csv")],
                               cwd=work, capture_output=True, timeout=60)
    ok(r.returncode == 2 and not line and said in err(r)
       and open(victim).read() == "keep me\n",
       f"scene f.csv --command of a forged CSV record ({forged[len('springpend '):][:60]}...): "
       f"refused, exit 2, nothing printed, the victim kept (exit {r.returncode}: "
       f"{err(r)[-160:]!r}; {line[-60:]!r}; re-run: {again.returncode if again else None})")

for name, want, figure in (("d.csv", " -o d.csv", False), ("m.csv", "--merge sh1.csv sh2.csv", True)):
    r = run("scene", name, "--command")
    ok(r.returncode == 0 and want in r.stdout.decode()
       and ("writes its figure too" in err(r)) == figure,
       f"scene {name} --command: a genuine CSV record (a data command's; a merge's, whose "
       f"figure the note names) is printed (exit {r.returncode}: {r.stdout.decode()[-80:]!r}; "
       f"{err(r)[-120:]!r})")

# ---- attack11 #3: POSIXLY_CORRECT does not stop the record's check at the scene file -------
r = run("still", chaotic, "--at", "1", "--size", "64x36", "-q", "-o", "a.png")
assert r.returncode == 0, err(r)
sptest.png_with_command(path("a.png"), path("p.png"),
                        f"springpend still {chaotic} --at 1 --size 64x36 --state {victim}")
for env in ({}, {"POSIXLY_CORRECT": "1"}):
    r = run("scene", "--command", "p.png", env=dict(os.environ, **env))
    ok(r.returncode == 2 and not r.stdout and "holds --state" in err(r),
       f"scene --command p.png (a forged --state after the scene file) with {env or 'no env'}: "
       f"refused (exit {r.returncode}: {err(r)[-120:]!r}; {r.stdout[-80:]!r})")

# ---- attack11 #7: the merge's look at a forged command's scene quotes no [timeline] line ----
for i in (1, 2):
    shutil.copy(path(f"sh{i}.csv"), path(f"lk{i}.csv"))
with open(path("secret.ini"), "w") as f:
    f.write("[timeline]\nghp_SECRET123456 = caption: x\n1 = speed AKIA_SECRET_KEY_99\n")
with open(path("sh1.csv-metadata.json")) as f:
    m1 = f.read()
with open(path("lk1.csv-metadata.json"), "w") as f:
    f.write(m1.replace(chaotic, path("secret.ini")))
shutil.copy(path("sh2.csv-metadata.json"), path("lk2.csv-metadata.json"))
r = run("sweep", "--merge", "lk1.csv", "lk2.csv", "-o", "lk.png")
ok(r.returncode == 2 and "what it holds is not said" in err(r) and "SECRET" not in err(r),
   f"sweep --merge of a shard whose command names a file with [timeline] lines: refused, "
   f"and nothing of the file said (exit {r.returncode}: {err(r)[-240:]!r})")

# ---- attack11 #11 (MEDIUM): an actual image named like an alternative is an error ----------
for d in ("env/e", "env/a", "env/a2"):
    os.makedirs(path(d), exist_ok=True)
for at, name in (("0", "A.png"), ("1", "Z.png")):
    r = run("still", default, "--at", at, "--size", "160x90", "-o", path("env", name), "-q")
    assert r.returncode == 0, err(r)
with open(path("env", "e", "compare.ini"), "w") as f:
    f.write("envs = llvm\n")
shutil.copy(path("env", "A.png"), path("env", "e", "x.png"))
shutil.copy(path("env", "A.png"), path("env", "a", "x.png"))
shutil.copy(path("env", "Z.png"), path("env", "a", "x.llvm.png"))   # a broken picture
shutil.copy(path("env", "Z.png"), path("env", "a2", "x.png"))
in_env = sptest.runner_bytes(exe, path("env"))
r = in_env("compare", "e", "a")
out = r.stdout.decode()
ok(r.returncode == 2 and "a/x.llvm.png is named like the llvm alternative of x.png" in out,
   f"compare e a with a/x.llvm.png (llvm on envs): an error naming it, exit 2 (exit "
   f"{r.returncode}: {out[-240:]!r})")
r = in_env("compare", "e", "a", "--update=missing")
r2 = in_env("compare", "e", "a", "--candidates", "cand")
r3 = in_env("compare", "e", "a2")
ok(not os.path.exists(path("env", "e", "x.llvm.png"))
   and not os.path.exists(path("env", "cand", "x.llvm.png")) and r3.returncode == 1,
   f"--update=missing adds no e/x.llvm.png, --candidates writes none, so a broken x.png "
   f"still fails (exit {r.returncode}, {r2.returncode}, {r3.returncode}: "
   f"{sorted(os.listdir(path('env', 'e')))}; {r3.stdout.decode()[-160:]!r})")

# ---- attack11 #13: a report never lands on a baseline video (or under a compared folder) ---
for d in ("fv/e/sub", "fv/a"):
    os.makedirs(path(d), exist_ok=True)
shutil.copy(path("a.mp4"), path("fv", "e", "v.mp4"))
shutil.copy(path("a.mp4"), path("fv", "a", "v.mp4"))
in_fv = sptest.runner_bytes(exe, path("fv"))
for opt, target in (("--report", "e/v.mp4"), ("--junit", "a/v.mp4"), ("--summary", "e/w.webm"),
                    ("--junit", "e/V.MKV"), ("--report", "e/sub/y.png")):
    r = in_fv("compare", "e", "a", opt, target)
    ok(r.returncode == 2 and f"{opt} {target} would overwrite an input" in err(r)
       and open(path("fv", "e", "v.mp4"), "rb").read() == open(path("a.mp4"), "rb").read()
       and (target.endswith("v.mp4") or not os.path.exists(path("fv", target))),
       f"compare e a {opt} {target}: refused before anything is written (exit {r.returncode}: "
       f"{err(r)[-160:]!r})")

# two-file mode: the compare.ini beside the expected file is an input too
os.makedirs(path("fv2", "e"), exist_ok=True)
os.makedirs(path("fv2", "a"), exist_ok=True)
shutil.copy(path("env", "A.png"), path("fv2", "e", "x.png"))
shutil.copy(path("env", "Z.png"), path("fv2", "a", "x.png"))
with open(path("fv2", "e", "compare.ini"), "w") as f:
    f.write("[*]\nmax_diff = 3\n")
in_fv2 = sptest.runner_bytes(exe, path("fv2"))
for opt in ("--diff", "--report", "--junit"):
    r = in_fv2("compare", "e/x.png", "a/x.png", opt, "e/compare.ini")
    ok(r.returncode == 2 and "would overwrite an input" in err(r)
       and open(path("fv2", "e", "compare.ini")).read() == "[*]\nmax_diff = 3\n",
       f"compare e/x.png a/x.png {opt} e/compare.ini: refused, the rules kept (exit "
       f"{r.returncode}: {err(r)[-160:]!r})")

# ---- attack11 #12: a merge's --csv never lands on a shard's metadata (an input too) -------
with open(path("sh1.csv-metadata.json"), "rb") as f:
    before = f.read()
r = run("sweep", "--merge", "sh1.csv", "sh2.csv", "-o", "mm.png", "--csv", "sh1.csv-metadata.json")
with open(path("sh1.csv-metadata.json"), "rb") as f:
    after = f.read()
ok(r.returncode == 2 and "would overwrite an input (the metadata of sh1.csv)" in err(r)
   and after == before and not os.path.exists(path("mm.png")),
   f"sweep --merge ... --csv sh1.csv-metadata.json: refused, the shard's metadata kept, nothing "
   f"written (exit {r.returncode}: {err(r)[-160:]!r})")

# ---- attack11 #4: two outputs at one file through a folder not made yet; a report in a ----
# folder compare fills
r = run("sweep", chaotic, *grid, "--csv", "nd/../s4.png", "-o", "s4.png")
ok(r.returncode == 2 and "name one file" in err(r) and not os.path.exists(path("s4.png")),
   f"sweep --csv nd/../s4.png -o s4.png (nd not there yet): refused as one file (exit "
   f"{r.returncode}: {err(r)[-160:]!r})")
shutil.copy(path("env", "Z.png"), path("env", "a", "x.png"))  # x.png fails: a candidate, a diff
os.remove(path("env", "a", "x.llvm.png"))
for opts, there in ((["--candidates", "c6", "--report", "c6/x.png"], "c6/x.png"),
                    (["--diff", "d6", "--junit", "d6/x.diff.png"], "d6/x.diff.png"),
                    (["--candidates", "c7", "--summary", "c7/sub/s.md"], "c7/sub/s.md")):
    r = in_env("compare", "e", "a", *opts)
    ok(r.returncode == 2 and "which compare fills with its own files" in err(r)
       and not os.path.exists(path("env", there)),
       f"compare e a {' '.join(opts)}: a report inside the folder compare fills is refused "
       f"(exit {r.returncode}: {err(r)[-160:]!r})")

# ---- attack11 #19: a tab in a timeline caption or pause note is refused, as in [view] text --
with open(default) as f:
    base_scene = f.read()
for cue, what in (("1 = caption: A\tB", "caption"), ("1 = pause 2: n\tote", "pause note")):
    with open(path("tab.ini"), "w") as f:
        f.write(base_scene + f"\n[timeline]\n{cue}\n")
    r = run("still", "tab.ini", "--at", "2", "--size", "320x180", "-o", "tab.png")
    ok(r.returncode == 2 and f"[timeline] {what}: byte 0x09 at byte 2 is not text" in err(r)
       and not os.path.exists(path("tab.png")),
       f"a tab in a timeline {what}: refused, exit 2 (exit {r.returncode}: {err(r)[-160:]!r})")

# ---- attack11 #20: the approve hint pastes as it reads (quoted, "--" before a '-' name) -----
for d in ("hint/-e", "hint/b a", "hint/a"):
    os.makedirs(path(d), exist_ok=True)
for d in ("-e", "b a"):
    shutil.copy(path("env", "A.png"), path("hint", d, "x.png"))
shutil.copy(path("env", "Z.png"), path("hint", "a", "x.png"))
in_hint = sptest.runner_bytes(exe, path("hint"))
for cand, base in (("-c", "-e"), ("c d", "b a")):
    r = in_hint("compare", "--candidates", cand, "--", base, "a")
    line = r.stdout.decode().strip().splitlines()[-1]
    cmd = line.split("to accept them after review: ", 1)[-1]
    again = subprocess.run(["sh", "-c", "'" + exe + "'" + cmd[len("springpend"):]],
                           cwd=path("hint"), capture_output=True, timeout=60) \
        if cmd.startswith("springpend compare --approve") else None
    ok(again is not None and again.returncode == 0
       and open(path("hint", base, "x.png"), "rb").read() == open(path("env", "Z.png"), "rb").read(),
       f"compare --candidates {cand!r} -- {base!r} a: its approve hint pasted into sh approves "
       f"({line[-100:]!r}; {again.returncode if again else None})")

# ---- attack11 #21: a PNG a viewer shows otherwise (an APNG, a gamma) is refused -----------
import struct  # noqa: E402
import zlib  # noqa: E402


def with_chunk(src, out, kind, body):
    """src's PNG with the chunk kind (body bytes, CRC made) before its first IDAT."""
    d = open(src, "rb").read()
    at, chunk = d.index(b"IDAT") - 4, struct.pack(">I", len(body)) + kind + body
    open(out, "wb").write(d[:at] + chunk + struct.pack(">I", zlib.crc32(kind + body)) + d[at:])


A, Z = path("env", "A.png"), path("env", "Z.png")
with_chunk(A, path("gam.png"), b"gAMA", struct.pack(">I", 10000))     # drawn near black
with_chunk(A, path("srgb.png"), b"gAMA", struct.pack(">I", 45455))    # sRGB's: as springpend's
with_chunk(A, path("apng.png"), b"acTL", struct.pack(">II", 1, 0))    # an animation control
for name, said, code in (("gam.png", "holds a gamma (gAMA) other than sRGB's", 2),
                         ("apng.png", "is an animated PNG (APNG", 2), ("srgb.png", "", 0)):
    r = run("compare", A, name)
    ok(r.returncode == code and said in err(r),
       f"compare A.png {name}: {'refused, exit 2' if code else 'compared'} (exit "
       f"{r.returncode}: {err(r)[-200:]!r})")
if shutil.which("ffmpeg"):
    ff("-framerate", "1", "-i", A, "-framerate", "1", "-i", Z, "-filter_complex",
       "[0][1]concat=n=2:v=1,format=rgb24", "-plays", "0", "-f", "apng", "an.png")
    r = run("compare", A, "an.png")
    ok(r.returncode == 2 and "is an animated PNG" in err(r),
       f"compare A.png an.png (ffmpeg's APNG: A, then Z): refused (exit {r.returncode}: "
       f"{err(r)[-160:]!r})")

# ---- attack11 #22: --diff or --candidates inside the actual folder is refused ---------------
for opt, where in (("--candidates", "a/cand"), ("--diff", "a/sub")):
    r = in_env("compare", "e", "a", opt, where)
    ok(r.returncode == 2 and "lies in the actual images a" in err(r)
       and not os.path.exists(path("env", where)),
       f"compare e a {opt} {where}: refused, nothing written (exit {r.returncode}: "
       f"{err(r)[-160:]!r})")

# ---- attack11 #23: side by side, a second scene's encoder settings are refused when they differ
with open(os.path.join(scenes, "stiff.ini")) as f:
    stiff = f.read()
# (attack12 #16: only the keys the output's encoder reads, so png_level with a PNG sequence)
for key, value, out in (("crf", "51", "enc.mp4"), ("preset", "veryslow", "enc.mp4"),
                        ("png_level", "9", "enc%03d.png")):
    with open(path("enc.ini"), "w") as f:
        f.write(stiff + f"\n[video]\n{key} = {value}\n")
    r = run("render", default, "enc.ini", "--size", "160x90", "--set", "video.duration=0.2",
            "-o", out, "-q")
    ok(r.returncode == 2 and f"video.{key} = {value}" in err(r)
       and not os.path.exists(path(out)) and not os.path.exists(path("enc000.png")),
       f"side by side with a second scene's {key} = {value}: refused, naming it (exit "
       f"{r.returncode}: {err(r)[-160:]!r})")
r = run("render", default, os.path.join(scenes, "stiff.ini"), "--size", "160x90", "--set",
        "video.duration=0.2", "-o", "enc.mp4", "-q")
ok(r.returncode == 0, f"side by side with the same encoder settings: made ({err(r)[-120:]!r})")

# ---- attack11 #24: data's scene column never starts a spreadsheet formula ------------------
shutil.copy(default, path("=cmd|x.ini"))
r = run("data", os.path.join(scenes, "stiff.ini"), "=cmd|x.ini", "--set", "video.duration=0.1",
        "-o", "inj.csv")
ok(r.returncode == 2 and "which a spreadsheet reads as the start of a formula" in err(r)
   and not os.path.exists(path("inj.csv")),
   f"data stiff.ini '=cmd|x.ini': refused, nothing written (exit {r.returncode}: "
   f"{err(r)[-160:]!r})")

# ---- attack11 #17: a compare.ini someone else could have planted is not read --------------
os.makedirs(path("ww"), exist_ok=True)
os.chmod(path("ww"), 0o1777)  # a shared folder, as /tmp is
shutil.copy(A, path("ww", "exp.png"))
shutil.copy(Z, path("ww", "act.png"))
with open(path("ww", "compare.ini"), "w") as f:
    f.write("[*]\nmax_pixels = 100%\nmax_diff = 255\n")  # passes anything
in_ww = sptest.runner_bytes(exe, path("ww"))
os.chmod(path("ww", "compare.ini"), 0o666)
r = in_ww("compare", "exp.png", "act.png")
ok(r.returncode == 2 and "compare.ini is writable by anyone: not read" in err(r),
   f"a compare.ini anyone may write: not read, exit 2 (exit {r.returncode}: {err(r)[-160:]!r})")
os.chmod(path("ww", "compare.ini"), 0o644)
if os.geteuid() == 0:
    os.chown(path("ww", "compare.ini"), 65534, 65534)  # as if user nobody wrote it
    r = in_ww("compare", "exp.png", "act.png")
    ok(r.returncode == 2 and "belongs to user 65534" in err(r) and b"ok " not in r.stdout,
       f"a compare.ini of another user in a folder anyone may write: not read, exit 2 (exit "
       f"{r.returncode}: {err(r)[-160:]!r})")
    os.chown(path("ww", "compare.ini"), 0, 0)
else:
    skip("a compare.ini of another user", "not root: cannot give the file away")
os.chmod(path("ww"), 0o755)
r = in_ww("compare", "exp.png", "act.png")
ok(r.returncode == 0, f"the owner's own compare.ini in a folder only they may write is read "
   f"(exit {r.returncode}: {err(r)[-120:]!r})")

# ---- attack11 #15: doc/ci.md's re-run recipe works for a record that ends "-- -c.ini" -------
os.makedirs(path("dash", "again"), exist_ok=True)
shutil.copy(chaotic, path("dash", "-c.ini"))
in_dash = sptest.runner_bytes(exe, path("dash"))
r = in_dash("still", "-q", "--at", "1", "--size", "64x36", "-o", "./-x.png", "--", "-c.ini")
assert r.returncode == 0, err(r)
with open(path("dash", "again", "-c.ini"), "wb") as f:
    f.write(in_dash("scene", "./-x.png").stdout)
cmd = in_dash("scene", "./-x.png", "--command").stdout.decode().strip()
recipe = 'w=${cmd#springpend }; eval "\"$exe\" ${w%% *} -o re.png ${w#* }"'
r = subprocess.run(["sh", "-c", recipe], cwd=path("dash", "again"), capture_output=True,
                   env=dict(os.environ, cmd=cmd, exe=exe), timeout=60)
same = os.path.exists(path("dash", "again", "re.png")) and \
    open(path("dash", "again", "re.png"), "rb").read() == open(path("dash", "-x.png"), "rb").read()
ok(cmd.endswith("-- -c.ini") and r.returncode == 0 and same,
   f"the record {cmd[-40:]!r}, run by doc/ci.md's recipe (-o NAME after the command word): "
   f"the same bytes (exit {r.returncode}: {err(r)[-160:]!r})")
with open(os.path.join(src, "..", "doc", "ci.md")) as f:
    ok('${w%% *} -o fig.png ${w#* }' in f.read(), "doc/ci.md's recipe puts -o after the command word")

# ---- attack11 #1: a ZWNJ after a virama with no letter before it is shown escaped ---------
for title, raw in (("\u094d\u200c\u0915", False), (" \u094d\u200c\u0915 x", False),
                   ("a\u094d\u200c\u0915", False), ("\u0915\u094d\u200c\u0937", True),
                   ("\u0915\u093c\u094d\u200c\u0937", True)):
    r = run("still", default, "--at", "0", "--size", "320x180", "--set", f"view.title={title}",
            "-o", "zw.png", "-q")
    line = run("scene", "zw.png", "--command").stdout.decode()
    want = "raw (it selects a form)" if raw else "escaped (it joins nothing)"
    ok(r.returncode == 0 and ("\u200c" in line) == raw and ("\\u200c" in line) != raw,
       f"view.title={title!r}: its ZWNJ {want} in the record ({line.strip()[-40:]!r})")

# ---- attack11 #25: the default output name keeps all but the scene file's last extension ---
os.makedirs(path("def"), exist_ok=True)
shutil.copy(default, path("def", "chaotic.v2.ini"))
shutil.copy(os.path.join(scenes, "stiff.ini"), path("def", "chaotic.v3.ini"))
in_def = sptest.runner_bytes(exe, path("def"))
for name in ("chaotic.v2.ini", "chaotic.v3.ini"):
    r = in_def("still", name, "--at", "1", "--size", "160x90", "-q")
    assert r.returncode == 0, err(r)
made = sorted(os.listdir(path("def", "out")))
ok(made == ["chaotic.v2.png", "chaotic.v3.png"],
   f"still chaotic.v2.ini and chaotic.v3.ini without -o: two files, neither replaced ({made})")

done()
