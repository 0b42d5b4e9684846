"""Sweeps of the swinging spring in three dimensions (initial.azimuth_rate):
`--measure precession` against scipy's DOP853 on the 3-D equations written
here, the precession measured from the horizontal motion with this test's own
rule (maxima of the period-averaged swing, the swing plane as the principal
axis of the horizontal positions over a period there); the largest Lyapunov
exponent of a 3-D start against scipy's Benettin on the 6-D tangent
equations; a planar point in a 3-D grid measures what a planar sweep does;
threads and shards give the same bytes; the measures of the planar motion
refuse 3-D grids, and precession a planar one.

usage: test_sweep3d.py SPRINGPEND SRCDIR/tests BUILDDIR/tests"""
import csv
import math
import os
import shutil
import sys

from sptest import done, model3, need_scipy, ok, runner, start3

need_scipy()
import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "sweep3d"))
scenes = os.path.join(src, "..", "scenes")
SWING = os.path.join(scenes, "swinging-spring.ini")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
# scenes/chaotic.ini's physics and start, without its poincare panel (which
# a 3-D scene refuses: the section is of the planar motion)
CHAOTIC = os.path.join(work, "chaotic3d.ini")
with open(CHAOTIC, "w") as f:
    f.write("[pendulum]\nnatural_length = 0.75\nstiffness = 39.24\nmass = 1\n"
            "[initial]\nlength = 1.2\nangle = 85.94\n[integrator]\nmethod = rk4\n"
            "dt = 0.0005\n")
run = runner(exe, work)
G = 9.81


def rows(name):
    with open(os.path.join(work, name)) as f:
        return list(csv.DictReader(f))


def read(name):
    with open(os.path.join(work, name), "rb") as f:
        return f.read()


# ---- the precession per exchange ----------------------------------------
def precession_ref(phd, T, k=39.24, L0=0.75, m=1.0, r0=1.05, th=1.0, dt=0.02):
    """scipy's run of the swinging spring turning at phd: the swing's maxima
    are the local maxima of x^2 + z^2 averaged over one pendulum period that
    are the largest within 10 periods either side and above half the
    largest; the swing plane there is the principal axis of (x, z) over the
    period around it. Returns the mean turn (degrees) and the mean time
    between maxima (s)."""
    ell = L0 + m * G / k
    period = 2 * math.pi / math.sqrt(G / ell)
    ts = np.arange(0, T + 1e-9, dt)
    sol = solve_ivp(model3(L0, k, m, g=G), (0, T), start3(r0, th, phd=phd), method="DOP853",
                    rtol=1e-11, atol=1e-13, t_eval=ts)
    x, z = sol.y[0], sol.y[2]
    n = int(round(period / dt))
    amp = np.convolve(x * x + z * z, np.ones(n) / n, mode="same")
    peaks = [i for i in range(n, len(ts) - n)
             if amp[i] == np.max(amp[max(0, i - 10 * n):i + 10 * n]) and amp[i] > 0.5 * amp.max()]
    angles, prev = [], None
    for i in peaks:
        xs, zs = x[i - n // 2:i + n // 2 + 1], z[i - n // 2:i + n // 2 + 1]
        a = 0.5 * math.atan2(2 * np.mean(xs * zs), np.mean(xs * xs) - np.mean(zs * zs))
        if prev is not None:
            a += math.pi * round((prev - a) / math.pi)
        angles.append(a)
        prev = a
    turns = np.degrees(np.diff(angles))
    return float(np.mean(turns)), float(np.mean(np.diff(ts[peaks]))), len(turns)


T = 240
r = run("sweep", SWING, "--vary", "initial.azimuth_rate=0.5:2:4", "--measure", "precession",
        "--time", str(T), "-o", "prec.png", "--csv", "prec.csv", "-q")
ok(r.returncode == 0, f"a precession sweep of scenes/swinging-spring.ini runs (exit "
   f"{r.returncode}) {r.stderr.strip()}")
got = rows("prec.csv") if r.returncode == 0 else []
for row in got:
    phd = float(row["initial.azimuth_rate"])
    want, want_period, n = precession_ref(phd, T)
    p, per = float(row["precession"]), float(row["exchange_period"])
    ok(n >= 3 and abs(p - want) < 0.03 * abs(want) and abs(per - want_period) < 0.03 * want_period,
       f"azimuth_rate {phd:g} rad/s: springpend's precession {p:.2f} degrees per exchange, "
       f"every {per:.2f} s ({row['exchanges']} exchanges); scipy's run {want:.2f} every "
       f"{want_period:.2f} s ({n}; within 3%)")
ok(len(got) == 4, f"one row per point ({len(got)})")
ok(os.path.getsize(os.path.join(work, "prec.png")) > 10000, "the line figure is drawn")

# a map over two keys, its bytes independent of the thread count and of shards
grid = ["--vary", "initial.azimuth_rate=0.5:1.5:3", "--vary", "pendulum.stiffness=38.5:40:3",
        "--measure", "precession", "--time", "150", "-q"]
r = run("sweep", SWING, *grid, "-o", "map.png", "--csv", "map.csv")
r1 = run("sweep", SWING, *grid, "--threads", "1", "-o", "map1.png", "--csv", "map1.csv")
ok(r.returncode == 0 and r1.returncode == 0 and read("map.csv") == read("map1.csv") and
   read("map.png") == read("map1.png"), "a 3x3 precession map: one thread gives the same CSV "
   "and PNG bytes as one per core")
parts = []
for i in (1, 2):
    rs = run("sweep", SWING, *grid, "--shard", f"{i}/2", "--csv", f"part{i}.csv")
    parts.append(rs.returncode)
rm = run("sweep", "--merge", "part1.csv", "part2.csv", "-o", "merged.png", "--csv", "merged.csv",
         "-q")
ok(parts == [0, 0] and rm.returncode == 0 and read("merged.csv") == read("map.csv") and
   read("merged.png") == read("map.png"),
   f"two shards merged equal the whole map byte for byte (exits {parts}, {rm.returncode}) "
   f"{rm.stderr.strip()}")


# ---- the largest Lyapunov exponent of a 3-D start -----------------------
def lyapunov_ref(phd, T, k=39.24, L0=0.75, m=1.0, r0=1.2, th=85.94):
    """Benettin with scipy's DOP853 on the 3-D state and a 6-D tangent
    vector started along x, renormalised every second."""
    km = k / m

    def f(t, s):
        x, y, z, vx, vy, vz = s[:6]
        d, dv = s[6:9], s[9:12]
        rho = math.sqrt(x * x + y * y + z * z)
        c = km * (1 - L0 / rho)
        a = km * L0 / rho ** 3
        q = np.array([x, y, z])
        J = -c * np.eye(3) - a * np.outer(q, q)
        return [vx, vy, vz, -c * x, -c * y - G, -c * z, *dv, *(J @ d)]

    s = np.array(start3(r0, th, phd=phd) + [1, 0, 0, 0, 0, 0], float)
    total = 0.0
    for k1 in range(1, int(T) + 1):
        s = solve_ivp(f, (k1 - 1, k1), s, method="DOP853", rtol=1e-11, atol=1e-12).y[:, -1]
        n = math.sqrt(sum(s[6:] ** 2))
        total += math.log(n)
        s[6:] /= n
    return total / T


T = 20
r = run("sweep", CHAOTIC, "--vary", "initial.azimuth_rate=0:0.5:2", "--measure", "lyapunov",
        "--time", str(T), "--set", "integrator.dt=0.001", "-o", "-", "--csv", "lyap.csv", "-q")
got = rows("lyap.csv") if r.returncode == 0 else []
ok(r.returncode == 0 and len(got) == 2, f"a lyapunov sweep over initial.azimuth_rate 0 and 0.5 "
   f"rad/s of chaotic.ini's start runs (exit {r.returncode}) {r.stderr.strip()}")
if len(got) == 2:
    lam, want = float(got[1]["lyapunov"]), lyapunov_ref(0.5, T)
    ok(abs(lam - want) < 1e-4 * abs(want) + 1e-6,
       f"3-D start (azimuth_rate 0.5 rad/s): lambda over {T} s = {lam:.6f} 1/s; scipy's "
       f"Benettin on the 6-D tangent equations {want:.6f}")
    rp = run("sweep", CHAOTIC, "--vary", "initial.angle=85.94:85.94:1", "--measure", "lyapunov",
             "--time", str(T), "--set", "integrator.dt=0.001", "-o", "-", "--csv", "planar.csv",
             "-q")
    planar = rows("planar.csv") if rp.returncode == 0 else [{}]
    ok(planar[0].get("lyapunov") == got[0]["lyapunov"] and
       planar[0].get("lyapunov_half") == got[0]["lyapunov_half"],
       f"the planar point of the 3-D grid (azimuth_rate 0) gives the planar sweep's numbers "
       f"exactly ({got[0]['lyapunov']} and {planar[0].get('lyapunov')})")

# ---- refusals ------------------------------------------------------------
for measure, extra in (("orbit", []), ("poincare", []), ("spectrum", []),
                       ("basins", ["--vary", "initial.angle=5:10:2", "--set",
                                   "pendulum.damping=0.1", "--set", "pivot.amplitude=0.01",
                                   "--set", "pivot.frequency=1"])):
    out = os.path.join(work, f"refused-{measure}.png")
    r = run("sweep", SWING, "--vary", "initial.length=1.02:1.08:2", *extra, "--measure", measure,
            "--time", "10", "-o", out, "-q")
    ok(r.returncode == 2 and not os.path.exists(out) and "leaves the x-y plane" in r.stderr and
       "lyapunov or precession" in r.stderr,
       f"--measure {measure} of a 3-D scene is refused with what 3-D points take (exit "
       f"{r.returncode}): {r.stderr.strip()[:160]}")
r = run("sweep", CHAOTIC, "--vary", "initial.angle=10:20:2", "--measure", "precession",
        "--time", "10", "-o", "refused.png", "-q")
ok(r.returncode == 2 and not os.path.exists(os.path.join(work, "refused.png")) and
   "initial.azimuth_rate" in r.stderr,
   f"--measure precession of a planar grid is refused (exit {r.returncode}): "
   f"{r.stderr.strip()[:160]}")
r = run("sweep", CHAOTIC, "--vary", "initial.azimuth_rate=0:0.5:2", "--measure", "lyapunov",
        "--time", "10", "--fast", "--set", "integrator.dt=0.001", "-o", "refused.png", "-q")
ok(r.returncode == 2 and not os.path.exists(os.path.join(work, "refused.png")) and
   ("planar pendulums only" in r.stderr or "AVX-512F" in r.stderr),
   f"--fast on a 3-D grid is refused (exit {r.returncode}): {r.stderr.strip()[:160]}")
done()
