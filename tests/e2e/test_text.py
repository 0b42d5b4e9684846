#!/usr/bin/env python3
"""springpend tests: text in every script a teacher would use, in a PNG
still, an SVG and a PDF (issue 19). For each script's title:
  - PDF: pdftotext returns the exact string (real text, logical order;
    mixed-direction lines too, and a longer one whose words and number with
    unit come back in order);
  - each format: its distinct characters, drawn apart, give distinct ink
    (no two alike, none blank: no missing-glyph boxes);
  - the three formats draw the same glyphs (their ink is as wide);
  - an Arabic word's letters join into one run of ink, as pango-view draws it
    (and the same letters apart do not).
Also: a Latin Modern figure embeds Latin Modern (pdffonts) and names its
font files in its provenance; a character no installed font has, a
noncharacter and an unknown family are exit 2 with a message and no output
in every format; an emoji and a mathematical italic are drawn in every
format; a title wraps, and one that cannot fit is refused. The README's
multilingual picture and Latin Modern figure show what their commands, run
as the README gives them, draw (their text bands pixel for pixel; pdffonts,
pdftotext).
usage: test_text.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR"""
import glob
import os
import re
import shlex
import shutil
import struct
import subprocess
import sys
import zlib

from sptest import done, ffmpeg_rgb, need_scipy, ok, runner, sets

need_scipy()
import numpy as np  # noqa: E402
import sptext  # noqa: E402
from sptext import gray, ink_columns, joined, segments  # noqa: E402

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "text"))
scene = os.path.join(src, "..", "scenes", "default.ini")
need = [t for t in ("rsvg-convert", "pdftoppm", "pdftotext", "pdffonts", "pdfinfo", "ffmpeg",
                    "pango-view") if not shutil.which(t)]
if need:
    print(f"1..0 # SKIP {', '.join(need)} not installed")
    sys.exit(77)
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
run = runner(exe, work)

SCRIPTS = [
    ("Latin", "Federpendel: Größe ß ł ő ø ñ"),
    ("combining marks", "x\u0303 e\u0301 a\u030a \u03b8\u0307"),
    ("Greek", "Ελατήριο εκκρεμές"),
    ("Cyrillic", "Пружинный маятник"),
    ("CJK", "弹簧摆"),
    ("Arabic", "البندول الزنبركي"),
    ("Hebrew", "מטוטלת קפיץ"),
    ("Devanagari", "स्प्रिंग लोलक"),
    ("mixed direction", "البندول 2 m/s"),
]
# Only the title: no panels, heads-up text or colourbar; 24 pt body text
# (a 41 px title).
BARE = {"view.panels": "none", "view.hud": "false", "view.colorbar": "false",
        "view.font_size": "24", "view.theme": "light"}
SIZE = ["--size", "900x240"]
BAND = 50  # px: the title band (41 px line and the gap above it)


def still(name, title, extra=None, size=SIZE):
    """Renders a still titled `title`; the CompletedProcess."""
    d = dict(BARE, **(extra or {}))
    d["view.title"] = title
    return run("still", scene, "--at", "0", *size, *sets(d), "-o", name, "-q")


def chars_of(text):
    """The distinct characters of text that draw alone (marks, virama and
    spaces belong to their neighbours)."""
    out = []
    for c in text:
        if c == " " or 0x300 <= ord(c) < 0x370 or c == "\u094d" or c in out:
            continue
        out.append(c)
    return out


def pdf_text(name):
    return sptext.pdf_text(os.path.join(work, name))


def pango_pdf_text(text):
    """What pdftotext reads from pango-view's PDF of text: the reference."""
    subprocess.run(["pango-view", "-q", "--font", "DejaVu Sans 24", "--text", text, "-o",
                    "pango.pdf"], check=True, cwd=work)
    return pdf_text("pango.pdf")


for name, text in SCRIPTS:
    tag = name.replace(" ", "_")
    files = {f: f"{tag}.{f}" for f in ("png", "svg", "pdf")}
    made = {f: still(n, text) for f, n in files.items()}
    if not ok(all(r.returncode == 0 for r in made.values()),
              f"{name}: PNG, SVG and PDF written ({[r.stderr.strip() for r in made.values() if r.returncode]})"):
        continue
    got = pdf_text(files["pdf"])
    if name == "mixed direction":  # exact: "2 m/s" is one ActualText stretch (doc/teaching.md)
        ok(got == text, f"{name}: pdftotext returns the exact string ({got!r}; from pango-view's "
           f"PDF of it {pango_pdf_text(text)!r})")
    else:
        ok(got == text or got == pango_pdf_text(text),
           f"{name}: pdftotext returns " + ("the exact string" if got == text else
           f"{got!r}, as for pango-view's PDF of it"))
    widths = {}
    for f, n in files.items():
        img = gray(os.path.join(work, n))[:BAND]
        x0, x1 = ink_columns(img)
        widths[f] = x1 - x0 + 1
    ok(min(widths.values()) > 0 and max(widths.values()) <= 1.08 * min(widths.values()),
       f"{name}: the PNG, SVG and PDF titles are as wide ({widths} px): the same glyphs")
    chars = chars_of(text)
    spread = "   ".join(chars)
    for f in ("png", "svg", "pdf"):
        n = f"{tag}_chars.{f}"
        r = still(n, spread)
        segs = segments(gray(os.path.join(work, n))[:BAND]) if r.returncode == 0 else []
        same = [(a, b) for a in range(len(segs)) for b in range(a + 1, len(segs))
                if segs[a].shape == segs[b].shape and np.abs(segs[a] - segs[b]).max() < 48]
        ok(r.returncode == 0 and len(segs) == len(chars) and not same,
           f"{name} in {f.upper()}: its {len(chars)} distinct characters draw {len(segs)} distinct "
           f"inks{' (alike: ' + str(same) + ')' if same else ''}")

# Mixed-direction lines in a PDF (doc/teaching.md, "Text extraction"): a
# number and a unit inside a right-to-left line are drawn in the Unicode
# bidirectional order ("m/s 2" on the page) and come back from pdftotext in
# the string's order, on a page of the title alone and, the stretch itself,
# on a mostly left-to-right page (heads-up text and panels), where poppler
# orders the whole line left to right.
for title in ("البندول 2 m/s 3 kg", "מטוטלת 2 m/s", "البندول 2.5 m/s"):
    r = still("mixed.pdf", title)
    got = pdf_text("mixed.pdf") if r.returncode == 0 else None
    ok(got == title, f"{title!r}: pdftotext returns the exact string ({got!r})")
# The longer line: no PDF gets "m/s في" back with its space where it was
# from poppler 22.12 (a space between a Latin letter and an Arabic one always
# comes out before the left-to-right stretch: doc/teaching.md); every word
# and the stretch "2.5 m/s" come back in order.
longer = "سرعة البندول 2.5 m/s في الثانية"
r = still("longer.pdf", longer)
got = pdf_text("longer.pdf") if r.returncode == 0 else ""
ok(got.replace(" ", "") == longer.replace(" ", "") and "2.5 m/s" in got,
   f"{longer!r}: pdftotext returns its words and \"2.5 m/s\" in order ({got!r})")
r = still("mixed_hud.pdf", "البندول 2 m/s",
          {"view.panels": "r,theta", "view.hud": "true", "view.colorbar": "true"}, ["--size", "900x500"])
first = pdf_text("mixed_hud.pdf").split("\n")[0] if r.returncode == 0 else ""
ok("2 m/s" in first and "البندول" in first,
   f"on a mostly left-to-right page, the stretch comes back as \"2 m/s\" ({first!r})")

# Arabic joining: "سلم" (three letters that join on both sides) is one run
# of ink, in every format and in pango-view's rendering; apart, it is not.
word = "سلم"
subprocess.run(["pango-view", "-q", "--font", "DejaVu Sans 41px", "--text", word, "-o",
                os.path.join(work, "pango.png")], check=True)
ref = joined(gray(os.path.join(work, "pango.png")))
ok(ref > 0.9, f"pango-view draws {word} as one run of ink ({ref:.2f} of its width)")
for f in ("png", "svg", "pdf"):
    still(f"join.{f}", word)
    still(f"apart.{f}", " ".join(word))
    j = joined(gray(os.path.join(work, f"join.{f}"))[:BAND])
    a = joined(gray(os.path.join(work, f"apart.{f}"))[:BAND])
    ok(j > 0.9 and a < 0.6, f"Arabic in {f.upper()}: the word's letters join into one run of ink "
       f"({j:.2f} of its width, as pango-view's {ref:.2f}); apart they do not ({a:.2f})")

# Latin Modern: embedded in the PDF, named in the provenance.
lm = {"view.font": "Latin Modern Roman", "view.panels": "r,theta", "view.hud": "true"}
r = run("still", scene, "--at", "2", "--size", "800x450", *sets(lm), "-o", "lm.pdf", "-q")
fonts = subprocess.run(["pdffonts", "lm.pdf"], capture_output=True, text=True, cwd=work).stdout
ok(r.returncode == 0 and "LMRoman10-Regular" in fonts, "a Latin Modern figure embeds Latin Modern "
   f"(pdffonts: {[l.split()[0] for l in fonts.splitlines()[2:]]})")
info = subprocess.run(["pdfinfo", "lm.pdf"], capture_output=True, text=True, cwd=work).stdout
ok("lmroman10-regular.otf" in info, "the PDF's keywords name the font files drawn from")
r = run("still", scene, "--at", "2", "--size", "800x450", *sets(lm), "-o", "lm.png", "-q")


def png_text(path):
    data, out, i = open(path, "rb").read(), {}, 8
    while i < len(data):
        n, kind = struct.unpack(">I4s", data[i:i + 8])
        body = data[i + 8:i + 8 + n]
        if kind == b"tEXt":
            k, v = body.split(b"\0", 1)
            out[k.decode()] = v.decode("latin-1")
        elif kind == b"zTXt":
            k, v = body.split(b"\0", 1)
            out[k.decode()] = zlib.decompress(v[1:]).decode("latin-1")
        i += 12 + n
    return out


prov = png_text(os.path.join(work, "lm.png")).get("springpend.fonts", "")
ok(r.returncode == 0 and "lmroman10-regular.otf" in prov,
   f"the PNG's provenance names the font files ({prov[:120]})")

# A family list: fontconfig tries "Latin Modern Roman, serif" in order, so the
# Greek Latin Modern lacks comes from the serif family fontconfig picks for it
# (asked of fc-match here), not from its sans-serif fallback.
def fc_ps(pattern):
    return subprocess.run(["fc-match", "-f", "%{postscriptname}", pattern], capture_output=True,
                          text=True).stdout


def pdf_fonts(name):
    out = subprocess.run(["pdffonts", name], capture_output=True, text=True, cwd=work).stdout
    return {l.split()[0].split("+")[-1] for l in out.splitlines()[2:]}


greek = {"view.panels": "r", "view.hud": "false"}
serif_greek, sans_greek = fc_ps("serif:charset=3b8"), fc_ps("Latin Modern Roman:charset=3b8")
TALL = ["--size", "900x400"]  # a panel with 24 pt text: 240 px tall takes 16 (attack11 #14)
r1 = still("lm-alone.pdf", "Angle θ", dict(greek, **{"view.font": "Latin Modern Roman"}), size=TALL)
r2 = still("lm-list.pdf", "Angle θ", dict(greek, **{"view.font": "Latin Modern Roman, serif"}), size=TALL)
alone, listed = pdf_fonts("lm-alone.pdf"), pdf_fonts("lm-list.pdf")
ok(r1.returncode == 0 and r2.returncode == 0 and serif_greek and serif_greek != sans_greek and
   "LMRoman10-Regular" in listed and serif_greek in listed and sans_greek not in listed and
   sans_greek in alone,
   f"view.font = \"Latin Modern Roman, serif\": θ from {serif_greek} (fc-match serif), not "
   f"{sans_greek} as for Latin Modern Roman alone (pdffonts: {sorted(listed)} | {sorted(alone)})")
# a later name that adds no character to those before it is still installed
# (attack12 #3: fontconfig's trimmed order leaves it out; it was "not installed")
r = still("lm-caps.png", "x", {"view.font": "Latin Modern Roman, Latin Modern Roman Caps"})
ok(r.returncode == 0, f"view.font = \"Latin Modern Roman, Latin Modern Roman Caps\": taken "
   f"({r.stderr.strip()[:140] if r.returncode else 'exit 0'})")
# side by side, one font list however spelt (attack12 #9: "Latin Modern
# Roman, serif" and "latin modern roman,serif" were "different fonts")
with open(scene) as f:
    base_text = f.read()
for name, value in (("sb1.ini", "Latin Modern Roman, serif"), ("sb2.ini", "latin modern roman,serif")):
    with open(os.path.join(work, name), "w") as f:
        f.write(base_text.replace("[view]\n", f"[view]\nfont = {value}\n", 1))
r = run("still", "sb1.ini", "sb2.ini", "--at", "1", "--size", "640x360", "-o", "sb.png", "-q")
ok(r.returncode == 0 and os.path.exists(os.path.join(work, "sb.png")),
   f"side by side: font lists spelt with other blanks and case are one list "
   f"({r.stderr.strip()[:140] if r.returncode else 'exit 0'})")
for value, said in (("Latin Modern Roman, Noto Serf", '"Noto Serif"'),
                    ("Latin Modern Roman,, serif", "an empty name"),
                    ("Latin Modern Roman,", "an empty name")):
    r = still("badlist.png", "x", {"view.font": value})
    ok(r.returncode == 2 and said in r.stderr and not os.path.exists(os.path.join(work, "badlist.png")),
       f"view.font = {value!r}: exit {r.returncode}, says {said}, no output ({r.stderr.strip()[:150]})")
default = run("still", scene, "--at", "0", "-o", "default.png", "-q")
prov = png_text(os.path.join(work, "default.png")).get("springpend.fonts", "")
ok(prov == "DejaVu Sans (embedded in springpend)", f"the default font is the embedded DejaVu Sans ({prov})")

# Refused in every format, with the character named, and nothing written.
for title, code in (("test tube \U0001f9ea", "U+1F9EA"), ("x \ufffe", "U+FFFE"),
                    ("x \uffff", "U+FFFF"), ("x \U0010ffff", "U+10FFFF")):
    for f in ("png", "svg", "pdf"):
        r = still(f"missing.{f}", title)
        ok(r.returncode == 2 and code in r.stderr and "tried" in r.stderr and
           not os.path.exists(os.path.join(work, f"missing.{f}")),
           f"{code} in {f.upper()}: exit {r.returncode}, no output ({r.stderr.strip()[:110]})")
for title in ("smile \U0001f600", "\U0001d703 = 0"):
    for f in ("png", "svg", "pdf"):
        r = still(f"ok.{f}", title)
        good = r.returncode == 0
        if f == "pdf" and good:
            got = pdf_text("ok.pdf")
            good = got in (title, pango_pdf_text(title))
            print(f"# pdftotext: {got!r}")
        ok(good, f"{title!r} in {f.upper()}: drawn{' (pdftotext: the text, as from pango-view)' if f == 'pdf' else ''}")
for f in ("png", "svg", "pdf"):
    r = still(f"unknown.{f}", "x", {"view.font": "Latin Modren Roman"})
    ok(r.returncode == 2 and '"Latin Modern Roman"' in r.stderr and
       not os.path.exists(os.path.join(work, f"unknown.{f}")),
       f"an unknown family in {f.upper()}: exit {r.returncode}, close matches listed ({r.stderr.strip()[:140]})")

# Titles wrap; one that cannot fit the frame is refused.
long_title = " ".join(["Federpendel"] * 8)
r = still("wrap.png", long_title, size=["--size", "900x480"])
img = gray(os.path.join(work, "wrap.png"))
rows = (img[:, :] > 96).any(axis=1)
bands = sum(1 for y in range(1, 120) if rows[y] and not rows[y - 1])
ok(r.returncode == 0 and bands >= 3, f"a long title wraps onto {bands} lines")
r = still("toolong.png", " ".join(["Federpendel"] * 20), size=["--size", "900x480"])
ok(r.returncode == 2 and "cannot fit" in r.stderr and not os.path.exists(os.path.join(work, "toolong.png")),
   f"a title that cannot fit the frame: exit {r.returncode} ({r.stderr.strip()[:120]})")

# The README's pictures: its commands, run as written (in the checkout, with
# this build and this folder for the output), draw what the README shows.
root = os.path.join(src, "..")


def doc_command(target):
    """(page, argv) of the shell command in the README (or a doc/ page) that
    writes target."""
    for page in [os.path.join(root, "README.md")] + sorted(glob.glob(os.path.join(root, "doc", "*.md"))):
        with open(page, encoding="utf-8") as f:
            text = f.read()
        for block in re.findall(r"```sh\n(.*?)```", text, re.S):
            for line in block.replace("\\\n", " ").splitlines():
                argv = shlex.split(line, comments=True) if target in line else []
                if target in argv:
                    return os.path.basename(page), argv
    return None, None


def same_rows(a, b, w, h, rows):
    """Whether two w x h pictures have the same pixels in the rows given:
    their text bands (the charts between follow other features' changes)."""
    return all(np.array_equal(ffmpeg_rgb(a, w, h)[r], ffmpeg_rgb(b, w, h)[r]) for r in rows)


def run_doc(target, out):
    page, argv = doc_command(target)
    if not argv:
        return page, None
    argv = [exe if a == "./build/springpend" else os.path.join(work, out) if a == target else a
            for a in argv]
    return page, subprocess.run(argv, cwd=root, capture_output=True, text=True)


page, r = run_doc("doc/pictures/multilingual.png", "readme-multilingual.png")
ok(r is not None and r.returncode == 0 and
   same_rows(os.path.join(work, "readme-multilingual.png"), os.path.join(root, "doc", "pictures", "multilingual.png"),
             1280, 720, [slice(0, 40), slice(684, 720)]),
   f"{page}: its command for doc/pictures/multilingual.png draws that picture's title and caption, pixel for pixel"
   f"{' (' + r.stderr.strip()[:100] + ')' if r is not None and r.returncode else ''}")
page, r = run_doc("doc/pictures/latin-modern.pdf", "readme-latin-modern.pdf")
made = os.path.join(work, "readme-latin-modern.pdf")
good = r is not None and r.returncode == 0
if good:
    fonts = subprocess.run(["pdffonts", made], capture_output=True, text=True, check=True).stdout
    embedded = [l.split()[0].split("+")[-1] for l in fonts.splitlines()[2:] if " yes " in l]
    subprocess.run(["pdftoppm", "-r", "144", "-png", "-singlefile", made, os.path.join(work, "readme-lm")],
                   check=True)
    good = ("LMRoman10-Regular" in embedded and
            "Energy exchange at 2:1 resonance" in sptext.pdf_text(made) and
            same_rows(os.path.join(work, "readme-lm.png"), os.path.join(root, "doc", "pictures", "latin-modern-pdf.png"),
                      984, 600, [slice(0, 60)]))
ok(good, f"{page}: its command for doc/pictures/latin-modern.pdf writes a PDF that embeds Latin Modern "
   f"({embedded if r is not None and r.returncode == 0 else 'not written'}), holds its title as text and "
   "rasterises (pdftoppm -r 144) to doc/pictures/latin-modern-pdf.png's title, pixel for pixel")
done()
