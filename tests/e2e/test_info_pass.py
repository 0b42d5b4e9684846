#!/usr/bin/env python3
"""springpend tests: info on a bob that passes close by the pivot. Inside
half the natural length the compressed spring pushes outward with at most
k L0, a bounded force, so a close pass is no rate a fixed step must keep
stable; it is a pass to resolve (dt < d/v) or to step over at some cost in
energy. info must not turn it into an absurd omega_max and safe dt: where
the passes make a fixed step impractical it says so and names dop853, checked
to complete. Scenes without such passes keep a safe dt that completes them.
Every expectation is a closed form (sqrt(k/m), the drive, L0 / 2) or a
property checked by running the step info suggests (drift under 0.1% of the
energy of the motion, computed here from the CSV), never a number from
springpend's own output.
usage: test_info_pass.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import csv
import io
import json
import math
import os
import shutil
import sys

from sptest import done, ok, runner, sets

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "info_pass"))
scenes = os.path.join(src, "..", "scenes")
PARAMETRIC = os.path.join(scenes, "parametric.ini")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


run = runner(exe, work)


def ini(path):
    """The scene file's [section] key = value pairs, comments dropped."""
    vals, section = {}, ""
    for line in open(path):
        line = line.split("#")[0].strip()
        if line.startswith("["):
            section = line.strip("[]")
        elif "=" in line:
            k, v = (s.strip() for s in line.split("=", 1))
            vals[f"{section}.{k}"] = v
    return vals


def drift(scene, d, every):
    """Runs data; (exit status, the largest |energy - energy0 - work| over the
    energy of the motion so far: energy above hanging still at l,
    -m g L0 - (m g)^2 / 2k, the least the scene can hold)."""
    r = run("data", scene, "-o", "-", "--every", str(every), *sets(d))
    if r.returncode:
        return r.returncode, math.inf, r.stderr.strip()[:300]
    p = {**ini(scene), **{k: str(v) for k, v in d.items()}}
    m, k = float(p["pendulum.mass"]), float(p["pendulum.stiffness"])
    L0, g = float(p["pendulum.natural_length"]), float(p["pendulum.gravity"])
    e_min = -m * g * L0 - 0.5 * (m * g) ** 2 / k
    rows = list(csv.DictReader(io.StringIO(r.stdout)))
    e0, scale, worst = float(rows[0]["energy"]), 0.0, 0.0
    for row in rows:
        e, w = float(row["energy"]), float(row["work"])
        scale = max(scale, e - e_min)
        worst = max(worst, abs(e - e0 - w) / scale)
    return 0, worst, f"{len(rows)} rows"


def info(scene, d):
    r = run("info", scene, "--json", *sets(d))
    return json.loads(r.stdout) if r.returncode == 0 else {"error": r.stderr}


# ---- the close pass: driven at 7.64 Hz (10 g), flung past the pivot --------
PASS = {"pivot.amplitude": 0.176, "pivot.frequency": 7.64, "pendulum.damping": 1,
        "initial.angle": 157}
p = ini(PARAMETRIC)
L0, k, m = (float(p[f"pendulum.{key}"]) for key in ("natural_length", "stiffness", "mass"))
w_s, W = math.sqrt(k / m), 2 * math.pi * PASS["pivot.frequency"]
T = float(p["video.duration"])
for method in ("rk4", "verlet", "yoshida4"):
    d = {**PASS, "integrator.method": method}
    j = info(PARAMETRIC, d)
    if not ok("error" not in j, f"{method}: info on the close-pass scene exits 0 ({j.get('error', '')})"):
        continue
    # outside a pass, the rates are sqrt(k/m), the drive and |v|/r at r >= L0/2:
    # a few hundred rad/s here, not the 1e5 of |v|/r at r -> 0
    ok(max(w_s, W) <= j["omega_max"] < 1e3 and j["stability_limit"] > 1e-3,
       f"{method}: omega_max {j['omega_max']:.4g} rad/s lies in [max(sqrt(k/m), Omega) = "
       f"{max(w_s, W):.4g}, 1e3), stability limit {j['stability_limit']:.3g} s > 1e-3 s")
    pd, pv = j.get("pass_distance"), j.get("pass_speed")
    ok(pd is not None and pv is not None and 0 < pd < L0 / 2 and pv > 0 and T * pv / pd > 2e6,
       f"{method}: the close pass is reported: {pd} m (< L0/2 = {L0 / 2}) at {pv} m/s, which "
       f"a fixed step would follow only in {T * (pv or 0) / (pd or 1):.3g} steps (> 2e6)")
    am, ac = j.get("adaptive_method"), j.get("adaptive_checked_until")
    ok(am == "dop853" and ac == T,
       f"{method}: info names {am!r} (dop853), checked to complete over [0, {ac}] s (the "
       f"whole {T} s run)")
    # the promise, kept: what info names completes with drift under 0.1%, and so
    # does its fixed step over the span it says it checked
    rc, worst, what = drift(PARAMETRIC, {**PASS, "integrator.method": "dop853"}, 0.01)
    ok(rc == 0 and worst < 1e-3,
       f"{method}: dop853, as named, completes the {T} s run: exit {rc}, drift {worst:.2e} "
       f"(< 1e-3) ({what})")
    if j["safe_dt"] is not None:
        span = j["safe_dt_checked_until"]
        rc, worst, what = drift(PARAMETRIC, {**d, "integrator.dt": j["safe_dt"],
                                             "video.duration": span}, span / 2000)
        ok(rc == 0 and worst < 1e-3 and (span < T) == (T / j["safe_dt"] > 2e6),
           f"{method}: its fixed step {j['safe_dt']} s completes [0, {span}] s: exit {rc}, drift "
           f"{worst:.2e} (< 1e-3), checked over less than the run exactly when the run needs "
           f"over 2e6 steps ({what})")

r = run("info", PARAMETRIC, *sets(PASS))
text = r.stdout
use = [line for line in text.splitlines() if line.lstrip().startswith("use ")]
ok(r.returncode == 0 and "close pass" in text and "impractical" in text
   and use and "integrator.method = dop853" in use[0]
   and "completes with it over [0, 60] s" in use[0] and "Use integrator.dt" not in text,
   f"text: says the fixed step is impractical past the close passes and names dop853 as "
   f"completing, without offering the tiny dt first: {text[text.find('  integrator'):][:900]!r}")

# ---- scenes without close passes: a safe dt that completes them -------------
for name in sorted(os.listdir(scenes)):
    if not name.endswith(".ini"):
        continue
    scene = os.path.join(scenes, name)
    for method in ("rk4", "verlet", "yoshida4"):
        d = {"integrator.method": method}
        j = info(scene, d)
        if not ok("error" not in j and j["safe_dt"] and j.get("pass_distance") is None
                  and j.get("adaptive_method") is None,
                  f"{name} {method}: a safe dt ({j.get('safe_dt')}), no close pass left out "
                  f"({j.get('pass_distance')}), no adaptive method needed "
                  f"({j.get('adaptive_method')}) {j.get('error', '')}"):
            continue
        span = j["safe_dt_checked_until"]
        rc, worst, what = drift(scene, {**d, "integrator.dt": j["safe_dt"], "video.duration": span},
                                span / 1000)
        ok(rc == 0 and worst < 1e-3,
           f"{name} {method}: info's safe dt {j['safe_dt']} s completes [0, {span}] s with drift "
           f"{worst:.2e} (< 1e-3; omega_max {j['omega_max']:.4g} rad/s) ({what})")

done()
