#!/usr/bin/env python3
"""springpend tests: compare --metric pixelmatch against the npm package
itself. mapbox/pixelmatch 5.3.0 and pngjs 7.0.0, installed with npm into the
build folder (once; reused), run under node on the same pairs must count the
same differing pixels at several thresholds. Then what the rule is for: it
tolerates anti-aliasing differences of text and curves (the same drawing
moved by 0.1 px, rasterised by librsvg) that the default rule fails, and
still catches a change of stiffness. Without node and npm (or without the
registry) the comparison with the package is skipped; the rest runs.
usage: test_pixelmatch.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR (TAP)"""
import json
import os
import shutil
import subprocess
import sys

from sptest import done, ok, skip

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
out = os.path.abspath(sys.argv[3])
work = os.path.join(out, "pixelmatch")
npm_dir = os.path.join(out, "npm-pixelmatch")  # kept between runs
default = os.path.join(src, "..", "scenes", "default.ini")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


def run(*args):
    return subprocess.run([exe, *args], capture_output=True, text=True, cwd=work, timeout=120)


def W(*p):
    return os.path.join(work, *p)


def ours(a, b, threshold):
    r = run("compare", W(a), W(b), "--metric", "pixelmatch", "--threshold", str(threshold),
            "--json")
    rec = json.loads(r.stdout)["results"][0]
    m = rec["measured"]
    return r.returncode, m.get("differing_pixels", 0) if not rec["exact"] else 0, \
        m.get("antialiased_pixels", 0)


# The pairs: springpend's own renders, and one drawing rasterised by librsvg
# at two sub-pixel offsets.
# (with the video's marks of now, as its frames: view.cursor = true)
panels = ["--size", "640x360", "--set", "view.panels=all", "--set", "view.hud=true",
          "--set", "view.cursor=true"]
for name, extra in (("base", ["--at", "3"]), ("later", ["--at", "3.003"]),
                    ("moved", ["--at", "3.05"]),
                    ("stiff", ["--at", "3", "--set", "pendulum.stiffness=2.2"]),
                    ("clear", ["--at", "3", "--set", "view.background=transparent"]),
                    ("clear2", ["--at", "3.05", "--set", "view.background=transparent"])):
    run("still", default, *panels, *extra, "-o", f"{name}.png", "-q")
pairs = [("base.png", "later.png"), ("base.png", "moved.png"), ("base.png", "stiff.png"),
         ("clear.png", "clear2.png")]
svg = ('<svg xmlns="http://www.w3.org/2000/svg" width="320" height="120">'
       '<rect width="320" height="120" fill="#14161c"/><g transform="translate({o},{o})">'
       '<text x="12" y="48" font-family="DejaVu Sans" font-size="30" fill="#e8e8f0">'
       'Spring k=2 N/m</text><circle cx="250" cy="80" r="22" fill="#f0a030"/>'
       '<path d="M20 100 C 80 60, 140 120, 200 80" stroke="#60c0ff" stroke-width="2" '
       'fill="none"/></g></svg>')
have_rsvg = shutil.which("rsvg-convert") is not None
if have_rsvg:
    for o in ("0", "0.1", "0.25"):
        with open(W(f"aa_{o}.svg"), "w") as f:
            f.write(svg.format(o=o))
        subprocess.run(["rsvg-convert", W(f"aa_{o}.svg"), "-o", W(f"aa_{o}.png")], check=True)
    pairs += [("aa_0.png", "aa_0.1.png"), ("aa_0.png", "aa_0.25.png")]

# ---- the npm package on the same pairs ----
node, npm = shutil.which("node"), shutil.which("npm")
why_not = None
if not (node and npm):
    why_not = "node and npm are not installed (Debian: nodejs npm)"
elif not os.path.exists(os.path.join(npm_dir, "node_modules", "pixelmatch", "package.json")):
    os.makedirs(npm_dir, exist_ok=True)
    try:
        inst = subprocess.run([npm, "install", "--no-audit", "--no-fund", "--silent",
                               "--prefix", npm_dir, "pixelmatch@5.3.0", "pngjs@7.0.0"],
                              capture_output=True, text=True, timeout=240)
        if inst.returncode:
            why_not = f"npm install failed (offline?): {inst.stderr.strip()[-200:]}"
    except subprocess.TimeoutExpired:
        why_not = "npm install took over 240 s"
if why_not is None:
    script = os.path.join(work, "count.js")
    with open(script, "w") as f:
        f.write("const fs = require('fs'), {PNG} = require('pngjs'), "
                "pixelmatch = require('pixelmatch');\n"
                "const [a, b, t] = process.argv.slice(2);\n"
                "const A = PNG.sync.read(fs.readFileSync(a)), B = PNG.sync.read(fs.readFileSync(b));\n"
                "console.log(pixelmatch(A.data, B.data, null, A.width, A.height, {threshold: +t}));\n")
    env = dict(os.environ, NODE_PATH=os.path.join(npm_dir, "node_modules"))
    for a, b in pairs:
        for t in (0.05, 0.1, 0.2):
            theirs = subprocess.run([node, script, W(a), W(b), str(t)], capture_output=True,
                                    text=True, env=env, timeout=120)
            mine = ours(a, b, t)
            ok(theirs.returncode == 0 and theirs.stdout.strip() == str(mine[1]),
               f"{a} vs {b}, threshold {t}: npm pixelmatch counts {theirs.stdout.strip()} "
               f"{theirs.stderr.strip()[-100:]}, springpend {mine[1]}")
else:
    for a, b in pairs:
        skip(f"{a} vs {b}: the same counts as npm pixelmatch", why_not)

# ---- what it is for ----
if have_rsvg:
    rc_ref = run("compare", W("aa_0.png"), W("aa_0.1.png")).returncode
    rc, diff, aa = ours("aa_0.png", "aa_0.1.png", 0.1)
    ok(rc_ref == 1 and rc == 0 and aa > 10 * max(diff, 1),
       f"text and curves 0.1 px apart: the default rule fails, pixelmatch passes "
       f"({diff} pixels differ, {aa} taken for anti-aliasing)")
else:
    skip("text and curves 0.1 px apart", "rsvg-convert is not installed (librsvg2-bin)")
rc_ref = run("compare", W("base.png"), W("later.png")).returncode
rc, diff, aa = ours("base.png", "later.png", 0.1)
ok(rc_ref == 1 and rc == 0, f"the pendulum 3 ms later (curves moved under a pixel): the default "
   f"rule fails, pixelmatch passes ({diff} pixels differ)")
rc, diff, aa = ours("base.png", "stiff.png", 0.1)
ok(rc == 1 and diff > 230, f"a stiffness of 2.2 N/m instead of 2 fails ({diff} pixels differ, "
   f"230 allowed)")
r = run("compare", W("base.png"), W("stiff.png"), "--metric", "pixelmatch", "--threshold", "1.5")
ok(r.returncode == 2 and "--threshold 1.5" in r.stderr, f"--threshold beyond 1 is refused ({r.stderr.strip()})")

done()
