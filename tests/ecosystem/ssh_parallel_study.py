"""A study's jobs.txt run by GNU parallel over ssh, for real (issue 35, item 2): an sshd on a
free loopback port, started and stopped by this test, is the only host of a
`parallel --sshloginfile` run of a `contact2d sweep --job-list` study, as README's "Other
machines over ssh" says; `contact2d merge` must then write the table of the same study run
in-process.

Everything lives in a temporary folder under $TMPDIR: a throwaway host key and user key, the
sshd_config (this port, loopback only, public key only, that key alone authorised), the
client's ssh_config and known_hosts, and the sshloginfile. The configs and keys in ~/.ssh and
/etc/ssh are neither used nor changed. sshd runs in the foreground as this script's child and
is stopped by its recorded pid whatever happens.

Every job goes through ssh, not the local shell: each one writes the SSH_CONNECTION its shell
was given, which must name this sshd's port and a client port for which sshd logged a session.

Usage (CTest: Ecosystem.SshParallelStudy): ssh_parallel_study.py CONTACT2D SCENE
Needs Debian's openssh-server, openssh-client and parallel (scripts/bootstrap.sh). When sshd
does not start the test fails with its log.
"""
import os
import pathlib
import pwd
import re
import sys
import tempfile
import time

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from ecosystem import (Daemon, Study, become_subreaper,  # noqa: E402
                       fail, free_port, merge_and_report, raise_on_termination, run,
                       script_main, stop_all, stop_then_end_leftovers, utc_now, wait_for)

SSHD = "/usr/sbin/sshd"  # sshd refuses to start by a relative path
# sshd's privilege separation directory (Debian's build: /run/sshd), which its init script
# or systemd unit makes at boot; a chroot or container has neither. Made if missing, mode 0755
# as the package makes it, and left in place (it is the system's, not this test's).
PRIVSEP_DIR = pathlib.Path("/run/sshd")
HOST_ALIAS = "c2d-test-sshd"
SLOTS = 2  # jobs at a time on that host
PARALLEL_DEADLINE_S = 240
STUDY = ["--method", "penalty", "--set", "contact.penalty.k=1e6:1e10:log:5"]
# parallel's command for each line of jobs.txt: record the job's SSH_CONNECTION in the study
# folder (the job's working directory) under its sequence number, then run the line as it is
# ({=uq=}: the input line unquoted, so the remote shell runs exactly jobs.txt's line). A
# constant: no data is put into it.
JOB_TEMPLATE = 'printenv SSH_CONNECTION > ssh_connection.{#}; {=uq=}'


class Sshd:
    """An sshd for this test alone, and the client files that reach it."""

    def __init__(self, root):
        self.root = root
        self.port = free_port()
        self.user = pwd.getpwuid(os.getuid()).pw_name
        self.log = root / "sshd.log"
        self.daemon = None

    def write_keys_and_config(self):
        r = self.root
        for key in ("host_key", "user_key"):
            run(["ssh-keygen", "-q", "-t", "ed25519", "-N", "", "-C", f"c2d test {key}",
                 "-f", str(r / key)], "ssh-keygen", timeout=30)
        (r / "authorized_keys").write_text((r / "user_key.pub").read_text())
        # StrictModes no: authorized_keys lies in the build tree, whose parent folders' modes
        # this test does not control (sshd would refuse a group-writable one).
        (r / "sshd_config").write_text(f"""\
Port {self.port}
ListenAddress 127.0.0.1
HostKey {r}/host_key
PidFile {r}/sshd.pid
AuthorizedKeysFile {r}/authorized_keys
PubkeyAuthentication yes
PasswordAuthentication no
KbdInteractiveAuthentication no
PermitRootLogin prohibit-password
AllowUsers {self.user}
UsePAM no
StrictModes no
LogLevel VERBOSE
""")
        algorithm, public = (r / "host_key.pub").read_text().split()[:2]
        (r / "known_hosts").write_text(f"[127.0.0.1]:{self.port} {algorithm} {public}\n")
        (r / "ssh_config").write_text(f"""\
Host {HOST_ALIAS}
  HostName 127.0.0.1
  Port {self.port}
  User {self.user}
  IdentityFile {r}/user_key
  IdentitiesOnly yes
  UserKnownHostsFile {r}/known_hosts
  GlobalKnownHostsFile /dev/null
  StrictHostKeyChecking yes
  BatchMode yes
  ConnectTimeout 20
""")

    def start(self):
        self.write_keys_and_config()
        if not PRIVSEP_DIR.is_dir():
            PRIVSEP_DIR.mkdir(mode=0o755, parents=True)
            print(f"made sshd's privilege separation directory {PRIVSEP_DIR} (it was missing)")
        config = str(self.root / "sshd_config")
        run([SSHD, "-t", "-f", config], "sshd -t (the config's check)", timeout=30)
        self.daemon = Daemon("sshd", [SSHD, "-D", "-e", "-f", config], self.log)
        listening = f"Server listening on 127.0.0.1 port {self.port}"
        wait_for(lambda: listening in self.log.read_text() or not self.daemon.running(), 20,
                 f"sshd listening on port {self.port}", [self.log])
        if not self.daemon.running():
            fail(f"sshd ended (exit {self.daemon.process.returncode})", [self.log])
        whoami = run(["ssh", "-F", str(self.root / "ssh_config"), HOST_ALIAS, "echo",
                      "$SSH_CONNECTION"], "ssh to the test's sshd", timeout=60, logs=[self.log])
        if f" 127.0.0.1 {self.port}" not in whoami:
            fail(f"ssh reached something else than the test's sshd: {whoami!r}", [self.log])

    def sshlogin(self):
        """The sshloginfile line: SLOTS jobs at a time through ssh with this test's config.
        parallel splits the line at spaces, so the folder must have none."""
        config = self.root / "ssh_config"
        if re.search(r"\s", str(config)):
            fail(f"{config}: a path with a space cannot go into an sshloginfile line; set "
                 f"TMPDIR to a folder without one")
        return f"{SLOTS}/ssh -F {config} {HOST_ALIAS}"

    def stop(self):
        if self.daemon:
            stop_all([self.daemon])


def run_jobs(sshd, study, jobs):
    """The job list through parallel's ssh logins (README: `parallel --sshloginfile hosts.txt
    --workdir DIR < jobs.txt`), each job also recording its SSH_CONNECTION. Returns the
    joblog's rows and the seconds it took."""
    logins = sshd.root / "sshlogins.txt"
    logins.write_text(sshd.sshlogin() + "\n")
    joblog = sshd.root / "joblog.tsv"
    env = {k: v for k, v in os.environ.items() if k not in ("SSH_CONNECTION", "SSH_CLIENT")}
    t0 = time.monotonic()
    with open(study.dir / "jobs.txt") as stdin:
        run(["parallel", "--sshloginfile", str(logins), "--workdir", str(study.dir),
             "--joblog", str(joblog), "--timeout", "120", JOB_TEMPLATE],
            "parallel over ssh", timeout=PARALLEL_DEADLINE_S, logs=[sshd.log, joblog],
            stdin=stdin, cwd=study.dir, env=env)
    seconds = time.monotonic() - t0
    print(f"{utc_now()} parallel ran {len(jobs)} jobs in {seconds:.1f} s", flush=True)
    header, *rows = [line.split("\t") for line in joblog.read_text().splitlines()]
    return [dict(zip(header, row)) for row in rows], seconds


def check_every_job_went_through_ssh(sshd, study, jobs, joblog):
    """Each job's shell was started by this sshd: its SSH_CONNECTION names the sshd's port,
    and sshd logged a session from its client port; parallel's log agrees, every exit 0."""
    if len(joblog) != len(jobs):
        fail(f"parallel's joblog has {len(joblog)} jobs for {len(jobs)} lines", [sshd.log])
    sessions = set(re.findall(rf"Starting session: command for {sshd.user} from 127\.0\.0\.1 "
                              r"port (\d+)", sshd.log.read_text()))
    clients = set()
    for k in range(1, len(jobs) + 1):
        record = study.dir / f"ssh_connection.{k}"
        words = record.read_text().split() if record.exists() else []
        if len(words) != 4 or words[3] != str(sshd.port) or words[1] not in sessions:
            fail(f"job {k} did not run through the test's sshd (port {sshd.port}): its "
                 f"SSH_CONNECTION is {' '.join(words)!r}; sshd's sessions came from ports "
                 f"{sorted(sessions)}", [sshd.log])
        clients.add(words[1])
    if len(clients) != len(jobs):
        fail(f"{len(jobs)} jobs came through {len(clients)} ssh connections", [sshd.log])
    for row in joblog:
        if row["Exitval"] != "0" or row["Signal"] != "0" or HOST_ALIAS not in row["Host"]:
            fail(f"parallel's joblog: {row}", [sshd.log])


def main(binary, scene):
    raise_on_termination()
    become_subreaper()
    root = pathlib.Path(tempfile.mkdtemp(prefix="c2d_ssh_", dir=os.environ.get("TMPDIR")))
    study = Study(binary, root, ["sweep", scene, *STUDY])
    sshd = Sshd(root)
    try:
        in_process_s = study.run_in_process()
        jobs = study.write_job_list()
        sshd.start()
        joblog, ssh_s = run_jobs(sshd, study, jobs)
        check_every_job_went_through_ssh(sshd, study, jobs, joblog)
    finally:
        stop_then_end_leftovers(sshd.stop, "sshd")
    merge_and_report(study, "ssh", ssh_s, len(jobs), in_process_s)


if __name__ == "__main__":
    script_main(main, __doc__)
