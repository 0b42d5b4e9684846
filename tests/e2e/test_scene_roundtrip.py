#!/usr/bin/env python3
"""springpend tests: `springpend scene FILE` prints the scene an output was
made from, as a scene file in user units (degrees, names rather than codes),
and `springpend scene FILE --command` the command that made it; that
command, read back by a shell and run on the printed scene, gives the same
bytes: PNG, MP4, WebM, SVG, PDF (under SOURCE_DATE_EPOCH), sweep figures and
CSV. Before, a PNG held only internal codes (view.panels=0x80, theme=0) and
the angle in radians, which --set would read as degrees."""
import html
import json
import os
import re
import shlex
import shutil
import subprocess
import sys

from sptest import done, ok, png_text

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "scene_roundtrip"))
shutil.rmtree(work, ignore_errors=True)
first, again = os.path.join(work, "first"), os.path.join(work, "again")
os.makedirs(first)
os.makedirs(again)
shutil.copy(os.path.join(src, "..", "scenes", "chaotic.ini"), os.path.join(first, "chaotic.ini"))

sets = ["--set", "initial.angle=33.3", "--set", "view.panels=energy,phase", "--set",
        "view.theme=light", "--set", "view.title=Run #3: ü 'x'"]
commands = {
    "png": ["still", "chaotic.ini", *sets, "--size", "320x200", "--at", "1.5", "-o", "out.png", "-q"],
    "mp4": ["render", "chaotic.ini", *sets, "--size", "160x96", "--fps", "10", "--set",
            "video.duration=1", "-o", "out.mp4", "-q"],
    "webm": ["render", "chaotic.ini", *sets, "--size", "160x96", "--fps", "10", "--set",
             "video.duration=0.5", "-o", "out.webm", "-q"],
    # data reads no [view] key (a --set of one is refused): the file's own are recorded
    "csv": ["data", "chaotic.ini", *sets[:2], "--every", "0.5", "-o", "out.csv", "-q"],
    # a printed size: the page's height from the scene's width:height, so the
    # scene is recorded as given, not with the pixels --size made of it
    "png-8.6cm": ["still", "chaotic.ini", *sets, "--size", "8.6cm", "--dpi", "100", "--at", "1.5",
                  "-o", "paper.png", "-q"],
    "svg": ["still", "chaotic.ini", *sets, "--size", "8.6cm", "--at", "1.5", "-o", "out.svg", "-q"],
    "pdf": ["still", "chaotic.ini", *sets, "--size", "8.6cm", "--at", "1.5", "-o", "out.pdf", "-q"],
    # a sweep's figure: the [view] panels are not its keys
    "sweep-pdf": ["sweep", "chaotic.ini", *sets[:2], *sets[4:], "--vary", "initial.length=0.8:1.6:3",
                  "--measure", "lyapunov", "--time", "2", "-o", "map.pdf", "-q"],
    "sweep-svg": ["sweep", "chaotic.ini", *sets[:2], *sets[4:], "--vary", "initial.length=0.8:1.6:3",
                  "--measure", "lyapunov", "--time", "2", "-o", "map.svg", "-q"],
    "sweep-png": ["sweep", "chaotic.ini", *sets[:2], *sets[4:], "--vary", "initial.length=0.8:1.6:3",
                  "--measure", "lyapunov", "--time", "2", "--size", "8.6cm", "--dpi", "100",
                  "-o", "map.png", "-q"],
}
# a PDF's date: the reproducible-builds convention, as a paper's build sets it
os.environ["SOURCE_DATE_EPOCH"] = "1700000000"


def run(cwd, args):
    return subprocess.run([exe, *args], capture_output=True, text=True, cwd=cwd)


def video_tags(path):
    """A video's container tags, as ffprobe reads them."""
    r = subprocess.run(["ffprobe", "-v", "error", "-show_entries", "format_tags", "-of", "json", path],
                       capture_output=True, text=True)
    tags = json.loads(r.stdout or "{}").get("format", {}).get("tags", {})
    return {k.lower(): v for k, v in tags.items()}  # Matroska's are upper-case


def read(path):
    with open(path, "rb") as f:
        return f.read()


for kind, args in commands.items():
    r = run(first, args)
    out = args[args.index("-o") + 1]
    if r.returncode:
        ok(False, f"{kind}: written (exit {r.returncode}: {r.stderr.strip()[-200:]})")
        continue
    s = run(first, ["scene", out])
    scene = s.stdout
    view = kind != "csv"  # data's: chaotic.ini's own [view], in names
    ok(s.returncode == 0 and "[initial]\n" in scene and "angle = 33.3\n" in scene and
       ("panels = energy, phase\n" in scene or kind.startswith("sweep") or
        (not view and "panels = theta, energy, phase, poincare\n" in scene)) and
       ("theme = light\n" in scene or not view) and
       ("title = \"Run #3: ü 'x'\"\n" in scene or not view) and "0x" not in scene,
       f"{kind}: `springpend scene` prints the scene in user units and names "
       f"(angle = 33.3 degrees, panels = energy, phase, theme = light) {s.stderr.strip()}")
    # every output records its command without the output's name; `scene
    # --command` prints it, and the PDF/SVG hold it as `pdfinfo` and XML show
    # (and without -q: what is printed is not what is written)
    want = ["springpend", *[a for i, a in enumerate(args)
                            if a not in ("-o", "-q") and (i == 0 or args[i - 1] != "-o")]]
    c = run(first, ["scene", out, "--command"])
    recorded = shlex.split(c.stdout) if c.returncode == 0 else None
    ok(recorded == (["springpend", *args] if kind == "csv" else want),
       f"{kind}: `springpend scene {out} --command` prints the command that made it "
       f"({c.stdout.strip()!r} {c.stderr.strip()[-160:]})")
    if kind.endswith("svg") or kind.endswith("pdf"):
        data = read(os.path.join(first, out))
        if kind.endswith("pdf"):
            info = subprocess.run(["pdfinfo", os.path.join(first, out)], capture_output=True,
                                  text=True).stdout if shutil.which("pdfinfo") else ""
            line = [l for l in info.splitlines() if l.startswith("# command: ")]
        else:
            m = re.search(rb'<metadata id="springpend.command">([^<]*)</metadata>', data)
            line = ["# command: " + html.unescape(m.group(1).decode())] if m else []
        got = shlex.split(line[0][len("# command: "):]) if len(line) == 1 else None
        ok(got == want or (kind.endswith("pdf") and not shutil.which("pdfinfo")),
           f"{kind}: the figure records its command without -o: {line}")
        # and, as a PNG does, the renderer and the font files drawn from
        if kind.endswith("pdf"):
            made = [l for l in info.splitlines() if l.startswith(("Producer:", "Keywords:"))]
        else:
            made = [f"{k.decode()}: {html.unescape(v.decode())}" for k, v in re.findall(
                rb'<metadata id="springpend.(renderer|fonts)">([^<]*)</metadata>', data)]
        ok(any(l.startswith(("Producer:", "renderer:")) and "cairo" in l for l in made) and
           any("fonts: DejaVu Sans (embedded in springpend)" in l for l in made)
           or (kind.endswith("pdf") and not shutil.which("pdfinfo")),
           f"{kind}: the figure names its renderer and fonts: {made}")
    elif kind != "csv":
        tag = (png_text(os.path.join(first, out)).get("springpend.command") if out.endswith(".png")
               else video_tags(os.path.join(first, out)).get("springpend.command"))
        ok(tag is not None and shlex.split(tag) == want,
           f"{kind}: the springpend.command {'text' if out.endswith('.png') else 'tag'} holds it: {tag!r}")
    # the recorded command, run where the scene file is the one printed
    with open(os.path.join(again, "chaotic.ini"), "w") as f:
        f.write(scene)
    if kind == "csv":
        recorded = json.loads(read(os.path.join(first, out + "-metadata.json")))["prov:wasGeneratedBy"]
        words = shlex.split(recorded)
        ok(words == ["springpend", *args], f"csv: the recorded command reads back into its words: {recorded}")
        args = words[1:]
    elif recorded:
        args = recorded[1:] + ["-o", out, "-q"]  # the printed command, with an output named
    r2 = run(again, args)
    ok(r2.returncode == 0 and read(os.path.join(first, out)) == read(os.path.join(again, out)),
       f"{kind}: the command run again on the printed scene gives the same bytes "
       f"({r2.stderr.strip()[-160:]})")
    if kind == "csv":
        ok(read(os.path.join(first, out + "-metadata.json")) ==
           read(os.path.join(again, out + "-metadata.json")),
           "csv: and the same metadata bytes (scene, command, versions)")

# A long [timeline] (about 9 KB of scene text, beyond the 8 KiB the chunks
# once held: they were written empty, and `scene` printed nothing, exit 0).
lesson = open(os.path.join(src, "..", "scenes", "lesson-exchange.ini")).read()
long_ini = lesson.split("\n[timeline]")[0] + "\n[timeline]\n" + "".join(
    f"{i * 0.2:.1f} = caption: Step {i}: the energy moves from the bounce into the swing\n"
    for i in range(120))
with open(os.path.join(first, "long.ini"), "w") as f:
    f.write(long_ini)
for out, args in (("long.png", ["still", "long.ini", "--at", "1", "--size", "320x180"]),
                  ("long.mp4", ["render", "long.ini", "--size", "160x96", "--fps", "2",
                                "--set", "video.duration=24"])):
    r = run(first, [*args, "-o", out, "-q"])
    s = run(first, ["scene", out])
    ok(r.returncode == 0 and s.returncode == 0 and "Step 119: the energy" in s.stdout
       and s.stdout.count("caption: \"Step") == 120,
       f"{out}: a scene of {len(long_ini)} bytes is recorded whole ({len(s.stdout)} bytes "
       f"printed, exit {s.returncode}) {r.stderr.strip()[-160:]} {s.stderr.strip()[-160:]}")

# A scene file whose name holds a terminal control (ESC) and a byte that is
# not UTF-8 (Latin-1 é): the command is recorded with them escaped, so no
# output holds a control byte and `scene --command` drives no terminal.
odd = b"c\x1b[31mx\xe9.ini"
with open(os.path.join(first.encode(), odd), "wb") as f:
    f.write(read(os.path.join(first, "chaotic.ini")))
for out, size in (("odd.png", [b"320x200"]), ("odd.svg", [b"8.6cm"])):
    r = subprocess.run([exe.encode(), b"still", odd, b"--size", *size, b"-o", out.encode(), b"-q"],
                       capture_output=True, cwd=first)
    c = subprocess.run([exe, "scene", out, "--command"], capture_output=True, cwd=first)
    held = ""
    if r.returncode == 0:  # the record itself: the PNG's text, the SVG's <metadata>
        held = (png_text(os.path.join(first, out)).get("springpend.command", "") if out.endswith("png")
                else read(os.path.join(first, out)).decode())
    line = b"springpend still 'c\\x1b[31mx\\xe9.ini' --size " + size[0]
    ok(r.returncode == 0 and c.returncode == 0 and c.stdout == line + b"\n" and
       "\x1b" not in held and line.decode() in held,
       f"{out}: a control and a Latin-1 byte in the command are recorded and printed escaped "
       f"({c.stdout!r} {r.stderr.decode(errors='replace').strip()[-120:]})")
shutil.copy(os.path.join(src, "golden", "default_t3.png"), os.path.join(first, "old.png"))
r = run(first, ["scene", "old.png", "--command"])
ok(r.returncode == 2 and "carries no command" in r.stderr,
   f"--command on a PNG that records none: exit 2 {r.stderr.strip()}")

# a PDF or SVG springpend did not write (or wrote before it recorded scenes)
with open(os.path.join(first, "other.pdf"), "wb") as f:
    f.write(b"%PDF-1.5\n1 0 obj << /Subject (notes) >> endobj\n%%EOF\n")
r = run(first, ["scene", "other.pdf"])
ok(r.returncode == 2 and "carries no scene" in r.stderr,
   f"a PDF whose /Subject is not a springpend scene: exit 2 {r.stderr.strip()}")
with open(os.path.join(first, "cut.svg"), "w") as f:
    f.write('<svg><metadata id="springpend.scene-file">[view]\ntitle = "a &bogus; b"\n</metadata></svg>\n')
r = run(first, ["scene", "cut.svg"])
ok(r.returncode == 2 and "holds '&bogus;'" in r.stderr,
   f"an SVG record with a bad escape: exit 2, naming it {r.stderr.strip()}")

r = run(first, ["scene", "chaotic.ini"])
ok(r.returncode == 2 and "not a PNG, video" in r.stderr, f"a scene file itself: exit 2 {r.stderr.strip()}")
shutil.copy(os.path.join(src, "golden", "default_t3.png"), os.path.join(first, "old.png"))
r = run(first, ["scene", "old.png"])
ok(r.returncode == 2 and "carries no scene" in r.stderr,
   f"a PNG an older springpend made (no springpend.scene-file): exit 2 {r.stderr.strip()}")
r = run(first, ["scene"])
ok(r.returncode == 2 and "expected one FILE" in r.stderr, "no FILE: exit 2")
done()
