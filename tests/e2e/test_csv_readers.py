#!/usr/bin/env python3
"""springpend tests: every CSV springpend writes is read by pandas read_csv,
numpy genfromtxt(names=True, delimiter=','), R read.csv and Python's csv
module with no options, each getting the header and every row; beside it,
NAME.csv-metadata.json (W3C CSV on the Web) names the same columns with
their units, and its scene (dc:source) run again gives the same bytes.
The sweep CSV's first line was a '# springpend sweep ...' comment: numpy and
pandas took it for the header."""
import csv
import io
import json
import os
import re
import shutil
import subprocess
import sys

from sptest import diag, done, ok, runner, skip

try:
    import numpy
    import pandas
except ImportError:  # a pyenv python3 without them: Debian's has both
    if os.path.exists("/usr/bin/python3") and not os.environ.get("SP_REEXEC"):
        os.environ["SP_REEXEC"] = "1"
        os.execv("/usr/bin/python3", ["/usr/bin/python3", *sys.argv])
    print("1..0 # SKIP pandas and numpy are not installed (Debian: python3-pandas)")
    sys.exit(77)

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "csv_readers"))
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
run = runner(exe, work)
scenes = os.path.join(src, "..", "scenes")
CHAOTIC, DEFAULT = os.path.join(scenes, "chaotic.ini"), os.path.join(scenes, "default.ini")
PARAMETRIC = os.path.join(scenes, "parametric.ini")
rscript = shutil.which("Rscript")

kinds = {
    "data": ["data", DEFAULT, "--every", "0.5"],
    "data_poincare": ["data", CHAOTIC, "--poincare", "--set", "video.duration=20"],
    "data_ensemble": ["data", DEFAULT, "--every", "1", "--set", "ensemble.count=3",
                      "--set", "ensemble.spread=2"],
    "sweep_lyapunov": ["sweep", CHAOTIC, "--vary", "initial.angle=20:60:3", "--vary",
                       "initial.length=1:1.2:2", "--measure", "lyapunov", "--time", "2"],
    "sweep_orbit": ["sweep", PARAMETRIC, "--vary", "pivot.amplitude=0:0.05:3", "--measure", "orbit",
                    "--transient", "2", "--time", "4"],
    "sweep_orbit_peak": ["sweep", PARAMETRIC, "--vary", "pivot.amplitude=0:0.05:3", "--measure",
                         "orbit", "--peak", "theta", "--time", "4"],
    "sweep_poincare": ["sweep", CHAOTIC, "--vary", "initial.length=0.8:1.2:3", "--set",
                       "initial.angle=0", "--measure", "poincare", "--time", "20"],
    "sweep_spectrum": ["sweep", CHAOTIC, "--vary", "initial.angle=20:60:2", "--measure",
                       "spectrum", "--time", "5"],
    "sweep_basins": ["sweep", PARAMETRIC, "--set", "pendulum.damping=0.2", "--set",
                     "pivot.amplitude=0.05", "--vary", "initial.angle=-20:20:3", "--vary",
                     "initial.angle_rate=-1:1:2", "--measure", "basins", "--transient", "2",
                     "--time", "10"],
    "sweep_shard": ["sweep", CHAOTIC, "--vary", "initial.angle=20:60:5", "--measure", "lyapunov",
                    "--time", "2", "--shard", "2/2"],
}
for name, args in kinds.items():
    out = ["--csv", name + ".csv"] if args[0] == "sweep" else ["-o", name + ".csv"]
    if args[0] == "sweep" and "--shard" not in args:
        out += ["-o", name + ".png"]
    r = run(*args, *out, "-q")
    csv_path = os.path.join(work, name + ".csv")
    if r.returncode or not os.path.exists(csv_path):
        ok(False, f"{name}: written (exit {r.returncode}: {r.stderr.strip()[-200:]})")
        continue
    text = open(csv_path).read()
    lines = text.splitlines()
    header, n_rows = lines[0].split(","), len(lines) - 1
    ok(n_rows > 0 and not any(l.startswith("#") for l in lines) and
       all(len(l.split(",")) == len(header) for l in lines),
       f"{name}: a header line of {len(header)} names, {n_rows} rows of as many fields, "
       "no comment line")
    # the four readers, no options
    df = pandas.read_csv(csv_path)
    ok(list(df.columns) == header and len(df) == n_rows,
       f"{name}: pandas read_csv gets the header and {len(df)} of {n_rows} rows")
    arr = numpy.genfromtxt(csv_path, names=True, delimiter=",")
    got = numpy.atleast_1d(arr)
    ok(arr.dtype.names is not None and len(arr.dtype.names) == len(header) and len(got) == n_rows,
       f"numpy genfromtxt(names=True, delimiter=','): {len(got)} of {n_rows} rows, "
       f"names {arr.dtype.names[:3] if arr.dtype.names else None}... ({name})")
    with open(csv_path, newline="") as f:
        rows = list(csv.reader(f))
    ok(rows[0] == header and len(rows) - 1 == n_rows and
       float(rows[1][0]) == float(df.iloc[0, 0]),
       f"{name}: Python's csv module gets the header and {len(rows) - 1} rows")
    if rscript:
        rr = subprocess.run([rscript, "-e", f"d <- read.csv('{csv_path}'); "
                             "cat(nrow(d), ncol(d), names(d)[1], '\\n')"],
                            capture_output=True, text=True)
        ok(rr.returncode == 0 and rr.stdout.split() == [str(n_rows), str(len(header)), header[0]],
           f"{name}: R read.csv gets {rr.stdout.strip()} (rows, columns, first name) of "
           f"{n_rows} {len(header)} {header[0]} {rr.stderr.strip()[-160:]}")
    else:
        skip(f"{name}: R read.csv", "Rscript is missing (Debian: r-base-core)")
    # the metadata beside it
    meta_path = csv_path + "-metadata.json"
    try:
        meta = json.load(open(meta_path))
    except (OSError, ValueError) as e:
        ok(False, f"{name}: {meta_path} reads as JSON ({e})")
        continue
    cols = meta.get("tableSchema", {}).get("columns", [])
    ok(meta.get("@context") == "http://www.w3.org/ns/csvw" and meta.get("url") == name + ".csv" and
       [c.get("name") for c in cols] == header and all(c.get("schema:unitText") for c in cols) and
       meta.get("schema:softwareVersion") and meta.get("dc:source", "").startswith("[pendulum]") and
       meta.get("prov:wasGeneratedBy", "").startswith("springpend " + args[0]),
       f"{name}: the metadata names the {len(header)} columns with units, the scene, the command, "
       f"the version")
    units = {c["name"]: c["schema:unitText"] for c in cols}
    if name == "data":
        ok(units["theta"] == "rad" and units["theta_dot"] == "rad/s" and units["t"] == "s" and
           units["energy"] == "J", f"data's units: theta rad, theta_dot rad/s, t s, energy J: {units}")
    if name == "sweep_lyapunov":
        ok(units["initial.angle"] == "degrees" and units["lyapunov"] == "1/s" and
           units["initial.length"] == "m", f"a sweep's key columns in file units: {units}")
    if name == "sweep_shard":
        ok(meta.get("schema:position") == "2/2" and meta.get("dc:extent") == n_rows,
           f"a shard's metadata: position 2/2, {meta.get('dc:extent')} rows")

# ---- the recorded scene runs again to the same bytes --------------------------
# The scene is written in user units (the angle in degrees, names not codes):
# `data` on it, with the recorded command's options, gives the same CSV.
# (data reads no [view] key, so the scene file holds them: a --set of one is refused)
with open(CHAOTIC) as f:
    viewed = re.sub(r"^panels\s*=.*$", "panels = energy, phase\ntitle = \"a 'b' # c ü\"",
                    f.read(), flags=re.M)
with open(os.path.join(work, "viewed.ini"), "w") as f:
    f.write(viewed)
args = ["data", "viewed.ini", "--every", "0.25", "--set", "initial.angle=33.3", "-o", "rt.csv", "-q"]
r = run(*args)
meta = json.load(open(os.path.join(work, "rt.csv-metadata.json")))
scene = meta["dc:source"]
ok("angle = 33.3\n" in scene and "panels = energy, phase\n" in scene and "theme = dark\n" in scene
   and "title = \"a 'b' # c ü\"\n" in scene,
   "the recorded scene is in user units and names: angle = 33.3 (degrees), panels = energy, "
   "phase, theme = dark, the title quoted")
with open(os.path.join(work, "recorded.ini"), "w") as f:
    f.write(scene)
r2 = run("data", "recorded.ini", "--every", "0.25", "-o", "rt2.csv", "-q")
ok(r.returncode == 0 and r2.returncode == 0 and
   open(os.path.join(work, "rt.csv"), "rb").read() == open(os.path.join(work, "rt2.csv"), "rb").read(),
   "data on the recorded scene gives the same CSV bytes")
ok(meta["prov:used"] == ["initial.angle=33.3"],
   f"prov:used lists the overrides in order: {meta['prov:used']}")

# ---- stdout: the CSV only; a failed run leaves neither file -------------------
r = run("data", DEFAULT, "--every", "1", "-o", "-")
ok(r.returncode == 0 and r.stdout.startswith("t,x,y,") and not os.path.exists(os.path.join(work, "-")) and
   not [f for f in os.listdir(work) if f.endswith("-metadata.json") and f.startswith("-")],
   "-o - writes the CSV on stdout and no metadata file")
r = run("data", DEFAULT, "--set", "pendulum.stiffness=1e7", "--set", "integrator.dt=0.01",
        "-o", "blown.csv")
ok(r.returncode == 3 and not [f for f in os.listdir(work) if f.startswith("blown")],
   f"an unstable run (exit {r.returncode}) leaves neither the CSV nor its metadata")
done()
