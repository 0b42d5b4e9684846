#!/usr/bin/env python3
"""springpend tests: vector figures (still -o fig.svg|fig.pdf) against the PNG
of the same frame, and the draw list's independence from GL.
usage: test_figures.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)

The SVG is rasterised with rsvg-convert, the PDF with pdftoppm at 72 dpi
(one pt per pixel). Edges and glyphs are antialiased differently by GL,
librsvg and poppler (full-size RMS 4-14 levels), so the rule compares what a
reader sees: both images are averaged over 8x8 blocks (ffmpeg's area
scaler) and at most 0.5% of the blocks may differ by more than 32 levels.
The same rule fails a frame 0.5 s later and a frame without its heads-up
text. Exits 77 (skip) without rsvg-convert, pdftoppm or ffmpeg."""
import os
import re
import shutil
import subprocess
import sys

from sptest import done, ok, runner

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "figures"))
root = os.path.join(src, "..")
need = [t for t in ("rsvg-convert", "pdftoppm", "pdftotext", "ffmpeg") if not shutil.which(t)]
if need:
    print(f"1..0 # SKIP {', '.join(need)} not installed")
    sys.exit(77)
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
RULE = ["--max-diff", "32", "--max-pixels", "0.5%"]


run = runner(exe, work)


def p(name):
    return os.path.join(work, name)


def still(name, scene, at, *args):
    r = run("still", os.path.join(root, "scenes", scene), "--at", str(at), "-o", p(name), "-q", *args)
    if r.returncode:
        print(f"# {name}: {r.stderr.strip()}")
    return r.returncode == 0


def raster(name):
    """The figure rasterised to NAME.png beside it; the path or None."""
    base, ext = os.path.splitext(p(name))
    if ext == ".svg":
        cmd = ["rsvg-convert", p(name), "-o", base + "_svg.png"]
        out = base + "_svg.png"
    else:
        cmd = ["pdftoppm", "-r", "72", "-png", "-singlefile", p(name), base + "_pdf"]
        out = base + "_pdf.png"
    return out if subprocess.run(cmd, capture_output=True).returncode == 0 else None


def blocks(png):
    out = png[:-4] + "_8x8.png"
    subprocess.run(["ffmpeg", "-v", "error", "-y", "-i", png, "-vf",
                    "scale=iw/8:ih/8:flags=area,format=rgb24", out], check=True)
    return out


def same(a, b):
    r = run("compare", blocks(a), blocks(b), *RULE)
    print("# " + (r.stdout.strip() or r.stderr.strip()))
    return r.returncode == 0


cases = [
    ("resonance.ini", 20, "640x360", ["--set", "view.panels=all"]),
    ("default.ini", 8.5, "1024x768", ["--set", "view.theme=light"]),
    ("chaotic.ini", 12, "320x240", []),
]
for i, (scene, at, size, extra) in enumerate(cases):
    args = ["--size", size, *extra]
    made = all(still(f"c{i}.{k}", scene, at, *args) for k in ("png", "svg", "pdf"))
    if not ok(made, f"{scene} at {size}: PNG, SVG and PDF written"):
        continue
    for k in ("svg", "pdf"):
        r = raster(f"c{i}.{k}")
        ok(r and same(p(f"c{i}.png"), r), f"{scene} {size}: the {k.upper()} rasterised matches the PNG")

# The rule is not blind: another moment, or the text missing, fails it.
still("later.png", "resonance.ini", 20.5, "--size", "640x360", "--set", "view.panels=all")
still("nohud.png", "resonance.ini", 20, "--size", "640x360", "--set", "view.panels=all",
      "--set", "view.hud=false")
svg0 = p("c0_svg.png")
ok(not same(p("later.png"), svg0), "the rule fails a frame 0.5 s later")
ok(not same(p("nohud.png"), svg0), "the rule fails a frame without its heads-up text")

# Real vectors and real text.
svg = open(p("c0.svg"), encoding="utf-8").read()
pdf = open(p("c0.pdf"), "rb").read()
ok("<image" not in svg and b"/Image" not in pdf, "no raster images inside the SVG or PDF")
ok(max(d.count(" L ") for d in re.findall(r' d="([^"]*)"', svg)) >= 200,
   "a chart curve is one SVG path of many segments, not a capsule per segment")
text = subprocess.run(["pdftotext", p("c0.pdf"), "-"], capture_output=True, text=True).stdout
ok("Spring length r" in text and "Poincaré" in text and "t = 20.00 s" in text,
   "the PDF's text is selectable (pdftotext finds the titles and the time)")
ok(b"DejaVu" in pdf, "the PDF embeds DejaVu Sans")


# Figure layout: title, caption and the speed marker are real text; without
# the pendulum its colourbar goes too; long titles are refused.
still("titled.pdf", "resonance.ini", 20, "--size", "1280x720", "--set", "view.pendulum=false",
      "--set", "view.panels=poincare,phase", "--set", "view.title=Résonance 2:1 — θ, r",
      "--set", "view.caption=Energy flows from bounce to swing", "--set", "video.speed=0.25",
      "--set", "view.colorbar=true")
text = subprocess.run(["pdftotext", p("titled.pdf"), "-"], capture_output=True, text=True).stdout
ok("Résonance 2:1 — θ, r" in text and "Energy flows from bounce to swing" in text,
   "the title and caption are written (UTF-8)")
ok("speed ×0.25" in text, "speed = 0.25 is marked 'speed ×0.25'")
ok("Poincaré" in text and "|v|" not in text, "view.pendulum = false drops the pendulum and its colourbar")


# Titles and captions have no byte limit (it was 255): a teacher's caption of
# several sentences wraps, in a PNG, an SVG, a PDF and a video alike; only a
# text that cannot fit the frame is refused, naming where it was set.
def ink_lines(png, top, frac=8):
    """Bands of rows with text ink in the bottom (top=False) or top 1/frac
    of png: the number of wrapped lines a reader sees."""
    w, h = (int(v) for v in subprocess.run(
        ["ffprobe", "-v", "error", "-select_streams", "v", "-show_entries", "stream=width,height",
         "-of", "csv=p=0", png], capture_output=True, text=True).stdout.strip().split(","))
    raw = subprocess.run(["ffmpeg", "-v", "error", "-i", png, "-vf", "format=gray", "-f", "rawvideo",
                          "-"], capture_output=True).stdout
    rows = range(0, h // frac) if top else range(h - h // frac, h)
    bands, inside = 0, False
    for y in rows:
        lit = max(raw[y * w:y * w + w]) > 120
        bands += lit and not inside
        inside = lit
    return bands


TEACH_TITLE = ("Das Federpendel: Energie wandert zwischen Schwingung und Pendelbewegung hin und "
               "her, wenn die Federkonstante das Dreifache des Gewichts durch die Ruhelänge ist")
TEACH = ("The spring pendulum near the 2:1 resonance. Watch how the energy moves from the "
         "bouncing motion into the swinging motion and back again. The swing's plane stays "
         "fixed, because the motion starts in a plane. Change the stiffness by a few percent "
         "and see how the exchange slows down. This caption has several sentences, as a "
         "teacher would write, far longer than the 255 bytes that used to be allowed.")
long_scene = p("teach.ini")
with open(long_scene, "w") as f:
    f.write(f'[video]\nwidth = 1280\nheight = 720\n[view]\ntitle = {TEACH_TITLE}\n'
            f'caption = "{TEACH}"\n')
assert len(TEACH.encode()) > 255 and len(TEACH_TITLE.encode()) > 150
lines = {}
for ext in ("png", "svg", "pdf"):
    r = run("still", long_scene, "--at", "3", "-o", p("teach." + ext), "-q")
    ok(r.returncode == 0, f"a {len(TEACH.encode())}-byte caption and a {len(TEACH_TITLE.encode())}-byte "
       f"title in a .{ext} still ({r.stderr.strip()[-200:]})")
    png = p("teach.png") if ext == "png" else raster("teach." + ext)
    if png:
        lines[ext] = (ink_lines(png, True), ink_lines(png, False))
ok(len(set(lines.values())) == 1 and all(t == 2 and c == 3 for t, c in lines.values()),
   f"the title and the caption each wrap to the same lines in PNG, SVG and PDF (title, caption lines: {lines})")
text = " ".join(subprocess.run(["pdftotext", p("teach.pdf"), "-"], capture_output=True,
                               text=True).stdout.split())
ok(TEACH in text and TEACH_TITLE in text, "pdftotext gives the whole title and caption back")
r = run("render", long_scene, "--set", "video.duration=0.2", "--size", "640x360", "-o", p("teach.mp4"), "-q")
frame = p("teach_mp4.png")
subprocess.run(["ffmpeg", "-v", "error", "-y", "-i", p("teach.mp4"), "-frames:v", "1", frame])
back = run("scene", p("teach.mp4"))
ok(r.returncode == 0 and os.path.exists(frame) and ink_lines(frame, False, 4) == 4 and
   f'caption = "{TEACH}"' in back.stdout,
   f"in a 640x360 video the caption wraps to {ink_lines(frame, False, 4) if os.path.exists(frame) else 0} "
   "lines, and the video's scene holds it whole")
r = run("still", long_scene, "--size", "320x180", "-o", p("teach_small.png"))
ok(r.returncode == 2 and f"{long_scene}:5: [view] title and {long_scene}:6: [view] caption" in r.stderr
   and "allowed: at most half the height (90 px)" in r.stderr and not os.path.exists(p("teach_small.png")),
   f"at 320x180 the same texts cannot fit: exit 2 naming FILE:LINE of each and the limit, no file "
   f"({r.stderr.strip()[-300:]})")
r = run("still", os.path.join(root, "scenes", "default.ini"), "--set", "view.caption=" + "Wort " * 2000,
        "-o", p("long.png"))
ok(r.returncode == 2 and "--set view.caption: the title and caption cannot fit: they wrap to 0 + " in r.stderr
   and not os.path.exists(p("long.png")),
   f"a 10 kB caption that cannot fit is refused, naming --set view.caption ({r.stderr.strip()[-200:]})")
still("fade.png", "resonance.ini", 20, "--size", "640x360", "--set", "view.panels=phase")
still("nofade.png", "resonance.ini", 20, "--size", "640x360", "--set", "view.panels=phase",
      "--set", "view.fade=false")
r = run("compare", p("fade.png"), p("nofade.png"))
ok(r.returncode == 1, "view.fade = false changes the trail and the phase curves")

# Transparent stills for slides: the theme names the slide. Over white, the
# light theme's heads-up text is dark; the dark theme's would vanish.
def darkest_top_left(png):
    """The darkest pixel (0..255 luma) of the top-left 300x40 px of png
    composited over white."""
    raw = subprocess.run(["ffmpeg", "-v", "error", "-f", "lavfi", "-i", "color=white:s=960x540", "-i", png,
                          "-filter_complex", "[0][1]overlay=format=auto,crop=300:40:0:0,format=gray",
                          "-frames:v", "1", "-f", "rawvideo", "-"], capture_output=True).stdout
    return min(raw) if raw else 255


for theme in ("light", "dark"):
    still(f"slide_{theme}.png", "resonance.ini", 20, "--size", "960x540", "--set", "view.background=transparent",
          "--set", f"view.theme={theme}")
ok(darkest_top_left(p("slide_light.png")) < 80, "transparent + light theme: dark text on a white slide")
ok(darkest_top_left(p("slide_dark.png")) > 150, "transparent + dark theme: light text (for dark slides)")

# Failure leaves nothing; bad names are refused.
r = run("still", os.path.join(root, "scenes", "default.ini"), "-o", p("nodir/x/../../c0.svg/x.svg"))
ok(r.returncode != 0 and not os.path.exists(p("c0.svg/x.svg")), "an impossible path fails and writes nothing")

# Reproducible bytes: the same figure twice, more than a second apart, is the
# same file (cairo 1.16 stamps a PDF with the clock unless told a date); a
# sweep figure too. SOURCE_DATE_EPOCH is written as the PDF's creation date
# (pdfinfo reads it back); a malformed one is refused (exit 2, no file).
import time
env0 = {k: v for k, v in os.environ.items() if k != "SOURCE_DATE_EPOCH"}
for ext in ("pdf", "svg"):
    names = []
    for i in (1, 2):
        name = f"repro{i}.{ext}"
        r = subprocess.run([exe, "still", os.path.join(root, "scenes", "default.ini"), "--at", "3",
                            "-o", p(name), "-q"], capture_output=True, text=True, cwd=work, env=env0)
        ok(r.returncode == 0, f"still {name} {r.stderr.strip()}")
        r = subprocess.run([exe, "sweep", os.path.join(root, "scenes", "chaotic.ini"), "--vary",
                            "initial.angle=10:80:4", "--measure", "lyapunov", "--time", "2", "-q",
                            "-o", p("sweep" + name)], capture_output=True, text=True, cwd=work, env=env0)
        ok(r.returncode == 0, f"sweep figure sweep{name} {r.stderr.strip()}")
        names.append(name)
        if i == 1:
            time.sleep(1.2)
    same = lambda a, b: os.path.exists(a) and os.path.exists(b) and open(a, "rb").read() == open(b, "rb").read()
    ok(same(p(names[0]), p(names[1])), f"a still's {ext.upper()} has the same bytes a second later")
    ok(same(p("sweep" + names[0]), p("sweep" + names[1])),
       f"a sweep figure's {ext.upper()} has the same bytes a second later")
info = subprocess.run(["pdfinfo", p("repro1.pdf")], capture_output=True, text=True).stdout
ok("CreationDate" not in info, "without SOURCE_DATE_EPOCH a PDF carries no creation date")
r = subprocess.run([exe, "still", os.path.join(root, "scenes", "default.ini"), "--at", "3",
                    "-o", p("epoch.pdf"), "-q"], capture_output=True, text=True, cwd=work,
                   env=dict(env0, SOURCE_DATE_EPOCH="1700000000"))
info = subprocess.run(["pdfinfo", p("epoch.pdf")], capture_output=True, text=True,
                      env=dict(env0, TZ="UTC")).stdout
ok(r.returncode == 0 and re.search(r"CreationDate:\s+Tue Nov 14 22:13:20 2023", info),
   f"SOURCE_DATE_EPOCH=1700000000 is the PDF's creation date ({info.strip()[:200]!r})")
r = subprocess.run([exe, "still", os.path.join(root, "scenes", "default.ini"), "--at", "3",
                    "-o", p("epochbad.pdf"), "-q"], capture_output=True, text=True, cwd=work,
                   env=dict(env0, SOURCE_DATE_EPOCH="17e8"))
ok(r.returncode == 2 and "SOURCE_DATE_EPOCH" in r.stderr and not os.path.exists(p("epochbad.pdf"))
   and not [f for f in os.listdir(work) if f.startswith("epochbad")],
   f"a malformed SOURCE_DATE_EPOCH is refused, no file (exit {r.returncode}: {r.stderr.strip()})")


# Nothing that composes a frame includes a GL (or cairo) header, directly or
# through another header of the tree (src/ flat or in folders).
def find(name):
    for d in ("src", "include"):
        for dirpath, _, _ in os.walk(os.path.join(root, d)):
            if os.path.exists(os.path.join(dirpath, name)):
                return os.path.join(dirpath, name)
    return None


def includes(f, seen):
    for inc in re.findall(r'#include [<"]([^>"]+)[>"]', open(f, encoding="utf-8").read()):
        if inc in seen:
            continue
        seen.add(inc)
        q = find(inc)
        if q:
            includes(q, seen)
    return seen


bad = {}
for f in ("compose.c", "canvas.c", "panels.c", "layout.c", "text.c", "figure.c", "draw_cache.c"):
    hit = [i for i in includes(find(f), set())
           if i.startswith(("GL/", "EGL/", "cairo")) or i in ("gl_api.h", "draw_gl.h", "gl_context.h")]
    if hit:
        bad[f] = hit
ok(not bad, f"composition and the draw cache's plan include no GL or cairo header {bad or ''}")

done()
