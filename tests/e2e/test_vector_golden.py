#!/usr/bin/env python3
"""springpend tests: SVG and PDF stills rasterised (rsvg-convert, pdftoppm)
against reviewed golden PNGs under the golden rule of test_golden.c (at most
0.01% of the pixels more than 1 level off). The figures test compares a
vector figure with the PNG of the same frame in 8x8 blocks at 32 levels,
which lets a change of the vector drawing alone (a ball's shading 10% darker
in cairo) pass; this catches it. SP_UPDATE_GOLDEN=1 writes the goldens
(review them before committing). Skips without rsvg-convert or pdftoppm.
usage: test_vector_golden.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP)"""
import os
import shutil
import subprocess
import sys

from sptest import done, ok, runner

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "vector-golden"))
if not shutil.which("rsvg-convert") or not shutil.which("pdftoppm"):
    print("1..0 # SKIP rsvg-convert (librsvg2-bin) or pdftoppm (poppler-utils) is not installed")
    sys.exit(77)
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
run = runner(exe, work)
RULE = ["--max-diff", "1", "--max-pixels", "0.01%"]
CASES = [("vector_default", "default.ini", 3, ["--set", "view.panels=none", "--set", "view.hud=false"]),
         ("vector_panels", "resonance.ini", 20, ["--set", "view.panels=r,phase", "--set",
                                                 "view.title=Spring pendulum", "--set", "view.hud=true"])]
for name, scene, at, extra in CASES:
    for ext in ("svg", "pdf"):
        fig = os.path.join(work, f"{name}.{ext}")
        r = run("still", os.path.join(src, "..", "scenes", scene), "--at", str(at), "--size", "480x270",
                "-o", fig, "-q", *extra)
        png = os.path.join(work, f"{name}_{ext}.png")
        cmd = (["rsvg-convert", fig, "-o", png] if ext == "svg" else
               ["pdftoppm", "-r", "72", "-png", "-singlefile", fig, png[:-4]])
        made = r.returncode == 0 and subprocess.run(cmd, capture_output=True).returncode == 0
        golden = os.path.join(src, "golden", f"{name}_{ext}.png")
        if made and os.environ.get("SP_UPDATE_GOLDEN"):
            shutil.copy(png, golden)
            print(f"# {golden} updated")
        c = run("compare", golden, png, *RULE) if made else None
        ok(made and c.returncode == 0,
           f"{name}.{ext} rasterised equals its golden (0.01% of pixels more than 1 level off): "
           f"{(c.stdout + c.stderr).strip()[:200] if c else r.stderr.strip()[:200]}")
done()
