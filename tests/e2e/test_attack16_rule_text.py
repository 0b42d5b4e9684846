#!/usr/bin/env python3
"""springpend tests (issue 28): the sixteenth attacker's pass
(doc/notes/2026-11-27/attack16.md), findings 7 and 9:
- #7: compare.ini loosened a command-line limit through a field the command
  line did not give: `metric = pixelmatch` with `threshold = 1`, or
  `max_diff = 255`, made `--max-pixels 0` pass images of another scene, and
  `metric = rms` with `max_diff = 255` built the command line's own reftest
  rule with compare.ini's max_diff. The command line's own rule is now built
  from its limits and the defaults alone and judged whenever it gives a
  limit; a matrix of command lines against compare.ini's fields for each
  metric (and a mask) is checked against verdicts computed here from the
  pixels (reftest counts, RMS and pixelmatch's YIQ distance);
- #9: the "Passed, but drawn with other text than the baseline" list and the
  "scene:" line compared values cut at 47 bytes: a caption changed after
  its 47th byte, a long non-Latin caption, a timeline cue's caption were
  never listed. Whole values are compared; long ones are shown cut around
  the first difference with an ellipsis, at a character boundary, the same
  in text, Markdown, JUnit, HTML and JSON.
usage: test_attack16_rule_text.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import json
import math
import os
import shutil
import struct
import zlib

import sptest
from sptest import done, err, ok

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack16-rule-text")
default = os.path.join(scenes, "default.ini")
lesson = os.path.join(scenes, "lesson-exchange.ini")

# ---- 7: a command-line limit is never judged with a field compare.ini loosened ----------------
W = H = 100
N = W * H
BASE = 128
G = [(x, y) for x in range(20, 24) for y in range(20, 25)]   # 20 px moved by 100 levels (grey)
S = [(x, y) for x in range(50, 60) for y in range(60, 65)]   # 50 px moved by 10 levels
MOVE = {**{p: 100 for p in G}, **{p: 10 for p in S}}
MASK_G = (20, 20, 4, 5)  # x, y, width, height: region G


def write_png(name, pix):
    """An 8-bit RGB PNG W x H from pix(x, y) -> grey level."""
    rows = b"".join(b"\0" + bytes(c for x in range(W) for c in (pix(x, y),) * 3) for y in range(H))

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    with open(name, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


E, A = path("e"), path("a")
os.makedirs(E)
os.makedirs(A)
write_png(os.path.join(E, "x.png"), lambda x, y: BASE)
write_png(os.path.join(A, "x.png"), lambda x, y: BASE + MOVE.get((x, y), 0))
for name in ("y.png", "z.png"):  # identical pairs: their sections put rms and pixelmatch in force
    write_png(os.path.join(E, name), lambda x, y: BASE)
    write_png(os.path.join(A, name), lambda x, y: BASE)


def figures(masked):
    """The pixels' figures, computed here: each moved pixel's level change
    (grey: the same in R, G and B, opaque), so the reftest count is the
    pixels moved by more than D, the RMS over RGB, and pixelmatch's YIQ
    distance (mapbox/pixelmatch 5.3: 0.5053 y^2 + 0.299 i^2 + 0.1957 q^2 with
    y, i, q the differences of its rgb2y/i/q); the moved regions are solid
    blocks on a flat ground, so no pixel is taken for anti-aliasing."""
    moves = [d for p, d in MOVE.items() if not (masked and p in G)]

    def yiq(v):
        return (v * 0.29889531 + v * 0.58662247 + v * 0.11448223,
                v * 0.59597799 - v * 0.27417610 - v * 0.32180189,
                v * 0.21147017 - v * 0.52261711 + v * 0.31114694)
    deltas = []
    for d in moves:
        a, b = yiq(BASE), yiq(BASE + d)
        y, i, q = (a[k] - b[k] for k in range(3))
        deltas.append(0.5053 * y * y + 0.299 * i * i + 0.1957 * q * q)
    return {"moves": moves, "deltas": deltas,
            "rms": math.sqrt(sum(3 * d * d for d in moves) / (3 * N))}


DEFAULTS = {"max_diff": 3, "max_pixels": ("%", 0.1), "tol": 2.0, "threshold": 0.1}


def allowed(v):
    return v[1] if v[0] == "n" else math.floor(v[1] / 100 * N)


def passes(metric, lim, fig):
    """Whether the rule metric with limits lim passes the pixels' figures."""
    if metric == "rms":
        return fig["rms"] <= lim["tol"]
    if metric == "reftest":
        return sum(d > lim["max_diff"] for d in fig["moves"]) <= allowed(lim["max_pixels"])
    return sum(dl > 35215 * lim["threshold"] ** 2 for dl in fig["deltas"]) <= allowed(lim["max_pixels"])


def stricter(f, a, b):
    return (a if allowed(a) <= allowed(b) else b) if f == "max_pixels" else min(a, b)


def expected_pass(ini, cli, fig):
    """The verdict doc/ci.md promises: compare.ini's rule, each field the
    stricter of compare.ini's and the command line's, passes, and so does
    the command line's own rule, built from its limits and the defaults."""
    return ini_rule_passes(ini, cli, fig) and own_rule_passes(cli, fig)


def ini_rule_passes(ini, cli, fig):
    metric = cli.get("metric") or ini.get("metric") or "reftest"
    lim = {}
    for f in DEFAULTS:
        lim[f] = ini.get(f, cli.get(f, DEFAULTS[f]))
        if f in cli:
            lim[f] = stricter(f, lim[f], cli[f])
    return passes(metric, lim, fig)


def own_rule_passes(cli, fig):
    own = {f: cli.get(f, DEFAULTS[f]) for f in DEFAULTS}
    limits = [f for f in DEFAULTS if f in cli]
    if not limits:
        return True
    if cli.get("metric"):
        rules = {cli["metric"]}
    else:
        rules = set()
        if "max_diff" in cli or ("max_pixels" in cli and "threshold" not in cli):
            rules.add("reftest")
        if "tol" in cli:
            rules.add("rms")
        if "threshold" in cli:
            rules.add("pixelmatch")
    return all(passes(m, own, fig) for m in rules)


def ini_text(ini):
    s = "[*]\n"
    for f, v in ini.items():
        if f == "mask":
            s += "mask = %d, %d, %d, %d\n" % v
        elif f == "max_pixels":
            s += f"max_pixels = {v[1]:g}{'%' if v[0] == '%' else ''}\n"
        else:
            s += f"{f} = {v:g}\n" if not isinstance(v, str) else f"{f} = {v}\n"
    return s + "[y.png]\nmetric = rms\n[z.png]\nmetric = pixelmatch\n"


def cli_args(cli):
    out = []
    for f, v in cli.items():
        out.append("--" + f.replace("_", "-"))
        out.append(v if isinstance(v, str) else f"{v[1]:g}{'%' if v[0] == '%' else ''}"
                   if f == "max_pixels" else f"{v:g}")
    return out


INIS = [{}, {"max_diff": 255}, {"max_pixels": ("%", 100)}, {"max_diff": 255, "max_pixels": ("%", 100)},
        {"metric": "pixelmatch", "threshold": 1}, {"metric": "pixelmatch", "max_pixels": ("%", 100)},
        {"metric": "pixelmatch", "threshold": 1, "max_diff": 255},
        {"metric": "rms", "tol": 255}, {"metric": "rms", "tol": 255, "max_diff": 255},
        {"metric": "rms", "tol": 255, "max_pixels": ("%", 100), "threshold": 1},
        {"max_diff": 0, "max_pixels": ("n", 0)}, {"metric": "pixelmatch", "threshold": 0.03,
                                                    "max_pixels": ("n", 0)},
        {"metric": "rms", "tol": 0.5}, {"max_diff": 255, "mask": MASK_G},
        {"metric": "pixelmatch", "threshold": 0.05, "mask": MASK_G}]
CLIS = [{}, {"max_pixels": ("n", 0)}, {"max_pixels": ("n", 30)}, {"max_pixels": ("n", 60)},
        {"max_diff": 10}, {"max_diff": 0}, {"max_diff": 255, "max_pixels": ("%", 100)},
        {"tol": 1}, {"tol": 10}, {"threshold": 0.03}, {"threshold": 0.1, "max_pixels": ("n", 0)},
        {"threshold": 0.5, "max_pixels": ("%", 100)}, {"metric": "pixelmatch", "max_pixels": ("n", 0)},
        {"metric": "pixelmatch", "threshold": 0.03, "max_pixels": ("n", 60)},
        {"metric": "rms", "tol": 1}, {"metric": "rms", "tol": 5}, {"metric": "reftest", "max_diff": 255},
        {"metric": "reftest", "max_pixels": ("n", 25)}, {"metric": "pixelmatch"}, {"metric": "rms"},
        {"max_diff": 0, "threshold": 0.1, "max_pixels": ("n", 25)}, {"tol": 10, "max_pixels": ("n", 25)},
        {"tol": 5, "threshold": 0.03}]
FIGS = {False: figures(False), True: figures(True)}
wrong, cells, loosened = [], 0, 0
for ini in INIS:
    with open(os.path.join(E, "compare.ini"), "w") as f:
        f.write(ini_text(ini))
    for cli in CLIS:
        cells += 1
        want = expected_pass(ini, cli, FIGS["mask" in ini])
        # compare.ini's rule (tightened field by field) passes, the command line's own fails
        loosened += ini_rule_passes(ini, cli, FIGS["mask" in ini]) and not want
        r = run("compare", E, A, *cli_args(cli))
        line = next((s for s in r.stdout.decode(errors="replace").splitlines() if " x.png:" in s), "")
        got = {0: True, 1: False}.get(r.returncode)
        if got != want or not line.startswith("ok" if want else "FAIL"):
            wrong.append(f"[{ini_text(ini).split('[y.png]')[0].strip()!r}] {' '.join(cli_args(cli))}: "
                         f"expected {'pass' if want else 'fail'}, exit {r.returncode} "
                         f"({(line or err(r))[:60]}…{line[-90:]})")
ok(not wrong, f"7: {cells} command lines against compare.ini's fields (each metric, a mask): each "
   f"verdict is the one computed here ({len(wrong)} differ; in {loosened} compare.ini's rule, "
   f"tightened field by field, passes and the command line's own rule fails){': ' + ' | '.join(wrong[:8]) if wrong else ''}")

# the attacker's three reproductions, as they read, with real frames of two scenes
e7, a7 = path("e7"), path("a7")
os.makedirs(e7)
os.makedirs(a7)
stiff = os.path.join(scenes, "stiff.ini")
assert run("still", default, "--at", "1", "--size", "320x180", "-o", os.path.join(e7, "x.png"), "-q").returncode == 0
assert run("still", stiff, "--at", "1", "--size", "320x180", "-o", os.path.join(a7, "x.png"), "-q").returncode == 0
for ini in ("[*]\nmetric = pixelmatch\nthreshold = 1\n", "[*]\nmax_diff = 255\n",
            "[*]\nmetric = rms\ntol = 255\nmax_diff = 255\n"):
    with open(os.path.join(e7, "compare.ini"), "w") as f:
        f.write(ini)
    r = run("compare", e7, a7, "--max-pixels", "0", "--json")
    try:
        res = json.loads(r.stdout)["results"][0]
        rules = res["tolerance"]["command_line_rules"]
    except (ValueError, KeyError, IndexError, TypeError):
        res, rules = {}, []
    ok(r.returncode == 1 and res.get("verdict") == "fail" and len(rules) == 1
       and rules[0].get("metric") == "reftest" and rules[0].get("max_channel_diff") == 3
       and rules[0].get("max_differing_pixels") == 0 and rules[0].get("differing_pixels", 0) > 0
       and rules[0].get("pass") is False,
       f"7: compare.ini {ini!r} with --max-pixels 0: fails, the JSON names the command line's reftest "
       f"rule at 3 levels, 0 allowed (exit {r.returncode}: {rules})")
    r = run("compare", e7, a7, "--max-pixels", "0")
    line = r.stdout.decode(errors="replace").splitlines()[0] if r.stdout else err(r)
    ok(r.returncode == 1 and line.startswith("FAIL") and "the command line's reftest rule" in line
       and "by more than 3 levels (0 allowed), which decided: fail" in line,
       f"7: compare.ini {ini!r} with --max-pixels 0: the line names the command line's rule at 3 "
       f"levels (exit {r.returncode}: {line[-150:]})")


# ---- 9: scene values compared whole, shown whole or cut around the first difference -----------
SHOWN, SLACK = 100, 24  # doc/ci.md: values over 100 bytes are cut; 24 more to reach the end
e9, a9 = path("e9"), path("a9")
os.makedirs(e9)
os.makedirs(a9)
with open(default) as f:
    default_text = f.read()
with open(lesson) as f:
    lesson_text = f.read()
assert "flows back to the bounce" in lesson_text and "[timeline]" not in default_text

ru = "Энергия переходит от вертикальных колебаний к маятниковым, прогон 1"
ja = "ばねの振り子でエネルギーが上下の振動から左右の振り子運動へ移り、また戻ってくる様子、試行一"
hi = ("मुख्य ऊर्जा का आदान-प्रदान उछाल और झूले के बीच स्प्रिंग लोलक में होता है और फिर वापस "
      "उछाल में लौटता है, प्रयोग संख्या एक")
CASES = [  # name, scene kind, text, key, (what the actual replaces, by what)
    ("latin48", None, "Energy exchange between bounce and swingg, run 1", "view.caption", ("run 1", "run 7")),
    ("ru_end", None, ru, "view.caption", ("прогон 1", "прогон 7")),
    ("ja_mid", None, ja, "view.caption", ("上下", "前後")),
    ("hi_mid", None, hi, "view.caption", ("झूले", "झूलों")),
    ("hi_end", None, hi, "view.title", ("संख्या एक", "संख्या दो")),
    ("cue_end", "lesson", "flows back to the bounce", "timeline.5", ("the bounce", "the bounce, 7")),
    ("cue_ja", "cue", ja, "timeline.0", ("試行一", "試行二")),
]


def scene_for(kind, text, key):
    if kind == "lesson":
        return lesson_text.replace("flows back to the bounce", text)
    if kind == "cue":
        return default_text + "\n[timeline]\n0 = caption: " + text + "\n"
    return default_text.replace("[view]\n", f"[view]\n{key.split('.')[1]} = {text}\n", 1)


assert "[view]\n" in default_text
whole = {}
for name, kind, text, key, (old, new) in CASES:
    texts = (text, text.replace(old, new, 1))
    assert texts[0] != texts[1]
    for folder, t in zip((e9, a9), texts):
        ini = os.path.join(work, f"{name}-{os.path.basename(folder)}.ini")
        with open(ini, "w") as f:
            f.write(scene_for(kind, t, key))
        at = "31" if kind == "lesson" else "1"
        r = run("still", ini, "--at", at, "--size", "1280x720", "-o", os.path.join(folder, name + ".png"), "-q")
        assert r.returncode == 0, (name, err(r))
    # the recorded values, as the scene records them (a cue: TIME caption 0 TEXT)
    if kind == "lesson":
        whole[name] = tuple(f"30 caption 0 ... and {t}" for t in texts)
    elif kind == "cue":
        whole[name] = tuple(f"0 caption 0 {t}" for t in texts)
    else:
        whole[name] = texts
# a cue only the actual has
with open(os.path.join(work, "added-e.ini"), "w") as f:
    f.write(lesson_text)
with open(os.path.join(work, "added-a.ini"), "w") as f:
    f.write(lesson_text.rstrip("\n") + "\n35 = caption: one more cue\n")
for folder, side in ((e9, "e"), (a9, "a")):
    assert run("still", os.path.join(work, f"added-{side}.ini"), "--at", "31", "--size", "1280x720", "-o",
               os.path.join(folder, "added.png"), "-q").returncode == 0

r = run("compare", e9, a9, "--max-pixels", "100%", "--json")
js = json.loads(r.stdout) if r.stdout else {"results": []}
rt = run("compare", e9, a9, "--max-pixels", "100%", "--summary", path("s.md"), "--junit", path("j.xml"),
         "--report", path("r.html"))
text = rt.stdout.decode(errors="replace")
md = open(path("s.md"), encoding="utf-8").read() if os.path.exists(path("s.md")) else ""
junit = open(path("j.xml"), encoding="utf-8").read() if os.path.exists(path("j.xml")) else ""
page = open(path("r.html"), encoding="utf-8").read() if os.path.exists(path("r.html")) else ""


def changes_of(name):
    res = next((x for x in js["results"] if x["name"] == name + ".png"), {})
    return {c["key"]: c for c in res.get("scene_changes", [])}


def md_unescape(cell):
    import html
    import re
    return html.unescape(re.sub(r"\\([\\~|`*_\[\]#!])", r"\1", cell.strip()))


def breaks_well(whole_text, piece, at_start):
    """A cut at a character boundary that splits nothing drawn as one: the
    piece does not start with a mark or format character, nor after a
    virama or joiner; nor ends before one (unicodedata, independently)."""
    import unicodedata
    i = whole_text.find(piece)
    if i < 0:
        return False
    if at_start:
        first, prev = piece[0], whole_text[i - 1] if i else ""
        return i == 0 or (unicodedata.category(first)[0] != "M" and unicodedata.category(first) != "Cf"
                          and prev not in "\u200c\u200d" and unicodedata.combining(prev) != 9)
    j = i + len(piece)
    if j == len(whole_text):
        return True
    nxt, last = whole_text[j], piece[-1]
    return (unicodedata.category(nxt)[0] != "M" and unicodedata.category(nxt) != "Cf"
            and last not in "\u200c\u200d" and unicodedata.combining(last) != 9)


for name, kind, text_, key, (old, new) in CASES:
    we, wa = whole[name]
    ch = changes_of(name).get(key)
    if not ok(ch is not None, f"9: {name}: {key} listed in the JSON's scene_changes ({list(changes_of(name))})"):
        ch = {"expected": "(not listed)", "actual": "(not listed)"}  # the checks below fail too
    se, sa = ch["expected"], ch["actual"]
    long_ = max(len(we.encode()), len(wa.encode())) > SHOWN
    d = next((i for i, (x, y) in enumerate(zip(we, wa)) if x != y), min(len(we), len(wa)))
    good = True
    why = ""
    if not long_:
        good = se == we and sa == wa and ch.get("cut") is False
        why = "whole"
    else:
        for w, shown in ((we, se), (wa, sa)):
            piece = shown[1:] if shown.startswith("…") else shown
            piece = piece[:-1] if piece.endswith("…") else piece
            i = w.find(piece)
            good &= (i >= 0 and i <= d <= i + len(piece) and shown.startswith("…") == (i > 0)
                     and shown.endswith("…") == (i + len(piece) < len(w))
                     and len(piece.encode()) <= SHOWN + SLACK
                     and breaks_well(w, piece, True) and breaks_well(w, piece, False))
        good &= ch.get("cut") is True and new.split()[-1][:1] in sa
        why = "cut around the first difference, at boundaries"
    ok(good, f"9: {name} ({len(we.encode())} bytes, first difference at character {d}): {key} shown "
       f"{why}: {se!r} vs {sa!r}")
    # the same values in text, Markdown, JUnit and HTML
    import html as html_
    import xml.etree.ElementTree as ET
    line = f"scene: {key} = {se} (expected) vs {sa} (actual)"
    in_text = line in text
    row = next((ln for ln in md.splitlines() if ln.startswith("| ") and len(ln.split(" | ")) == 4
                and md_unescape(ln.split(" | ")[0][2:]) == name + ".png"
                and md_unescape(ln.split(" | ")[1]) == key), "")
    cells = row.split(" | ")
    in_md = len(cells) == 4 and md_unescape(cells[2]) == se and md_unescape(cells[3].rstrip(" |")) == sa
    try:
        jtext = " ".join(t for t in ET.fromstring(junit).itertext())
    except ET.ParseError:
        jtext = ""
    pair = f"scene {key}: {se} vs {sa}"
    in_junit, in_html = pair in jtext, pair in html_.unescape(page)
    ok(in_text and in_md and in_junit and in_html,
       f"9: {name}: the same values in text ({in_text}), the Markdown list ({in_md}: {row[:100]!r}), "
       f"JUnit ({in_junit}) and HTML ({in_html})")

ch = changes_of("added").get("timeline.6")
ok(ch is not None and ch["expected"] == "(none)" and ch["actual"] == "35 caption 0 one more cue"
   and "| added.png | timeline.6 | (none) | 35 caption 0 one more cue |" in md,
   f"9: a cue only the actual has is listed: {ch}")

# a video under the default block rule, a 70-character caption changed at its end
ev, av = path("ev"), path("av")
os.makedirs(ev)
os.makedirs(av)
cap = "Energy exchange between bounce and swing of the spring pendulum, run 1"
for folder, c in ((ev, cap), (av, cap.replace("run 1", "run 7"))):
    assert run("render", default, "--set", "video.duration=0.5", "--size", "640x360", "--set",
               f"view.caption={c}", "-o", os.path.join(folder, "v.mp4"), "-q").returncode == 0
r = run("compare", ev, av, "--summary", path("v.md"))
vmd = open(path("v.md"), encoding="utf-8").read() if os.path.exists(path("v.md")) else ""
ok(r.returncode == 0 and f"scene: view.caption = {cap} (expected) vs {cap.replace('run 1', 'run 7')} (actual)"
   in r.stdout.decode(errors="replace") and "other text than the baseline" in vmd
   and "run 7" in vmd,
   f"9: a video passing under the block rule with its 70-character caption changed at the end: "
   f"the scene line and the Markdown list show it (exit {r.returncode})")
done()
