#!/usr/bin/env python3
"""springpend tests: the attacker's fifth pass (doc/notes/2026-11-27/
attack5.md). Each check is a class, run as the attacker ran it:
- compare --update and --approve never write through a baseline folder that
  is a link out of the baselines (they replaced files anywhere);
- compare --approve copies only regular files inside the candidates folder
  that decode as PNGs (a *.png link to a secret was copied into the
  baselines);
- folder-mode compare walks dot-folders and dot-files, reports a link to a
  folder, and refuses folders nested too deep, instead of passing without
  them; the reports then do not read as a pass;
- [view] font = Sans, serif or a name with many near matches (it crashed
  with SIGSEGV in the near-match list);
- a font_size or font_scale whose text cannot fit the frame is refused (the
  HUD's text covered the whole frame, exit 0);
- names with bidi controls, @mentions and bare domains: escaped in the
  terminal, the PR summary and the JUnit report;
- sweep --merge refuses values in forms the writers never print (e-00,
  5.0) and precession counts that cannot be;
- the CSV metadata's url is a URL: the file name percent-encoded;
- a title of 22 000 zero-width bidi controls is laid out in seconds, not
  minutes and 2 GB (the wrap shaped every prefix);
- an unknown [view] font is refused at its FILE:LINE or --set;
- --diff or --candidates inside the baselines is refused (the walk skipped
  that subfolder and advised adding a baseline that exists);
- a report written in another folder links the videos from its own folder
  (the links were relative to the working folder, and broken);
- a still of physical size at 200:1 drops the HUD and panels, as a small
  frame does, instead of drawing them over each other;
- C1 control characters in a title or caption are refused, in a scene file
  and from --set (springpend scene printed them raw);
- a sweep whose key spans a few ulps, or repeats one value, is refused (the
  figure's tick loop never ended);
- folder compare refuses one folder inside the other (--update all removed
  actual images; --update=missing nested the baselines a level deeper).
usage: test_attack5.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import hashlib
import json
import os
import xml.dom.minidom

import sptest
from sptest import done, err, ok

exe, src, work, _ = sptest.setup("attack5", ["fc-list"])
run = sptest.runner_bytes(exe, work)
default = os.path.join(src, "..", "scenes", "default.ini")


def path(*names):
    return os.path.join(work, *names)


def read(p):
    with open(p, "rb") as f:
        return f.read()


def copy(a, b):
    os.makedirs(os.path.dirname(b), exist_ok=True)
    with open(b, "wb") as f:
        f.write(read(a))


for t, name in ((1, "b1.png"), (2, "b2.png")):
    r = run("still", default, "--at", str(t), "--size", "64x48", "-q", "-o", name)
    assert r.returncode == 0, err(r)
b1, b2 = path("b1.png"), path("b2.png")

# ---- a baseline folder that links out of the baselines ----------------------
copy(b2, path("up", "outside", "x.png"))
copy(b1, path("up", "act", "sub", "x.png"))
os.makedirs(path("up", "exp"))
os.symlink("../outside", path("up", "exp", "sub"))
r = run("compare", "up/exp", "up/act", "--update", "all")
ok(r.returncode == 2 and read(path("up", "outside", "x.png")) == read(b2)
   and "link" in r.stdout.decode(),
   f"--update all: a baseline subfolder linking out is not written through (exit "
   f"{r.returncode}, the file outside unchanged)")

copy(b1, path("ap2", "cand", "sub", "new.png"))
os.makedirs(path("ap2", "base"))
os.makedirs(path("ap2", "outside"))
os.symlink("../outside", path("ap2", "base", "sub"))
r = run("compare", "--approve", "ap2/cand", "ap2/base")
ok(r.returncode == 2 and os.listdir(path("ap2", "outside")) == []
   and "through a link out of ap2/base" in err(r),
   f"--approve: a baseline subfolder linking out is not written through (exit "
   f"{r.returncode}: {err(r)[-120:]!r})")

# ---- what --approve copies ----------------------------------------------------
os.makedirs(path("ap", "cand"))
os.makedirs(path("ap", "base"))
with open(path("ap", "secret.txt"), "w") as f:
    f.write("SECRET\n")
os.symlink("../secret.txt", path("ap", "cand", "leak.png"))
with open(path("ap", "cand", "fake.png"), "w") as f:
    f.write("SECRET but named .png\n")
copy(b1, path("ap", "cand", "good.png"))
r = run("compare", "--approve", "ap/cand", "ap/base")
ok(r.returncode == 2 and sorted(os.listdir(path("ap", "base"))) == ["good.png"]
   and "leak.png is a link to" in err(r) and "fake.png does not decode as a PNG" in err(r),
   f"--approve copies only a PNG inside the candidates folder; a link to a secret and a "
   f"file that is not a PNG are named and not copied (exit {r.returncode}, "
   f"base: {sorted(os.listdir(path('ap', 'base')))})")

# ---- what a folder compare walks ---------------------------------------------
for side, img in (("e", b1), ("a", b2)):
    copy(img, path("d2", side, ".hid", "y.png"))
    copy(img, path("d2", side, ".z.png"))
    copy(b1, path("d2", side, "real", "x.png"))
    os.symlink("real", path("d2", side, "lnk"))
r = run("compare", "d2/e", "d2/a", "--junit", "d2.xml")
out = r.stdout.decode()
ok(r.returncode == 2 and "FAIL .hid/y.png" in out and "FAIL .z.png" in out,
   f"folder compare: images in dot-folders and dot-files are compared (exit {r.returncode})")
ok("lnk/ is a link to a folder" in out and "ok   real/x.png" in out,
   "folder compare: a link to a folder is reported as not compared, not passed over")

deep = "/".join(["d"] * 70)
copy(b1, path("deep", "e", deep, "x.png"))
copy(b2, path("deep", "a", deep, "x.png"))
copy(b1, path("deep", "e", "top.png"))
copy(b1, path("deep", "a", "top.png"))
r = run("compare", "deep/e", "deep/a", "--junit", "deep.xml")
junit = xml.dom.minidom.parse(path("deep.xml"))
fails = sum(int(s.getAttribute("failures") or 0) + int(s.getAttribute("errors") or 0)
            for s in junit.getElementsByTagName("testsuite"))
ok(r.returncode == 2 and "nested more than 64 deep" in err(r) and fails >= 1
   and not r.stdout.decode().startswith("ok"),
   f"folder compare: folders nested too deep are refused, and the JUnit report is not a "
   f"pass (exit {r.returncode}, {fails} failures/errors)")

# ---- generic and much-matched font names ------------------------------------
for fam in ("Sans", "serif", "monospace"):
    r = run("still", default, "--at", "1", "--size", "160x120", "--set", f"view.font={fam}",
            "-o", f"font-{fam}.png")
    ok(r.returncode == 0 and os.path.exists(path(f"font-{fam}.png")),
       f"[view] font = {fam}, one of fontconfig's generic names, renders (exit {r.returncode})")
r = run("still", default, "--at", "1", "--size", "160x120", "--set", "view.font=Noto",
        "-o", "font-noto.png")
ok(r.returncode == 2 and "close matches:" in err(r) and err(r).count('"Noto') >= 6
   and not os.path.exists(path("font-noto.png")),
   f"[view] font = Noto (dozens of near matches): exit 2 listing six (exit {r.returncode})")

# ---- text too large for the frame ------------------------------------------
for size, key, val in (("320x180", "view.font_size", "200"), ("1280x720", "view.font_size", "60"),
                       ("320x180", "view.font_scale", "3"), ("8.6cm", "view.font_size", "200")):
    out = "big-text." + ("pdf" if size.endswith("cm") else "png")
    r = run("still", default, "--at", "1", "--size", size, "--set", f"{key}={val}", "-o", out)
    ok(r.returncode == 2 and f"--set {key}" in err(r) and "cannot fit" in err(r)
       and not os.path.exists(path(out)),
       f"{key} = {val} at {size}: exit 2 saying the text cannot fit (exit {r.returncode})")
r = run("still", default, "--at", "1", "--size", "1280x720", "--set", "view.font_size=40",
        "-o", "text40.png")
ok(r.returncode == 0, f"font_size 40 at 1280x720 still renders (exit {r.returncode})")
with open(path("big.ini"), "w") as f:
    f.write(open(default).read() + "\n[view]\nfont_size = 150\n")
r = run("still", "big.ini", "--at", "1", "--size", "320x180", "-o", "big.png")
ok(r.returncode == 2 and "big.ini:" in err(r), f"a scene's font_size is refused at its FILE:LINE "
   f"({err(r)[:60]!r})")

# ---- names that display as others, mention people or link --------------------
names = ["@octocat", "www.evil.example", "r\u202egnp.exe", "x~~strike~~"]
for n in names:
    copy(b1, path("cmp", "e", n + ".png"))
    copy(b2, path("cmp", "a", n + ".png"))
r = run("compare", "cmp/e", "cmp/a", "--summary", "sum.md", "--junit", "j.xml")
out = r.stdout.decode()
ok("\u202e" not in out and "\\u202e" in out,
   "a bidi override in a name is shown escaped on the terminal")
md = open(path("sum.md"), encoding="utf-8").read()
ok("@octocat" not in md and "www.evil" not in md and "~~" not in md and "\u202e" not in md,
   "the PR summary mentions nobody, links nothing and strikes nothing out from names")
jx = open(path("j.xml"), encoding="utf-8").read()
ok("\u202e" not in jx, "JUnit shows a bidi override in a name escaped")

# ---- merge: forms the writers never print, counts that cannot be -------------
spring = os.path.join(src, "..", "scenes", "swinging-spring.ini")
for i in (1, 2):
    r = run("sweep", spring, "--vary", "initial.azimuth_rate=0.01:0.1:4", "--measure",
            "precession", "--time", "60", "--shard", f"{i}/2", "--csv", f"p{i}.csv", "-q")
    assert r.returncode == 0, err(r)


def reseal(name, text):
    """Writes the shard name with text and its metadata made to match."""
    meta = json.loads(read(path(name + "-metadata.json")))
    open(path("q.csv"), "w").write(text)
    meta["dc:extent"] = len(text.splitlines()) - 1
    meta["schema:sha256"] = hashlib.sha256(text.encode()).hexdigest()
    meta["url"] = "q.csv"
    open(path("q.csv-metadata.json"), "w").write(json.dumps(meta))


rows = read(path("p1.csv")).decode().splitlines()
head, first = rows[0], rows[1].split(",")
edits = {"e-00": first[2] + "e-00", "5.0": None, "-5": None, "0.5": None}
for what in edits:
    f2 = list(first)
    if what == "e-00":
        f2[2] = first[2] + "e-00"
    else:
        f2[3] = what
    reseal("p1.csv", "\n".join([head, ",".join(f2)] + rows[2:]) + "\n")
    r = run("sweep", "--merge", "q.csv", "p2.csv", "-o", "m.png")
    ok(r.returncode == 2 and not os.path.exists(path("m.png")),
       f"merge refuses a precession shard with {what!r} written in (exit {r.returncode}: "
       f"{err(r)[-90:]!r})")
reseal("p1.csv", "\n".join(rows) + "\n")
r = run("sweep", "--merge", "q.csv", "p2.csv", "-o", "m.png")
ok(r.returncode == 0, f"the same shard resealed unchanged merges (exit {r.returncode})")

# ---- the CSV metadata's url ---------------------------------------------------
r = run("data", default, "--set", "video.duration=0.1", "-o", "run #3%.csv")
meta = json.loads(read(path("run #3%.csv-metadata.json")))
ok(r.returncode == 0 and meta.get("url") == "run%20%233%25.csv",
   f"the metadata's url percent-encodes the file name ({meta.get('url')!r})")

# ---- a title of zero-width characters ---------------------------------------
with open(path("zw.ini"), "w", encoding="utf-8") as f:
    f.write("[view]\ntitle = a" + "\u202e\u202d" * 11000 + "\n")
code, e = sptest.hangs(run, "still", "zw.ini", "--at", "1", "--size", "320x180", "-o", "zw.png",
                       timeout=60)
ok(code != "hung", f"a title of 22 000 zero-width controls is laid out, not minutes of shaping "
   f"(exit {code})")

# ---- where an unknown font was set -----------------------------------------
with open(path("lm.ini"), "w") as f:
    f.write("[view]\nfont = Latin Modren Roman\n")
r = run("still", "lm.ini", "--at", "1", "--size", "160x120", "-o", "lm.png")
ok(r.returncode == 2 and "lm.ini:2: [view] font" in err(r),
   f"an unknown font is refused at its FILE:LINE ({err(r)[-140:]!r})")
r = run("still", default, "--at", "1", "--size", "160x120", "--set", "view.font=Nosuch Fam",
        "-o", "lm.png")
ok(r.returncode == 2 and '--set view.font = "Nosuch Fam"' in err(r),
   f"an unknown font from --set names --set view.font ({err(r)[-120:]!r})")

# ---- output folders inside the baselines -------------------------------------
copy(b1, path("df", "e", "sub", "x.png"))
copy(b1, path("df", "a", "sub", "x.png"))
for opt, where in (("--diff", "df/e/sub"), ("--diff", "df/e/new"), ("--candidates", "df/e/c")):
    r = run("compare", "df/e", "df/a", opt, where)
    ok(r.returncode == 2 and "lies in the baselines" in err(r) and "ok" not in r.stdout.decode(),
       f"{opt} {where}, inside the baselines, is refused before comparing (exit {r.returncode})")
r = run("compare", "df/e", "df/a", "--diff", "df/a/d")
# attack11 #22: the next walk took its diffs for snapshots, and --update=missing added them
ok(r.returncode == 2 and "lies in the actual images" in err(r),
   f"--diff inside the actual folder is refused too (exit {r.returncode})")

# ---- video links in a report written elsewhere ---------------------------------
for side, angle in (("e", "10"), ("a", "30")):
    os.makedirs(path("vid", side), exist_ok=True)
    r = run("render", default, "--size", "64x48", "--set", "video.duration=0.2", "--set",
            f"initial.angle={angle}", "-q", "-o", f"vid/{side}/v.mp4")
    assert r.returncode == 0, err(r)
os.makedirs(path("rep", "sub"))
run("compare", "vid/e", "vid/a", "--report", "rep/sub/vr.html")
import re  # noqa: E402
links = re.findall(r'href="([^"#][^"]*)"', open(path("rep", "sub", "vr.html")).read())
ok(links and all(os.path.exists(os.path.normpath(os.path.join(path("rep", "sub"), u)))
                 for u in links),
   f"a report in rep/sub links its videos from its own folder ({links})")

# ---- a still of physical size with a degenerate aspect ratio -------------------
r = run("still", default, "--at", "1", "--size", "200inx1in", "--dpi", "20", "-o", "wide.png")
ok(r.returncode == 0 and "drawn without them" in err(r),
   f"a 200:1 still of physical size drops the HUD and panels, saying so ({err(r)[:80]!r})")

# ---- C1 controls in text ---------------------------------------------------------
with open(path("nel.ini"), "wb") as f:
    f.write(b"[view]\ntitle = A\xc2\x85B\n")
r = run("still", "nel.ini", "--at", "1", "--size", "320x180", "-o", "nel.png")
ok(r.returncode == 2 and "nel.ini:2" in err(r) and "C1" in err(r)
   and not os.path.exists(path("nel.png")), f"a C1 control in a scene's title is refused "
   f"({err(r)[:80]!r})")
r = run("still", default, "--at", "1", "--size", "320x180", "--set", "view.caption=C\u009bD",
        "-o", "nel.png")
ok(r.returncode == 2 and "C1" in err(r) and not os.path.exists(path("nel.png")),
   "a C1 control (CSI) in a caption from --set is refused")

# ---- grids whose values cannot be told apart -------------------------------------
chaotic = os.path.join(src, "..", "scenes", "chaotic.ini")
for vary in ("initial.length=1:1.0000000000000002:3", "initial.angle=5:5:3"):
    code, e = sptest.hangs(run, "sweep", chaotic, "--vary", "initial.angle=1:2:3", "--vary", vary,
                           "--measure", "lyapunov", "--time", "2", "-o", "tiny.png", timeout=60)
    ok(code == 2 and "--vary" in e and not os.path.exists(path("tiny.png")),
       f"--vary {vary}: refused, not a hang in the figure's axes (exit {code})")

# ---- one compared folder inside the other ----------------------------------------
copy(b1, path("nest", "snap", "x.png"))
copy(b2, path("nest", "snap", "new", "x.png"))
r = run("compare", "nest/snap", "nest/snap/new", "--update", "all")
ok(r.returncode == 2 and "inside the other" in err(r)
   and read(path("nest", "snap", "new", "x.png")) == read(b2),
   f"compare refuses a folder inside the other; nothing removed (exit {r.returncode})")
r = run("compare", "nest/snap/new", "nest/snap", "--update", "missing")
ok(r.returncode == 2 and not os.path.exists(path("nest", "snap", "new", "new")),
   f"the other way round too; no nested copy made (exit {r.returncode})")

done()
