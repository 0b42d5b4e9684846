#!/usr/bin/env python3
"""springpend: plants small, plausible bugs one at a time in a scratch copy of
the tree and reports which ones the test suite catches (run by hand, not in
CI; never commits anything). Each bug is an exact text edit of one source
file (off-by-one, wrong unit, swapped order, dropped flag or check, an option
parsed and ignored); the copy is rebuilt and the tests named for that bug run
(or the whole suite with --all-tests), stopping at the first failing test.
A bug is CAUGHT when a test fails, MISSED when all pass, BROKEN when the
planted tree does not build (a bad bug, not counted).

usage: tests/plant_bugs.py [--list] [--bug NAME]... [--all-tests] [--tests T,...]
                           [--scratch DIR] [--keep-going]
  --list         the bugs, their module and the tests each runs
  --bug NAME     only that bug (repeatable; a prefix of a name works)
  --all-tests    run the whole suite for each bug instead of its tests
  --tests T,...  run these meson tests for every bug instead
  --scratch DIR  where the copy and its build live (default /tmp/springpend-plant);
                 kept between runs, so later runs rebuild only what changed
  --keep-going   run every chosen test instead of stopping at the first failure
  --fresh        wipe the scratch build first (after main's meson.build changed:
                 a kept build once lacked the symbols a new module needed)
The copy is made from the working tree of the repository that holds this
script (tracked and untracked files git does not ignore). Needs meson, ninja.
Build and test jobs: -j2 (SP_PLANT_JOBS to change)."""
import argparse
import filecmp
import os
import re
import shutil
import subprocess
import sys
import time

# name, module, file, old text, new text, tests that should catch it
BUGS = [
    ("angle-rate-in-degrees", "scene", "src/scene/scene.c",
     '{"initial", "angle_rate", KEY_REAL,', '{"initial", "angle_rate", KEY_DEGREES,',
     "keys,scene,numbers"),
    ("frame-count-truncated", "scene", "src/scene/scene.c",
     "return (int)lround(s->video.duration * s->video.fps / s->video.speed);",
     "return (int)(s->video.duration * s->video.fps / s->video.speed);",
     "keys,timing,scene,sink,output"),
    ("mass-default", "scene", "src/scene/scene.c",
     '{"pendulum", "mass", KEY_REAL, F(pendulum.mass), 0.50,',
     '{"pendulum", "mass", KEY_REAL, F(pendulum.mass), 0.55,',
     "scene,numbers,golden,keys"),
    ("drive-hz-as-rad", "sim", "src/sim/sim.c",
     ".drive_omega = 2 * M_PI * scene->pivot.frequency,",
     ".drive_omega = scene->pivot.frequency,",
     "keys,numbers,guard-drive,sim"),
    ("damping-relative-to-pivot", "sim", "src/sim/sim.c",
     "d[3] -= p->b_over_m * (u[3] + vp);", "d[3] -= p->b_over_m * u[3];",
     "keys,numbers,sim"),
    ("omega-pendulum-uses-L0", "sim", "src/sim/sim.c",
     "out->omega_p = sqrt(p->g / out->ell);", "out->omega_p = sqrt(p->g / p->L0);",
     "numbers,sim,info-pass"),
    ("part-without-o-excl", "base", "src/base/outfile.c",
     "O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOCTTY, 0666);",
     "O_WRONLY | O_CREAT | O_CLOEXEC | O_NOCTTY, 0666);",
     "formats,safety,output"),
    ("crlf-counts-two-lines", "base", "src/base/ini_lines.c",
     "len += start[len] == '\\r' && start[len + 1] == '\\n' ? 2 : start[len] ? 1 : 0;",
     "len += start[len] ? 1 : 0;",
     "formats,scene,safety,validation"),
    ("second-signal-exit-128", "base", "src/base/signals.c",
     "_exit(128 + sig);", "_exit(128);", "safety,output,seams"),
    ("time-base-whole-fps", "sinks", "src/sinks/sink_video.c",
     "AVRational rate = av_d2q(d->fps, 1001000);", "AVRational rate = {(int)lround(d->fps), 1};",
     "timing,sink,output"),
    ("gif-halves-at-50-fps", "sinks", "src/sinks/sink_gif.c",
     "while (fps / step > GIF_MAX_FPS)", "while (fps / step >= GIF_MAX_FPS)",
     "timing,output,sink"),
    ("png-numbers-from-zero", "sinks", "src/sinks/sink_png.c",
     "j->number = s->desc.first_frame + s->frames;", "j->number = s->frames;",
     "output,cli,sink,options"),
    ("shard-skips-first-frame", "pipeline", "src/pipeline/pipeline.c",
     "*first = (int)((long)n_frames * i / n);", "*first = (int)((long)n_frames * i / n) + (i > 0);",
     "output,sink,cli"),
    ("trail-duration-one-short", "pipeline", "src/pipeline/pipeline.c",
     "? (int)fmin(ceil(sc->view.trail_duration / frame_dt * slow) + 1, n + 1)",
     "? (int)fmin(ceil(sc->view.trail_duration / frame_dt * slow), n + 1)",
     "keys,trails"),
    ("sweep-second-axis-fastest", "sweep", "src/sweep/sweep.c",
     "    for (int a = 0; a < SP_SWEEP_MAX_AXES; a++) {\n        int n = a < d->n_axes",
     "    for (int a = SP_SWEEP_MAX_AXES - 1; a >= 0; a--) {\n        int n = a < d->n_axes",
     "formats,sweep"),
    ("lyapunov-half-over-T", "sweep", "src/sweep/sweep.c",
     "half[i] = sum[i] / (k * tau);", "half[i] = sum[i] / (K * tau);",
     "formats,sweep"),
    ("batch-pivot-skips-last-lane", "sweep", "src/sim/batch.c",
     "    for (int l = 0; l < B; l++) {\n        if (p->amp[l] == 0) {",
     "    for (int l = 0; l < B - 1; l++) {\n        if (p->amp[l] == 0) {",
     "batch,sweep,ensemble"),
    ("merge-takes-next-shards-point", "sweep", "src/sweep/sweep_merge.c",
     "struct sp_sweep_rows r = {.d = d, .first = first, .last = last, .point = -1};",
     "struct sp_sweep_rows r = {.d = d, .first = first, .last = last + 1, .point = -1};",
     "formats,seams,sweep,attack6-fixes"),
    ("still-scale-ignored", "cli", "src/cli/cli_render.c",
     ".supersample = o.still.scale,", ".supersample = 1,",
     "options,cli,figures"),
    ("quality-medium-25-fps", "cli", "src/cli/cli.c",
     '{"medium", 1280, 720, 30}', '{"medium", 1280, 720, 25}',
     "options,cli,cli-numbers"),
    ("every-one-row-short", "frame", "src/frame/data_export.c",
     "n = (long)floor(sc->video.duration / every * (1 + 1e-12)) + 1;",
     "n = (long)floor(sc->video.duration / every * (1 + 1e-12));",
     "options,numbers,cli"),
    ("compare-max-diff-plus-one", "compare", "src/compare/image_compare.c",
     ": m > res->max_diff ? 2 : m > 0;", ": m > res->max_diff + 1 ? 2 : m > 0;",
     "compare,compare-ci,options"),
    ("compare-allowed-rounded-up", "compare", "src/compare/image_compare.c",
     "res->allowed = (long)floor(", "res->allowed = (long)ceil(",
     "compare,compare-ci,options"),
    ("mask-misses-last-column", "compare", "src/compare/image_compare.c",
     "x1 = x1 > expected->width ? expected->width : x1;",
     "x1 = x1 > expected->width ? expected->width - 1 : x1;",
     "options,compare,compare-ci"),
    ("bob-radius-4pc-larger", "frame", "src/frame/compose.c",
     "#define BOB_RADIUS 0.022f", "#define BOB_RADIUS 0.0229f",
     "golden,render,figures"),
    ("ensemble-spread-over-n", "frame", "src/frame/ensemble.c",
     "scene->ensemble.spread * ((double)i / (n - 1) - 0.5);",
     "scene->ensemble.spread * ((double)i / n - 0.5);",
     "keys,ensemble"),
    ("cairo-ball-darker", "render", "src/render/draw_cairo.c",
     "{{0, 1.0}, {0.45, 0.95}, {0.85, 0.62}, {1, 0.38}}",
     "{{0, 1.0}, {0.45, 0.85}, {0.85, 0.62}, {1, 0.38}}",
     "vector-golden,figures,seams"),
]

JOBS = os.environ.get("SP_PLANT_JOBS", "2")


def sh(cmd, cwd=None, quiet=True):
    return subprocess.run(cmd, cwd=cwd, capture_output=quiet, text=True)


def make_copy(repo, scratch):
    """scratch/src: the working tree's files (git's list), each copied when it
    differs, so that a later run rebuilds only what changed; a fresh build
    folder the first time."""
    src = os.path.join(scratch, "src")
    files = sh(["git", "ls-files", "-co", "--exclude-standard", "-z"], cwd=repo).stdout
    for rel in filter(None, files.split("\0")):
        a, b = os.path.join(repo, rel), os.path.join(src, rel)
        if os.path.islink(a) or not os.path.isfile(a):
            continue
        if not os.path.exists(b) or not filecmp.cmp(a, b, shallow=False):
            os.makedirs(os.path.dirname(b), exist_ok=True)
            shutil.copy2(a, b)
    build = os.path.join(scratch, "build")
    if not os.path.exists(os.path.join(build, "build.ninja")):
        r = sh(["meson", "setup", build, src])
        if r.returncode:
            sys.exit(f"plant_bugs: meson setup failed:\n{r.stdout[-2000:]}{r.stderr[-2000:]}")
    return src, build


def build(build_dir):
    r = sh(["ninja", "-C", build_dir, f"-j{JOBS}"])
    return r.returncode == 0, (r.stdout + r.stderr)[-1500:]


def run_tests(build_dir, tests, keep_going):
    """Runs the named meson tests; returns (names that failed, seconds)."""
    # --maxfail kills the tests still running beside the one that failed, and
    # a test killed half-way can leave what it set up (test_output's tmpfs
    # mount stayed, and failed every later run): one test at a time then.
    cmd = ["meson", "test", "-C", build_dir, "--no-rebuild", "--print-errorlogs",
           f"--num-processes={JOBS if keep_going else 1}"]
    if not keep_going:
        cmd.append("--maxfail=1")
    t0 = time.time()
    r = sh(cmd + tests)
    failed = list(dict.fromkeys(re.findall(r"^\s*\d+/\d+\s+(\S+)\s+(?:FAIL|TIMEOUT|ERROR)",
                                           r.stdout, re.M)))
    if r.returncode and not failed:
        failed = ["(meson test exit %d)" % r.returncode]
    log = os.path.join(build_dir, "meson-logs", "testlog.txt")
    check = ""
    if failed and os.path.exists(log):
        m = re.search(r"^not ok \d+ - (.*)$", open(log, errors="replace").read(), re.M)
        check = m.group(1)[:110] if m else "(no 'not ok' line: crashed or timed out?)"
    return failed, time.time() - t0, check


def main():
    head, rest = __doc__.split("\nusage:", 1)
    ap = argparse.ArgumentParser(description=head,
                                 epilog=rest.split("\nThe copy is made", 1)[1].join(
                                     ["The copy is made", ""]),
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--list", action="store_true",
                    help="the bugs, their module and the tests each runs")
    ap.add_argument("--bug", action="append", default=[], metavar="NAME",
                    help="only that bug (repeatable; a prefix of a name works)")
    ap.add_argument("--all-tests", action="store_true",
                    help="run the whole suite for each bug instead of its tests")
    ap.add_argument("--tests", metavar="T,...",
                    help="run these meson tests for every bug instead")
    ap.add_argument("--scratch", default="/tmp/springpend-plant", metavar="DIR",
                    help="where the copy and its build live (default %(default)s; "
                         "kept between runs, so later runs rebuild only what changed)")
    ap.add_argument("--keep-going", action="store_true",
                    help="run every chosen test instead of stopping at the first failure")
    ap.add_argument("--fresh", action="store_true",
                    help="wipe the scratch build first (after main's meson.build changed)")
    a = ap.parse_args()
    bugs = [b for b in BUGS if not a.bug or any(b[0].startswith(n) for n in a.bug)]
    if a.list:
        for name, module, path, _, _, tests in BUGS:
            print(f"{name:32} {module:9} {path:30} {tests}")
        print(f"{len(BUGS)} bugs in {len({b[1] for b in BUGS})} modules")
        return 0
    if not bugs:
        sys.exit("plant_bugs: no bug of that name (see --list)")
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    if a.fresh:
        shutil.rmtree(os.path.join(a.scratch, "build"), ignore_errors=True)
    src, bdir = make_copy(repo, a.scratch)
    ok, log = build(bdir)
    if not ok:
        sys.exit(f"plant_bugs: the unplanted copy does not build:\n{log}")
    known = set(sh(["meson", "test", "-C", bdir, "--no-rebuild", "--list"]).stdout.split())
    # the unplanted copy must pass what will be run, or a bug would be
    # "caught" by a test that fails anyway
    wanted = [] if a.all_tests else sorted({t for b in bugs for t in (a.tests or b[5]).split(",")
                                            if t in known})
    failed, secs, check = run_tests(bdir, wanted, True)
    print(f"baseline (unplanted): {', '.join(wanted) or 'all tests'}: "
          f"{'failed ' + ', '.join(failed) + ': ' + check if failed else 'pass'} ({secs:.0f} s)",
          flush=True)
    if failed:
        sys.exit("plant_bugs: the unplanted copy fails these tests; fix them first")
    results = []
    for name, module, path, old, new, tests in bugs:
        tests = [] if a.all_tests else [t for t in (a.tests or tests).split(",") if t in known]
        target = os.path.join(src, path)
        text = open(target).read()
        if text.count(old) != 1:
            results.append((name, module, "STALE", f"the text to change is found {text.count(old)} times"))
            print(f"{name}: STALE (the text to change is found {text.count(old)} times in {path})", flush=True)
            continue
        try:
            with open(target, "w") as f:
                f.write(text.replace(old, new))
            ok, log = build(bdir)
            if not ok:
                results.append((name, module, "BROKEN", log.strip().split("\n")[-1]))
            else:
                failed, secs, check = run_tests(bdir, tests, a.keep_going)
                results.append((name, module, "CAUGHT" if failed else "MISSED",
                                f"by {', '.join(failed)}: {check}" if failed else
                                f"ran {', '.join(tests) or 'all tests'}") + (secs,))
        finally:
            with open(target, "w") as f:
                f.write(text)
        r = results[-1]
        print(f"{name}: {r[2]} {r[3]}" + (f" ({r[4]:.0f} s)" if len(r) > 4 else ""), flush=True)
    build(bdir)  # leave the copy's build unplanted
    counted = [r for r in results if r[2] in ("CAUGHT", "MISSED")]
    caught = sum(r[2] == "CAUGHT" for r in counted)
    print(f"\n{'bug':32} {'module':9} result")
    for r in results:
        print(f"{r[0]:32} {r[1]:9} {r[2]} {r[3]}")
    if counted:
        print(f"\ncaught {caught} of {len(counted)} ({100 * caught / len(counted):.0f}%) in "
              f"{len({r[1] for r in counted})} modules")
    return 0 if caught == len(counted) else 1


if __name__ == "__main__":
    sys.exit(main())
