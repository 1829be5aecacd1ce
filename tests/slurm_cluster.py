"""A real single-node Slurm cluster for tests (Debian packages slurmctld, slurmd, munge).

Everything lives under a temporary folder (keys, sockets, state, logs); the daemons run in the
foreground and are stopped by their PIDs at the end, whatever happens. Slurm's job steps look
for /etc/slurm/slurm.conf (the executor plugin strips SLURM_CONF before its nested srun), so the
generated config is also placed there for the duration, and any existing file restored.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import socket
import subprocess
import time
from collections.abc import Iterator
from pathlib import Path

DAEMONS = ("munged", "slurmctld", "slurmd", "sinfo", "sbatch", "squeue", "srun")


def missing_requirements() -> str | None:
    """Why a cluster cannot be started here (None if it can)."""
    if os.geteuid() != 0:
        return "needs root (to run slurmd and write /etc/slurm/slurm.conf)"
    absent = [d for d in DAEMONS if shutil.which(d) is None
              and not Path(f"/usr/sbin/{d}").exists()]
    if absent:
        return ("Slurm/munge not installed (missing " + ", ".join(absent)
                + "; apt-get install slurmctld slurmd slurm-client munge)")
    return None


def _which(name: str) -> str:
    return shutil.which(name) or f"/usr/sbin/{name}"


def _conf(tmp: Path, host: str, sock: Path) -> str:
    mem_mb = int(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**20 * 0.6)
    cpus = os.cpu_count() or 2
    return f"""\
ClusterName=robomilltest
SlurmctldHost={host}
SlurmUser=root
AuthType=auth/munge
AuthInfo=socket={sock}
CredType=cred/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MpiDefault=none
ReturnToService=2
MinJobAge=300
SchedulerType=sched/backfill
StateSaveLocation={tmp}/state
SlurmdSpoolDir={tmp}/spool
SlurmctldPidFile={tmp}/slurmctld.pid
SlurmdPidFile={tmp}/slurmd.pid
SlurmctldLogFile={tmp}/slurmctld.log
SlurmdLogFile={tmp}/slurmd.log
SlurmctldPort=6817
SlurmdPort=6818
NodeName={host} CPUs={cpus} RealMemory={mem_mb} State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
"""


@contextlib.contextmanager
def single_node_slurm(tmp: Path, *, timeout_s: float = 60) -> Iterator[dict[str, str]]:
    """Start munged, slurmctld and slurmd; yield the environment for clients; stop them."""
    tmp = Path(tmp)
    for d in ("state", "spool", "munge-key", "munge-sock", "munge-run"):
        (tmp / d).mkdir(parents=True, exist_ok=True)
    os.chmod(tmp / "munge-key", 0o700)
    os.chmod(tmp / "munge-sock", 0o755)
    os.chmod(tmp, 0o755)
    key = tmp / "munge-key" / "munge.key"
    key.write_bytes(os.urandom(1024))
    os.chmod(key, 0o400)
    sock = tmp / "munge-sock" / "munge.socket.2"
    host = socket.gethostname().split(".")[0]
    conf = tmp / "slurm.conf"
    conf.write_text(_conf(tmp, host, sock))
    etc = Path("/etc/slurm/slurm.conf")
    backup = etc.read_bytes() if etc.exists() else None
    etc.parent.mkdir(parents=True, exist_ok=True)
    etc.write_text(conf.read_text())
    env = {**os.environ, "SLURM_CONF": str(conf)}
    procs: list[subprocess.Popen] = []
    logs = []
    try:
        munge_log = open(tmp / "munged.out", "w")  # noqa: SIM115
        logs.append(munge_log)
        procs.append(subprocess.Popen(
            [_which("munged"), "-F", "--force", f"--key-file={key}", f"--socket={sock}",
             f"--pid-file={tmp}/munge-run/munged.pid", f"--log-file={tmp}/munged.log",
             f"--seed-file={tmp}/munge-run/munge.seed"],
            stdout=munge_log, stderr=subprocess.STDOUT))
        t0 = time.monotonic()
        while not sock.exists():
            if time.monotonic() - t0 > 15 or procs[0].poll() is not None:
                raise RuntimeError(f"munged did not start: {(tmp / 'munged.out').read_text()}")
            time.sleep(0.1)
        for daemon in ("slurmctld", "slurmd"):
            out = open(tmp / f"{daemon}.out", "w")  # noqa: SIM115
            logs.append(out)
            procs.append(subprocess.Popen([_which(daemon), "-D", "-f", str(conf)], env=env,
                                          stdout=out, stderr=subprocess.STDOUT))
        t0 = time.monotonic()
        state = ""
        while time.monotonic() - t0 < timeout_s:
            r = subprocess.run([_which("sinfo"), "-h", "-o", "%T"], env=env,
                               capture_output=True, text=True)
            state = r.stdout.strip()
            if state == "idle":
                break
            if any(p.poll() is not None for p in procs):
                break
            time.sleep(0.3)
        else:
            state = f"timeout ({state})"
        if state != "idle":
            tails = {n: (tmp / n).read_text()[-1500:] for n in
                     ("slurmctld.log", "slurmd.log", "slurmctld.out", "slurmd.out")
                     if (tmp / n).exists()}
            raise RuntimeError(f"slurm node not idle ({state}): {tails}")
        yield env
    finally:
        for p in reversed(procs):
            if p.poll() is None:
                p.terminate()
        for p in reversed(procs):
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
        for f in logs:
            f.close()
        if backup is None:
            etc.unlink(missing_ok=True)
        else:
            etc.write_bytes(backup)
