#!/usr/bin/env python3
"""springpend tests: the command line, end to end, as a user meets it.
usage: test_cli.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import glob
import json
import math
import os
import resource
import shutil
import signal
import struct
import subprocess
import sys
import time

import sptest

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "cli"))
scenes = os.path.join(src, "..", "scenes")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
count = failed = 0


def ok(cond, what):
    global count, failed
    count += 1
    failed += not cond
    what = what.replace("\n", " | ")
    print(f"{'' if cond else 'not '}ok {count} - {what}", flush=True)
    return cond


def run(*args):
    return subprocess.run([exe, *args], capture_output=True, text=True, cwd=work)


def write(name, text):
    path = os.path.join(work, name)
    with open(path, "w") as f:
        f.write(text)
    return path


# Bad input: exit 2, FILE:LINE naming the key and the range, no output file.
bad = [
    ("[pendulum]\nmass = 0\n", "bad.ini:2: pendulum.mass = 0 is out of range", "0 < mass"),
    ("[pendulum]\nstiffness = nan\n", "bad.ini:2: pendulum.stiffness = nan is not finite", "stiffness"),
    ("[pendulum]\nmas = 1\n", "bad.ini:2: unknown key 'mas' in [pendulum]", "did you mean 'mass'"),
    ("[video]\nfps = abc\n", "bad.ini:2: video.fps = 'abc' is not a decimal number", "0 < fps"),
    ("[integrator]\ndt = -1\n", "bad.ini:2: integrator.dt = -1 is out of range", "0 < dt"),
    ("[video]\nwidth = 99999\n", "bad.ini:2: video.width = 99999 is out of range", "16 to 7680"),
    ("[initial]\nlength = 0\n[video]\nfps = 0\n", "bad.ini:2: initial.length", "bad.ini:4: video.fps"),
    ("[integrator]\nmethod = rk5\n", "bad.ini:2: integrator.method = 'rk5' is not a method",
     "rk4, verlet, yoshida4, dopri5, dop853, rkn1210"),
    ("[integrator]\nmethod = rkn1210\n[pendulum]\ndamping = 0.1\n",
     "integrator.method = rkn1210 needs a force that depends on the position only", "dop853"),
    ("[integrator]\ntolerance = 1\n", "bad.ini:2: integrator.tolerance = 1 is out of range", "0.01"),
    ("[pivot]\namplitud = 1\n", "bad.ini:2: unknown key 'amplitud' in [pivot]", "did you mean 'amplitude'"),
]
for text, want1, want2 in bad:
    scene = write("bad.ini", text)
    out = os.path.join(work, "bad.mp4")
    r = run("render", scene, "-o", out, "-q")
    ok(r.returncode == 2 and want1 in r.stderr and want2 in r.stderr and not os.path.exists(out),
       f"bad scene {text.strip()!r}: exit 2, says {want1!r} and {want2!r}, no file "
       f"(got {r.returncode}: {r.stderr.strip()[:200]!r})")

default = os.path.join(scenes, "default.ini")


# The bad input catalogue: each is refused with exit 2 and its message, and
# leaves no file behind (each runs in an empty folder of its own).
def refused(what, content, args, *needles):
    global case_no
    case_no += 1
    d = os.path.join(work, f"bad{case_no}")
    os.makedirs(d)
    inputs = set()
    if content is not None:
        with open(os.path.join(d, "scene.ini"), "wb") as f:
            f.write(content if isinstance(content, bytes) else content.encode())
        inputs.add("scene.ini")
    for name in ("file.txt",):  # a plain file, for "not a folder" paths
        with open(os.path.join(d, name), "w") as f:
            f.write("x")
        inputs.add(name)
    os.makedirs(os.path.join(d, "folder.png"))
    inputs.add("folder.png")
    t0 = time.monotonic()
    r = subprocess.run([exe, *args], capture_output=True, text=True, cwd=d,
                       errors="replace")
    left = set(os.listdir(d)) - inputs
    ok(r.returncode == 2 and all(n in r.stderr for n in needles) and not left,
       f"bad input: {what}: exit 2, says {needles}, no file "
       f"(got {r.returncode} in {time.monotonic() - t0:.1f} s, left {sorted(left)}: "
       f"{r.stderr.strip()[:300]!r})")


case_no = 0
SC = "scene.ini"
still = ["still", SC, "-o", "out.png", "--size", "64x48"]
refused("empty file", "", still, "scene.ini: the scene is empty")
refused("only blank lines", "\n  \n\t\n", still, "the scene is empty")
refused("binary garbage", bytes(range(256)) * 64, still, "contains NUL bytes")
refused("a PNG given as the scene", open(os.path.join(src, "golden", "default_t0_notrail.png"), "rb").read(),
        still, "contains NUL bytes")
refused("binary without NUL bytes", "[pendulum]\n".encode() + bytes(range(128, 256)) * 8, still,
        "scene.ini:2: byte 0x80 at column 1 is not text")
refused("a 10 MB line", "[pendulum]\nmass = " + "1" * 10_000_000 + "\n", still,
        "scene.ini: scene file is 10000019 bytes; at most 1 MiB")
refused("a 100 kB line", "[pendulum]\nmass = " + "1" * 100_000 + "\n", still,
        "scene.ini:2: line is 100008 bytes long")
refused("duplicate keys", "[video]\nfps = 30\nwidth = 320\nfps = 60\n", still,
        "scene.ini:4: video.fps is set twice (first on line 2)")
refused("unknown key", "[initial]\nangel = 30\n", still,
        "scene.ini:2: unknown key 'angel' in [initial]; did you mean 'angle'?")
refused("unknown section", "[pendulm]\nmass = 1\n", still,
        "scene.ini:1: unknown section [pendulm]; did you mean [pendulum]?")
refused("unknown key in --set", "[video]\nfps = 30\n", still + ["--set", "pendulum.stifness=3"],
        "--set pendulum.stifness=3: unknown key 'stifness' in [pendulum]; did you mean 'stiffness'?")
for key, value, says in [
        ("pendulum.stiffness", "nan", "is not finite"), ("pendulum.mass", "inf", "is not finite"),
        ("pendulum.gravity", "-inf", "is not finite"), ("initial.length", "NaN", "is not finite"),
        ("pendulum.mass", "-0.5", "is out of range"), ("pendulum.natural_length", "0", "is out of range"),
        ("pendulum.stiffness", "-2", "is out of range"), ("integrator.dt", "0", "is out of range"),
        ("pendulum.damping", "-1", "is out of range"), ("video.fps", "-30", "is out of range"),
        ("video.speed", "0", "is out of range"), ("pendulum.mass", "1e400", "is not finite")]:
    section, name = key.split(".")
    refused(f"{key} = {value}", f"[{section}]\n{name} = {value}\n", still,
            f"scene.ini:2: {key} = {value} {says}; expected")
refused("absurd width", "[video]\nwidth = 1000000000\n", still,
        "video.width = 1000000000 is out of range; expected an integer from 16 to 7680 px")
refused("absurd --size", "[video]\nfps = 30\n", ["still", SC, "-o", "out.png", "--size", "100000x100000"],
        "video.width = 100000 is out of range")
refused("height beyond 8K", "[video]\nwidth = 7680\nheight = 4320\n", still[:4] + ["--set", "video.height=4321"],
        "video.height = 4321 is out of range")
refused("absurd frame count", "[video]\nduration = 1e6\nfps = 1000\n",
        ["render", SC, "-o", "out.mp4", "-q"], "= 1000000000 frames; at most 1000000 are allowed")
refused("absurd trail", "[view]\ntrail = 1e12\n", still, "view.trail = 1e12 is out of range")
refused("absurd step count", "[integrator]\ndt = 1e-9\n[video]\nduration = 1e3\n",
        ["render", SC, "-o", "out.mp4", "-q"], "steps; at most 1e10 are allowed")
refused("absurd --at", "[video]\nfps = 30\n", still + ["--at", "1e9"],
        "--at 1e+09: reaching it takes 1e+12 steps")
refused("output under a plain file", "[video]\nfps = 30\n", ["still", SC, "-o", "file.txt/x.png"],
        "output file.txt/x.png: file.txt is not a folder")
refused("output deep under a plain file", "[video]\nfps = 30\n",
        ["render", SC, "-o", "file.txt/a/b/%03d.png"], "file.txt is not a folder")
refused("output is a folder", "[video]\nfps = 30\n", ["still", SC, "-o", "folder.png"],
        "output folder.png is a folder")
refused("output is the scene", "[video]\nfps = 30\n", ["still", SC, "-o", SC], "is the scene file itself")
refused("output is the scene by another path", "[video]\nfps = 30\n",
        ["still", SC, "-o", "./folder.png/../scene.ini"], "is the scene file itself")
refused("--state is the scene", "[video]\nfps = 30\n", still + ["--state", SC],
        "--state scene.ini would overwrite the scene or the image")
refused("--state is the image", "[video]\nfps = 30\n", still + ["--state", "out.png"],
        "would overwrite the scene or the image")
refused("--state under a plain file", "[video]\nfps = 30\n", still + ["--state", "file.txt/s.json"],
        "--state file.txt/s.json: file.txt is not a folder")
refused("--state on render", "[video]\nfps = 30\n", ["render", SC, "--state", "s.json"],
        "--state is for 'springpend still'")
if os.geteuid() != 0:  # root may write anywhere
    ro = os.path.join(work, "readonly")
    os.makedirs(ro)
    os.chmod(ro, 0o555)
    refused("output in a read-only folder", "[video]\nfps = 30\n", still[:2] + ["-o", ro + "/x.png"],
            "cannot write in folder")
r = run("render", default, "--set", "video.fps=0", "-o", "x.mp4")
ok(r.returncode == 2 and "--set video.fps=0: video.fps = 0 is out of range" in r.stderr
   and not os.path.exists(os.path.join(work, "x.mp4")), "a bad --set names the override")
r = run("render", default, "--size", "12x", "-o", "x.mp4")
ok(r.returncode == 2 and "--size" in r.stderr, "a malformed --size is refused")
r = run("render", os.path.join(work, "missing.ini"))
ok(r.returncode == 2 and "missing.ini: cannot open scene" in r.stderr, "a missing scene file")
r = run("render", default, "-o", os.path.join(work, "x.avi"))
ok(r.returncode == 2 and ".avi" in r.stderr and not os.path.exists(os.path.join(work, "x.avi")),
   "an unknown output extension is refused with exit 2")
r = run("render", default, "-o", default)
ok(r.returncode == 2 and "scene file itself" in r.stderr, "the output may not overwrite the scene")
r = run("frobnicate")
ok(r.returncode == 2 and "unknown command" in r.stderr, "an unknown command")
for cmd in ([], ["render"], ["still"], ["data"], ["info"], ["compare"]):
    r = run(*cmd, "--help")
    ok(r.returncode == 0 and "usage:" in r.stdout, f"springpend {' '.join(cmd)} --help")
ok("compare" in run("--help").stdout, "springpend --help lists compare")
# FFmpeg, cairo and GL are loaded on first use: the executable itself links
# none of them, nor what they bring (libavutil once did, for SHA-256).
r = subprocess.run(["ldd", exe], capture_output=True, text=True)
linked = [w for w in r.stdout.split() if w.startswith("lib")]
media = [w for w in linked if w.split(".so")[0] in
         ("libavutil", "libavcodec", "libavformat", "libswscale", "libavfilter", "libva",
          "libva-drm", "libva-x11", "libX11", "libOpenCL", "libmfx", "libcairo", "libOSMesa")]
ok(r.returncode == 0 and linked and not media,
   f"the executable links no media library ({len(linked)} libraries; {media or 'none of them'})")

# A blow-up is an error with exit 3, never a file.
r = run("render", default, "--set", "pendulum.stiffness=5e6", "--set", "pendulum.mass=0.5",
        "-o", "unstable.mp4", "-q")
ok(r.returncode == 3 and "unstable" in r.stderr and "use integrator.dt = " in r.stderr
   and not os.path.exists(os.path.join(work, "unstable.mp4")),
   f"an unstable scene exits 3 with a fix and writes nothing ({r.returncode})")

# A short MP4 that ffprobe reads back: codec, frames, duration.
r = run("render", default, "--set", "video.duration=2", "--size", "320x240", "--fps", "30",
        "-o", "short.mp4", "-q")
mp4 = os.path.join(work, "short.mp4")
ok(r.returncode == 0 and os.path.exists(mp4) and not glob.glob(glob.escape(mp4) + ".*.part"),
   f"render writes an mp4 ({r.stderr.strip()[:200]})")
if shutil.which("ffprobe") and os.path.exists(mp4):
    p = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-show_streams", "-show_format",
                        "-of", "json", mp4], capture_output=True, text=True)
    info = json.loads(p.stdout)
    v = info["streams"][0]
    ok(v["codec_name"] == "h264" and v["pix_fmt"] == "yuv420p" and v["width"] == 320
       and int(v["nb_read_frames"]) == 60 and abs(float(info["format"]["duration"]) - 2.0) < 0.05,
       f"ffprobe: {v['codec_name']} {v['pix_fmt']} {v['width']}x{v['height']}, "
       f"{v['nb_read_frames']} frames, {info['format']['duration']} s")

# A PNG sequence: one file per frame, folders created.
r = run("render", default, "--set", "video.duration=0.5", "--size", "160x120", "--fps", "10",
        "-o", "seq/deep/%03d.png", "-q")
files = sorted(os.listdir(os.path.join(work, "seq/deep"))) if r.returncode == 0 else []
ok(files == [f"{i:03d}.png" for i in range(5)], f"PNG sequence of 5 frames: {files}")

# Defaults: out/<scene>.png for a still.
r = run("still", default, "--at", "1.5", "--size", "320x180")
ok(r.returncode == 0 and os.path.exists(os.path.join(work, "out", "default.png")),
   "still without -o writes out/default.png")


def png_text(path):
    """The tEXt chunks of a PNG as a dict, and the list of chunk types."""
    data, chunks, text = open(path, "rb").read(), [], {}
    i = 8
    while i < len(data):
        n, kind = struct.unpack(">I4s", data[i:i + 8])
        chunks.append(kind.decode())
        if kind == b"tEXt":
            k, v = data[i + 8:i + 8 + n].split(b"\0", 1)
            text[k.decode("latin-1")] = v.decode("latin-1")
        i += 12 + n
    return text, chunks


# Determinism: the same still (all panels and text), whatever LP_NUM_THREADS,
# gives the same bytes.
det = os.path.join(work, "det")
os.makedirs(det)
stills = {}
for threads in ("1", "2", "4", "4"):
    path = os.path.join(det, f"t{threads}-{len(stills)}.png")
    r = subprocess.run([exe, "still", default, "--at", "2.5", "--size", "480x270", "-o", path, "-q",
                        "--set", "view.panels=all", "--set", "view.hud=true"],
                       capture_output=True, text=True, env=dict(os.environ, LP_NUM_THREADS=threads))
    stills[path] = open(path, "rb").read() if r.returncode == 0 else b""
first = next(iter(stills.values()))
ok(first and all(v == first for v in stills.values()),
   f"LP_NUM_THREADS=1, 2, 4 and a second run at 4 give identical PNG bytes (panels, text) "
   f"({[len(v) for v in stills.values()]} bytes)")
paths = list(stills)
r = run("compare", paths[0], paths[2], "--max-diff", "0", "--max-pixels", "0")
ok(r.returncode == 0 and "identical pixels (129600" in r.stdout,
   f"compare: 1 thread and 4 threads give identical pixels ({r.stdout.strip()})")

# Provenance: text chunks, no timestamp; the --state file agrees with them.
r = run("still", default, "--at", "1.5", "--size", "320x180", "-o", "prov.png",
        "--state", "prov.json", "-q")
text, chunks = png_text(os.path.join(work, "prov.png"))
state = json.load(open(os.path.join(work, "prov.json"))) if r.returncode == 0 else {}
ok(text.get("Software") == "springpend 0.1.0" and text.get("springpend.time") == "1.5"
   and len(text.get("springpend.scene-sha256", "")) == 64 and text.get("Source")
   and "tIME" not in chunks and chunks[0] == "IHDR" and chunks[-1] == "IEND",
   f"PNG text chunks: {text}, chunks {sorted(set(chunks))}")
ok(state.get("scene_sha256") == text.get("springpend.scene-sha256") and state.get("t") == 1.5,
   "--state carries the image's scene hash and time")
E = state.get("energy", {})
ok(abs(math.hypot(state.get("x", 0), state.get("y", 0)) - state.get("r", -1)) < 1e-12
   and abs(E.get("total", 1) - E.get("initial_total", 0)) < 1e-6 * abs(E.get("initial_total", 1))
   and abs(E.get("kinetic", 0) - 0.25 * (state.get("vx", 0) ** 2 + state.get("vy", 0) ** 2)) < 1e-12,
   f"--state: r = |(x, y)|, kinetic = m|v|^2/2, energy conserved ({E})")
r = run("still", default, "--at", "1.5", "--size", "320x180", "-o", "prov2.png", "-q",
        "--set", "pendulum.damping=0.01")
text2, _ = png_text(os.path.join(work, "prov2.png"))
ok(text2.get("springpend.scene-sha256") not in (None, text.get("springpend.scene-sha256")),
   "a changed scene key changes the scene hash")
r = run("render", default, "--set", "video.duration=0.2", "--size", "64x48", "--fps", "10",
        "-o", "pseq/%02d.png", "-q")
times = [png_text(os.path.join(work, "pseq", f"{k:02d}.png"))[0].get("springpend.time")
         for k in range(2)] if r.returncode == 0 else []
ok(times == ["0", "0.1"], f"each PNG of a sequence carries its own time: {times}")

# compare, end to end.
cmp_dir = os.path.join(work, "cmp")
for name, at, size, *extra in (("a", "3", "320x240"), ("b", "3", "320x240"),
                               ("moved", "3.05", "320x240"), ("small", "3", "160x120"),
                               ("damped", "3", "320x240", "--set", "pendulum.damping=0.1")):
    run("still", default, "--at", at, "--size", size, *extra, "-o", f"cmp/{name}.png", "-q")
P = lambda name: os.path.join(cmp_dir, name)
r = run("compare", P("a.png"), P("b.png"), "--diff", P("d-same.png"))
ok(r.returncode == 0 and r.stdout.startswith("ok") and not os.path.exists(P("d-same.png")),
   f"compare: identical renders match, no diff image ({r.stdout.strip()})")
r = run("compare", P("a.png"), P("moved.png"), "--diff", P("d.png"))
ok(r.returncode == 1 and r.stdout.startswith("FAIL") and "d.png" in r.stdout
   and png_text(P("d.png"))[1][0] == "IHDR",
   f"compare: a moved bob fails with a diff image ({r.stdout.strip()})")
r = run("compare", P("a.png"), P("moved.png"), "--json")
j = json.loads(r.stdout)["results"][0] if r.returncode == 1 else {}
m, t = j.get("measured", {}), j.get("tolerance") or {}
ok(j.get("pass") is False and m.get("differing_pixels", 0) > t.get("max_differing_pixels", 1)
   and t.get("max_channel_diff") == 3 and m.get("pixels") == 76800
   and len(m.get("bbox") or []) == 4 and m.get("rms", 0) > 0,
   f"compare --json: {r.stdout.strip()[:300]}")
r = run("compare", P("a.png"), P("moved.png"))
ok(r.returncode == 1 and "note" not in r.stdout, "compare: no provenance note between renders of one scene")
r = run("compare", P("a.png"), P("damped.png"))
ok(r.returncode == 1 and "note: the scene differs (springpend.scene-sha256)" in r.stdout,
   f"compare: a failure notes that the scene hashes differ ({r.stdout.strip()[:200]})")
r = run("compare", P("a.png"), P("moved.png"), "--max-pixels", "100%")
ok(r.returncode == 0, "compare --max-pixels 100% lets anything of the same size pass")
r = run("compare", P("a.png"), P("moved.png"), "--metric", "rms", "--tol", "0.5")
ok(r.returncode == 1 and "> tol 0.5" in r.stdout, f"compare --metric rms --tol 0.5: {r.stdout.strip()}")
r = run("compare", P("a.png"), P("small.png"))
ok(r.returncode == 1 and "expected 320x240, actual 160x120" in r.stdout,
   f"compare: different sizes fail, exit 1 ({r.stdout.strip()})")
write("cmp/text.png", "not a png")
r = run("compare", P("a.png"), P("text.png"))
ok(r.returncode == 2 and "text.png: cannot read PNG" in r.stderr, f"compare: unreadable exits 2 ({r.stderr.strip()})")
r = run("compare", P("a.png"), P("b.png"), "--diff", P("a.png"))
ok(r.returncode == 2 and "would overwrite an input" in r.stderr, "compare: --diff may not overwrite an input")
for bad_opt in (["--max-diff", "300"], ["--max-pixels", "5x"], ["--metric", "ssim"], ["--tol", "-1"]):
    r = run("compare", P("a.png"), P("b.png"), *bad_opt)
    ok(r.returncode == 2 and bad_opt[0] in r.stderr, f"compare {' '.join(bad_opt)} is refused")

# Folders: a baseline folder against a render folder.
base, new, diffs = (os.path.join(work, d) for d in ("base", "new", "diffs"))
for d in (base, new):
    os.makedirs(d)
for name in ("one.png", "two.png"):
    shutil.copy(P("a.png"), os.path.join(base, name))
    shutil.copy(P("b.png"), os.path.join(new, name))
r = run("compare", base, new)
ok(r.returncode == 0 and "2 compared, 2 passed" in r.stdout, f"compare folders: all match ({r.stdout.strip()})")
shutil.copy(P("moved.png"), os.path.join(new, "two.png"))
r = run("compare", base, new, "--diff", diffs, "--json")
j = json.loads(r.stdout)["counts"] if r.returncode == 1 else {}
ok(j.get("passed") == 1 and j.get("failed") == 1 and os.listdir(diffs) == ["two.diff.png"],
   f"compare folders: one fails, its diff in --diff ({r.stdout.strip()[:200]})")
shutil.copy(P("a.png"), os.path.join(new, "three.png"))
os.remove(os.path.join(new, "one.png"))
r = run("compare", base, new)
ok(r.returncode == 2 and "ERROR one.png: no actual image" in r.stdout
   and "ERROR three.png: no baseline" in r.stdout and "FAIL two.png" in r.stdout,
   f"compare folders: a missing render and a missing baseline are errors ({r.stdout.strip()})")


# Videos, frame by frame (320x240: at 160x120 the default scene's four
# panels leave the pendulum no room, and 1 degree showed in one 8x8 block of
# a chart's few pixels, or in none).
for name, extra in (("v1", []), ("v2", []), ("angle", ["--set", "initial.angle=11"]),
                    ("short", ["--set", "video.duration=0.9"])):
    run("render", default, "--size", "320x240", "--fps", "30", "--set", "video.duration=1",
        *extra, "-o", f"vid/{name}.mp4", "-q")
V = lambda name: os.path.join(work, "vid", name + ".mp4")
r = run("compare", V("v1"), V("v2"))
ok(r.returncode == 0 and "0 of 30 frames differ" in r.stdout, f"compare videos: two renders match ({r.stdout.strip()})")
r = run("compare", V("v1"), V("angle"), "--json", "--diff", os.path.join(work, "vid", "worst.png"))
j = json.loads(r.stdout)["results"][0] if r.returncode == 1 else {}
ok(j.get("video", {}).get("frames") == 30 and j["video"].get("failed_frames")
   and j.get("measured", {}).get("differing_pixels", 0) > 0
   and os.path.exists(os.path.join(work, "vid", "worst.png")),
   f"compare videos: 1 degree more fails, worst frame {(j.get('video') or {}).get('worst_frame')}, diff written")
r = run("compare", V("v1"), V("short"))
ok(r.returncode == 2 and "v1.mp4 has 30 frames" in r.stdout and "short.mp4 has 27" in r.stdout,
   f"compare videos: a frame count mismatch exits 2, both counts named ({r.stdout.strip()})")
r = run("compare", V("v1"), P("a.png"))
ok(r.returncode == 2 and "two PNG images or two videos" in r.stderr, "compare: a video against a PNG is refused")


# Interrupted: SIGINT or SIGTERM mid-render stops cleanly, exit 128 + signal,
# no .part left: the frames so far are a playable file (test_output.py checks
# it plays), or nothing if no frame was done yet.
for sig in (signal.SIGINT, signal.SIGTERM):
    target = os.path.join(work, "intr", f"{sig.name}.mp4")
    p = subprocess.Popen([exe, "render", default, "--size", "320x240", "-o", target, "-q"],
                         stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 30
    while not glob.glob(glob.escape(target) + ".*.part") and p.poll() is None and time.monotonic() < deadline:
        time.sleep(0.01)
    p.send_signal(sig)
    err = p.communicate()[1]
    folder = os.path.dirname(target)  # removed when the run left it empty
    left = os.listdir(folder) if os.path.isdir(folder) else []
    ok(p.returncode == 128 + sig and "interrupted" in err and
       not [n for n in left if n.endswith(".part")],
       f"{sig.name} during a render: exit {p.returncode}, says {err.strip()!r}, left {left}")

# The same for a long `data` run: exit 128 + signal, no CSV and no .part.
for sig in (signal.SIGINT, signal.SIGTERM):
    target = os.path.join(work, "intr", f"{sig.name}.csv")
    p = subprocess.Popen([exe, "data", default, "--set", "video.duration=900", "--every", "0.0001",
                          "-o", target, "-q"], stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 30
    while not glob.glob(glob.escape(target) + ".*.part") and p.poll() is None and time.monotonic() < deadline:
        time.sleep(0.01)
    p.send_signal(sig)
    err = p.communicate()[1]
    folder = os.path.dirname(target)
    left = [n for n in (os.listdir(folder) if os.path.isdir(folder) else [])
            if n.startswith(sig.name + ".csv")]
    ok(p.returncode == 128 + sig and "interrupted" in err and not left,
       f"{sig.name} during data: exit {p.returncode}, says {err.strip()!r}, left {left}")

# A still far in the future and a render's camera pre-pass are long
# integrations: a signal stops them too (no file, exit 128 + signal). The
# 30 s bound only catches a run that ignores the signal (minutes).
# (--at 4e6: 4e9 steps, twice with the camera's pre-pass, under the 1e10 limit)
for what, args in (("still --at 4e6", ["still", default, "--at", "4e6", "--size", "160x90"]),
                   ("a render's pre-pass", ["render", default, "--fps", "1", "--size", "160x90",
                                            "--set", "video.duration=900000"])):
    target = os.path.join(work, "intr", "long.png" if args[0] == "still" else "long.mp4")
    p = subprocess.Popen([exe, *args, "-o", target, "-q"], stderr=subprocess.PIPE, text=True)
    sptest.wait_caught(p, signal.SIGINT)
    time.sleep(0.5)
    p.send_signal(signal.SIGINT)
    try:
        err = p.communicate(timeout=30)[1]
    except subprocess.TimeoutExpired:
        p.kill()
        err = p.communicate()[1] + " (ignored SIGINT for 30 s)"
    folder = os.path.dirname(target)
    left = [n for n in (os.listdir(folder) if os.path.isdir(folder) else [])
            if n.startswith("long.")]
    ok(p.returncode == 130 and "interrupted by SIGINT before the first frame" in err and not left,
       f"SIGINT during {what}: exit {p.returncode}, says {err.strip()!r}, left {left}")
# Every panel, the HUD and the colourbar at frames far too small for them:
# squeezed, never a crash (a plot under a pixel wide once divided by zero).
for size in ("16x16", "64x48", "400x16", "16x400"):
    r = run("render", default, "--size", size, "--fps", "10", "--set", "video.duration=0.3",
            "--set", "view.panels=all", "-o", f"tiny/{size}_%02d.png", "-q")
    made = [n for n in os.listdir(os.path.join(work, "tiny")) if n.startswith(size + "_")] \
        if r.returncode == 0 else []
    ok(r.returncode == 0 and len(made) == 3,
       f"all panels at {size}: exit {r.returncode} {r.stderr.strip()[:120]!r}")

# Faults: a write that fails half way (the file size limit stands in for a
# full disk) is exit 1 with the reason, and leaves no file behind.
def small_files():
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (600, 600))


for what, args, says in (
        ("still", ["still", default, "--size", "640x360", "-o", "full/s.png"], "s.png: cannot write: File too large"),
        ("mp4", ["render", default, "--size", "320x240", "--set", "video.duration=1", "-o", "full/v.mp4", "-q"],
         "File too large"),
        ("PNG sequence", ["render", default, "--size", "320x240", "--set", "video.duration=1",
                          "-o", "full/%03d.png", "-q"], ".png: cannot write: File too large"),
        ("compare --diff", ["compare", P("a.png"), P("moved.png"), "--diff", "full/d.png"], "d.png")):
    shutil.rmtree(os.path.join(work, "full"), ignore_errors=True)
    os.makedirs(os.path.join(work, "full"))
    r = subprocess.run([exe, *args], capture_output=True, text=True, cwd=work, preexec_fn=small_files)
    left = os.listdir(os.path.join(work, "full"))
    ok(r.returncode == 1 and says in r.stderr and not left,
       f"a write beyond the file size limit ({what}): exit 1, says {says!r}, nothing left "
       f"(got {r.returncode}, {left}: {r.stderr.strip()[:200]!r})")


# Stills for slides: --scale supersamples to the same size; a transparent
# background writes RGBA with see-through corners and an opaque bob.
def png_header(path):
    with open(path, "rb") as f:
        head = f.read(33)
    return int.from_bytes(head[16:20], "big"), int.from_bytes(head[20:24], "big"), head[25]


r = run("still", default, "--at", "2", "--size", "320x180", "--scale", "3", "-o", "ss.png", "-q")
ok(r.returncode == 0 and png_header(os.path.join(work, "ss.png"))[:2] == (320, 180),
   f"still --scale 3 writes the asked size ({r.stderr.strip()[:200]})")
r = run("still", default, "--scale", "9", "-o", "ss9.png")
ok(r.returncode == 2 and "--scale" in r.stderr and not os.path.exists(os.path.join(work, "ss9.png")),
   "--scale beyond 4 is refused")
r = run("render", default, "--scale", "2", "-o", "x.mp4")
ok(r.returncode == 2 and "--scale" in r.stderr, "--scale is for stills only")
r = run("still", default, "--at", "2", "--size", "320x180", "--set", "view.background=transparent",
        "-o", "alpha.png", "-q")
ok(r.returncode == 0 and png_header(os.path.join(work, "alpha.png"))[2] == 6,
   "a transparent background writes an RGBA PNG (its alpha: see the golden test)")
r = run("still", default, "--set", "view.panels=r,bogus", "-o", "bogus.png")
ok(r.returncode == 2 and "'bogus' is not a panel" in r.stderr
   and not os.path.exists(os.path.join(work, "bogus.png")), "an unknown panel is refused")

# Every preset renders a still with its panels.
for name in sorted(os.listdir(scenes)):
    if name.endswith(".ini"):
        out = os.path.join(work, name[:-4] + ".png")
        r = run("still", os.path.join(scenes, name), "--at", "3", "--size", "480x270", "-o", out, "-q")
        # A blank 480x270 frame compresses to well under 1 kB.
        ok(r.returncode == 0 and os.path.getsize(out) > 2000, f"preset {name} renders a still")

# data: CSV rows at the requested times, physics that holds, every method.
import csv
import io
import math

cols = "t,x,y,vx,vy,r,theta,r_dot,theta_dot,kinetic,spring,gravity,energy".split(",")
for method in ("rk4", "verlet", "yoshida4", "dopri5", "dop853", "rkn1210"):
    r = run("data", default, "--every", "0.25", "--set", f"integrator.method={method}", "-o", "-")
    rows = list(csv.DictReader(io.StringIO(r.stdout))) if r.returncode == 0 else []
    ts = [float(x["t"]) for x in rows]
    e = [float(x["energy"]) for x in rows]
    polar_ok = all(abs(float(x["r"]) * math.sin(float(x["theta"])) - float(x["x"])) < 1e-9
                   and abs(float(x["bounce"]) + float(x["swing"]) - float(x["energy"])
                           - (float(rows[0]["bounce"]) + float(rows[0]["swing"])
                              - float(rows[0]["energy"]))) < 1e-9 for x in rows)
    ok(r.returncode == 0 and len(rows) == 41 and ts[0] == 0 and ts[-1] == 10
       and all(c in rows[0] for c in cols) and polar_ok
       and max(e) - min(e) < {"verlet": 1e-4, "dopri5": 1e-6, "dop853": 1e-6, "rkn1210": 1e-6}.get(method, 1e-7),
       f"data --every 0.25 with {method}: 41 rows t = 0..10, r/theta match x, "
       f"energy spread {max(e) - min(e) if e else -1:.1e} J ({r.stderr.strip()[:200]})")
r = run("data", default, "--set", "video.duration=1", "-q")
path = os.path.join(work, "out", "default.csv")
n = sum(1 for _ in open(path)) if os.path.exists(path) else 0
ok(r.returncode == 0 and n == 61, f"data without -o writes out/default.csv, 60 frame rows + header ({n})")
r = run("data", default, "--set", "pendulum.stiffness=5e6", "-o", "blow.csv")
ok(r.returncode == 3 and "stability limit" in r.stderr and not os.path.exists(os.path.join(work, "blow.csv"))
   and not glob.glob(os.path.join(work, "blow.csv.*.part")),
   "an unstable data run exits 3, names the stability limit, and leaves no file")
r = run("data", default, "--every", "0", "-o", "-")
ok(r.returncode == 2 and "--every 0" in r.stderr, "--every 0 is refused with exit 2")
r = run("data", default, "--set", "pendulum.stiffness=5e6", "--set", "pendulum.mass=0.5",
        "--set", "integrator.method=dop853", "--set", "video.duration=0.5", "-o", "-")
ok(r.returncode == 0 and len(r.stdout.splitlines()) == 31,
   "the same stiff scene runs clean with dop853")

# info: the resonance check, with l = L0 + m g / k, and the stability warning.
r = run("info", default)
ok(r.returncode == 0 and "l = L0 + m g / k = 2.9525 m" in r.stdout
   and "sqrt(g/l) = 1.8228" in r.stdout and "not near 2:1" in r.stdout and "warning" not in r.stdout,
   "info on the default scene: l = 2.9525 m, omega_p = sqrt(g/l), not near 2:1")
r = run("info", default, "--set", "pendulum.stiffness=29.43", "--set", "initial.length=0.8")
ok(r.returncode == 0 and "near 2:1 (+0.00%)" in r.stdout and "growth rate" in r.stdout,
   f"info at k L0 = 3 m g: near 2:1 with the exchange estimate")
r = run("info", default, "--set", "pendulum.stiffness=5e6")
ok(r.returncode == 0 and "warning: dt = 0.001 s is stopped as unstable" in r.stdout
   and "Use integrator.dt = 2e-05" in r.stdout, "info warns about an unstable dt with a safe one")

print(f"1..{count}")
sys.exit(1 if failed else 0)
