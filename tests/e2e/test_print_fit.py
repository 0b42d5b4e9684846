#!/usr/bin/env python3
"""springpend tests (issue 28, fix21): a still at a printed size whose
panels cannot hold their texts is refused (attack13 #19, fix17), and the
refusal now says what fits, each found by laying the figure out again: the
smallest --size in the user's unit (for WIDTH alone the smallest height at
that width; for WIDTHxHEIGHT the same aspect), the largest view.font_size
at the given size, the longest list of the first view.panels.

For shipped scenes at 8.6 cm (a journal column), 3.4 in, 86 mm, 8.6cmx5cm,
as PDF, SVG and PNG, and two scenes side by side, this parses the
suggestions from the message and runs each: it must be drawn (exit 0), its
page the suggested size (pdfinfo), its words (pdftotext -bbox, independent
of springpend) inside the page and none over another; one step under the
suggested size (0.1 cm, 1 mm, 0.1 in), half a point over the suggested
font size and one panel more must still be refused, so each is the
extreme that fits. The refusal's numbers add up as printed: the title and
legend rows, the padding and ticks under the plot and what is left for the
plot make the panel's height.
usage: test_print_fit.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import re
import shutil
import struct
import subprocess

import sptest
from sptest import done, ok, skip

exe, src, work, run, path, scenes, asan = sptest.attack_setup("print-fit")
tools = all(shutil.which(t) for t in ("pdftotext", "pdfinfo"))
PT = {"cm": 72 / 2.54, "mm": 72 / 25.4, "in": 72.0, "pt": 1.0}
STEP = {"cm": 0.1, "mm": 1.0, "in": 0.1, "pt": 1.0}


def side(s):
    """(value, unit) of '8.6cm'."""
    m = re.fullmatch(r"([\d.]+)(cm|mm|in|pt)", s)
    return float(m.group(1)), m.group(2)


def size_pt(size, aspect):
    """(w, h) pt of a --size; WIDTH alone takes the scene's aspect h/w."""
    parts = [side(p) for p in size.split("x")]
    w = parts[0][0] * PT[parts[0][1]]
    return w, (parts[1][0] * PT[parts[1][1]] if len(parts) > 1 else w * aspect)


def fmt(v, unit):
    return f"{v:.1f}{unit}" if STEP[unit] < 1 else f"{v:.0f}{unit}"


def smaller(given, suggested):
    """The size one step under the suggested one, grown as the message
    says: WIDTH alone given and WxH suggested at that width: the height a
    step less; WxH given: the width a step less, the height at the given
    aspect to the step; WIDTH alone suggested: the width a step less."""
    g, s = given.split("x"), suggested.split("x")
    (sw, su) = side(s[0])
    if len(s) == 1:
        return fmt(sw - STEP[su], su)
    (sh, hu) = side(s[1])
    if len(g) == 1:
        return f"{s[0]}x{fmt(sh - STEP[hu], hu)}"
    (gw, gu), (gh, ghu) = side(g[0]), side(g[1])
    aspect = gh * PT[ghu] / (gw * PT[gu])
    w = sw - STEP[su]
    h = round(w * PT[su] * aspect / (STEP[hu] * PT[hu])) * STEP[hu]
    return f"{fmt(w, su)}x{fmt(h, hu)}"


def words(pdf):
    """[(text, x0, y0, x1, y1)] in pt, from pdftotext -bbox."""
    out = subprocess.run(["pdftotext", "-bbox", pdf, "-"], capture_output=True, timeout=60).stdout.decode()
    return [(m.group(5), *map(float, m.group(1, 2, 3, 4))) for m in
            re.finditer(r'<word xMin="([-\d.]+)" yMin="([-\d.]+)" xMax="([-\d.]+)" yMax="([-\d.]+)">([^<]*)</word>', out)]


def page(pdf):
    """(w, h) pt of the PDF's page, from pdfinfo."""
    out = subprocess.run(["pdfinfo", pdf], capture_output=True, timeout=60).stdout.decode()
    m = re.search(r"Page size:\s+([\d.]+) x ([\d.]+) pts", out)
    return float(m.group(1)), float(m.group(2))


def text_fits(pdf):
    """What is wrong with the PDF's words: outside the page, or over another."""
    W, H = page(pdf)
    ws = words(pdf)
    bad = [f"'{t}' outside {W:.1f}x{H:.1f}" for t, x0, y0, x1, y1 in ws
           if x0 < -0.5 or y0 < -0.5 or x1 > W + 0.5 or y1 > H + 0.5]
    for i, a in enumerate(ws):
        for b in ws[i + 1:]:
            across = min(a[3], b[3]) - max(a[1], b[1])
            down = min(a[4], b[4]) - max(a[2], b[2])
            if across > 0.5 and down > 0.25 * min(a[4] - a[2], b[4] - b[2]):
                bad.append(f"'{a[0]}' over '{b[0]}'")
    return bad if ws else ["no words"]


def png_size(f):
    with open(f, "rb") as fp:
        head = fp.read(24)
    return struct.unpack(">II", head[16:24])


def still(scenes_, size, out, more):
    return run("still", *[os.path.join(scenes, s) for s in scenes_], "--at", "5", "--size", size,
               "-o", path(out), "-q", *more)


SUGGEST = re.compile(r"laid out again, each of these fits: (.*)$", re.M)


def suggestions(msg):
    """{'size': ..., 'font': ..., 'panels': ...} from the message's last line."""
    m = SUGGEST.search(msg)
    if not m:
        return None
    s = m.group(1)
    out = {}
    for key, rx in (("size", r"--size (\S+)"), ("font", r"--set view\.font_size=([\d.]+)"),
                    ("panels", r"--set view\.panels=(\S+)")):
        f = re.search(rx, s)
        if f:
            out[key] = f.group(1)
    return out


def adds_up(name, msg):
    """The refusal's heights add up as printed."""
    m = re.search(r"of its ([\d.]+) pt height its title row.*? takes? ([\d.]+) pt and the padding "
                  r"and ticks under the plot ([\d.]+) pt, leaving (-?[\d.]+) pt for the plot", msg)
    if not m:  # the form before fix21: "take T of its H pt height, leaving L pt"
        m = re.search(r"take ([\d.]+) of its ([\d.]+) pt height, leaving (-?[\d.]+) pt", msg)
        t, h, left = map(float, m.groups()) if m else (0, 0, 1)
        ok(False, f"{name}: the refusal's heights add up: {t} + {left} = {h} pt, its plot's "
           f"height not named as such")
        return
    h, t, b, left = map(float, m.groups())
    ok(abs(t + b + left - h) < 0.051 and left < 1,
       f"{name}: the refusal's heights add up: {t} + {b} + {left} = {h} pt, under 1 pt left")


def check(name, scene_list, size, ext, more=(), aspect=None):
    """One refused still, its suggestions run, the steps past them refused."""
    out = f"{name}.{ext}"
    r = still(scene_list, size, out, list(more))
    msg = sptest.err(r)
    if not ok(r.returncode == 2 and not os.path.exists(path(out)),
              f"{name}: --size {size} refused, nothing written (exit {r.returncode})"):
        return
    adds_up(name, msg)
    sug = suggestions(msg)
    sug = sug or {}
    for what in ("size", "font", "panels"):  # each of these cases has all three
        ok(what in sug, f"{name}: says the {what} that fits: {msg.splitlines()[-1][:300]!r}")
    tries = [("size", ["--size", sug.get("size")], sug.get("size")),
             ("font", ["--size", size, "--set", f"view.font_size={sug.get('font')}"], size),
             ("panels", ["--size", size, "--set", f"view.panels={sug.get('panels')}"], size)]
    for what, args, sz in tries:
        if what not in sug:
            ok(False, f"{name}: the {what} suggested is drawn (none said)")
            continue
        f = f"{name}-{what}.{ext}"
        r2 = run("still", *[os.path.join(scenes, s) for s in scene_list], "--at", "5", *args,
                 "-o", path(f), "-q", *more)
        if not ok(r2.returncode == 0 and os.path.exists(path(f)),
                  f"{name}: the {what} suggested ({' '.join(args)}) is drawn: exit {r2.returncode} "
                  f"{sptest.err(r2)[:200]}"):
            continue
        w, h = size_pt(sz, aspect)
        if ext == "pdf" and tools:
            W, H = page(path(f))
            ok(abs(W - w) < 0.05 and abs(H - h) < 0.05,
               f"{name}: the {what} suggested makes a {W:.2f}x{H:.2f} pt page ({w:.2f}x{h:.2f})")
            bad = text_fits(path(f))
            ok(not bad, f"{name}: the {what} suggested: every word inside the page, none over "
               f"another {bad[:5]}")
        elif ext == "png":
            dpi = float(more[more.index("--dpi") + 1])
            ok(png_size(path(f)) == (round(w * dpi / 72), round(h * dpi / 72)),
               f"{name}: the {what} suggested is {png_size(path(f))} px at {dpi:g} dpi")
    # one step past each suggestion is refused: each is the extreme that fits
    if "size" not in sug:
        ok(False, f"{name}: one step past the size suggested is refused (none said)")
        return
    past = [("size", ["--size", smaller(size, sug["size"])])]
    if "font" in sug:
        past.append(("font", ["--size", size, "--set", f"view.font_size={float(sug['font']) + 0.5:g}"]))
    if "panels" in sug:
        key = re.search(r"^panels\s*=\s*([^\n#]+)", open(os.path.join(scenes, scene_list[0])).read(),
                        re.M)
        listed = re.sub(r"\s", "", key.group(1)).split(",") if key else []
        if listed == ["all"]:  # the scene reference's order of "all"
            listed = ["r", "theta", "energy", "extension", "phase", "poincare", "modes"]
        n = len(sug["panels"].split(","))
        if "(the first" in msg and n < len(listed):
            past.append(("panels", ["--size", size, "--set",
                                    f"view.panels={','.join(listed[:n + 1])}"]))
    for what, args in past:
        f = f"{name}-past-{what}.{ext}"
        r3 = run("still", *[os.path.join(scenes, s) for s in scene_list], "--at", "5", *args,
                 "-o", path(f), "-q", *more)
        ok(r3.returncode == 2 and not os.path.exists(path(f)),
           f"{name}: one step past the {what} suggested ({' '.join(args)}) is refused "
           f"(exit {r3.returncode})")


def aspect_of(scene):
    text = open(os.path.join(scenes, scene)).read()
    w = re.search(r"^width\s*=\s*(\d+)", text, re.M)
    h = re.search(r"^height\s*=\s*(\d+)", text, re.M)
    return int(h.group(1)) / int(w.group(1)) if w and h else 720 / 1280


if not tools:
    skip("print-fit", "pdftotext or pdfinfo is not installed")
else:
    for scene in ("default.ini", "resonance.ini", "driven.ini", "damped.ini", "pure_swing.ini"):
        check(scene.split(".")[0] + "-86", [scene], "8.6cm", "pdf", aspect=aspect_of(scene))
    check("default-34in", ["default.ini"], "3.4in", "pdf", aspect=aspect_of("default.ini"))
    check("default-86mm", ["default.ini"], "86mm", "pdf", aspect=aspect_of("default.ini"))
    check("default-86x5", ["default.ini"], "8.6cmx5cm", "pdf")
    check("resonance-svg", ["resonance.ini"], "8.6cm", "svg", aspect=aspect_of("resonance.ini"))
    check("default-png", ["default.ini"], "8.6cm", "png", ("--dpi", "300"),
          aspect=aspect_of("default.ini"))
    check("side-by-side", ["default.ini", "stiff.ini"], "12cm", "pdf",
          aspect=aspect_of("default.ini"))
    # a still that fits says nothing more; a refusal not of its layout says no sizes
    r = still(["chaotic.ini"], "8.6cm", "chaotic.pdf", [])
    ok(r.returncode == 0 and "laid out again" not in sptest.err(r),
       f"chaotic.ini at 8.6 cm is drawn, with no suggestion: {sptest.err(r)[:200]}")
done()
