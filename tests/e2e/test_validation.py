#!/usr/bin/env python3
"""springpend tests: numbers are read whole and in decimal only. Scene keys
(in a file and through --set), view.trail and compare.ini (and compare's
options) refuse what strtod takes beyond a decimal number (hex floats, inf,
nan, blanks) and say what is wrong and what is allowed: FILE:LINE, or the
--set argument, exit status 2, no output file. Each case also accepts the
decimal spellings it must keep accepting.
usage: test_validation.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import shutil
import subprocess
import sys

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "validation"))
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
count = failed = 0
SMALL = ["--size", "32x24", "--set", "video.duration=0.1"]
# strtod's extras, and what is no number at all ("  " reads as "" in a file)
NOT_DECIMAL = ["0x1p1", "0x10", "1e", "  ", "1_000", "1e+", ".", "2 2"]
NOT_FINITE = ["inf", "-Infinity", "nan", "NAN(1)"]


def ok(cond, what, why=""):
    global count, failed
    count += 1
    failed += not cond
    print(f"{'' if cond else 'not '}ok {count} - {what}", flush=True)
    if not cond:
        print("# " + why.replace("\n", "\n# "), flush=True)
    return cond


def run(*args):
    return subprocess.run([exe, *args], capture_output=True, text=True, cwd=work)


def write(name, text):
    with open(os.path.join(work, name), "w") as f:
        f.write(text)
    return name


def still(scene, *extra):
    """A tiny still; returns (completed process, whether out.png exists), out.png removed."""
    out = os.path.join(work, "out.png")
    if os.path.exists(out):
        os.remove(out)
    r = run("still", scene, *SMALL, "-q", *extra, "-o", "out.png")
    made = os.path.exists(out)
    if made:
        os.remove(out)
    return r, made


def refused(r, made, prefix, *needles):
    """'' when r is a refusal (exit 2, no file) whose one message starts with
    prefix and holds every needle, else what is wrong with it."""
    lines = r.stderr.strip().splitlines()
    if r.returncode != 2 or made:
        return f"exit {r.returncode}, file written: {made}, stderr {r.stderr.strip()!r}"
    if len(lines) != 1 or not lines[0].startswith(prefix):
        return f"expected one line starting {prefix!r}, got {r.stderr.strip()!r}"
    missing = [n for n in needles if n not in lines[0]]
    return f"{lines[0]!r} lacks {missing}" if missing else ""


# ---- every numeric key kind: a real, an angle (degrees), an integer ----

KINDS = [  # key, its range as messages give it, values that must still work
    ("view.font_scale", "0.25 <= font_scale <= 4", ["2", "1.5", ".5", "3.", "+1", "2.5e-1", "1E0"]),
    ("pendulum.mass", "0 < mass <= 1e+06 kg", ["1", "0.25", "5e-1", "1e+0"]),
    ("initial.angle", "-360 <= angle <= 360 degrees", ["-45", "0", "1.5e1", "-0"]),
    ("video.width", "an integer from 16 to 7680 px", ["64", "6.4e1", "64.0", "+64"]),
]
for key, rng, good in KINDS:
    section, name = key.split(".")
    for via in ("file", "--set"):
        wrong = []
        for value in NOT_DECIMAL + NOT_FINITE:
            says = "is not finite" if value in NOT_FINITE else "is not a decimal number"
            if via == "file":
                scene = write("bad.ini", f"# a comment\n[{section}]\n{name} = {value}\n")
                shown = value.strip()
                prefix = f"bad.ini:3: {key} = " + (shown if value in NOT_FINITE else f"'{shown}'")
                r, made = still(scene)
            else:
                prefix = f"--set {key}={value}: {key} = " + (value if value in NOT_FINITE else f"'{value}'")
                r, made = still(write("good.ini", "[video]\nfps = 30\n"), "--set", f"{key}={value}")
            needles = [says, "; expected", rng]
            if value not in NOT_FINITE:
                needles.append("written in decimal (digits with an optional sign, point and exponent")
            why = refused(r, made, prefix, *needles)
            if why:
                wrong.append(f"{value!r}: {why}")
        for value in good:
            text = f"[{section}]\n{name} = {value}\n"
            r, made = (still(write("good.ini", text)) if via == "file" else
                       still(write("good.ini", "[video]\nfps = 30\n"), "--set", f"{key}={value}"))
            if r.returncode != 0 or not made:
                wrong.append(f"{value!r} refused: {r.stderr.strip()!r}")
        ok(not wrong, f"{key} from a {via}: hex, inf, nan, '1e', blanks, '1_000' refused with "
           f"{'FILE:LINE' if via == 'file' else 'the --set argument'}, what is allowed, exit 2, "
           f"no file; {', '.join(good)} accepted", "\n".join(wrong))

# A value the parser once took is the value the scene gets: font_scale = 0x1p1
# was read as 2 (a still identical to font_scale = 2).
r, made = still(write("hex.ini", "[view]\nfont_scale = 0x1p1\nhud = true\n"))
ok(r.returncode == 2 and not made and "hex.ini:2: view.font_scale = '0x1p1' is not a decimal number"
   in r.stderr, "the report's case: font_scale = 0x1p1 in a scene file is refused at line 2",
   r.stderr)

# ---- view.trail: frames, a duration, all; nothing after them ----

TRAIL = ("allowed: frames as an integer from 0 to 1000000, a duration D such as 5s "
         "(0 < D <= 1e+06 simulated s, a decimal number then s), or all")
for via in ("file", "--set"):
    wrong = []
    cases = [("5s5", "is not a number of frames, a duration or all"), ("5ss", "is not"),
             ("s", "is not"), ("0x10", "is not"), ("0x1p1s", "is not"), ("1_000", "is not"),
             ("1e", "is not"), ("5 s", "is not"), ("ALL", "is not"), ("inf", "is not finite"),
             ("nan", "is not finite"), ("2.5", "is not an integer"), ("1e12", "is out of range"),
             ("0s", "is out of range"), ("-1", "is out of range"), ("-2s", "is out of range")]
    for value, says in cases:
        quoted = value if says.startswith(("is not finite", "is not an", "is out")) else f"'{value}'"
        if via == "file":
            r, made = still(write("trail.ini", f"[view]\ntrail = {value}\n"))
            prefix = f"trail.ini:2: view.trail = {quoted} "
        else:
            r, made = still(write("good.ini", "[video]\nfps = 30\n"), "--set", f"view.trail={value}")
            prefix = f"--set view.trail={value}: view.trail = {quoted} "
        why = refused(r, made, prefix, says, TRAIL)
        if why:
            wrong.append(f"{value!r}: {why}")
    for value in ("5s", "0.5s", "2.5e-1s", "all", "0", "600", "6e2"):
        r, made = (still(write("trail.ini", f"[view]\ntrail = {value}\n")) if via == "file" else
                   still(write("good.ini", "[video]\nfps = 30\n"), "--set", f"view.trail={value}"))
        if r.returncode != 0 or not made:
            wrong.append(f"{value!r} refused: {r.stderr.strip()!r}")
    ok(not wrong, f"view.trail from a {via}: '5s5' and other junk refused with one message that "
       "lists frames, a duration and all; 5s, 0.5s, all, 600 accepted", "\n".join(wrong))

# `springpend keys` describes the trail as the message does.
r = run("keys")
ok(r.returncode == 0 and TRAIL.split("allowed: ")[1] in r.stdout,
   "springpend keys lists the trail's frames, duration and all as its message does", r.stdout)

# ---- compare.ini and compare's options ----

cmp = os.path.join(work, "cmp")
os.makedirs(os.path.join(cmp, "exp"))
os.makedirs(os.path.join(cmp, "act"))
r = run("still", os.path.join(src, "..", "scenes", "default.ini"), *SMALL, "-q",
        "-o", os.path.join(cmp, "exp", "a.png"))
shutil.copy(os.path.join(cmp, "exp", "a.png"), os.path.join(cmp, "act", "a.png"))
DECIMAL = "written in decimal (digits with an optional sign, point and exponent"
CMP = {  # key: (refused values and what the message says, accepted values, what is allowed)
    "max_pixels": ([("200%", "out of range"), ("100.5%", "out of range"), ("-5%", "out of range"),
                    ("-1", "out of range"), ("1e19", "out of range"), ("nan", "not finite"),
                    ("nan%", "not finite"), ("inf", "not finite"), ("0x10", "not a decimal number"),
                    ("0x10%", "not a decimal number"), ("2.5", "not an integer"),
                    ("%", "not a decimal number"), ("5%%", "not a decimal number")],
                   ["100%", "0.5%", "0%", "100", "1e3", "0"],
                   "expected a pixel count (an integer from 0 to 1e18, like 100) or a percentage "
                   "from 0% to 100% (like 0.5%)"),
    "max_diff": ([("0x10", "not a decimal number"), ("nan", "not finite"), ("2.5", "not an integer"),
                  ("256", "out of range"), ("-1", "out of range"), ("1e", "not a decimal number")],
                 ["0", "4", "1e1", "255"], "expected an integer from 0 to 255 (levels)"),
    "tol": ([("0x1p1", "not a decimal number"), ("nan", "not finite"), ("inf", "not finite"),
             ("-1", "out of range"), ("256", "out of range"), ("1_0", "not a decimal number")],
            ["1.5", "0", "2e0", "255"], "expected an RMS from 0 to 255 (levels)"),
    "mask": ([("0x10, 0, 5, 5", "x not a decimal number"), ("0, 0, 4294967297, 5", "width out of range"),
              ("1, 2, 3, 99999999999", "height out of range"), ("1.5, 2, 3, 4", "x not an integer"),
              ("1, nan, 3, 4", "y not finite"), ("1, 2, 0, 4", "width out of range"),
              ("1, 2, 3", "not four numbers"), ("1, 2, 3, 4, 5", "not four numbers"),
              ("1, 2, 3, 4,", "not four numbers")],
             ["0, 0, 5, 5", "1,2,3,4", "1 , 2 ,3 , 4", "+1, 2, 3, 4"],
             "expected x, y, width, height in px: integers with x, y >= 0 and width, height >= 1, "
             "all at most 1000000000"),
}
outputs = ["--report", "r.html", "--junit", "j.xml", "--diff", "d"]


def written():
    """The report, JUnit file and diff folder compare made, removed."""
    made = [o for o in ("r.html", "j.xml", "d") if os.path.exists(os.path.join(work, o))]
    for o in made:
        shutil.rmtree(os.path.join(work, o)) if o == "d" else os.remove(os.path.join(work, o))
    return made


for key, (bad, good, allowed) in CMP.items():
    wrong = []
    for value, says in bad:
        write(os.path.join("cmp", "exp", "compare.ini"), f"# tolerances\n[*]\n{key} = {value}\n")
        r = run("compare", "cmp/exp", "cmp/act", *outputs)
        made = written()
        needles = [says, allowed] + ([DECIMAL] if "decimal" in says else [])
        why = refused(r, made, f"cmp/exp/compare.ini:3: {key} {value}: ", *needles)
        if why:
            wrong.append(f"{value!r}: {why}")
    for value in good:
        write(os.path.join("cmp", "exp", "compare.ini"), f"[*]\n{key} = {value}\n")
        r = run("compare", "cmp/exp", "cmp/act")
        if r.returncode != 0:
            wrong.append(f"{value!r} refused: {r.stderr.strip()!r}")
    ok(not wrong, f"compare.ini {key}: {', '.join(repr(v) for v, _ in bad)} refused with FILE:LINE, "
       f"what is wrong and what is allowed, exit 2, no report; {', '.join(map(repr, good))} accepted",
       "\n".join(wrong))
os.remove(os.path.join(cmp, "exp", "compare.ini"))

# The same rules on the command line, named by the option.
wrong = []
for opt, value, says in [("--max-pixels", "200%", "out of range"), ("--max-pixels", "0x10", "not a decimal"),
                         ("--max-diff", "0x10", "not a decimal"), ("--tol", "0x1p1", "not a decimal")]:
    r = run("compare", "cmp/exp/a.png", "cmp/act/a.png", f"{opt}={value}", *outputs)
    made = written()
    why = refused(r, made, f"springpend: {opt} {value}: {says}", "expected")
    if why:
        wrong.append(f"{opt} {value}: {why}")
ok(not wrong, "compare --max-pixels 200%, hex in --max-pixels, --max-diff, --tol: refused, "
   "exit 2, no report", "\n".join(wrong))

print(f"1..{count}")
sys.exit(1 if failed else 0)
