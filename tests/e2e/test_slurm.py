#!/usr/bin/env python3
"""springpend tests: a sharded sweep through a real Slurm on this machine.
Starts munged (own key and socket), slurmctld and slurmd (a generated
slurm.conf, free ports, everything in a temporary folder), runs
`sbatch --array=1-4 --wait` with one `sweep --shard I/4` per task (for
lyapunov, spectrum and basins), merges the parts and compares them with an
unsharded run, byte for byte. Every
daemon it started is stopped at the end, also on failure or a signal.
Skips (77) only when slurm-wlm or munge is not installed, or when not root
(slurmd must be).
usage: test_slurm.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

from sptest import done, ok

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
out = os.path.abspath(os.path.join(sys.argv[3], "slurm"))
scene = os.path.abspath(os.path.join(src, "..", "scenes", "chaotic.ini"))

tools = ["munged", "mungekey", "slurmctld", "slurmd", "sbatch", "sinfo"]
missing = [t for t in tools if not shutil.which(t, path=os.environ.get("PATH", "") + ":/usr/sbin:/sbin")]
if missing:
    print(f"1..0 # SKIP not installed: {' '.join(missing)} (Debian: slurm-wlm munge)")
    sys.exit(77)
if os.geteuid() != 0:
    print("1..0 # SKIP slurmd must run as root here")
    sys.exit(77)

daemons = []  # Popen objects we started, stopped in reverse order


def stop_daemons():
    for p in reversed(daemons):
        if p.poll() is None:
            p.terminate()
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
    daemons.clear()


def on_signal(sig, frame):
    stop_daemons()
    sys.exit(128 + sig)


for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
    signal.signal(s, on_signal)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def sbin(name):
    return shutil.which(name, path=os.environ.get("PATH", "") + ":/usr/sbin:/sbin")


# every measure that shards: the largest exponent, the spectrum (four copies
# a point) and basins (a damped, driven scene)
parametric = os.path.abspath(os.path.join(src, "..", "scenes", "parametric.ini"))
sweeps = {
    "lyapunov": ["sweep", scene, "--vary", "initial.angle=20:160:6", "--vary", "initial.length=0.9:1.5:4",
                 "--measure", "lyapunov", "--time", "3", "--set", "integrator.dt=0.002", "-q"],
    "spectrum": ["sweep", scene, "--vary", "initial.angle=40:90:5", "--vary", "initial.length=1:1.3:2",
                 "--measure", "spectrum", "--time", "6", "--set", "integrator.dt=0.002", "-q"],
    "basins": ["sweep", parametric, "--vary", "initial.angle=-90:90:7", "--vary",
               "initial.angle_rate=-4:4:5", "--set", "pivot.amplitude=0.01", "--measure", "basins",
               "--transient", "10", "--time", "60", "--set", "integrator.dt=0.002", "-q"],
}

shutil.rmtree(out, ignore_errors=True)
os.makedirs(out)
tmp = tempfile.mkdtemp(prefix="springpend-slurm-")
os.chmod(tmp, 0o755)
try:
    host = socket.gethostname().split(".")[0]
    key, sock = os.path.join(tmp, "munge.key"), os.path.join(tmp, "munge.socket")
    subprocess.run([sbin("mungekey"), "--create", f"--keyfile={key}"], check=True)
    daemons.append(subprocess.Popen(
        [sbin("munged"), "--foreground", "--force", f"--socket={sock}", f"--key-file={key}",
         f"--pid-file={tmp}/munged.pid", f"--log-file={tmp}/munged.log",
         f"--seed-file={tmp}/munged.seed"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
    for d in ("state", "spool"):
        os.makedirs(os.path.join(tmp, d))
    conf = os.path.join(tmp, "slurm.conf")
    with open(conf, "w") as f:
        f.write(f"""ClusterName=springpend-test
SlurmctldHost={host}(127.0.0.1)
SlurmctldPort={free_port()}
SlurmdPort={free_port()}
AuthType=auth/munge
AuthInfo=socket={sock}
CredType=cred/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SlurmUser=root
ReturnToService=2
StateSaveLocation={tmp}/state
SlurmdSpoolDir={tmp}/spool
SlurmctldPidFile={tmp}/slurmctld.pid
SlurmdPidFile={tmp}/slurmd.pid
SlurmctldLogFile={tmp}/slurmctld.log
SlurmdLogFile={tmp}/slurmd.log
JobCompType=jobcomp/none
MpiDefault=none
SchedulerType=sched/backfill
NodeName={host} NodeAddr=127.0.0.1 CPUs={os.cpu_count()} RealMemory=4000 State=UNKNOWN
PartitionName=debug Nodes={host} Default=YES MaxTime=INFINITE State=UP
""")
    env = dict(os.environ, SLURM_CONF=conf)
    time.sleep(0.5)
    daemons.append(subprocess.Popen([sbin("slurmctld"), "-D", "-f", conf], env=env,
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
    daemons.append(subprocess.Popen([sbin("slurmd"), "-D", "-f", conf], env=env,
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
    state = ""
    for _ in range(60):
        r = subprocess.run([sbin("sinfo"), "-h", "-o", "%t"], env=env, capture_output=True, text=True)
        state = r.stdout.strip()
        if state == "idle":
            break
        time.sleep(0.5)
    if not ok(state == "idle", f"slurmctld and slurmd up, the node is idle (sinfo: {state!r})"):
        for log in ("slurmctld.log", "slurmd.log", "munged.log"):
            p = os.path.join(tmp, log)
            if os.path.exists(p):
                with open(p) as f:
                    print("# " + log + ": " + " | ".join(f.read().splitlines()[-5:]))
    else:
        def read(p):
            with open(p, "rb") as f:
                return f.read()
        for name, sweep in sweeps.items():
            job = os.path.join(out, f"{name}.sh")
            with open(job, "w") as f:
                f.write("#!/bin/sh\n# one shard of the sweep per array task\n"
                        f"exec {exe} {' '.join(sweep)} --threads 1 "
                        f"--shard ${{SLURM_ARRAY_TASK_ID}}/4 --csv {out}/{name}${{SLURM_ARRAY_TASK_ID}}.csv\n")
            os.chmod(job, 0o755)
            r = subprocess.run([sbin("sbatch"), "--array=1-4", "--wait", "--chdir", out, "-o",
                                f"{out}/{name}_%a.log", job], env=env, capture_output=True, text=True,
                               timeout=180)
            parts = [os.path.join(out, f"{name}{i}.csv") for i in range(1, 5)]
            ok(r.returncode == 0 and all(os.path.exists(p) for p in parts),
               f"{name}: sbatch --array=1-4 --wait ran four shards (exit {r.returncode}) "
               f"{r.stdout.strip()} {r.stderr.strip()}")
            m = subprocess.run([exe, "sweep", "--merge", *parts, "-o", f"{out}/{name}_merged.png",
                                "--csv", f"{out}/{name}_merged.csv", "-q"], capture_output=True, text=True)
            w = subprocess.run([exe, *sweep, "-o", f"{out}/{name}_whole.png", "--csv",
                                f"{out}/{name}_whole.csv"], capture_output=True, text=True)
            ok(m.returncode == 0 and w.returncode == 0 and
               read(f"{out}/{name}_merged.csv") == read(f"{out}/{name}_whole.csv") and
               read(f"{out}/{name}_merged.png") == read(f"{out}/{name}_whole.png"),
               f"{name}: the merged job array equals the unsharded run, CSV and PNG byte for byte "
               f"{m.stderr.strip()}")
finally:
    stop_daemons()
    shutil.rmtree(tmp, ignore_errors=True)

done()
