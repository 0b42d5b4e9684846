#!/usr/bin/env python3
"""springpend tests: the command line's numbers are read as scene files read
theirs (decimal only: no hex, inf, nan, blanks or trailing junk; whole
numbers where a count, size, frame or shard is meant), in every command.
A refused value gets one stderr line naming the option as typed, what is
wrong and what is allowed, exit status 2 and no output file. The decimal
spellings that must keep working are run too, and give what the plain
spelling gives (--at 1e1 draws the still --at 10 draws).
usage: test_cli_numbers.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import shutil
import subprocess
import sys

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "cli_numbers"))
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
scene = os.path.join(src, "..", "scenes", "default.ini")
count = failed = 0
# 6 frames (0..5) at 60 fps; tiny pictures
SHORT = ["--set", "video.duration=0.1", "-q"]
SMALL = ["--size", "32x24"] + SHORT
DECIMAL = "written in decimal (digits with an optional sign, point and exponent"
OUTPUTS = ("out.png", "out.csv", "out.gif", "frames")


def ok(cond, what, why=""):
    global count, failed
    count += 1
    failed += not cond
    print(f"{'' if cond else 'not '}ok {count} - {what}", flush=True)
    if not cond:
        print("# " + why.replace("\n", "\n# "), flush=True)
    return cond


def run(*args):
    """Runs springpend in work; returns (completed process, the outputs it left), removed."""
    r = subprocess.run([exe, *args], capture_output=True, text=True, cwd=work)
    made = [o for o in OUTPUTS if os.path.exists(os.path.join(work, o))]
    for o in made:
        path = os.path.join(work, o)
        shutil.rmtree(path) if os.path.isdir(path) else os.remove(path)
    return r, made


def refused(r, made, prefix, *needles):
    """'' when r is a refusal (exit 2, nothing written, stdout empty) whose
    one stderr line starts with prefix and holds every needle, else what is
    wrong with it."""
    lines = r.stderr.strip().splitlines()
    if r.returncode != 2 or made or r.stdout:
        return f"exit {r.returncode}, written: {made}, stdout {r.stdout[:80]!r}, stderr {r.stderr.strip()!r}"
    if len(lines) != 1 or not lines[0].startswith(prefix):
        return f"expected one line starting {prefix!r}, got {r.stderr.strip()!r}"
    missing = [n for n in needles if n not in lines[0]]
    return f"{lines[0]!r} lacks {missing}" if missing else ""


def says(wrong):
    """The needles of a message that says `wrong`: it, and the decimal
    syntax when the text is no decimal number."""
    return [wrong] + ([DECIMAL] if "not a decimal number" in wrong else [])


def check(what, command, cases, good):
    """cases: (option, value, what the message says, what it allows); each
    refused as refused() wants, named "springpend: OPTION VALUE: ". good:
    argument lists (after the command's own) that must succeed."""
    wrong = []
    for opt, value, bad, allowed in cases:
        r, made = run(*command(opt, value))
        why = refused(r, made, f"springpend: {opt} {value}: ", *says(bad), "; expected " + allowed)
        if why:
            wrong.append(f"{opt} {value!r}: {why}")
    for args in good:
        r, made = run(*args)
        if r.returncode != 0 or (not made and args[0] != "info"):
            wrong.append(f"{' '.join(args[2:])} refused (exit {r.returncode}): {r.stderr.strip()!r}")
    ok(not wrong, what, "\n".join(wrong))


# ---- still: --at, --scale ----

AT = "a simulated time in seconds, 0 <= t <= 1e9"
SCALE = "a supersampling factor, an integer from 1 to 4"
check("still --at and --scale: hex, inf, nan, blanks, '1_0', '2s' refused naming the option; "
      "--at 2.5, 1e1, 0, .5 and --scale 2, 2e0 accepted",
      lambda opt, v: ["still", scene, *SMALL, opt, v, "-o", "out.png"],
      [("--at", "0x1p1", "not a decimal number", AT), ("--at", "0x10", "not a decimal number", AT),
       ("--at", " 2", "not a decimal number", AT), ("--at", "2 ", "not a decimal number", AT),
       ("--at", "1_0", "not a decimal number", AT), ("--at", "2s", "not a decimal number", AT),
       ("--at", "1e", "not a decimal number", AT), ("--at", "inf", "not finite", AT),
       ("--at", "nan", "not finite", AT), ("--at", "1e400", "not finite", AT),
       ("--at", "-1", "out of range", AT), ("--at", "2e9", "out of range", AT),
       ("--scale", "0x2", "not a decimal number", SCALE), ("--scale", " 2", "not a decimal number", SCALE),
       ("--scale", "2x", "not a decimal number", SCALE), ("--scale", "2.5", "not an integer", SCALE),
       ("--scale", "nan", "not finite", SCALE), ("--scale", "5", "out of range", SCALE)],
      [["still", scene, *SMALL, "--at", v, "-o", "out.png"] for v in ("2.5", "1e1", "0", ".5", "+3")] +
      [["still", scene, *SMALL, "--at", "1", "--scale", v, "-o", "out.png"] for v in ("2", "2e0", "1.0")])

def without_command(png):
    """The PNG's bytes less its springpend.command tEXt chunk."""
    out, i = png[:8], 8
    while i + 8 <= len(png):
        n = int.from_bytes(png[i:i + 4], "big")
        chunk = png[i:i + 12 + n]
        if not (chunk[4:8] == b"tEXt" and chunk[8:].startswith(b"springpend.command\0")):
            out += chunk
        i += 12 + n
    return out


# the value read is the value used: --at 1e1 and 5e-1 draw what 10 and 0.5 draw
same = []
for a, b in (("1e1", "10"), ("5e-1", "0.5")):
    pngs = []
    for v in (a, b):
        out = os.path.join(work, f"at{v}.png")
        subprocess.run([exe, "still", scene, *SMALL, "--set", "video.duration=20", "--at", v, "-o", out],
                       cwd=work)
        pngs.append(open(out, "rb").read() if os.path.exists(out) else b"")
    # every byte but the command the PNG records as typed (springpend.command:
    # "--at 1e1" there), which differs as the words do
    kept = [without_command(png) for png in pngs]
    same.append(pngs[0] and kept[0] == kept[1] and pngs[0] != pngs[1] and
                f"--at {a}".encode() in pngs[0] and f"--at {b}".encode() in pngs[1])
ok(all(same), "still --at 1e1 and --at 5e-1 draw the stills --at 10 and --at 0.5 draw, byte for byte "
   "(all but the springpend.command chunk, which records each as typed)")

# ---- data: --every ----

EVERY = "a sampling interval in simulated seconds, 0 < every <= 1e9"
check("data --every: hex, inf, blanks, '0.5s' refused naming the option; 0.5, 5e-2, .25 accepted",
      lambda opt, v: ["data", scene, *SHORT, opt, v, "-o", "out.csv"],
      [("--every", "0x1p-3", "not a decimal number", EVERY), ("--every", " 0.5", "not a decimal number", EVERY),
       ("--every", "0.5s", "not a decimal number", EVERY), ("--every", "inf", "not finite", EVERY),
       ("--every", "-nan", "not finite", EVERY), ("--every", "0", "out of range", EVERY)],
      [["data", scene, *SHORT, "--every", v, "-o", "out.csv"] for v in ("0.5", "5e-2", ".25")])

# --every 5e-2 samples every 0.05 s: t = 0, 0.05, 0.1 (to video.duration inclusive)
r = subprocess.run([exe, "data", scene, *SHORT, "--every", "5e-2", "-o", "-"], capture_output=True, text=True)
times = [round(float(line.split(",")[0]), 9) for line in r.stdout.splitlines()[1:]]
ok(r.returncode == 0 and times == [0, 0.05, 0.1], f"data --every 5e-2 samples at 0, 0.05 and 0.1 s: {times}")

# ---- render: --frames, --shard ----

FRAMES = "A:B, A: or :B, integers with 0 <= A < B <= 6 (the video's frames are 0..5; B is not included)"
SHARD = "I/N, integers with 1 <= I <= N <= 6 (the video's frames), e.g. --shard 2/4"
check("render --frames and --shard: hex, blanks, '1.5', junk refused naming the option and the "
      "part (A, B, I, N); 1:3, 4:, :2, 2e0:3, 2/4 accepted",
      lambda opt, v: ["render", scene, *SMALL, opt, v, "-o", "out.gif"],
      [("--frames", "0x1:5", "A not a decimal number", FRAMES), ("--frames", " 1:5", "A not a decimal number", FRAMES),
       ("--frames", "1:5 ", "B not a decimal number", FRAMES), ("--frames", "1:+5x", "B not a decimal number", FRAMES),
       ("--frames", "1.5:5", "A not an integer", FRAMES), ("--frames", "1:nan", "B not finite", FRAMES),
       ("--frames", "1:9", "B out of range", FRAMES), ("--frames", "3:3", "A not below B", FRAMES),
       ("--frames", "3", "not A:B", FRAMES), ("--frames", "1:2:3", "not A:B", FRAMES),
       ("--shard", "1/0x2", "N not a decimal number", SHARD), ("--shard", " 1/2", "I not a decimal number", SHARD),
       ("--shard", "1/ 2", "N not a decimal number", SHARD), ("--shard", "1/2x", "N not a decimal number", SHARD),
       ("--shard", "1.5/2", "I not an integer", SHARD), ("--shard", "1/inf", "N not finite", SHARD),
       ("--shard", "3/2", "I out of range", SHARD), ("--shard", "1/7", "N out of range", SHARD),
       ("--shard", "2", "not I/N", SHARD), ("--shard", "1/2/3", "not I/N", SHARD)],
      [["render", scene, *SMALL, "--frames", v, "-o", "out.gif"] for v in ("1:3", "4:", ":2", "2e0:3", "+1:2")] +
      [["render", scene, *SMALL, "--shard", "2/4", "-o", "out.gif"]])

# the frames asked for are the frames written: 1e0:3 writes 001.png and 002.png
r = subprocess.run([exe, "render", scene, *SMALL, "--frames", "1e0:3", "-o", "frames/%03d.png"], cwd=work)
listed = sorted(os.listdir(os.path.join(work, "frames"))) if os.path.isdir(os.path.join(work, "frames")) else []
shutil.rmtree(os.path.join(work, "frames"), ignore_errors=True)
ok(r.returncode == 0 and listed == ["001.png", "002.png"], f"render --frames 1e0:3 writes frames 1 and 2: {listed}")

# ---- --fps and --size: shorthands for keys, named as typed ----

wrong = []
for cmd, out in (("still", ["-o", "out.png"]), ("info", [])):
    base = SHORT if cmd == "still" else SHORT[:2]  # info prints: it takes no -q
    for opt, value, key, bad in [
            ("--fps", "0x1e", "video.fps = '0x1e'", "is not a decimal number"),
            ("--fps", " 30", "video.fps = ' 30'", "is not a decimal number"),
            ("--fps", "inf", "video.fps = inf", "is not finite"),
            ("--fps", "2000", "video.fps = 2000", "is out of range"),
            ("--size", "32.5x24", "video.width = 32.5", "is not an integer"),
            ("--size", "32x24junk", "video.height = '24junk'", "is not a decimal number"),
            ("--size", "0x20x24", "", "not WIDTHxHEIGHT"),
            ("--size", "32", "", "not WIDTHxHEIGHT"),
            ("--size", "32x99999", "video.height = 99999", "is out of range")]:
        if cmd == "info" and opt == "--size":
            continue  # info draws no frame: --size is refused there (test_attack6_fixes.py)
        args = [cmd, scene, *base, opt, value, *out]
        if opt == "--fps" and cmd == "still":
            args[2:2] = ["--size", "32x24"]
        r, made = run(*args)
        prefix = f"{opt} {value}: {key} " if key else f"springpend: {opt} {value}: "
        allowed = ("WIDTHxHEIGHT in pixels" if not key else "0 < fps <= 1000 frames/s" if opt == "--fps"
                   else "an integer from 16 to")
        why = refused(r, made, prefix, *says(bad), "; expected", allowed)
        if why:
            wrong.append(f"{cmd} {opt} {value!r}: {why}")
    for opt, value in (("--fps", "30"), ("--fps", "2.5e1"), ("--size", "32x24"), ("--size", "3.2e1x24.0")):
        if cmd == "info" and opt == "--size":
            continue
        r, made = run(cmd, scene, *base, *(["--size", "32x24"] if opt == "--fps" and cmd == "still"
                                            else []), opt, value, *out)
        if r.returncode != 0 or (cmd == "still" and not made):
            wrong.append(f"{cmd} {opt} {value} refused: {r.stderr.strip()!r}")
ok(not wrong, "still and info --fps 0x1e, still --size 32.5x24 and other junk: one line naming --fps or --size "
   "as typed (not --set), the key's range, exit 2, no file; --fps 2.5e1 and --size 3.2e1x24.0 accepted",
   "\n".join(wrong))

# ---- sweep: --vary, --time, --transient, --energy, --threads, --shard ----

VARY = ("KEY=FROM:TO:COUNT, FROM and TO in the key's file units, COUNT an integer from 1 to 100000, "
        "e.g. --vary initial.angle=10:170:256")
TIME = "simulated seconds measured, 0 < T <= 1e7"
TRANSIENT = "simulated seconds integrated first, T0 >= 0"
ENERGY = "the orbits' energy in J"
THREADS = "worker threads, an integer from 1 to 1024"
GRID = "I/N, integers with 1 <= I <= N <= 3 (the grid's points), e.g. --shard 2/4"
SWEEP = ["--measure", "lyapunov", "-q", "--set", "integrator.dt=0.01"]


def sweep(opt, value):
    args = {"--vary": [], "--time": ["--vary", "initial.angle=10:20:3"]}.get(
        opt, ["--vary", "initial.angle=10:20:3", "--time", "2"])
    outs = ["--csv", "out.csv"] if opt == "--shard" else ["-o", "out.png", "--csv", "out.csv"]
    rest = ["--time", "2"] if opt == "--vary" else []
    return ["sweep", scene, *SWEEP, *args, *rest, opt, value, *outs]


check("sweep --vary, --time, --transient, --energy, --threads, --shard: hex, inf, blanks, junk "
      "refused naming the option (and FROM, TO, COUNT, I or N); decimal spellings accepted",
      sweep,
      [("--vary", "initial.angle=0x10:20:3", "FROM not a decimal number", VARY),
       ("--vary", "initial.angle=10: 20:3", "TO not a decimal number", VARY),
       ("--vary", "initial.angle=10:inf:3", "TO not finite", VARY),
       ("--vary", "initial.angle=10:20:0x3", "COUNT not a decimal number", VARY),
       ("--vary", "initial.angle=10:20:3.5", "COUNT not an integer", VARY),
       ("--vary", "initial.angle=10:20:3x", "COUNT not a decimal number", VARY),
       ("--vary", "initial.angle=10:20:0", "COUNT out of range", VARY),
       ("--vary", "initial.angle=10:20:3:4", "not KEY=FROM:TO:COUNT", VARY),
       ("--vary", "initial.angle=10:20", "not KEY=FROM:TO:COUNT", VARY),
       ("--time", "0x1p-1", "not a decimal number", TIME), ("--time", "nan", "not finite", TIME),
       ("--time", "0", "out of range", TIME), ("--time", "1s", "not a decimal number", TIME),
       ("--transient", "0x1", "not a decimal number", TRANSIENT), ("--transient", "inf", "not finite", TRANSIENT),
       ("--transient", "-1", "out of range", TRANSIENT),
       ("--energy", "0x1", "not a decimal number", ENERGY), ("--energy", "-inf", "not finite", ENERGY),
       ("--energy", "1 J", "not a decimal number", ENERGY),
       ("--threads", "0x2", "not a decimal number", THREADS), ("--threads", "2.5", "not an integer", THREADS),
       ("--threads", " 2", "not a decimal number", THREADS), ("--threads", "0", "out of range", THREADS),
       ("--shard", "1/0x2", "N not a decimal number", GRID), ("--shard", "1.0/2x", "N not a decimal number", GRID),
       ("--shard", "1/4", "N out of range", GRID)],
      [sweep("--vary", "initial.angle=10:20:3"), sweep("--vary", "initial.angle=1e1:2e1:3e0"),
       sweep("--vary", "initial.angle=-5.5:+5:2"), sweep("--time", "2e0"),
       sweep("--transient", "0.25"), sweep("--threads", "2"), sweep("--threads", "1e0")])

# the grid read is the grid used: 1e1:2e1:3e0 gives the rows 10:20:3 gives
rows = []
for vary in ("initial.angle=1e1:2e1:3e0", "initial.angle=10:20:3"):
    r = subprocess.run([exe, "sweep", scene, *SWEEP, "--vary", vary, "--time", "2", "-o", "g.png",
                        "--csv", "g.csv"], cwd=work, capture_output=True, text=True)
    path = os.path.join(work, "g.csv")
    rows.append(open(path).read() if r.returncode == 0 and os.path.exists(path) else "")
ok(rows[0] and rows[0] == rows[1] and len(rows[0].splitlines()) == 4,
   "sweep --vary initial.angle=1e1:2e1:3e0 writes the rows 10:20:3 writes", "\n---\n".join(rows))

print(f"1..{count}")
sys.exit(1 if failed else 0)
