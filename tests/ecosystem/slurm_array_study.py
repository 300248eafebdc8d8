"""A study's slurm.sh through a real Slurm (issue 35, item 1): a one-node cluster on this
machine, started and stopped by this test, runs a `contact2d compare --job-list` study as an
sbatch array; `contact2d merge` must then write the table of the same study run in-process.

The cluster lives in a temporary folder under $TMPDIR: its own munge key and socket (munged),
a slurm.conf naming this host as controller and compute node on two free ports, and the
state, spool, pid and log files of slurmctld and slurmd. The system's Slurm and munge setup
(/etc/slurm, /etc/munge, /run/munge) is neither used nor changed, and no systemd is needed: every
daemon runs in the foreground as this script's child and is stopped by its recorded pid
whatever happens (a job still queued is cancelled first).

The study asks the cluster for what slurm.sh carries: --slurm-partition (the test cluster has
no default partition, so a missing line is refused), --slurm-time, --slurm-mem and
--slurm-cpus-per-task; each array task's record in slurmctld must show them.

Usage (CTest: Ecosystem.SlurmArrayStudy): slurm_array_study.py CONTACT2D SCENE
Needs root (slurmd starts each job as its user) and Debian's slurmctld, slurmd, slurm-client
and munge (scripts/bootstrap.sh). A daemon that does not start fails the test with its log.
"""
import os
import pathlib
import socket
import sys
import tempfile
import time

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from ecosystem import (Daemon, Study, TestFailure, become_subreaper,  # noqa: E402
                       fail, free_port, merge_and_report, raise_on_termination, run,
                       script_main, stop_all, stop_then_end_leftovers, utc_now, wait_for)

PARTITION = "c2dtest"
TASK_MEM_MB = 512        # --slurm-mem: two tasks side by side on the node's 1024 MB
TASK_TIME_MIN = 10       # --slurm-time (the partition allows 15)
ARRAY_DEADLINE_S = 180   # the whole array, queued to finished (about 10 s on 2 idle cores)
STUDY = ["--levels", "2", "--methods", "penalty,lagrange,ssn"]


class Cluster:
    """munged, slurmctld and slurmd configured in `root`, and the environment of their
    clients (SLURM_CONF set, any SLURM_* of an enclosing job removed)."""

    def __init__(self, root):
        self.root = root
        self.host = socket.gethostname().split(".")[0]
        self.daemons = []
        self.job = None  # the array job's id, once submitted
        for d in ("munge", "run", "state", "spool", "log"):
            (root / d).mkdir()
        (root / "munge").chmod(0o700)  # munged refuses a key or seed others can read
        self.socket = root / "run" / "munge.socket"
        self.conf = root / "slurm.conf"
        self.env = {k: v for k, v in os.environ.items() if not k.startswith("SLURM_")}
        self.env["SLURM_CONF"] = str(self.conf)
        # (munged in the foreground logs to its stderr, munged.out, not to its --log-file)
        self.logs = [root / "log" / n for n in ("munged.out", "slurmctld.log", "slurmd.log")]

    def write_config(self):
        r = self.root
        cpus = os.cpu_count() or 1
        (r / "plugstack.conf").write_text("")  # not the system's /etc/slurm/plugstack.conf
        self.conf.write_text(f"""\
ClusterName=c2dtest
SlurmctldHost={self.host}(127.0.0.1)
SlurmctldPort={free_port()}
SlurmdPort={free_port()}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket={self.socket}
StateSaveLocation={r}/state
SlurmdSpoolDir={r}/spool
SlurmctldPidFile={r}/run/slurmctld.pid
SlurmdPidFile={r}/run/slurmd.pid
SlurmctldLogFile={r}/log/slurmctld.log
SlurmdLogFile={r}/log/slurmd.log
PlugStackConfig={r}/plugstack.conf
MailProg=/bin/true
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU_Memory
SchedulerType=sched/builtin
MpiDefault=none
SwitchType=switch/none
ReturnToService=2
MinJobAge=600
NodeName={self.host} NodeAddr=127.0.0.1 CPUs={cpus} RealMemory={2 * TASK_MEM_MB} State=UNKNOWN
PartitionName={PARTITION} Nodes={self.host} Default=NO MaxTime=15 State=UP
""")

    def start(self):
        r = self.root
        run(["mungekey", "--create", "--keyfile", str(r / "munge" / "munge.key")],
            "mungekey", timeout=30)
        self.write_config()
        self.daemons.append(Daemon("munged", [
            "munged", "--foreground", "--socket", str(self.socket),
            "--key-file", str(r / "munge" / "munge.key"), "--seed-file", str(r / "munge" / "seed"),
            "--pid-file", str(r / "run" / "munged.pid"),
            "--log-file", str(r / "log" / "munged.log")],
            r / "log" / "munged.out"))
        wait_for(lambda: self.socket.exists() or not self.daemons[0].running(), 15,
                 "munged's socket", self.logs[:1])
        self.require_running(self.daemons[0])
        self.daemons.append(Daemon("slurmctld", ["slurmctld", "-D", "-i", "-f", str(self.conf)],
                                   r / "log" / "slurmctld.out", self.env))
        wait_for(lambda: self.answers(["scontrol", "ping"], "UP"), 30,
                 "slurmctld answering scontrol ping", self.logs)
        self.daemons.append(Daemon("slurmd", ["slurmd", "-D", "-f", str(self.conf),
                                              "-N", self.host],
                                   r / "log" / "slurmd.out", self.env))
        wait_for(lambda: self.answers(["sinfo", "-h", "-p", PARTITION, "-o", "%t"], "idle"), 40,
                 f"node {self.host} idle in partition {PARTITION}", self.logs)

    def answers(self, argv, word):
        for d in self.daemons:
            self.require_running(d)
        try:
            return word in run(argv, argv[0], timeout=20, env=self.env)
        except TestFailure:
            return False

    def require_running(self, daemon):
        if not daemon.running():
            fail(f"{daemon.name} ended (exit {daemon.process.returncode}) while the test needs "
                 f"it", [daemon.log, *self.logs])

    def array_done(self, job):
        for d in self.daemons:
            self.require_running(d)
        return not self.queued(job)

    def queued(self, job):
        out = run(["squeue", "-h", "-j", job, "-o", "%i %T"], "squeue", timeout=30, env=self.env)
        return out.split("\n") if out.strip() else []

    def task_records(self, job):
        """slurmctld's record of each array task: a dict of its `scontrol -o show job` fields."""
        out = run(["scontrol", "-o", "show", "job", job], "scontrol show job", timeout=30,
                  env=self.env)
        records = []
        for line in out.splitlines():
            fields = dict(w.split("=", 1) for w in line.split() if "=" in w)
            if fields.get("ArrayTaskId"):
                records.append(fields)
        return records

    def stop(self):
        """Cancels the array if it is still queued or running, then stops every daemon."""
        job = self.job
        try:
            if job and self.daemons and all(d.running() for d in self.daemons) and self.queued(job):
                run(["scancel", job], "scancel", timeout=30, env=self.env)
                wait_for(lambda: not self.queued(job), 30, f"job {job} cancelled", self.logs)
        finally:
            stop_all(self.daemons)


def task_logs(cluster, study):
    """The daemons' logs and each task's output (slurm.sh's --output)."""
    return [*cluster.logs, *sorted(study.dir.glob("slurm-*.out"))]


def check_tasks(records, cases, job, logs):
    """Every task of the array completed, with what slurm.sh asked for."""
    if len(records) != cases:
        fail(f"job {job}: {len(records)} array tasks known to slurmctld, {cases} expected", logs)
    wanted = {"JobState": "COMPLETED", "ExitCode": "0:0", "Partition": PARTITION,
              "TimeLimit": f"00:{TASK_TIME_MIN:02d}:00", "MinMemoryNode": f"{TASK_MEM_MB}M",
              "CPUs/Task": "1"}
    for r in records:
        for key, value in wanted.items():
            if r.get(key) != value:
                fail(f"job {job} task {r.get('ArrayTaskId')}: {key}={r.get(key)}, expected "
                     f"{value}: {r}", logs)
    ids = sorted(int(r["ArrayTaskId"]) for r in records)
    if ids != list(range(1, cases + 1)):
        fail(f"job {job}: array tasks {ids}, expected 1..{cases}", logs)


def run_array(cluster, study, cases):
    """sbatch slurm.sh from the study folder, as README says; waits for the array to end.
    Returns the job id and the seconds from submission to the end of the last task."""
    t0 = time.monotonic()
    job = run(["sbatch", "--parsable", "slurm.sh"], "sbatch slurm.sh", timeout=60,
              logs=cluster.logs, cwd=study.dir, env=cluster.env).strip().split(";")[0]
    print(f"{utc_now()} submitted job {job} ({cases} array tasks)", flush=True)
    cluster.job = job
    wait_for(lambda: cluster.array_done(job), ARRAY_DEADLINE_S,
             f"job {job}'s {cases} tasks finished",
             lambda: task_logs(cluster, study))
    seconds = time.monotonic() - t0
    print(f"{utc_now()} job {job} finished: {seconds:.1f} s from sbatch", flush=True)
    return job, seconds


def main(binary, scene):
    raise_on_termination()
    become_subreaper()
    if os.geteuid() != 0:
        fail("this test starts slurmd, which needs root to start jobs; run it as root")
    root = pathlib.Path(tempfile.mkdtemp(prefix="c2d_slurm_", dir=os.environ.get("TMPDIR")))
    # munged's socket must be reachable by everyone along its whole path (it checks), and
    # mkdtemp makes this folder owner-only: traversable, still not listable by others.
    root.chmod(0o711)
    study = Study(binary, root, ["compare", scene, *STUDY])
    cluster = Cluster(root)
    try:
        in_process_s = study.run_in_process()
        cases = len(study.write_job_list(["--slurm-partition", PARTITION,
                                          "--slurm-time", str(TASK_TIME_MIN),
                                          "--slurm-mem", f"{TASK_MEM_MB}M",
                                          "--slurm-cpus-per-task", "1"]))
        cluster.start()
        job, slurm_s = run_array(cluster, study, cases)
        check_tasks(cluster.task_records(job), cases, job, task_logs(cluster, study))
    finally:
        stop_then_end_leftovers(cluster.stop, "the cluster")
    merge_and_report(study, "Slurm", slurm_s, cases, in_process_s)


if __name__ == "__main__":
    script_main(main, __doc__)
