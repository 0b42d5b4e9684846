#!/usr/bin/env python3
"""springpend tests: the CI page's snippets (doc/ci.md), run (issue 24). The
GitHub Actions job's shell steps, taken from doc/ci.md, run as its debian:12
container would run them: in a bare Debian 12 (bookworm, debootstrap's
minbase variant) under chroot, in a fresh project folder, with exactly the
packages the snippet installs, from Debian's mirror. springpend is fetched at
a pinned commit from a repository (a bare copy of this one, as file://),
its build dependencies installed by `apt-get build-dep` from debian/control,
built by dpkg-buildpackage into a Debian package, installed from the .deb
with what it depends on, and the project's snapshots are rendered and
compared with its baselines. The GitLab job must run the same commands.

Needs the network (Debian's mirror, deb.debian.org): without it the test
FAILS, saying so. The bare system is cached as a tarball in
OUTPUT_DIR/ci-snippet-cache (delete it to bootstrap afresh), and so are the
.debs apt downloads; the chroot itself (about 2 GB) stays in
OUTPUT_DIR/ci-snippet until the next run. Each step runs in its own mount namespace (unshare),
which takes its /proc, /dev/pts and /dev/shm mounts away when it ends.
The package is built from the commit checked out (HEAD): commit first.
Skips (77) when not root (chroot), outside a git checkout, or without git or
python3-yaml; fails without debootstrap (.ci/run installs it).
In the 'package' suite (a whole package build).
usage: test_ci_snippet.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR (TAP)"""
import os
import shlex
import shutil
import subprocess
import sys
import time
import urllib.request

from sptest import diag, done, ok, readme_ci

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
root = os.path.abspath(os.path.join(src, ".."))
work = os.path.abspath(os.path.join(sys.argv[3], "ci-snippet"))
cache = os.path.abspath(os.path.join(sys.argv[3], "ci-snippet-cache"))
MIRROR = "http://deb.debian.org/debian"
try:
    import yaml
except ImportError:
    yaml = None
head = subprocess.run(["git", "-C", root, "rev-parse", "HEAD"], capture_output=True, text=True)
if os.geteuid() != 0 or not shutil.which("git") or not yaml or head.returncode:
    why = ("not root: the bare Debian runs under chroot" if os.geteuid() != 0 else
           "git is not installed" if not shutil.which("git") else
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
ok(job.get("container") == "debian:12" and gl["snapshots"].get("image") == "debian:12",
   "both jobs run in debian:12, which this test bootstraps (bookworm)")

# Debian's mirror, or a clear failure: the test is about what a bare
# system needs, which only the real archive can tell.
try:
    urllib.request.urlopen(MIRROR + "/dists/bookworm/InRelease", timeout=30).read(64)
    net = None
except OSError as e:
    net = e
if not ok(net is None, f"Debian's mirror is reachable ({MIRROR}: {net or 'ok'})"):
    print(f"Bail out! this test needs the network: it installs the snippet's packages into a "
          f"bare Debian 12 from {MIRROR}, which answered: {net}")
    sys.exit(1)
if not ok(shutil.which("debootstrap"), "debootstrap is installed (.ci/run's install line)"):
    print("Bail out! debootstrap is not installed: apt-get install debootstrap")
    sys.exit(1)

# The bare system: debootstrap's minbase (what debian:12 holds), made once
# and kept as a tarball.
timing = {}
t0 = time.monotonic()
os.makedirs(os.path.join(cache, "archives", "partial"), exist_ok=True)
base = os.path.join(cache, "bookworm-minbase.tar")
if not os.path.exists(base):
    fresh = os.path.join(cache, "bootstrap")
    shutil.rmtree(fresh, ignore_errors=True)
    r = subprocess.run(["debootstrap", "--variant=minbase", "bookworm", fresh, MIRROR],
                       capture_output=True, text=True, timeout=1800)
    if not ok(r.returncode == 0, f"debootstrap --variant=minbase bookworm (exit {r.returncode}) "
              f"{r.stdout[-400:] + r.stderr[-400:] if r.returncode else ''}"):
        done()
    subprocess.run(["tar", "--numeric-owner", "-C", fresh, "-cf", base + ".part", "."], check=True)
    os.rename(base + ".part", base)
    shutil.rmtree(fresh)
shutil.rmtree(work, ignore_errors=True)
chroot = os.path.join(work, "root")
os.makedirs(chroot)
subprocess.run(["tar", "--numeric-owner", "-C", chroot, "-xpf", base], check=True)
timing["bare system"] = time.monotonic() - t0
bare_packages = set(subprocess.run(["chroot", chroot, "dpkg-query", "-W", "-f", "${Package}\\n"],
                                   capture_output=True, text=True).stdout.split())
# as the debian:12 image has them: the release, its updates and security
with open(os.path.join(chroot, "etc/apt/sources.list"), "w") as f:
    f.write(f"deb {MIRROR} bookworm main\ndeb {MIRROR} bookworm-updates main\n"
            "deb http://deb.debian.org/debian-security bookworm-security main\n")
shutil.copy("/etc/resolv.conf", os.path.join(chroot, "etc/resolv.conf"))
ok("springpend" not in bare_packages and "git" not in bare_packages and
   "libosmesa6" not in bare_packages and not os.path.exists(os.path.join(chroot, "usr/bin/springpend")),
   f"the bare system has {len(bare_packages)} packages: no git, no OSMesa, no springpend")

# springpend's repository, as the job reaches it (a bare copy, by URL), and
# the project: its own scenes and doc/ci.md's snapshots.sh, in a folder of
# its own.
inside = "/builds/project"
project = chroot + inside
subprocess.run(["git", "clone", "-q", "--bare", "--no-local", root,
                os.path.join(chroot, "srv/springpend.git")], check=True)
shutil.copytree(os.path.join(root, "scenes"), os.path.join(project, "scenes"))
with open(os.path.join(project, "snapshots.sh"), "w") as f:
    f.write(block("# snapshots.sh OUTDIR"))
env = {"PATH": "/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin", "HOME": "/root",
       "LANG": "C.UTF-8", "CI": "true",
       **{k: str(v) for k, v in job["env"].items()},
       "SPRINGPEND_GIT": "file:///srv/springpend.git", "SPRINGPEND_REF": sha,
       "GITHUB_STEP_SUMMARY": "/github/step-summary.md"}
os.makedirs(os.path.join(chroot, "github"))
# A step: sh -e in the project folder, as the runner runs a `run:` block,
# in a mount namespace of its own with /proc, /dev/pts and /dev/shm, and the
# download cache over /var/cache/apt/archives.
MOUNT = ('R=$1; mount -t proc proc "$R/proc" && mount -t tmpfs tmpfs "$R/dev/shm" && '
         'mount -t devpts -o newinstance,ptmxmode=0666 devpts "$R/dev/pts" && '
         'mount --bind "$2" "$R/var/cache/apt/archives" && shift 2 && exec chroot "$R" "$@"')


def sh(script, timeout=600):
    cmd = ["unshare", "--mount", "--pid", "--fork", "--kill-child", "sh", "-c", MOUNT, "step",
           chroot, os.path.join(cache, "archives"), "/usr/bin/env", "-i",
           *[f"{k}={v}" for k, v in env.items()], "sh", "-e", "-c",
           f"cd {shlex.quote(inside)}\n{script}"]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout,
                          stdin=subprocess.DEVNULL)


t0 = time.monotonic()
r = sh(install, timeout=3000)
timing["install step"] = time.monotonic() - t0
history = open(os.path.join(chroot, "var/log/apt/history.log")).read() \
    if os.path.exists(os.path.join(chroot, "var/log/apt/history.log")) else ""
calls = [l.split(": ", 1)[1] for l in history.splitlines() if l.startswith("Commandline: ")]
ok(r.returncode == 0, f"the install step, as doc/ci.md prints it, on the bare system (exit "
   f"{r.returncode}) {(r.stdout + r.stderr)[-1200:] if r.returncode else ''}")
ok([c.split()[:2] for c in calls] == [["apt-get", "install"], ["apt-get", "build-dep"],
                                     ["apt-get", "install"]]
   and calls[-1].endswith(".deb"),
   f"apt installed only what the snippet asked for: {calls}")
dpkg = sh("dpkg-query -W -f '${Status} ${Version}\\n' springpend && command -v springpend && "
          "git -C \"$SPRINGPEND_SRC\" rev-parse HEAD")
lines = dpkg.stdout.split()
ok(dpkg.returncode == 0 and "installed" in lines and "/usr/bin/springpend" in lines and
   lines[-1] == sha,
   f"springpend is the installed package's /usr/bin/springpend, built from the pinned commit "
   f"{sha[:12]} ({dpkg.stdout.strip()} {dpkg.stderr.strip()[-200:]})")
# The project's baselines, as doc/ci.md's first run adds them.
first = [l for l in block("--update=missing").splitlines() if l.startswith("springpend ")]
r = sh("sh snapshots.sh actual && " + " && ".join(first))
ok(r.returncode == 0 and os.path.exists(os.path.join(project, "snapshots", "default_t3.png")),
   f"the installed springpend renders and adds the baselines ({r.stderr.strip()[-300:]})")
shutil.rmtree(os.path.join(project, "actual"), ignore_errors=True)
# The job's remaining steps, as they are: render, compare, keep the reports.
rest = [s for s in steps if s != install]
t0 = time.monotonic()
results = [sh(s) for s in rest]
timing["render and compare steps"] = time.monotonic() - t0
made = [n for n in ("report.html", "report.xml") if os.path.exists(os.path.join(project, n))]
summary_path = chroot + env["GITHUB_STEP_SUMMARY"]
summary = open(summary_path).read() if os.path.exists(summary_path) else ""
ok(all(x.returncode == 0 for x in results) and made == ["report.html", "report.xml"] and
   "springpend compare: ok" in summary,
   f"the job's steps pass on unchanged snapshots, with the report, JUnit and the step summary "
   f"({[x.returncode for x in results]}, {made}, {summary[:60]!r}) "
   f"{' '.join((x.stdout + x.stderr)[-300:] for x in results if x.returncode)}")
# A change to what the project renders fails the same steps.
subprocess.run(["sed", "-i", "s/^stiffness *=.*/stiffness = 2.2/",
                os.path.join(project, "scenes", "default.ini")], check=True)
results = [sh(s) for s in rest]
ok(results[-1].returncode == 1 and os.path.exists(os.path.join(project, "candidates", "default_t3.png")),
   f"a stiffer spring fails the compare step and leaves a candidate ({results[-1].stdout.strip()[-200:]})")
diag("seconds: " + ", ".join(f"{k} {v:.0f}" for k, v in timing.items()))
done()  # the chroot (2 GB) stays for a look; the next run removes it first
