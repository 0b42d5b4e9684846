#!/usr/bin/env python3
"""Benchmark of sweeps (meson test -C build --benchmark sweep --verbose).
In one run, on chaotic.ini's physics (the numba peer's: m 1, k 39.24, L0 0.75,
r0 1.2, 256 angles 1..179 deg, RK4 at dt 1e-3, tangent renormalised every
second, T = 100 s):
  - the numba peer (../shared/peers/numba_lyap_peer.py, Debian's python3-numba);
  - springpend's batched integrator (bench_batch): state alone and with the
    tangent, one thread and one per core; GSL odeiv2 rk4 per trajectory;
  - `springpend sweep` itself on the same grid, and the lambdas each gets;
  - lambda against T for a chaotic and a regular start;
  - unless --quick: a 256x256 Lyapunov map over (theta0, r0) at T = 200 s,
    timed, and 16 of its points against a run at a quarter of the step.
usage: bench_sweep.py SPRINGPEND BENCH_BATCH SCENES_DIR [--quick]"""
import csv
import os
import shutil
import subprocess
import sys
import tempfile
import time

if "-h" in sys.argv or "--help" in sys.argv:
    print(__doc__)
    sys.exit(0)
if len([a for a in sys.argv[1:] if not a.startswith("--")]) < 3:
    sys.exit(__doc__.split("usage: ")[1].split("\n")[0].join(("usage: ", "")))
exe, bench_batch, scenes = (os.path.abspath(a) for a in sys.argv[1:4])
quick = "--quick" in sys.argv
chaotic = os.path.join(scenes, "chaotic.ini")
PEER = os.environ.get("SP_NUMBA_PEER", os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                    "..", "..", "..", "shared", "peers",
                                                    "numba_lyap_peer.py"))
N, T, DT = 256, 100, 0.001
STEPS = N * T / DT
work = tempfile.mkdtemp(prefix="springpend-bench-sweep-")
print(f"# load average before: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")


import resource

last_cpu = 0.0  # CPU seconds (user + sys) of the last sweep


def sweep(*args):
    """Runs springpend sweep; returns its wall time (and sets last_cpu)."""
    global last_cpu
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    r = subprocess.run([exe, "sweep", *args, "-q"], capture_output=True, text=True, cwd=work)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    last_cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    if r.returncode:
        sys.exit(f"springpend sweep failed: {r.stderr}")
    return time.perf_counter() - t0


def rows(name):
    with open(os.path.join(work, name)) as f:
        return list(csv.DictReader(l for l in f if not l.startswith("#")))


# ---- throughput, side by side --------------------------------------------
results = {}
python = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable
peer = peer_cpu = peer_lam = None
SNIPPET = """
import importlib.util, sys, time
import numpy as np
spec = importlib.util.spec_from_file_location("peer", sys.argv[1])
m = importlib.util.module_from_spec(spec)
spec.loader.exec_module(m)
N, T, dt = int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
km, L0, g, r0 = 39.24, 0.75, 9.81, 1.2
m.grid(np.radians(np.linspace(1, 179, 2)), r0, km, L0, g, 1.0, dt, 1.0)  # compile
ths = np.radians(np.linspace(1, 179, N))
t0, c0 = time.perf_counter(), time.process_time()
lam = m.grid(ths, r0, km, L0, g, T, dt, 1.0)
print(time.perf_counter() - t0, time.process_time() - c0)
print(",".join(repr(float(x)) for x in lam))
"""
if os.path.exists(PEER):
    r = subprocess.run([python, "-c", SNIPPET, PEER, str(N), str(T), str(DT)], capture_output=True, text=True)
    try:
        lines = r.stdout.split("\n")
        wall, cpu = (float(x) for x in lines[0].split())
        peer_lam = [float(x) for x in lines[1].split(",")]
        peer, peer_cpu = STEPS / wall, STEPS / cpu
        results["numba peer, RK4 + tangent, all cores"] = (peer, peer_cpu, [peer_lam[i] for i in (0, N // 2, N - 1)])
    except (ValueError, IndexError):
        print("# numba peer failed:", r.stdout, r.stderr)
b = subprocess.run([bench_batch, str(N), str(T), str(DT)], capture_output=True, text=True).stdout
kv = dict(line.split(" = ") for line in b.splitlines() if " = " in line)
cores = int(kv["cores"])
angles = ["1.0", f"{1 + 178 * (N // 2) / (N - 1):.1f}", "179.0"]
sp_lam = [float(kv[f"springpend_lambda_{a}"]) for a in angles]
for what, key in (("state alone", "state"), ("RK4 + tangent", "tangent")):
    results[f"springpend batch, {what}, 1 thread"] = (float(kv[f"springpend_{key}_1"]), None, None)
    results[f"springpend batch, {what}, {cores} threads"] = (
        float(kv[f"springpend_{key}_{cores}"]), float(kv[f"springpend_{key}_cpu"]),
        sp_lam if key == "tangent" else None)
if "gsl_state_1" in kv:
    results["GSL odeiv2 rk4 per trajectory, state alone, 1 thread"] = (
        float(kv["gsl_state_1"]), float(kv["gsl_state_cpu"]), None)
    results["GSL odeiv2 rk4 per trajectory, + tangent, 1 thread"] = (
        float(kv["gsl_tangent_1"]), float(kv["gsl_tangent_cpu"]),
        [float(kv[f"gsl_lambda_{a}"]) for a in angles])
el = sweep(chaotic, "--vary", f"initial.angle=1:179:{N}", "--measure", "lyapunov", "--time", str(T),
           "--set", f"integrator.dt={DT}", "-o", "line.png", "--csv", "line.csv")
got = rows("line.csv")
sweep_lam = [float(g["lyapunov"]) for g in got]
results[f"springpend sweep (the command, start to PNG), {cores} threads"] = (
    STEPS / el, STEPS / last_cpu, [sweep_lam[i] for i in (0, N // 2, N - 1)])

print(f"\n{N} trajectories x {T} s at dt {DT} ({STEPS / 1e6:.1f} M trajectory-steps each):\n")
print(f"| run | M trajectory-steps/s (wall) | x numba | per CPU-second | x numba | "
      f"lambda at {', '.join(angles)} deg (1/s) |")
print("|---|---:|---:|---:|---:|---|")
for name, (rate, cpu, lam) in results.items():
    ratio = f"{rate / peer:.1f}" if peer else "-"
    cpur = f"{cpu / 1e6:.1f}" if cpu else ""
    cratio = f"{cpu / peer_cpu:.1f}" if cpu and peer_cpu else ""
    lams = ", ".join(f"{x:.4f}" for x in lam) if lam else ""
    print(f"| {name} | {rate / 1e6:.1f} | {ratio} | {cpur} | {cratio} | {lams} |")
if peer_lam:
    same = sum(abs(a - b) < 1e-3 for a, b in zip(sweep_lam, peer_lam))
    mean = lambda v: sum(v) / len(v)
    sd = (sum((x - mean(peer_lam)) ** 2 for x in peer_lam) / len(peer_lam)) ** 0.5
    print(f"\nlambda over the {N} angles: springpend and numba agree within 1e-3 at {same} points "
          f"(the others are chaotic: after 100 s the two runs are different orbits); grid mean "
          f"springpend {mean(sweep_lam):.4f}, numba {mean(peer_lam):.4f} 1/s (spread of the grid's "
          f"values: sd {sd:.3f}, standard error of the mean {sd / len(peer_lam) ** 0.5:.4f})")

# ---- lambda against T --------------------------------------------------------
print("\nlambda (1/s) against T: chaotic.ini's start (85.94 deg, 1.2 m) and a regular orbit "
      "(60 deg, 1.6 m, L0 0.5, k 19.62):\n")
print("| T (s) | chaotic | regular | regular x T |")
print("|---:|---:|---:|---:|")
for t in (25, 50, 100, 200, 400):
    lam = []
    for extra in ([], ["--set", "initial.angle=60", "--set", "initial.length=1.6",
                       "--set", "pendulum.natural_length=0.5", "--set", "pendulum.stiffness=19.62"]):
        sweep(chaotic, *extra, "--vary", "initial.length_rate=0:0:1", "--measure", "lyapunov",
              "--time", str(t), "-o", "t.png", "--csv", "t.csv")
        lam.append(float(rows("t.csv")[0]["lyapunov"]))
    print(f"| {t} | {lam[0]:.4f} | {lam[1]:.4f} | {lam[1] * t:.2f} |")

# ---- the 256x256 map -----------------------------------------------------------
if not quick:
    grid = ["--vary", "initial.angle=1:179:256", "--vary", "initial.length=0.8:1.6:256"]
    el = sweep(chaotic, *grid, "--measure", "lyapunov", "--time", "200", "--set", "integrator.dt=0.001",
               "-o", "map.png", "--csv", "map.csv")
    map_cpu = last_cpu
    full = rows("map.csv")
    sweep(chaotic, "--vary", "initial.angle=1:179:4", "--vary", "initial.length=0.8:1.6:4",
          "--measure", "lyapunov", "--time", "200", "--set", "integrator.dt=0.00025",
          "-o", "tight.png", "--csv", "tight.csv")
    tight = rows("tight.csv")
    diffs = {"regular (tight lambda < 0.05)": [], "chaotic": []}
    for p, t in enumerate(tight):
        i, j = (p % 4) * 85, (p // 4) * 85
        a, b2 = float(full[j * 256 + i]["lyapunov"]), float(t["lyapunov"])
        diffs["regular (tight lambda < 0.05)" if b2 < 0.05 else "chaotic"].append((abs(a - b2), b2))
    print(f"\n256x256 Lyapunov map of chaotic.ini's physics over (theta0 1..179 deg, r0 0.8..1.6 m), "
          f"T = 200 s, RK4 dt = 1e-3, {cores} threads: {el:.1f} s wall, {map_cpu:.1f} s CPU "
          f"({65536 * 200 / 0.001 / el / 1e6:.0f} M trajectory-steps/s; "
          f"{65536 * 200 / 0.001 / map_cpu / 1e6:.0f} M per CPU-second); load average now "
          f"{os.getloadavg()[0]:.2f}")
    for k, v in diffs.items():
        if v:
            ds = sorted(d for d, _ in v)
            print(f"  against dt = 2.5e-4 at {len(v)} {k} points: median |dlambda| {ds[len(ds) // 2]:.2g}, "
                  f"max {ds[-1]:.2g} 1/s (lambda {min(x for _, x in v):.3f}..{max(x for _, x in v):.3f})")
shutil.rmtree(work, ignore_errors=True)
