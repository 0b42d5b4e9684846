#!/usr/bin/env python3
"""springpend tests: a sweep figure is drawn and recorded as a still is.
Its text is the stills' text (issue 19):
laid out by the text module (HarfBuzz, FriBidi, fontconfig), in PNG, SVG
and PDF alike:
  - an Arabic and CJK title is real text in the PDF (pdftotext returns it,
    as from pango-view's PDF), as wide in every format as pango-view draws
    it, an Arabic word's letters join into one run of ink (as pango-view
    draws it) and CJK characters draw distinct ink;
  - [view] font is honoured (pdffonts), an unknown family is exit 2;
  - a character no installed font has, in the title or a label, is exit 2
    naming it, before the sweep runs, with no file;
  - a title wraps to the figure's width; one that cannot fit is exit 2.
Its PNG carries a still's provenance chunks, and `springpend scene` reads
the scene back, as from its PDF (also after --merge); a printed PNG has a
pHYs. Its axes are its own: an xlabel with '|' (a still's names per
panel) is refused, whatever the scene's panels. A PDF's bytes (still or
sweep) do not depend on where its fonts are installed (issue 20).
usage: test_sweep_figure.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR"""
import os
import shutil
import subprocess
import sys
import time

from sptest import done, need_scipy, ok, png_text, sets, setup

need_scipy()
import numpy as np  # noqa: E402
import sptext  # noqa: E402
from sptext import gray, ink_columns, joined, segments  # noqa: E402

exe, src, work, run = setup("sweep_figure", ("rsvg-convert", "pdftoppm", "pdftotext", "pdffonts",
                                             "pdfinfo", "ffmpeg", "pango-view", "fc-match"))
scene = os.path.join(src, "..", "scenes", "chaotic.ini")

GRID = ["--vary", "initial.angle=1:179:8", "--vary", "initial.length=0.8:1.6:6",
        "--measure", "lyapunov", "--time", "2"]
# The default figure (900 x 600 pt) at 2 px per pt: its title's 17 pt line
# starts 10 pt down at 80 pt from the left; nothing else is drawn there.
BAND = (slice(0, 64), slice(140, None))
FORMATS = ("png", "svg", "pdf")


def sweep(name, title=None, extra=None, args=()):
    """A Lyapunov map titled `title` on a light page; the CompletedProcess."""
    d = dict({"view.theme": "light"}, **(extra or {}))
    if title is not None:
        d["view.title"] = title
    return run("sweep", scene, *GRID, *args, *sets(d), "-o", name, "-q")


def band(name):
    """The title's band of a default figure, as ink (vector figures rasterised at 2 px per pt:
    an SVG's pt are 4/3 of rsvg-convert's px)."""
    return gray(os.path.join(work, name), zoom=1.5 if name.endswith(".svg") else 2)[BAND]


def pango(text, name):
    """pango-view's rendering of text at the title's size (17 pt at 2 px per pt), as ink."""
    subprocess.run(["pango-view", "-q", "--font", "DejaVu Sans 34px", "--text", text, "-o",
                    os.path.join(work, name)], check=True)
    return gray(os.path.join(work, name))


def pdf_words(path, below=1e9):
    """pdftotext -bbox's words whose bottom is above `below` pt, left to right as placed."""
    import xml.etree.ElementTree as ET
    out = subprocess.run(["pdftotext", "-bbox", path, "-"], capture_output=True, text=True).stdout
    root = ET.fromstring(out.replace('xmlns="http://www.w3.org/1999/xhtml"', ""))
    words = [(float(w.get("xMin")), w.text) for w in root.iter("word") if float(w.get("yMax")) < below]
    return [t for _, t in sorted(words)]


# Arabic and CJK in one title: real text, the same glyphs in every format and as pango-view's.
title = "البندول 弹簧摆"
ref = pango(title, "pango_title.png")
x0, x1 = ink_columns(ref)
ref_w = x1 - x0 + 1
for f in FORMATS:
    r = sweep(f"title.{f}", title)
    if not ok(r.returncode == 0, f"an Arabic and CJK title in {f.upper()}: written ({r.stderr.strip()})"):
        continue
    x0, x1 = ink_columns(band(f"title.{f}"))
    w = x1 - x0 + 1
    ok(abs(w - ref_w) <= 0.06 * ref_w, f"{f.upper()}: the title's ink is {w} px wide, "
       f"pango-view's {ref_w} px: the same glyphs (shaped, CJK from a fallback font)")
    if f == "pdf":
        # pdftotext orders a line's words by the page's main direction, and
        # this page's is left to right: the words whole, in either order
        got = sptext.pdf_text(os.path.join(work, "title.pdf")).splitlines()[0]
        ok(sorted(got.split()) == sorted(title.split()), f"PDF: pdftotext returns the title's "
           f"words whole ({got!r})")
        subprocess.run(["pango-view", "-q", "--font", "DejaVu Sans 17", "--text", title, "-o",
                        os.path.join(work, "pango.pdf")], check=True)
        ours, theirs = pdf_words(os.path.join(work, "title.pdf"), 30), \
            pdf_words(os.path.join(work, "pango.pdf"))
        ok(ours == theirs, f"PDF: the title's glyphs, left to right, are pango-view's ({ours})")

# An Arabic word's letters join into one run of ink, as pango-view draws
# them; apart they do not. CJK characters draw distinct ink.
word = "سلم"
ref = joined(pango(word, "pango_word.png"))
ok(ref > 0.9, f"pango-view draws {word} as one run of ink ({ref:.2f} of its width)")
for f in FORMATS:
    sweep(f"join.{f}", word)
    sweep(f"apart.{f}", " ".join(word))
    j, a = joined(band(f"join.{f}")), joined(band(f"apart.{f}"))
    ok(j > 0.9 and a < 0.6, f"Arabic in a sweep {f.upper()}: the word's letters join into one "
       f"run of ink ({j:.2f} of its width, as pango-view's {ref:.2f}); apart they do not ({a:.2f})")
    chars = "弹簧摆"
    r = sweep(f"cjk.{f}", "   ".join(chars))
    segs = segments(band(f"cjk.{f}")) if r.returncode == 0 else []
    same = [(i, k) for i in range(len(segs)) for k in range(i + 1, len(segs))
            if segs[i].shape == segs[k].shape and np.abs(segs[i] - segs[k]).max() < 48]
    ok(len(segs) == 3 and not same, f"CJK in a sweep {f.upper()}: 3 characters draw "
       f"{len(segs)} distinct inks (alike: {same})")

# [view] font: the family asked for is embedded; an unknown one is refused.
r = sweep("lm.pdf", "Latin Modern", {"view.font": "Latin Modern Roman"})
fonts = subprocess.run(["pdffonts", "lm.pdf"], capture_output=True, text=True, cwd=work).stdout
ok(r.returncode == 0 and "LMRoman10-Regular" in fonts and "DejaVu" not in fonts,
   f"view.font = Latin Modern Roman: the sweep PDF embeds it "
   f"({[line.split()[0] for line in fonts.splitlines()[2:]]})")
r = sweep("unknown.png", "x", {"view.font": "Latin Modren Roman"})
ok(r.returncode == 2 and '"Latin Modern Roman"' in r.stderr and
   not os.path.exists(os.path.join(work, "unknown.png")),
   f"an unknown family: exit {r.returncode}, close matches listed ({r.stderr.strip()[:140]})")

# A character no installed font has: refused before the sweep runs (this
# grid would take minutes), naming it, with nothing written.
BIG = ["--vary", "initial.angle=1:179:400", "--vary", "initial.length=0.8:1.6:400",
       "--measure", "lyapunov", "--time", "50"]
for key, value in (("view.title", "test tube \U0001f9ea"), ("view.xlabel", "angle \U0001f9ea"),
                   ("view.colorbar_label", "\U0001f9ea")):
    for f in ("png", "pdf"):
        t0 = time.monotonic()
        try:
            r = subprocess.run([exe, "sweep", scene, *BIG, "--set", f"{key}={value}", "--csv",
                                "m.csv", "-o", f"missing.{f}", "-q"], capture_output=True,
                               text=True, cwd=work, timeout=20)
        except subprocess.TimeoutExpired:  # killed: it ran the sweep
            r = subprocess.CompletedProcess([], -9, "", "still running after 20 s")
        took = time.monotonic() - t0
        ok(r.returncode == 2 and "U+1F9EA" in r.stderr and key in r.stderr and took < 20 and
           not os.path.exists(os.path.join(work, f"missing.{f}")) and
           not os.path.exists(os.path.join(work, "m.csv")),
           f"{key} with U+1F9EA in {f.upper()}: exit {r.returncode} after {took:.1f} s, nothing "
           f"written ({r.stderr.strip()[:120]})")

# A long title wraps to a column-wide figure and stays on the page; one that
# cannot fit is refused.
long_title = "البندول الزنبركي 弹簧摆: Federpendel, Größe und Energie über der Zeit"
for f in FORMATS:
    r = sweep(f"wrap.{f}", long_title, args=["--size", "8.6cm"])
    if not ok(r.returncode == 0, f"a long title at 8.6 cm in {f.upper()}: written ({r.stderr.strip()})"):
        continue
    img = gray(os.path.join(work, f"wrap.{f}"), zoom=2) if f != "png" else \
        gray(os.path.join(work, f"wrap.{f}"))
    # the plot's frame: the first row with an unbroken run of ink over 40% of the width
    runs = [max((len(k) for k in "".join("x" if v else " " for v in row).split()), default=0)
            for row in img > 96]
    top = next(y for y, n in enumerate(runs) if n > 0.4 * img.shape[1])
    rows = (img[:max(top - 12, 1)] > 96).any(axis=1)
    lines = sum(1 for y in range(1, len(rows)) if rows[y] and not rows[y - 1])
    x0, x1 = ink_columns(img[:max(top - 12, 1)])
    ok(lines >= 2 and x0 > 0 and x1 < img.shape[1] - 1,
       f"{f.upper()}: the title wraps onto {lines} lines within the page (ink from column {x0} "
       f"to {x1} of {img.shape[1]})")
r = sweep("toolong.pdf", " ".join(["Federpendel"] * 60), args=["--size", "8.6cm"])
ok(r.returncode == 2 and "cannot fit" in r.stderr and "--set view.title" in r.stderr and
   not os.path.exists(os.path.join(work, "toolong.pdf")),
   f"a title that cannot fit the figure: exit {r.returncode} ({r.stderr.strip()[:160]})")

# Provenance: a sweep PNG carries a still's chunks (but the time), and
# `springpend scene` prints its scene, the one its PDF records; so does a
# merged figure's.
r = sweep("prov.png")
chunks = png_text(os.path.join(work, "prov.png"), compressed=True) if r.returncode == 0 else {}
want = ["Software", "Source", "springpend.scene-sha256", "springpend.scene", "springpend.environment",
        "springpend.fonts", "springpend.scene-file"]
ok(all(k in chunks for k in want) and "DejaVu Sans (embedded in springpend)" in chunks.get("springpend.fonts", ""),
   f"a sweep PNG carries {sorted(chunks)}")
sweep("prov.pdf")
png_scene, pdf_scene = run("scene", "prov.png"), run("scene", "prov.pdf")
ok(png_scene.returncode == 0 and "[pendulum]" in png_scene.stdout and
   png_scene.stdout == pdf_scene.stdout, f"`springpend scene` reads the PNG's scene back, the PDF's "
   f"({png_scene.returncode}: {png_scene.stderr.strip()[:100]})")
for i in (1, 2):
    run("sweep", scene, *GRID, "--set", "view.theme=light", "--shard", f"{i}/2", "--csv", f"part{i}.csv",
        "-q")
r = run("sweep", "--merge", "part1.csv", "part2.csv", "-o", "merged.png", "-q")
merged = run("scene", "merged.png")
ok(r.returncode == 0 and merged.returncode == 0 and merged.stdout == pdf_scene.stdout,
   f"a merged PNG records the scene too ({r.stderr.strip()[:80]} {merged.stderr.strip()[:80]})")
r = sweep("dpi.png", args=["--size", "8.6cm", "--dpi", "150"])
data = open(os.path.join(work, "dpi.png"), "rb").read() if r.returncode == 0 else b""
at = data.find(b"pHYs")
ppm = int.from_bytes(data[at + 4:at + 8], "big") if at > 0 else 0
ok(ppm == round(150 / 0.0254), f"a printed sweep PNG says its dpi (pHYs: {ppm} px/m for 150 dpi)")

# The figure's axes are its own: '|' (a still's name per panel) is refused
# whatever the scene's panels; one name is drawn.
for value in ("AAA|BBB|CCC|DDD|EEE", "a|b"):
    r = sweep("bar.png", extra={"view.xlabel": value})
    ok(r.returncode == 2 and "one plot" in r.stderr and not os.path.exists(os.path.join(work, "bar.png")),
       f"--set view.xlabel={value}: exit {r.returncode} ({r.stderr.strip()[:110]})")
with open(os.path.join(work, "labels.ini"), "w") as f:
    f.write("[view]\npanels = theta, energy\nxlabel = t | t2\n")
r = run("sweep", "labels.ini", *GRID, "-o", "labels.pdf", "-q")
ok(r.returncode == 2 and "view.xlabel" in r.stderr and "one plot" in r.stderr,
   f"a scene's per-panel xlabel: exit {r.returncode} ({r.stderr.strip()[:110]})")
r = run("sweep", "labels.ini", *GRID, "--set", "view.xlabel=swing", "-o", "labels.pdf", "-q")
ok(r.returncode == 0 and "swing" in sptext.pdf_text(os.path.join(work, "labels.pdf")),
   f"--set view.xlabel=swing names the sweep's x axis ({r.stderr.strip()[:80]})")

# A PDF's bytes do not depend on where its fonts are installed: the same
# figure with fontconfig shown a copy of the font elsewhere.
lm = subprocess.run(["fc-match", "-f", "%{file}", "Latin Modern Roman"], capture_output=True,
                    text=True).stdout
if lm.endswith(".otf"):
    os.makedirs(os.path.join(work, "fonts"))
    shutil.copy(lm, os.path.join(work, "fonts"))
    with open(os.path.join(work, "fonts.conf"), "w") as f:
        f.write(f'<?xml version="1.0"?>\n<!DOCTYPE fontconfig SYSTEM "fonts.dtd">\n<fontconfig>'
                f'<dir>{work}/fonts</dir><cachedir>{work}/fc-cache</cachedir></fontconfig>\n')
    moved = dict(os.environ, FONTCONFIG_FILE=os.path.join(work, "fonts.conf"))
    latin = ["--set", "view.font=Latin Modern Roman", "--set", "view.title=Latin Modern"]
    cmds = {"sweep": ["sweep", scene, *GRID, *latin, "--set", "view.legend=none", "--set",
                      "view.ylabel=lambda", "--set", "view.colorbar_label=lambda"],
            "still": ["still", os.path.join(src, "..", "scenes", "default.ini"), "--at", "1", *latin,
                      "--set", "view.panels=none", "--set", "view.hud=false"]}
    for what, cmd in cmds.items():
        a = subprocess.run([exe, *cmd, "-o", f"{what}_here.pdf", "-q"], cwd=work, capture_output=True,
                           text=True)
        b = subprocess.run([exe, *cmd, "-o", f"{what}_there.pdf", "-q"], cwd=work, capture_output=True,
                           text=True, env=moved)
        same = a.returncode == b.returncode == 0 and \
            open(os.path.join(work, f"{what}_here.pdf"), "rb").read() == \
            open(os.path.join(work, f"{what}_there.pdf"), "rb").read()
        info = subprocess.run(["pdfinfo", f"{what}_there.pdf"], capture_output=True, text=True,
                              cwd=work).stdout if b.returncode == 0 else ""
        keywords = [line for line in info.splitlines() if line.startswith("Keywords")]
        ok(same and keywords and "lmroman10-regular.otf" in keywords[0] and "/" not in keywords[0],
           f"a {what} PDF: the same bytes with its font in {os.path.dirname(lm)} and in a copy elsewhere "
           f"({keywords}; {a.stderr.strip()[:60]} {b.stderr.strip()[:60]})")
else:
    ok(True, "# SKIP Latin Modern Roman is not an installed .otf")
done()
