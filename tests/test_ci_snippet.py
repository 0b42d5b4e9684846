#!/usr/bin/env python3
"""springpend tests: the README's CI snippets, run (issue 24). The GitHub
Actions job's shell steps, taken from the README, run in a fresh project
folder outside springpend's checkout, as its container would run them:
springpend is fetched at a pinned commit from a repository (a bare copy of
this one, as file://), built into a Debian package with the build
dependencies debian/control names, installed from the .deb, and the
project's snapshots are rendered and compared with its baselines. The
GitLab job must run the same commands.

Offline, as far as it goes: apt-get is a stand-in that asks the real
apt-get to simulate each call (every package named must exist and install
here; apt-get build-dep must be satisfiable; the .deb's dependencies must
resolve) and then unpacks the .deb into the test's folder instead of
installing it, putting its springpend first on PATH. `apt-get update` does
nothing. git and dpkg-buildpackage are real. This machine already has the
build's packages, so the test cannot show that the snippet's list alone
suffices on a bare container; apt-get build-dep reads that list from
debian/control, which test 'deb' checks against meson.build.

The package is built from the commit checked out (HEAD): commit first.
Skips (77) outside a git checkout, or without dpkg-buildpackage, debhelper,
git or python3-yaml. In the 'package' suite (a whole package build).
usage: test_ci_snippet.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR (TAP)"""
import os
import shutil
import subprocess
import sys

from sptest import done, ok, readme_ci

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
root = os.path.abspath(os.path.join(src, ".."))
work = os.path.abspath(os.path.join(sys.argv[3], "ci-snippet"))
try:
    import yaml
except ImportError:
    yaml = None
head = subprocess.run(["git", "-C", root, "rev-parse", "HEAD"], capture_output=True, text=True)
missing = [t for t in ("dpkg-buildpackage", "dh", "dpkg-deb", "git", "apt-get") if not shutil.which(t)]
if missing or not yaml or head.returncode:
    why = (f"not installed: {' '.join(missing)}" if missing else
           "python3-yaml is not installed" if not yaml else "not a git checkout")
    print(f"1..0 # SKIP {why}")
    sys.exit(77)
sha = head.stdout.strip()

blocks, block = readme_ci(root)
gh = yaml.safe_load(block("actions/checkout", "yaml"))
gl = yaml.safe_load(block("image: debian:12", "yaml"))
job = gh["jobs"]["snapshots"]
steps = [s["run"] for s in job["steps"] if "run" in s]
install = next((s for s in steps if "dpkg-buildpackage" in s), "")
gl_script = gl["snapshots"]["script"]
ok(install and [l for l in install.splitlines() if l.strip()] ==
   [l for l in gl_script if l in install] and
   gh["jobs"]["snapshots"]["env"].keys() <= gl["snapshots"]["variables"].keys(),
   "GitLab's job installs springpend with the same commands and variables as GitHub's")
ok(all(k in job["env"] for k in ("SPRINGPEND_GIT", "SPRINGPEND_REF", "SPRINGPEND_SRC")) and
   "meson" not in install and "apt-get install" in install and ".deb" in install,
   f"springpend comes from a pinned ref ({job['env'].get('SPRINGPEND_REF')}), as a Debian "
   "package, not built in the project's checkout")

shutil.rmtree(work, ignore_errors=True)
project, shim, unpacked = (os.path.join(work, n) for n in ("project", "shim", "root"))
for d in (project, shim, unpacked):
    os.makedirs(d)
# springpend's repository, as the job reaches it: a bare copy, by URL
bare = os.path.join(work, "springpend.git")
subprocess.run(["git", "clone", "-q", "--bare", "--no-local", root, bare], check=True)
# the project: its own scenes and the README's snapshots.sh
shutil.copytree(os.path.join(root, "scenes"), os.path.join(project, "scenes"))
with open(os.path.join(project, "snapshots.sh"), "w") as f:
    f.write(block("# snapshots.sh OUTDIR"))
log = os.path.join(work, "apt.log")
with open(os.path.join(shim, "apt-get"), "w") as f:
    f.write(r'''#!/bin/sh
# apt-get as the CI snippet calls it, offline (see test_ci_snippet.py).
echo "apt-get $*" >> "$SHIM_LOG"
verb=$1; shift
names=""; debs=""
for a; do case "$a" in -*) ;; *.deb) debs="$debs $a" ;; *) names="$names $a" ;; esac; done
case "$verb" in
update) exit 0 ;;
install)
    /usr/bin/apt-get install -s --no-install-recommends $names $debs > "$SHIM_LOG.sim" 2>&1 || exit 100
    for d in $debs; do dpkg-deb -x "$d" "$SHIM_ROOT" || exit 100; done
    [ -z "$debs" ] || ln -sf "$SHIM_ROOT/usr/bin/springpend" "$(dirname "$0")/springpend" ;;
build-dep)
    /usr/bin/apt-get build-dep -s --no-install-recommends $names > "$SHIM_LOG.sim" 2>&1 || exit 100
    for d in $names; do (cd "$d" && dpkg-checkbuilddeps) || exit 100; done ;;
*) echo "apt-get $verb: not in the test's stand-in" >&2; exit 100 ;;
esac
''')
os.chmod(os.path.join(shim, "apt-get"), 0o755)
env = dict(os.environ, **{k: str(v) for k, v in job["env"].items()})
env.update(SPRINGPEND_GIT="file://" + bare, SPRINGPEND_REF=sha,
           SPRINGPEND_SRC=os.path.join(work, "springpend-src"), SHIM_LOG=log, SHIM_ROOT=unpacked,
           GITHUB_STEP_SUMMARY=os.path.join(work, "step-summary.md"),
           PATH=shim + os.pathsep + os.environ["PATH"])
env.pop("DEB_BUILD_OPTIONS", None)


def sh(script, timeout=600):
    return subprocess.run(["sh", "-e", "-c", script], cwd=project, env=env, capture_output=True,
                          text=True, timeout=timeout)


r = sh(install, timeout=3000)
calls = open(log).read().splitlines() if os.path.exists(log) else []
prog = shutil.which("springpend", path=env["PATH"])
ok(r.returncode == 0 and prog and os.path.realpath(prog).startswith(unpacked),
   f"the install step fetches {sha[:12]}, builds the package and installs it (simulated apt, "
   f"{len(calls)} calls: {calls}) (exit {r.returncode}) {(r.stdout + r.stderr)[-800:] if r.returncode else ''}")
built = sh("git -C \"$SPRINGPEND_SRC\" rev-parse HEAD").stdout.strip()
ok(built == sha, f"the package was built from the pinned commit ({built[:12]})")
# The project's baselines, as the README's first run adds them.
first = [l for l in block("--update=missing").splitlines() if l.startswith("springpend ")]
r = sh("sh snapshots.sh actual && " + " && ".join(first))
ok(r.returncode == 0 and os.path.exists(os.path.join(project, "snapshots", "default_t3.png")),
   f"the installed springpend renders and adds the baselines ({r.stderr.strip()[-300:]})")
shutil.rmtree(os.path.join(project, "actual"))
# The job's remaining steps, as they are: render, compare, keep the reports.
rest = [s for s in steps if s != install]
results = [sh(s) for s in rest]
made = [n for n in ("report.html", "report.xml") if os.path.exists(os.path.join(project, n))]
summary = open(env["GITHUB_STEP_SUMMARY"]).read() if os.path.exists(env["GITHUB_STEP_SUMMARY"]) else ""
ok(all(x.returncode == 0 for x in results) and made == ["report.html", "report.xml"] and
   "springpend compare: ok" in summary,
   f"the job's steps pass on unchanged snapshots, with the report, JUnit and the step summary "
   f"({[x.returncode for x in results]}, {made}, {summary[:60]!r})")
# A change to what the project renders fails the same steps.
subprocess.run(["sed", "-i", "s/^stiffness *=.*/stiffness = 2.2/",
                os.path.join(project, "scenes", "default.ini")], check=True)
results = [sh(s) for s in rest]
ok(results[-1].returncode == 1 and os.path.exists(os.path.join(project, "candidates", "default_t3.png")),
   f"a stiffer spring fails the compare step and leaves a candidate ({results[-1].stdout.strip()[-200:]})")
done()
