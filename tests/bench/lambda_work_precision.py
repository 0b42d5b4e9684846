#!/usr/bin/python3
"""Work-precision of a Lyapunov map (issue 25): chaotic.ini over 512 angles
1..179 degrees, lambda over T = 200 s with RK4 and the tangent equations,
from `springpend sweep` at several dt against a reference at dt 1.25e-4,
and from the numba peer (../../../shared/peers/numba_lyap_peer.py, Debian's
python3-numba) at its own dt 5e-4. Error: |lambda - lambda_ref| over the
grid (median, mean, max); work: CPU time (user + sys of every thread).
Writes OUT.tsv (drawn by lambda_work_precision.R) and prints a Markdown
table. usage: lambda_work_precision.py SPRINGPEND SCENES_DIR OUT.tsv"""
import csv
import os
import resource
import subprocess
import sys
import tempfile
import time


if sys.argv[1:2] in (["-h"], ["--help"]):
    sys.exit(print(__doc__))
if len(sys.argv) < 4:
    print(__doc__, file=sys.stderr)
    sys.exit(2)
import numpy as np  # noqa: E402 (after the usage check: --help needs no numpy)

exe, scenes, out = sys.argv[1], sys.argv[2], sys.argv[3]
work = tempfile.mkdtemp(prefix="springpend-wp-")
DTS = ["1.25e-4", "2.5e-4", "5e-4", "1e-3", "2e-3", "4e-3"]


def sweep(dt):
    """lambda per angle and the sweep's CPU seconds."""
    path = os.path.join(work, f"l_{dt}.csv")
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([exe, "sweep", os.path.join(scenes, "chaotic.ini"), "--vary",
                    "initial.angle=1:179:512", "--measure", "lyapunov", "--time", "200", "--set",
                    f"integrator.dt={dt}", "-o", os.path.join(work, "l.png"), "--csv", path, "-q"],
                   check=True)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    rows = [r for r in csv.reader(open(path)) if r and not r[0].startswith("#")][1:]
    return (np.array([float(r[2]) for r in rows]),
            r1.ru_utime + r1.ru_stime - r0.ru_utime - r0.ru_stime)


def peer(dt):
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..",
                                    "shared", "peers"))
    import numba_lyap_peer as P
    km, L0, g, r0 = 39.24, 0.75, 9.81, 1.2
    P.grid(np.radians(np.linspace(1, 179, 2)), r0, km, L0, g, 1.0, dt, 1.0)  # compile
    c0 = time.process_time()
    lam = P.grid(np.radians(np.linspace(1, 179, 512)), r0, km, L0, g, 200.0, dt, 1.0)
    return lam, time.process_time() - c0


res = {dt: sweep(dt) for dt in DTS}
ref = res[DTS[0]][0]
rows = [("springpend", dt, cpu, lam) for dt, (lam, cpu) in res.items() if dt != DTS[0]]
lam, cpu = peer(5e-4)
rows.append(("numba", "5e-4", cpu, lam))
with open(out, "w") as f:
    f.write("who\tdt\tcpu\tmedian\tmean\tmax\tblowups\n")
    print("| run | dt | CPU s | median abs(λ − λ_ref) | mean | max | blow-ups |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for who, dt, cpu, lam in rows:
        ok = np.isfinite(lam)
        e = np.abs(lam[ok] - ref[ok])
        f.write(f"{who}\t{dt}\t{cpu:.3f}\t{np.median(e):.3g}\t{np.mean(e):.4f}\t{np.max(e):.4f}"
                f"\t{np.sum(~ok)}\n")
        print(f"| {who} | {dt} | {cpu:.2f} | {np.median(e):.2g} | {np.mean(e):.4f} | "
              f"{np.max(e):.4f} | {np.sum(~ok)} |")
