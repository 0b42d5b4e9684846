#!/usr/bin/env python3
"""springpend tests (issue 28): what the thirteenth attacker's pass found in
compare (/work/notes/attack13.md, copied to doc/notes/2026-11-27/):
- attack13 #18: --candidates DIR over a folder an earlier run filled kept
  that run's candidates, which the printed --approve then installed: a
  candidates folder that holds images already is refused, exit 2;
- attack13 #16: a rule's option without its rule (--tol without --metric
  rms, --threshold without pixelmatch, --max-diff/--max-pixels under rms)
  and --report-failures-only without --report were taken and ignored:
  refused, exit 2 (a compare.ini section's metric counts as in force);
- attack13 #24: the Markdown summary of more than 50 failures sent the
  reader to "the report" when none was asked for: it names where the rest
  are (the report, the JUnit file, or compare's output);
- attack13 #12: two --update=missing runs at once both "added" every
  image, the second replacing the first's new baselines: an added baseline
  never replaces one that appeared meanwhile (said, not added).
usage: test_attack13_compare.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import shutil
import subprocess

import sptest
from sptest import done, err, ok

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack13-compare")
default = os.path.join(scenes, "default.ini")
stiff = os.path.join(scenes, "stiff.ini")


def still(scene, at, out, size="160x90"):
    r = run("still", scene, "--at", at, "--size", size, "-o", out, "-q")
    assert r.returncode == 0, err(r)


def same(a, b):
    with open(a, "rb") as fa, open(b, "rb") as fb:
        return fa.read() == fb.read()


# ---- attack13 #18: a candidates folder that holds images already is refused ----------------
for d in ("e", "a"):
    os.makedirs(path("cand", d), exist_ok=True)
still(default, "0", path("cand", "e", "x.png"))
still(default, "1", path("cand", "e", "y.png"))
still(stiff, "0", path("cand", "a", "x.png"))
shutil.copy(path("cand", "e", "y.png"), path("cand", "a", "y.png"))
c = path("cand", "c")
r = run("compare", path("cand", "e"), path("cand", "a"), "--candidates", c, "-q")
ok(r.returncode == 1 and sorted(os.listdir(c)) == ["x.diff.png", "x.png"],
   f"run 1: x fails, its candidate and diff in c (exit {r.returncode}: {sorted(os.listdir(c))})")
shutil.copy(path("cand", "e", "x.png"), path("cand", "a", "x.png"))   # x fixed
still(stiff, "1", path("cand", "a", "y.png"))                         # y changed on purpose
r = run("compare", path("cand", "e"), path("cand", "a"), "--candidates", c)
ok(r.returncode == 2 and "holds 2 images already" in err(r)
   and sorted(os.listdir(c)) == ["x.diff.png", "x.png"],
   f"run 2 over c (run 1's candidate in it): refused, nothing written, exit 2 (exit "
   f"{r.returncode}: {sorted(os.listdir(c))}; {err(r)[-200:]!r})")
os.makedirs(path("cand", "c2"), exist_ok=True)
r = run("compare", path("cand", "e"), path("cand", "a"), "--candidates", path("cand", "c2"))
ok(r.returncode == 1 and sorted(os.listdir(path("cand", "c2"))) == ["y.diff.png", "y.png"],
   f"an empty existing folder is taken: y's candidate alone (exit {r.returncode}: "
   f"{sorted(os.listdir(path('cand', 'c2')))}; {err(r)[-160:]!r})")

# ---- attack13 #16: an option no rule in force reads is refused ------------------------------
os.makedirs(path("rule", "e"), exist_ok=True)
os.makedirs(path("rule", "a"), exist_ok=True)
E, A = path("rule", "e", "x.png"), path("rule", "a", "x.png")
still(default, "0", E)
still(stiff, "0", A)
for opts, said in ((["--tol", "100"], "--tol: no rule in force reads it"),
                   (["--threshold", "1"], "--threshold: no rule in force reads it"),
                   (["--metric", "rms", "--max-diff", "255"], "--max-diff: no rule in force"),
                   (["--metric", "rms", "--max-pixels", "100%"], "--max-pixels: no rule in force"),
                   (["--metric", "pixelmatch", "--tol", "100"], "--tol: no rule in force"),
                   (["--report-failures-only", "--json"], "--report-failures-only shapes the "
                                                          "HTML page: it needs --report")):
    r = run("compare", E, A, *opts)
    ok(r.returncode == 2 and said in err(r) and not r.stdout.strip(),
       f"compare {' '.join(opts)}: refused, exit 2, nothing compared (exit {r.returncode}: "
       f"{err(r)[-200:]!r})")
for opts, code in ((["--metric", "rms", "--tol", "100"], 0),
                   (["--metric", "pixelmatch", "--max-pixels", "100%"], 0),
                   (["--max-diff", "255", "--max-pixels", "100%"], 0),
                   (["--metric", "pixelmatch", "--threshold", "1"], 0)):
    r = run("compare", E, A, *opts)
    ok(r.returncode == code, f"compare {' '.join(opts)}: taken, exit {code} (exit "
       f"{r.returncode}: {err(r)[-160:]!r})")
with open(path("rule", "e", "compare.ini"), "w") as f:
    f.write("[x.png]\nmetric = rms\n")
r = run("compare", E, A, "--tol", "100")
ok(r.returncode == 0 and "<= tol 100" in r.stdout.decode(),
   f"--tol with a compare.ini section of metric = rms: read there, exit 0 (exit "
   f"{r.returncode}: {r.stdout.decode()[:160]!r} {err(r)[-120:]!r})")
os.remove(path("rule", "e", "compare.ini"))

# ---- attack13 #24: the summary names where the failures past 50 are ------------------------
for d in ("e", "a"):
    os.makedirs(path("many", d), exist_ok=True)
still(default, "0", path("many", "x.png"), "64x36")
still(stiff, "0.5", path("many", "y.png"), "64x36")
for i in range(1, 61):
    shutil.copy(path("many", "x.png"), path("many", "e", f"f{i}.png"))
    shutil.copy(path("many", "y.png"), path("many", "a", f"f{i}.png"))
in_many = sptest.runner_bytes(exe, path("many"))
for extra, want in (([], "not listed here: compare's output lists them"),
                    (["--junit", "j.xml"], "not listed here: the JUnit file `j.xml`"),
                    (["--report", "r.html"], "and 10 more failures and errors: see the report.")):
    for f in ("s.md", "j.xml", "r.html"):
        if os.path.exists(path("many", f)):
            os.remove(path("many", f))
    r = in_many("compare", "e", "a", "--summary", "s.md", *extra, timeout=180)
    text = open(path("many", "s.md")).read()
    ok(r.returncode == 1 and want in text and ("see the report" in text) == ("--report" in extra)
       and "and 10 more" in text,
       f"--summary {' '.join(extra) or '(no report)'}: the 10 past 50 are said to be where "
       f"they are (exit {r.returncode}: {text[-200:]!r})")

# ---- attack13 #12: two --update=missing at once never replace each other's baselines ------
for d in ("e", "a1", "a2"):
    shutil.rmtree(path("cu", d), ignore_errors=True)
    os.makedirs(path("cu", d))
n = 12
for i in range(n):
    still(default, f"0.{i + 1}", path("cu", "a1", f"x{i}.png"))
    still(stiff, f"0.{i + 1}", path("cu", "a2", f"x{i}.png"))
bad, tries = [], 3
for t in range(tries):
    for f in os.listdir(path("cu", "e")):
        os.remove(path("cu", "e", f))
    ps = [subprocess.Popen([exe, "compare", "e", a, "--update=missing"], cwd=path("cu"),
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE) for a in ("a1", "a2")]
    outs = [p.communicate(timeout=120)[0].decode() for p in ps]
    for i in range(n):
        name = f"x{i}.png"
        said = [f"added    e/{name}" in o or f"added e/{name}" in o for o in outs]
        here = [same(path("cu", "e", name), path("cu", a, name)) for a in ("a1", "a2")]
        # whoever says it added the baseline is the one whose baseline is there
        if said.count(True) != 1 or here != said:
            bad.append((t, name, said, here))
ok(not bad, f"two --update=missing at once, {tries} times, {n} images: each baseline is the "
   f"one the run that said 'added' wrote, never replaced by the other ({bad[:4]})")

done()
