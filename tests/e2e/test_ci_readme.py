#!/usr/bin/env python3
"""springpend tests: the CI page (doc/ci.md) as a CI engineer uses it
(issue 24). Its GitHub Actions and GitLab CI snippets parse as YAML, give
the JUnit reporter `checks: write`, and install springpend as a Debian
package built from a pinned ref of its repository, outside the project's
checkout (test ci-snippet runs those steps). Then the walkthrough's shell
steps, taken from doc/ci.md, run in a fresh folder outside springpend's
checkout: render, add the baselines, a change fails with candidates and a
summary, the candidates are approved, the next run passes.
usage: test_ci_readme.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR (TAP)"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

from sptest import done, ok, readme_ci, skip

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
root = os.path.join(src, "..")
blocks, block = readme_ci(root)


# ---- the YAML snippets ----
try:
    import yaml
except ImportError:
    yaml = None
gh, gl = block("actions/checkout", "yaml"), block("image: debian:12", "yaml")
if yaml:
    g, l = yaml.safe_load(gh), yaml.safe_load(gl)
    ok(g.get("permissions", {}).get("checks") == "write",
       f"GitHub: permissions checks: write for the JUnit reporter ({g.get('permissions')})")
    gh_run = "\n".join(s.get("run", "") for s in g["jobs"]["snapshots"]["steps"])
    gl_run = "\n".join(l["snapshots"]["script"])
else:
    skip("the GitHub snippet's permissions", "python3-yaml is not installed")
    gh_run, gl_run = gh, gl
# springpend as a user installs it: a Debian package, here built from a
# pinned ref of its repository outside the project's checkout (test
# ci-snippet, in the 'package' suite, runs these steps).
for name, text in (("GitHub", gh_run), ("GitLab", gl_run)):
    ok('fetch -q --depth 1 "$SPRINGPEND_GIT" "$SPRINGPEND_REF"' in text and
       'apt-get build-dep -y --no-install-recommends "$SPRINGPEND_SRC"' in text and
       "dpkg-buildpackage -b" in text and re.search(r"apt-get install .*springpend_\*\.deb", text)
       and "meson" not in text,
       f"{name}: springpend is fetched at SPRINGPEND_REF, built into a Debian package with "
       "debian/control's build dependencies, and installed from the .deb; nothing is built "
       "in the project's checkout")
ok(all(f"{k}:" in t for k in ("SPRINGPEND_GIT", "SPRINGPEND_REF", "SPRINGPEND_SRC") for t in (gh, gl))
   and "/tmp/" in block("actions/checkout", "yaml"),
   "both snippets name the repository, the pinned ref and a source folder outside the checkout")

# ---- the walkthrough's shell steps, in a fresh folder outside the checkout ----
with tempfile.TemporaryDirectory(prefix="springpend-ci-") as d:
    os.makedirs(os.path.join(d, "bin"))
    os.symlink(exe, os.path.join(d, "bin", "springpend"))
    shutil.copytree(os.path.join(root, "scenes"), os.path.join(d, "scenes"))
    with open(os.path.join(d, "snapshots.sh"), "w") as f:
        f.write(block("# snapshots.sh OUTDIR"))
    env = dict(os.environ, PATH=os.path.join(d, "bin") + os.pathsep + os.environ["PATH"])

    def sh(cmd):
        return subprocess.run(cmd, shell=True, cwd=d, env=env, capture_output=True, text=True,
                              timeout=300)

    def step(marker):
        return next((l for l in block(marker, "sh").splitlines()
                     if marker in l and l.startswith("springpend ")), "")

    first = [l for l in block("--update=missing").splitlines() if not l.startswith("git ")]
    r = sh("sh snapshots.sh actual && " + " && ".join(first))
    ok(r.returncode == 0 and os.path.exists(os.path.join(d, "snapshots", "default_t3.png")),
       f"render and add the baselines as doc/ci.md says ({r.stderr.strip()[-200:]})")
    # A change meant to alter a picture: the same snapshot, stiffer.
    sh("springpend still scenes/default.ini --at 3 --size 640x360 --set pendulum.stiffness=2.2 "
       "-o actual/default_t3.png -q")
    review = step("--candidates candidates")
    r = sh(review)
    summary = open(os.path.join(d, "summary.md")).read() if os.path.exists(
        os.path.join(d, "summary.md")) else ""
    ok(review and r.returncode == 1 and os.path.exists(os.path.join(d, "candidates",
                                                                    "default_t3.png"))
       and "default\\_t3.png | fail" in summary and "pendulum.stiffness" in r.stdout,
       f"the review step fails with a candidate, a summary and the changed key: {review!r} "
       f"exit {r.returncode}")
    approve = step("--approve candidates")
    r = sh(approve)
    r2 = sh("springpend compare snapshots actual")
    ok(approve and r.returncode == 0 and r2.returncode == 0,
       f"{approve!r} approves it and the next run passes ({r2.stdout.strip()[-100:]})")

done()
