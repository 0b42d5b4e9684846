#!/usr/bin/env python3
"""springpend tests (issue 28): the twelfth attacker's pass
(doc/notes/2026-11-27/attack12.md), what is seen:
- #17: a ZWNJ or ZWJ between consonant + virama and a consonant was written
  raw (scene --command, compare's notes, file names) in the scripts whose
  virama joins only a few consonants (Tamil, Gurmukhi, Sinhala), where it
  draws nothing. The oracle is the picture: a still with and without the
  joiner (decoded by ffmpeg, not by springpend); the record keeps the
  joiner raw exactly when their pixels differ, else writes \\u200c / \\u200d.
  Controls where it draws: Tamil KSSA and SRI, Gurmukhi's subjoined HA and
  post-base YA, Sinhala's yansaya, rakaransaya, repaya and a touching
  letter, Malayalam and Devanagari conjuncts (tests/unit/
  test_joiner_shaping.c checks every pair of the three scripts by shaping);
- #19: at a font size the size check allowed, a wide (monospace) view.font
  ran the heads-up time ("t = 987654.32 s", DejaVu Sans Mono, 640x360, 24
  px) under the first panel: refused, exit 2, from where the size was set
  (--set, FILE:LINE), saying the largest size that fits with this font;
  at that size the time keeps off the panel's box, measured in the pixels:
  in the time's rows a still with the HUD and one without differ only
  left of the box's left edge (found by its fill colour), 3 px clear of it
  (the box is drawn over what runs under it) (tests/unit/
  test_legibility.c checks the layout with both fonts at five sizes).
usage: test_attack12_seen.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import shutil
import subprocess

import sptest
from sptest import done, ok, skip

exe, src, work, run = sptest.setup("attack12-seen", [])
scenes = os.path.abspath(os.path.join(src, "..", "scenes"))
default = os.path.join(scenes, "default.ini")
command = sptest.scene_command(sptest.runner_bytes(exe, work))

ZWNJ, ZWJ = "\u200c", "\u200d"
TA_KA, TA_NA, TA_RA, TA_SA, TA_SSA, TA_II, PULLI = "\u0b95", "\u0ba8", "\u0bb0", "\u0bb8", "\u0bb7", "\u0bc0", "\u0bcd"
GU_KA, GU_HA, GU_YA, GU_V = "\u0a15", "\u0a39", "\u0a2f", "\u0a4d"
SI_KA, SI_YA, SI_RA, SI_SSA, SI_VA, AL = "\u0d9a", "\u0dba", "\u0dbb", "\u0dc2", "\u0dc0", "\u0dca"
# (title with the joiner, why); the same title without it is the control
cases = [
    (TA_KA + PULLI + ZWNJ + TA_KA, "Tamil KA PULLI ZWNJ KA (the pulli shown either way)"),
    (TA_NA + PULLI + ZWNJ + TA_RA, "Tamil NA PULLI ZWNJ RA"),
    (TA_KA + PULLI + ZWJ + TA_KA, "Tamil KA PULLI ZWJ KA"),
    (TA_SA + PULLI + ZWNJ + TA_RA, "Tamil SA PULLI ZWNJ RA (SRI needs the II)"),
    (TA_KA + PULLI + ZWNJ + TA_SSA, "Tamil KA PULLI ZWNJ SSA (breaks KSSA)"),
    (TA_KA + PULLI + ZWJ + TA_SSA, "Tamil KA PULLI ZWJ SSA (breaks KSSA)"),
    (TA_SA + PULLI + ZWNJ + TA_RA + TA_II, "Tamil SA PULLI ZWNJ RA II (breaks SRI)"),
    (GU_KA + GU_V + ZWNJ + GU_KA, "Gurmukhi KA VIRAMA ZWNJ KA"),
    (GU_KA + GU_V + ZWJ + GU_KA, "Gurmukhi KA VIRAMA ZWJ KA"),
    (GU_KA + GU_V + ZWNJ + GU_HA, "Gurmukhi KA VIRAMA ZWNJ HA (breaks the subjoined HA)"),
    (GU_KA + GU_V + ZWJ + GU_YA, "Gurmukhi KA VIRAMA ZWJ YA (breaks the post-base YA)"),
    (SI_KA + AL + ZWNJ + SI_KA, "Sinhala KA AL-LAKUNA ZWNJ KA"),
    (SI_KA + AL + ZWNJ + SI_YA, "Sinhala KA AL-LAKUNA ZWNJ YA (only a ZWJ joins)"),
    (SI_KA + AL + ZWJ + SI_KA, "Sinhala KA AL-LAKUNA ZWJ KA (no touching KA+KA)"),
    (SI_KA + AL + ZWJ + SI_YA, "Sinhala KA AL-LAKUNA ZWJ YA (yansaya)"),
    (SI_KA + AL + ZWJ + SI_RA, "Sinhala KA AL-LAKUNA ZWJ RA (rakaransaya)"),
    (SI_RA + AL + ZWJ + SI_KA, "Sinhala RA AL-LAKUNA ZWJ KA (repaya)"),
    (SI_KA + AL + ZWJ + SI_VA, "Sinhala KA AL-LAKUNA ZWJ VA (a touching letter)"),
    ("\u0d15\u0d4d" + ZWNJ + "\u0d15", "Malayalam KA VIRAMA ZWNJ KA (breaks the conjunct)"),
    ("\u0915\u094d" + ZWNJ + "\u0915", "Devanagari KA VIRAMA ZWNJ KA (breaks the conjunct)"),
]


def pixels(name):
    """The picture's RGB bytes, decoded by ffmpeg (not by springpend)."""
    return subprocess.run(["ffmpeg", "-v", "error", "-i", os.path.join(work, name), "-f", "rawvideo",
                           "-pix_fmt", "rgb24", "-"], capture_output=True, check=True).stdout


for i, (title, why) in enumerate(cases):
    if not shutil.which("ffmpeg"):
        skip(f"#17: {why}", "ffmpeg missing")
        continue
    bare = title.replace(ZWNJ, "").replace(ZWJ, "")
    pix = []
    for name, t in ((f"j{i}.png", title), (f"n{i}.png", bare)):
        r = run("still", default, "--at", "0", "--size", "640x200", "--set", "view.panels=none",
                "--set", "view.hud=false", "--set", f"view.title={t}", "-o", name, "-q")
        pix.append(pixels(name) if r.returncode == 0 else None)
    if pix[0] is None or pix[1] is None:
        ok(False, f"#17: {why}: the stills")
        continue
    drawn = pix[0] != pix[1]
    joiner = ZWNJ if ZWNJ in title else ZWJ
    said = command(os.path.join(work, f"j{i}.png"))
    raw = f"view.title={title}" in said
    escaped = "view.title=" + title.replace(joiner, "\\u%04x" % ord(joiner)) in said
    ok(raw == drawn and escaped != drawn,
       f"#17: {why}: the joiner {'changes' if drawn else 'changes no'} pixels and the record "
       f"writes it {'raw' if raw else 'escaped' if escaped else '?'} ({said[-60:]!r})")

# 19: a video whose time reaches six digits (100000.99 s; a monospace
# font's digits are all as wide), integrated coarsely (yoshida4 keeps the
# energy at dt = 0.05) and at 4 fps (under the 1e6 frames a still spans)
import re

text = open(default).read()
text = re.sub(r"(?m)^duration\s*=.*$", "duration = 100001", text)
text = re.sub(r"(?m)^fps\s*=.*$", "fps = 4", text)
with open(os.path.join(work, "long.ini"), "w") as f:
    f.write(text)
with open(os.path.join(work, "mono.ini"), "w") as f:
    f.write(text + "\n[view]\nfont = DejaVu Sans Mono\nfont_size = 24\n")
font_line = (text + "\n[view]\nfont = DejaVu Sans Mono\n").count("\n") + 1
fast = ["--set", "integrator.method=yoshida4", "--set", "integrator.dt=0.05", "--set", "view.colorbar=false"]
MONO = ["--set", "view.font=DejaVu Sans Mono"]

r = run("still", "long.ini", "--at", "1", "--size", "640x360", "--set", "view.font_size=24", *MONO, *fast,
        "-o", "m24.png")
said = re.search(r"at most (\d+) px with this font at this size", r.stderr)
ok(r.returncode == 2 and r.stderr.startswith("springpend: --set view.font_size: text of 24 px") and said
   and int(said.group(1)) < 24 and not os.path.exists(os.path.join(work, "m24.png")),
   f"#19: 24 px in DejaVu Sans Mono at 640x360, a 100001 s video: refused, exit 2, the largest size "
   f"said, nothing written (exit {r.returncode}: {r.stderr.strip()[-260:]})")
largest = int(said.group(1)) if said else 24
r = run("still", "mono.ini", "--at", "1", "--size", "640x360", *fast, "-o", "m24f.png")
ok(r.returncode == 2 and r.stderr.startswith(f"springpend: mono.ini:{font_line}: text of 24 px")
   and "with this font at this size" in r.stderr and not os.path.exists(os.path.join(work, "m24f.png")),
   f"#19: the same from the scene file: mono.ini:{font_line} named, exit 2 (exit {r.returncode}: "
   f"{r.stderr.strip()[-200:]})")


def time_clear(name, px, font):
    """Stills at t = 100000.99 s with and without the HUD, px body text in
    font: (whether the HUD put no pixel right of the first panel's box
    edge in the time's rows, what was seen)."""
    pix = {}
    for hud in ("true", "false"):
        r = run("still", "long.ini", "--at", "100000.99", "--size", "640x360", "--set",
                f"view.font_size={px}", *font, *fast, "--set", f"view.hud={hud}",
                "-o", f"{name}-{hud}.png", "-q")
        if r.returncode != 0 or not shutil.which("ffmpeg"):
            return False, f"still exit {r.returncode}: {r.stderr.strip()[-160:]}"
        pix[hud] = pixels(f"{name}-{hud}.png")
    W = 640
    px_at = lambda img, x, y: img[(y * W + x) * 3:(y * W + x) * 3 + 3]
    on, off = pix["true"], pix["false"]
    # the time's rows: from the first row where the two differ left of x 40
    # ("t =") to the next row where they are alike there again
    rows = [y for y in range(120) if any(px_at(on, x, y) != px_at(off, x, y) for x in range(40))]
    if not rows:
        return False, "no time drawn"
    band = [y for y in range(rows[0], 120) if y in rows]
    band = band[:next((i for i in range(1, len(band)) if band[i] != band[i - 1] + 1), len(band))]
    fill = px_at(off, W - 12, band[len(band) // 2])  # the first panel's fill, by its right edge
    edge = min(next((x for x in range(W // 4, W) if px_at(off, x, y) == fill), W) for y in band)
    # the HUD's ink: where the two differ; the panel is drawn over what runs
    # under it (the 's' cut), so the ink must end 3 columns before the box
    inked = [(x, y) for y in band for x in range(W) if px_at(on, x, y) != px_at(off, x, y)]
    right = max(x for x, y in inked)
    return (edge < W - 20 and right < edge - 3,
            f"time rows {band[0]}..{band[-1]}, its ink to x {right}, the panel's box from x {edge}")


good, seen = time_clear("mono", largest, MONO)
ok(good, f"#19: at {largest} px (the largest said) in DejaVu Sans Mono, t = 100000.99 s: the time keeps "
   f"off the first panel's box ({seen})")
good, seen = time_clear("sans", 24, [])
ok(good, f"#19: at 24 px in the default DejaVu Sans, t = 100000.99 s: taken, the time off the panel's "
   f"box ({seen})")

done()
