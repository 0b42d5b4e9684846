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
  them; the reports then do not read as a pass.
usage: test_attack5.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import xml.dom.minidom

import sptest
from sptest import done, err, ok

exe, src, work, _ = sptest.setup("attack5", [])
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

done()
