#!/usr/bin/env python3
"""springpend tests (issue 28): the thirteenth attacker's pass, its sweep
findings (doc/notes/2026-11-27/attack13.md; fix16's notes):
- #1: a sweep over a falling range (--vary KEY=170:10:N) drew no ticks on
  the key's axis and a line figure cut off both end points: the axis is
  drawn ascending, every point at its value, so the figure is the one of
  the same range written rising (line, map, orbit diagram, basins);
- #2: --continue up over a falling range ran downward: up is in increasing
  values of the key, whichever way FROM:TO is written;
- #3: --continue over an [initial] key silently replaced the key by the
  carried state: refused, exit 2, no output;
- #4: sweep, data and info refused a 3-D run of a scene whose [view]
  panels holds poincare, a panel they never draw (and sweep refused the
  --set that would fix it): [view]-only checks are made where the view is
  drawn (render, still), which still refuse with FILE:LINE; --vary's scene
  messages start with "springpend:" and name the option and the end;
- #9: the figure's subtitle said "dopri5 at dt = 0.05 s" for a sweep that
  ran DOP853 at its tolerance: "DOP853 at tolerance 1e-06 (dopri5 runs as
  DOP853)"; fixed-step methods keep "rk4 at dt = ...";
- #10: the basin entropies were not over 5x5 boxes: whole boxes of 5x5
  points from the grid's first point, the remainder left out and said; a
  grid under 5 on a side has none; S_b and S_bb recomputed here (numpy) from
  the labels;
- #13: an orbit diagram over pivot.frequency reaching 0 wrote no row for
  that point: refused (allowed: FROM > 0 and TO > 0), as basins refuses it;
- #17: a continued diagram counted blow-ups per branch ("8 of 4 points"),
  and a sweep whose every point blew up wrote an empty figure, exit 0: the
  point counts once, and with nothing finite the sweep writes nothing, exit
  3 (as data does);
- #20: an orbit or Poincare sweep's rows had no estimate or cap (only its
  steps): past 1e8 rows refused with their number and size in GB, exit 2;
- #27: a grid point the scene check refuses inside a range whose ends pass
  (initial.angle=-5:5:3 with an azimuth rate: 0 on the vertical) was
  skipped as "cannot have energy 0 J": the grid is refused, naming the
  point, exit 2.
usage: test_attack13_sweep.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import csv
import json
import os
import shutil
import subprocess

import sptest
from sptest import done, err, ok, skip

sptest.need_scipy()  # numpy (Debian's python3)
import numpy as np  # noqa: E402

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack13-sweep")
chaotic = os.path.join(scenes, "chaotic.ini")
parametric = os.path.join(scenes, "parametric.ini")
resonance = os.path.join(scenes, "resonance.ini")
default = os.path.join(scenes, "default.ini")


def pixels(name):
    """A PNG's pixels as an int array (ffmpeg decodes, rgb24)."""
    p = subprocess.run(["ffmpeg", "-v", "error", "-i", path(name), "-f", "rawvideo", "-pix_fmt",
                        "rgb24", "-"], capture_output=True, check=True)
    w, h = (int(v) for v in subprocess.run(
        ["ffprobe", "-v", "error", "-select_streams", "v:0", "-show_entries",
         "stream=width,height", "-of", "csv=p=0", path(name)], capture_output=True, text=True,
        check=True).stdout.strip().split(","))
    return np.frombuffer(p.stdout, np.uint8).reshape(h, w, 3).astype(int)


def same_figure(a, b, what):
    """Two sweep figures are the same picture (lines drawn the other way
    round may differ by an antialiasing level or two)."""
    pa, pb = pixels(a), pixels(b)
    if pa.shape != pb.shape:
        return ok(False, f"{what}: {pa.shape} against {pb.shape}")
    d = np.abs(pa - pb).max(axis=2)
    return ok(int((d > 8).sum()) == 0,
              f"{what}: the same figure as the rising range's ({int((d > 8).sum())} pixels differ "
              f"by more than 8 levels, largest {int(d.max())})")


# ---- #1: a falling range is drawn ascending, every point inside -------------------------------
have_ff = shutil.which("ffmpeg") and shutil.which("ffprobe")
for what, key, fall, rise, extra in [
        ("lyapunov line", "initial.angle", ["initial.angle=170:10:5"], ["initial.angle=10:170:5"],
         [chaotic, "--measure", "lyapunov", "--time", "4"]),
        ("lyapunov map", "initial.angle",
         ["initial.angle=170:10:12", "initial.length=1.6:0.8:6"],
         ["initial.angle=10:170:12", "initial.length=0.8:1.6:6"],
         [chaotic, "--measure", "lyapunov", "--time", "4"]),
        ("orbit diagram", "pivot.amplitude", ["pivot.amplitude=0.024:0:9"],
         ["pivot.amplitude=0:0.024:9"],
         [parametric, "--measure", "orbit", "--transient", "20", "--time", "5"]),
        ("basins", "initial.angle",
         ["initial.angle=180:-180:8", "initial.angle_rate=10:-10:6"],
         ["initial.angle=-180:180:8", "initial.angle_rate=-10:10:6"],
         [parametric, "--set", "pivot.amplitude=0.01", "--measure", "basins", "--transient", "10",
          "--time", "10"])]:
    tag = what.split()[-1]
    outs = []
    for name, vary in (("fall", fall), ("rise", rise)):
        args = ["sweep", *extra, "-o", f"{tag}-{name}.png", "--csv", f"{tag}-{name}.csv", "-q"]
        for v in vary:
            args += ["--vary", v]
        r = run(*args, timeout=120)
        outs.append(r.returncode == 0)
        if r.returncode:
            ok(False, f"{what} ({name}): exit {r.returncode}: {err(r)[-200:]!r}")
    if all(outs):
        if have_ff:
            same_figure(f"{tag}-fall.png", f"{tag}-rise.png", f"{what} over {' '.join(fall)}")
        else:
            skip(f"{what}: the figures compared", "ffmpeg is not installed")

# ---- #2: --continue up is in increasing values of the key --------------------------------------
def branches(name):
    """{(branch, key value): [(t, theta, r, peak) ...]} of a continued CSV."""
    out = {}
    with open(path(name)) as fp:
        rows = [row for row in csv.reader(line for line in fp if not line.startswith("#"))]
    for row in rows[1:]:
        out.setdefault((int(row[5]), round(float(row[1]), 12)), []).append(tuple(row[2:5] + row[6:]))
    return out


cont = {}
for name, rng, way in (("up-rise", "0:0.024:7", "up"), ("up-fall", "0.024:0:7", "up"),
                       ("down-rise", "0:0.024:7", "down"), ("down-fall", "0.024:0:7", "down"),
                       ("both-fall", "0.024:0:7", "both")):
    r = run("sweep", parametric, "--vary", f"pivot.amplitude={rng}", "--measure", "orbit",
            "--continue", way, "--peak", "theta", "--transient", "40", "--time", "4",
            "-o", f"{name}.png", "--csv", f"{name}.csv", "-q", timeout=120)
    cont[name] = branches(f"{name}.csv") if r.returncode == 0 else None
    if r.returncode:
        ok(False, f"--continue {way} over {rng}: exit {r.returncode}: {err(r)[-200:]!r}")
if all(cont.values()):
    # the up branch of the rising range is the one that differs from down
    # (the swing starts higher going up than it persists going down)
    ok(cont["up-rise"] != {(-1, k[1]): v for k, v in cont["down-rise"].items()},
       "the two branches of parametric.ini differ (hysteresis): the check below means something")
    ok(cont["up-fall"] == cont["up-rise"],
       "--continue up over pivot.amplitude=0.024:0:7: the same runs as over 0:0.024:7 "
       "(each value from the next lower one's state), branch 1")
    ok(cont["down-fall"] == cont["down-rise"],
       "--continue down over 0.024:0:7: the same runs as over 0:0.024:7, branch -1")
    both = cont["both-fall"]
    ok({k: v for k, v in both.items() if k[0] == 1} == cont["up-rise"] and
       {k: v for k, v in both.items() if k[0] == -1} == cont["down-rise"],
       "--continue both over 0.024:0:7: up and down as over the rising range")

# ---- #3: --continue refuses an [initial] key -------------------------------------------------
for key in ("initial.angle=1:170:5", "initial.length=0.9:1.1:3", "initial.angle_rate=0:1:3"):
    r = run("sweep", parametric, "--set", "pivot.amplitude=0.02", "--vary", key, "--measure", "orbit",
            "--continue", "up", "--transient", "5", "--time", "3", "-o", "c.png", "--csv", "c.csv")
    ok(r.returncode == 2 and err(r).startswith("springpend: --continue up:")
       and "allowed: vary a [pendulum] or [pivot] key" in err(r)
       and not os.path.exists(path("c.png")) and not os.path.exists(path("c.csv")),
       f"--continue over --vary {key}: refused, exit 2, nothing written "
       f"(exit {r.returncode}: {err(r)[-200:]!r})")

# ---- #4: [view]-only checks where the view is drawn ---------------------------------------
vectors_scene = path("vectors3d.ini")  # default.ini with its own [view] vectors line
with open(vectors_scene, "w") as f:
    f.write(open(default).read().replace("[view]\n", "[view]\nvectors = velocity\n", 1))

for what, args in [
        ("sweep chaotic.ini over initial.azimuth_rate",
         ["sweep", chaotic, "--vary", "initial.azimuth_rate=0:1:3", "--measure", "lyapunov",
          "--time", "4", "-o", "-", "-q"]),
        ("sweep resonance.ini (panels = all) over initial.azimuth_rate",
         ["sweep", resonance, "--vary", "initial.azimuth_rate=0.5:1:2", "--measure", "precession",
          "--time", "20", "-o", "-", "-q"]),
        ("sweep chaotic.ini --set initial.azimuth_rate=1",
         ["sweep", chaotic, "--set", "initial.azimuth_rate=1", "--vary", "initial.angle=10:20:2",
          "--measure", "precession", "--time", "20", "-o", "-", "-q"]),
        ("data chaotic.ini --set initial.azimuth_rate=1",
         ["data", chaotic, "--set", "initial.azimuth_rate=1", "--set", "video.duration=0.5",
          "-o", "d3.csv", "-q"]),
        # (data and info refuse a --set of a [view] key they do not read: tests
        # attack13-lead, attack15-lead; the scene's own line is taken)
        ("info with view.vectors and a 3-D scene",
         ["info", vectors_scene, "--set", "initial.azimuth_rate=1"]),
        ("info chaotic.ini --set initial.azimuth_rate=1",
         ["info", chaotic, "--set", "initial.azimuth_rate=1"])]:
    r = run(*args, timeout=120)
    wrote = r.stdout or (args[0] == "data" and os.path.exists(path(args[-2])))
    ok(r.returncode == 0 and wrote, f"{what}: taken (no panel is drawn), exit {r.returncode} "
       f"{err(r)[-200:]!r}")
for cmd in ("still", "render"):
    out = f"v3.{'png' if cmd == 'still' else 'mp4'}"
    r = run(cmd, chaotic, "--set", "initial.azimuth_rate=1", "--set", "video.duration=0.2",
            "--size", "320x180", "-o", out, "-q", timeout=120)
    ok(r.returncode == 2 and f"{chaotic}:37: the poincare panel" in err(r)
       and not os.path.exists(path(out)),
       f"{cmd} chaotic.ini --set initial.azimuth_rate=1: still refused with FILE:LINE "
       f"(exit {r.returncode}: {err(r)[:160]!r})")
r = run("sweep", default, "--set", "initial.angle=0", "--vary", "initial.azimuth_rate=0:1:3",
        "--measure", "lyapunov", "--time", "4", "-o", "-")
ok(r.returncode == 2 and err(r).startswith("springpend: --vary initial.azimuth_rate=0:1:3 (TO 1): "),
   f"a --vary end the scene refuses: 'springpend: --vary KEY=FROM:TO:N (TO v): ...' "
   f"(exit {r.returncode}: {err(r)[:120]!r})")

# ---- #9: the subtitle names the method that ran ------------------------------------------
if shutil.which("pdftotext"):
    for method, tol, want, unwanted in [
            ("dopri5", "1e-6", ("DOP853 at tolerance 1e", "06 (dopri5 runs as DOP853)"), "dt ="),
            ("dop853", "1e-9", ("DOP853 at tolerance 1e", "09"), "dt ="),
            ("rk4", None, ("rk4 at dt = 0.0005 s",), "DOP853")]:
        args = ["sweep", chaotic, "--set", f"integrator.method={method}", "--set",
                "integrator.dt=0.0005", "--vary", "initial.angle=10:20:3", "--measure", "lyapunov",
                "--time", "4", "-o", f"m-{method}.pdf", "-q"]
        if tol:
            args += ["--set", f"integrator.tolerance={tol}"]
        r = run(*args, timeout=120)
        text = subprocess.run(["pdftotext", path(f"m-{method}.pdf"), "-"], capture_output=True,
                              text=True).stdout if r.returncode == 0 else ""
        sub = next((ln for ln in text.splitlines() if "over 4 s" in ln), "")
        ok(all(w in sub for w in want) and unwanted not in sub,
           f"integrator.method = {method}: the subtitle says how it ran: {sub!r}")
else:
    skip("the sweep figure's subtitle", "pdftotext is not installed")


# ---- #10: basin entropies over whole 5x5 boxes ------------------------------------------
def entropies(labels, nx, ny, box=5):
    """Daza et al.'s S_b and S_bb over whole box x box boxes from the first
    point (the remainder left out, as Attractors.jl's basin_entropy), blown-up
    points (-1) left out of their box; (nan, nan) with no box."""
    lab = np.asarray(labels).reshape(ny, nx)
    sb, nb, nbb = 0.0, 0, 0
    for j0 in range(0, ny - box + 1, box):
        for i0 in range(0, nx - box + 1, box):
            cell = lab[j0:j0 + box, i0:i0 + box].ravel()
            cell = cell[cell >= 0]
            if not cell.size:
                continue
            _, counts = np.unique(cell, return_counts=True)
            p = counts / cell.size
            sb += float(-(p * np.log(p)).sum())
            nb += 1
            nbb += len(counts) > 1
    if not nb:
        return float("nan"), float("nan")
    return sb / nb, (sb / nbb if nbb else 0.0)


for nx, ny, said in [(12, 7, "boxes of 5x5 points; the last 2 of 12 columns and the last 2 of 7 rows left out"),
                     (10, 10, "boxes of 5x5 points)"),
                     (13, 5, "the last 3 of 13 columns left out"),
                     (9, 4, "none: the 9x4 grid has no box of 5x5 points")]:
    args = ["sweep", parametric, "--set", "pivot.amplitude=0.01", "--vary",
            f"initial.angle=-150:150:{nx}", "--vary", f"initial.angle_rate=-6:6:{ny}",
            "--measure", "basins", "--transient", "20", "--time", "20"]
    r = run(*args, "--format", "json", "-o", f"b{nx}x{ny}.png", timeout=200)
    j = json.loads(r.stdout) if r.returncode == 0 else {}
    if not ok(r.returncode == 0 and len(j.get("labels", [])) == nx * ny,
              f"basins {nx}x{ny}: exit {r.returncode} {err(r)[-160:]!r}"):
        continue
    sb, sbb = entropies(j["labels"], nx, ny)
    got_sb, got_sbb = j.get("basin_entropy"), j.get("boundary_basin_entropy")
    if np.isnan(sb):
        ok(got_sb is None and got_sbb is None and j.get("entropy_boxes") == [nx // 5, ny // 5],
           f"basins {nx}x{ny}: no 5x5 box, no entropies (JSON null), "
           f"got {got_sb}, {got_sbb}, boxes {j.get('entropy_boxes')}")
    else:
        ok(got_sb is not None and abs(got_sb - sb) < 1e-9 and abs(got_sbb - sbb) < 1e-9
           and j.get("entropy_box") == 5 and j.get("entropy_boxes") == [nx // 5, ny // 5],
           f"basins {nx}x{ny}: S_b {got_sb} and S_bb {got_sbb} over {j.get('entropy_boxes')} boxes "
           f"of 5x5: recomputed here from the labels, {sb:.10f}, {sbb:.10f}")
    ok(said in err(r), f"basins {nx}x{ny}: stderr says how: {said!r} in "
       f"{[ln for ln in err(r).splitlines() if 'entrop' in ln]}")

# ---- #13: an orbit diagram over a frequency range reaching 0 ------------------------------
for rng, extra in (("0:2:3", []), ("2:0:3", ["--continue", "up"])):
    r = run("sweep", parametric, "--vary", f"pivot.frequency={rng}", "--measure", "orbit",
            *extra, "--transient", "5", "--time", "5", "-o", "fq.png", "--csv", "fq.csv")
    ok(r.returncode == 2 and "allowed: FROM > 0 and TO > 0" in err(r)
       and err(r).startswith(f"springpend: --vary pivot.frequency={rng}")
       and not os.path.exists(path("fq.png")) and not os.path.exists(path("fq.csv")),
       f"orbit over pivot.frequency={rng} {' '.join(extra)}: refused, exit 2, nothing written "
       f"(exit {r.returncode}: {err(r)[-200:]!r})")
r = run("sweep", parametric, "--vary", "pivot.frequency=0.5:2:3", "--measure", "orbit",
        "--transient", "5", "--time", "5", "-o", "-", "-q")
points = {line.split(",")[0] for line in r.stdout.decode().splitlines()[1:]} if r.returncode == 0 else set()
ok(points == {"0", "1", "2"}, f"orbit over pivot.frequency=0.5:2:3: rows for every point ({sorted(points)})")

# ---- #17: blow-ups counted by point; nothing finite, nothing written ----------------------
for what, args in [
        ("a continued diagram, both branches",
         [parametric, "--set", "integrator.dt=0.3", "--vary", "pivot.amplitude=0:0.03:4", "--measure",
          "orbit", "--continue", "both", "--time", "20"]),
        ("a lyapunov line", [chaotic, "--set", "integrator.dt=0.2", "--vary", "initial.angle=10:170:4",
                             "--measure", "lyapunov", "--time", "20"])]:
    r = run("sweep", *args, "-o", "blown.png", "--csv", "blown.csv")
    ok(r.returncode == 3 and "every point of the grid blew up (4 of 4)" in err(r)
       and not os.path.exists(path("blown.png")) and not os.path.exists(path("blown.csv")),
       f"{what}, every point blown up: exit 3, nothing written ({r.returncode}: {err(r)[-200:]!r})")
r = run("sweep", parametric, "--set", "integrator.dt=0.05", "--vary", "pivot.amplitude=0:0.6:4", "--measure",
        "orbit", "--continue", "both", "--time", "20", "-o", "-", "--transient", "5")
lines = [ln for ln in err(r).splitlines() if "blew up" in ln]
nan_points = {ln.split(",")[0] for ln in r.stdout.decode().splitlines()[1:] if ",nan," in ln}
ok(r.returncode in (0, 3) and (not nan_points or any(f"{len(nan_points)} of 4 points" in ln for ln in lines)),
   f"a continued diagram counts a point whose branches blew up once: {sorted(nan_points)} in the CSV, {lines}")

# ---- #20: an orbit sweep's rows estimated and held to a limit ----------------------------
r = run("sweep", default, "--set", "pivot.amplitude=1e-7", "--vary", "pivot.frequency=400:500:1000",
        "--measure", "orbit", "--time", "500", "-o", "rows.png", "--csv", "rows.csv", timeout=60)
# independently: one row per drive period at most 500 Hz over 500 s, 1000 points
want = 1000 * 500 * 500
ok(r.returncode == 2 and f"at most {want:.2g} rows" in err(r) and "GB of CSV" in err(r)
   and "allowed: fewer points" in err(r) and not os.path.exists(path("rows.png"))
   and not os.path.exists(path("rows.csv")),
   f"orbit over 1000 points at up to 500 Hz for 500 s (about {want:.2g} rows): refused, exit 2 "
   f"({r.returncode}: {err(r)[-220:]!r})")
r = run("sweep", default, "--set", "pivot.amplitude=1e-7", "--vary", "pivot.frequency=400:500:4",
        "--measure", "orbit", "--time", "50", "-o", "-", timeout=60)
ok(r.returncode == 0 and "GB of CSV" not in err(r) and len(r.stdout.decode().splitlines()) > 4 * 50 * 400,
   f"a small orbit sweep (about 1e5 rows): taken without a note ({r.returncode}: {err(r)[-160:]!r})")

# ---- #27: a grid point the scene check refuses, inside the range --------------------------
swinging = os.path.join(scenes, "swinging-spring.ini")
for vary, point in ((["initial.angle=-5:5:3"], 1),
                    (["initial.angle=-5:5:3", "initial.azimuth_rate=0:1:2"], 4)):
    args = ["sweep", swinging, "--measure", "lyapunov", "--time", "5", "-o", "v.png", "--csv", "v.csv"]
    for v in vary:
        args += ["--vary", v]
    r = run(*args)
    ok(r.returncode == 2 and f"point {point} has initial.angle = 0 degrees" in err(r)
       and "allowed: a grid whose initial.angle values miss 0 and 180 degrees" in err(r)
       and "energy" not in err(r) and not os.path.exists(path("v.csv")),
       f"--vary {' '.join(vary)} on swinging-spring.ini: refused, naming point {point}, exit 2 "
       f"({r.returncode}: {err(r)[-220:]!r})")
r = run("sweep", swinging, "--vary", "initial.angle=-5:5:4", "--measure", "lyapunov", "--time", "5", "-o", "-", "-q")
ok(r.returncode == 0 and len(r.stdout.decode().splitlines()) == 5,
   f"initial.angle=-5:5:4 (no point on the vertical): every point measured ({r.returncode})")
done()
