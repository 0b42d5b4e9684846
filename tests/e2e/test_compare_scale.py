#!/usr/bin/env python3
"""springpend tests: compare at a CI's scale (issue 24). Baselines per
environment (NAME.KEY.png alternatives, --env), review outside the checkout
(--candidates, --approve), a Markdown summary, subfolders, videos in folder
mode, wildcard sections in compare.ini, several threads, and the HTML
report's failures-only mode, identical pairs embedded once, full-size images
with zoom and masks drawn.
usage: test_compare_scale.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR (TAP)"""
import base64
import json
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

from sptest import done, ok

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "compare_scale"))
default = os.path.join(src, "..", "scenes", "default.ini")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


def run(*args):
    return subprocess.run([exe, *args], capture_output=True, text=True, cwd=work, timeout=300)


def W(*p):
    return os.path.join(work, *p)


def put(src_name, *dst):
    os.makedirs(os.path.dirname(W(*dst)), exist_ok=True)
    shutil.copy(W(src_name), W(*dst))


def data(path):
    return open(path, "rb").read()


for name, extra in (("a", ["--at", "3"]), ("m", ["--at", "3.05"]), ("m2", ["--at", "3.1"])):
    run("still", default, "--size", "160x120", *extra, "-o", f"{name}.png", "-q")

# ---- baselines per environment ----
# one.png's plain baseline differs; its alternative one.llvm19.png matches.
put("a.png", "env", "base", "one.png")
put("m.png", "env", "base", "one.llvm19.png")
put("m.png", "env", "act", "one.png")
with open(W("env", "base", "compare.ini"), "w") as f:
    f.write("envs = llvm19, ci9\n")  # the keys of alternatives (doc/ci.md)
r = run("compare", W("env", "base"), W("env", "act"), "--json")
j = json.loads(r.stdout)
rec = j["results"][0] if j["results"] else {}
ok(r.returncode == 0 and len(j["results"]) == 1 and rec.get("baseline_key") == "llvm19"
   and rec.get("expected", "").endswith("one.llvm19.png") and rec.get("alternatives") == 1,
   f"an alternative baseline NAME.KEY.png that matches passes, and the record says which "
   f"({rec.get('baseline_key')}, {rec.get('expected')})")
r = run("compare", W("env", "base"), W("env", "act"))
ok("matched the alternative baseline for llvm19" in r.stdout,
   f"the text line says which baseline matched ({r.stdout.strip()})")
# Neither matches: a failure against the plain baseline, with a note.
put("m2.png", "env", "act", "one.png")
r = run("compare", W("env", "base"), W("env", "act"), "--json")
rec = json.loads(r.stdout)["results"][0]
ok(r.returncode == 1 and rec["expected"].endswith("/one.png") and rec["baseline_key"] is None
   and any("alternative" in n for n in rec["notes"]),
   f"no baseline matches: the failure is against the plain one, noted ({rec['notes']})")
# --update=changed --env KEY writes NAME.KEY.png and leaves the plain one.
plain = data(W("env", "base", "one.png"))
r = run("compare", W("env", "base"), W("env", "act"), "--update=changed", "--env", "ci9")
ok(r.returncode == 0 and data(W("env", "base", "one.ci9.png")) == data(W("m2.png"))
   and data(W("env", "base", "one.png")) == plain,
   f"--update=changed --env ci9 writes one.ci9.png, the plain baseline untouched ({r.stdout.strip()[-120:]})")
r = run("compare", W("env", "base"), W("env", "act"), "--json")
ok(r.returncode == 0 and json.loads(r.stdout)["results"][0]["baseline_key"] == "ci9",
   "the next run matches the new alternative")
# Without --env, --update writes the plain name.
put("m.png", "env", "act", "one.png")
put("m2.png", "env", "base", "one.llvm19.png")
put("m2.png", "env", "base", "one.ci9.png")
r = run("compare", W("env", "base"), W("env", "act"), "--update=changed")
ok(data(W("env", "base", "one.png")) == data(W("m.png")) and "replaced" in r.stdout,
   "--update=changed without --env replaces the plain baseline")
r = run("compare", W("env", "base"), W("env", "act"), "--env", "a/b")
ok(r.returncode == 2 and "--env a/b" in r.stderr, f"--env refuses a key that is no plain word ({r.stderr.strip()})")

# ---- review outside the checkout: --candidates, then --approve ----
for n, (e, a) in {"same.png": ("a.png", "a.png"), "near.png": ("a.png", "a.png"),
                  "moved.png": ("a.png", "m.png"), "sub/deep.png": ("a.png", "m2.png")}.items():
    put(e, "rev", "base", n)
    put(a, "rev", "act", n)
put("a.png", "rev", "act", "new.png")
before = {n: data(W("rev", "base", n)) for n in ("same.png", "moved.png", "sub/deep.png")}
r = run("compare", W("rev", "base"), W("rev", "act"), "--candidates", W("rev", "cands"))
cands = sorted(os.path.relpath(os.path.join(d, f), W("rev", "cands"))
               for d, _, fs in os.walk(W("rev", "cands")) for f in fs)
ok(r.returncode == 2 and cands == ["moved.diff.png", "moved.png", "new.png", "sub/deep.diff.png",
                                   "sub/deep.png"]
   and {n: data(W("rev", "base", n)) for n in before} == before,
   f"--candidates writes the would-be baselines whose pixels differ and their diffs, the "
   f"baselines untouched, and the run still fails (exit {r.returncode}): {cands}")
ok("--approve" in r.stdout, f"the output says how to approve ({r.stdout.strip().splitlines()[-1]})")
r = run("compare", "--approve", W("rev", "cands"), W("rev", "base"))
ok(r.returncode == 0 and data(W("rev", "base", "moved.png")) == data(W("m.png"))
   and data(W("rev", "base", "sub", "deep.png")) == data(W("m2.png"))
   and data(W("rev", "base", "new.png")) == data(W("a.png"))
   and not os.path.exists(W("rev", "base", "moved.diff.png")),
   f"--approve copies the candidates over the baselines, not the diffs ({r.stdout.strip()})")
r = run("compare", W("rev", "base"), W("rev", "act"))
ok(r.returncode == 0, f"after approval the run passes ({r.stdout.strip().splitlines()[-1]})")
mtime = os.stat(W("rev", "base", "moved.png")).st_mtime_ns
r = run("compare", "--approve", W("rev", "cands"), W("rev", "base"))
ok(os.stat(W("rev", "base", "moved.png")).st_mtime_ns == mtime and "unchanged" in r.stdout,
   "approving again leaves baselines whose pixels are unchanged untouched")

# ---- a summary for the pull request ----
for n, (e, a) in {"same.png": ("m2.png", "m2.png"), "moved.png": ("a.png", "m.png")}.items():
    put(e, "sum", "base", n)
    put(a, "sum", "act", n)
r = run("compare", W("sum", "base"), W("sum", "act"), "--summary", W("summary.md"), "--report",
        W("rep.html"))
md = open(W("summary.md")).read()
rows = [l for l in md.splitlines() if l.startswith("| ") and not l.startswith("| image")]
ok(md.startswith("### springpend compare: FAIL") and "| image | verdict | measured | allowed |" in md
   and any("moved.png" in l and "px differ" in l and "fail" in l for l in rows)
   and "rep.html" in md and len(md) < 65536,
   f"--summary: status, counts, a table of failures with measured against allowed, the report "
   f"({len(md)} bytes, {len(rows)} rows)")
ok(all("same.png" not in l for l in rows), "the summary's table lists failures only")

# ---- subfolders, videos in folder mode, wildcard sections ----
put("a.png", "tree", "base", "top.png")
put("a.png", "tree", "base", "ui", "hud", "clock.png")
put("m.png", "tree", "act", "ui", "hud", "clock.png")
put("a.png", "tree", "act", "top.png")
for side, angle in (("base", 10), ("act", 10)):
    os.makedirs(W("tree", side, "vid"), exist_ok=True)
    run("render", default, "--size", "96x64", "--fps", "10", "--set", "video.duration=0.3",
        "--set", f"initial.angle={angle}", "-o", W("tree", side, "vid", "clip.mp4"), "-q")
run("render", default, "--size", "96x64", "--fps", "10", "--set", "video.duration=0.3",
    "--set", "initial.angle=30", "--set", "view.theme=light", "-o",
    W("tree", "act", "vid", "other.mp4"), "-q")
shutil.copy(W("tree", "base", "vid", "clip.mp4"), W("tree", "base", "vid", "other.mp4"))
r = run("compare", W("tree", "base"), W("tree", "act"), "--json")
names = {x["name"]: x["verdict"] for x in json.loads(r.stdout)["results"]}
ok(names == {"top.png": "pass", "ui/hud/clock.png": "fail", "vid/clip.mp4": "pass",
             "vid/other.mp4": "fail"},
   f"folder mode walks subfolders and compares videos too ({names})")
with open(W("tree", "base", "compare.ini"), "w") as f:
    f.write("[ui/*/*.png]\nmask = 0, 0, 160, 120\n[other.*]\nmax_pixels = 100%\n")
r = run("compare", W("tree", "base"), W("tree", "act"))
ok(r.returncode == 0 and "19200 pixels masked" in r.stdout,
   f"wildcard sections: [ui/*/*.png] by path, [other.*] by file name ({r.stdout.strip()})")
with open(W("tree", "base", "compare.ini"), "w") as f:
    f.write("[*.png]\nmax_pixels = 100%\n[top.png]\nmax_pixels = 0\n")
r = run("compare", W("tree", "base"), W("tree", "act"), "--json")
res = {x["name"]: x["tolerance"] and x["tolerance"]["max_differing_pixels"]
       for x in json.loads(r.stdout)["results"]}
ok(res.get("ui/hud/clock.png") == 19200 and res.get("top.png") == 0,
   f"a file's own section overrides a wildcard section ({res})")
os.remove(W("tree", "base", "compare.ini"))
r = run("compare", W("tree", "base"), W("tree", "act"), "--junit", W("tree.xml"))
suites = sorted(s.get("name").rsplit("base", 1)[-1] for s in ET.parse(W("tree.xml")).getroot()
                .iter("testsuite"))
ok(suites == ["", "/ui/hud", "/vid"], f"JUnit: a suite per folder ({suites})")

# ---- threads: the same records whatever --jobs says ----
r1 = run("compare", W("tree", "base"), W("tree", "act"), "--json", "--jobs", "1")
r4 = run("compare", W("tree", "base"), W("tree", "act"), "--json", "--jobs", "4")
strip = lambda s: [{k: v for k, v in x.items() if k != "seconds"} for x in json.loads(s)["results"]]
ok(r1.returncode == r4.returncode == 1 and strip(r1.stdout) == strip(r4.stdout),
   "--jobs 1 and --jobs 4 give the same records, in the same order")
r = run("compare", W("tree", "base"), W("tree", "act"), "--jobs", "0")
ok(r.returncode == 2 and "--jobs 0" in r.stderr, f"--jobs 0 is refused ({r.stderr.strip()})")

# ---- the HTML report ----
r = run("compare", W("sum", "base"), W("sum", "act"), "--report", W("all.html"))
run("compare", W("sum", "base"), W("sum", "act"), "--report", W("fails.html"),
    "--report-failures-only")
full, fails = open(W("all.html")).read(), open(W("fails.html")).read()
same = base64.b64encode(data(W("sum", "base", "same.png"))).decode()
ok(full.count(same) == 1 and "identical pixels to the expected image" in full,
   f"an identical pair embeds its image once ({full.count(same)} times)")
ok('class="row v-pass"' not in fails and 'class="row v-fail"' in fails
   and re.search(r"\d+ passing images? not shown", fails),
   "--report-failures-only: failures and errors only, and how many passes were left out")
put("a.png", "mask", "base", "one.png")
put("m.png", "mask", "act", "one.png")
with open(W("mask", "base", "compare.ini"), "w") as f:
    f.write("[one.png]\nmask = 16, 12, 40, 30\n")
run("compare", W("mask", "base"), W("mask", "act"), "--report", W("mask.html"))
h = open(W("mask.html")).read()
ok('class="mask"' in h and "left:10.0000%;top:10.0000%;width:25.0000%;height:25.0000%" in h,
   "masks are drawn over the images, placed in percent of the image")
ok("max-width:280px" not in h.split("<script>")[0] and 'data-z="4"' in h,
   "images at full size, with zoom buttons")

done()
