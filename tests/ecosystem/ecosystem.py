"""What the ecosystem tests share (tests/ecosystem, issue 35): daemons started in the
foreground and stopped by the pid recorded at their start, free ports, bounded waits, a study
run by contact2d itself and the same study written as a job list, and the check that a merged
table is the in-process one.

Every external program is started with an argument list, never through a shell line built
from data. A failure raises TestFailure with the logs that explain it; nothing is skipped.
"""
import csv
import ctypes
import datetime
import json
import math
import os
import pathlib
import signal
import socket
import sys
import subprocess
import time

# Numbers of a merged table against the in-process table. The same program on the same inputs
# in another process agrees to round-off, not bit for bit (a penalty case's p_max differed by
# 8e-14 relative, its Hertz fit's b by 1e-11), and the table prints 8 digits: a relative 1e-9
# is equality for every printed number. Values below ABS_TOL (an exact method's penetration,
# 1e-18) count as zero. The error_* columns are x / reference - 1, whose round-off is absolute
# (a fit's 1e-11 in b is 1e-11 in error_fit_b, 4e-8 of its 2.8e-4): compared to ERROR_ABS_TOL,
# which is x to a relative 1e-9.
REL_TOL = 1e-9
ABS_TOL = 1e-15
ERROR_ABS_TOL = 1e-9
# p_max as each case's summary.json holds it (17 digits), in-process against the job list's.
P_MAX_REL_TOL = 1e-12
# Columns measured by different processes at different times: never compared.
TIME_COLUMNS = ("wall",)


class TestFailure(Exception):
    """The test failed; the message says why and carries the logs that show it."""


def utc_now():
    return datetime.datetime.now(datetime.timezone.utc).strftime("%H:%M:%S.%f")[:-3]


def log_tail(path, lines=60):
    path = pathlib.Path(path)
    if not path.exists():
        return f"--- {path}: not written\n"
    text = path.read_text(errors="replace").splitlines()[-lines:]
    return f"--- {path} (last {len(text)} lines)\n" + "\n".join(text) + "\n"


def fail(message, logs=()):
    raise TestFailure(message + "\n" + "".join(log_tail(p) for p in logs))


def raise_on_termination():
    """SIGTERM and SIGHUP (CTest, a closed terminal) end the test through its `finally`
    blocks, as Ctrl-C does, so that the daemons are stopped."""
    def handler(signum, _frame):
        raise TestFailure(f"interrupted by signal {signum}")
    for s in (signal.SIGTERM, signal.SIGHUP):
        signal.signal(s, handler)


def free_port():
    """A TCP port free on every address now (the daemon binds it a moment later)."""
    with socket.socket() as s:
        s.bind(("", 0))
        return s.getsockname()[1]


def _die_with_parent():
    # In the daemon, before exec: SIGTERM when this test process dies, even by SIGKILL, so a
    # daemon never outlives its test (prctl(PR_SET_PDEATHSIG, SIGTERM)).
    ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGTERM)


class Daemon:
    """A daemon run in the foreground as this process's child: its pid is the daemon's."""

    def __init__(self, name, argv, log, env=None):
        self.name, self.log = name, pathlib.Path(log)
        try:
            with open(self.log, "ab") as out:
                self.process = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=out,
                                                stderr=subprocess.STDOUT, env=env,
                                                preexec_fn=_die_with_parent)
        except FileNotFoundError as e:
            fail(f"{name}: {argv[0]} is not installed ({e}); scripts/bootstrap.sh installs it")
        self.pid = self.process.pid
        self.started = time.monotonic()
        print(f"{utc_now()} started {name} (pid {self.pid}, log {self.log})", flush=True)

    def running(self):
        return self.process.poll() is None

    def stop(self, grace=15):
        """SIGTERM to the recorded pid, SIGKILL after `grace` seconds; waits for the end."""
        if self.running():
            os.kill(self.pid, signal.SIGTERM)
            try:
                self.process.wait(grace)
            except subprocess.TimeoutExpired:
                os.kill(self.pid, signal.SIGKILL)
                self.process.wait()
        print(f"{utc_now()} stopped {self.name} (pid {self.pid}, exit {self.process.returncode},"
              f" up {time.monotonic() - self.started:.1f} s)", flush=True)


def stop_all(daemons):
    """Stops every daemon, the last started first, even when one of them fails to stop."""
    errors = []
    for d in reversed(daemons):
        try:
            d.stop()
        except Exception as e:  # noqa: BLE001 - the others must still be stopped
            errors.append(f"{d.name} (pid {d.pid}): {e}")
    if errors:
        raise TestFailure("could not stop " + "; ".join(errors))


def become_subreaper():
    """Orphans among this process's descendants (a daemon's detached helpers, such as
    slurmstepd) become its children instead of init's (prctl(PR_SET_CHILD_SUBREAPER)), so
    that end_descendants() sees, stops and reaps them."""
    if ctypes.CDLL("libc.so.6", use_errno=True).prctl(36, 1) != 0:
        fail(f"prctl(PR_SET_CHILD_SUBREAPER): {os.strerror(ctypes.get_errno())}")


def descendants():
    """(pid, state) of every process below this one, from /proc."""
    children = {}
    for entry in pathlib.Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        fields = stat[stat.rindex(")") + 2:].split()  # after "pid (comm) "
        children.setdefault(int(fields[1]), []).append((int(entry.name), fields[0]))
    found, todo = [], [os.getpid()]
    while todo:
        for pid, state in children.get(todo.pop(), []):
            found.append((pid, state))
            todo.append(pid)
    return found


def end_descendants(grace=10):
    """Ends whatever this test started that still runs once its daemons are stopped (a job,
    a slurmstepd): SIGTERM to each pid, SIGKILL after `grace` s; then reaps them. Returns the
    pids that were still running."""
    running = [pid for pid, state in descendants() if state != "Z"]
    for sig in (signal.SIGTERM, signal.SIGKILL):
        for pid in running:
            try:
                os.kill(pid, sig)
            except ProcessLookupError:
                pass
        deadline = time.monotonic() + grace
        while time.monotonic() < deadline and any(s != "Z" for _, s in descendants()):
            time.sleep(0.1)
    while True:
        try:
            if os.waitpid(-1, os.WNOHANG) == (0, 0):
                break
        except ChildProcessError:
            break
    return running


def stop_then_end_leftovers(stop, what):
    """Calls `stop` (the test's daemons), then ends whatever still runs below this process,
    whatever `stop` did; fails naming what outlived `what`."""
    try:
        stop()
    finally:
        leftovers = end_descendants()
    if leftovers:
        fail(f"processes still running after {what} stopped (now ended): {leftovers}")


def merge_and_report(study, route, route_s, cases, in_process_s):
    """Merges the study's case folders, checks the table against the in-process one and prints
    the times."""
    study.merge()
    merged = study.check_merged_table()
    print(f"in-process study {in_process_s:.1f} s, through {route} {route_s:.1f} s "
          f"({cases} cases, {len(merged[1])} rows merged and equal)")


def script_main(main, doc):
    """A test script's entry: main(binary, source_dir); exit 1 with FAILED on a TestFailure."""
    if len(sys.argv) != 3:
        sys.exit(doc)
    try:
        main(sys.argv[1], sys.argv[2])
    except TestFailure as e:
        print(f"FAILED: {e}", file=sys.stderr)
        sys.exit(1)
    print("PASSED")


def wait_for(condition, seconds, what, logs=()):
    """Polls `condition` until it holds; fails after `seconds` naming `what`, with the logs
    (`logs` may be a function that lists them then, for logs written while waiting)."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if condition():
            return
        time.sleep(0.2)
    fail(f"{what}: not within {seconds} s", logs() if callable(logs) else logs)


def run(argv, what, timeout, logs=(), **kwargs):
    """Runs a program to its end (within `timeout` seconds); fails unless it exits 0."""
    try:
        p = subprocess.run(argv, capture_output=True, text=True, timeout=timeout, **kwargs)
    except FileNotFoundError as e:
        fail(f"{what}: {argv[0]} is not installed ({e}); scripts/bootstrap.sh installs it", logs)
    except subprocess.TimeoutExpired as e:
        fail(f"{what}: still running after {timeout} s\n{e.stdout or ''}{e.stderr or ''}", logs)
    if p.returncode != 0:
        fail(f"{what}: exit {p.returncode}: {' '.join(map(str, argv))}\n{p.stdout}{p.stderr}", logs)
    return p.stdout


class Study:
    """A study of `args` (verb, scene, options) run by contact2d in-process into
    root/in_process and written as a job list into root/study."""

    def __init__(self, binary, root, args):
        # Each case within a minute (about 1 s each here): a case that hangs ends, in-process
        # and in the job list's slurm.sh alike.
        self.binary, self.args = binary, [*args, "--case-timeout", "60"]
        self.in_process = pathlib.Path(root) / "in_process"
        self.dir = pathlib.Path(root) / "study"
        self.table = {"compare": "compare.csv", "sweep": "sweep.csv"}[args[0]]

    def run_in_process(self):
        """Runs the study in this process's way; returns its wall time in seconds."""
        t0 = time.monotonic()
        run([self.binary, *self.args, "--quiet", "--out", str(self.in_process)],
            "the in-process study", timeout=180)
        return time.monotonic() - t0

    def write_job_list(self, extra=()):
        """Writes jobs.txt, slurm.sh and study.json (with `extra` options); returns the jobs."""
        run([self.binary, *self.args, *extra, "--job-list", "--quiet", "--out", str(self.dir)],
            "the job list", timeout=120)
        jobs = (self.dir / "jobs.txt").read_text().splitlines()
        if not jobs:
            fail(f"{self.dir / 'jobs.txt'}: no jobs")
        return jobs

    def merge(self):
        run([self.binary, "merge", str(self.dir), "--quiet"], "contact2d merge", timeout=120)

    def case_folders(self):
        manifest = json.loads((self.dir / "study.json").read_text())
        return [c["folder"] for c in manifest["cases"]]

    def baseline_folders(self):
        manifest = json.loads((self.dir / "study.json").read_text())
        return [c["folder"] for c in manifest["cases"] if "baseline" in c]

    def check_merged_table(self):
        """The merged table is the in-process one (see REL_TOL), every row converged, and each
        case's p_max is the in-process case's (P_MAX_REL_TOL)."""
        reference = read_table(self.in_process / self.table)
        merged = read_table(self.dir / self.table)
        folders = self.case_folders()
        # A sweep's baseline case (lagrange on the same mesh) is in its verdict, not a row.
        rows = len(folders) - len(self.baseline_folders())
        if len(reference[1]) != rows:
            fail(f"{self.table}: {len(reference[1])} in-process rows for {rows} cases")
        require_comparison_can_fail(reference)
        differences = table_differences(reference, merged)
        if differences:
            fail(f"merged {self.table} differs from the in-process study's:\n" +
                 "\n".join(differences[:20]))
        for row in merged[1]:
            if row["status"] != "converged":
                fail(f"merged {self.table}: a row says {row['status']!r}: {row}")
        for folder in folders:
            a, b = p_max(self.in_process / folder), p_max(self.dir / folder)
            if not math.isclose(a, b, rel_tol=P_MAX_REL_TOL, abs_tol=0):
                fail(f"{folder}: p_max {b!r} through the job list, {a!r} in-process")
        return merged


def read_table(path):
    """(columns, rows as dicts) of a study's CSV table."""
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        return list(reader.fieldnames or []), list(reader)


def p_max(case_folder):
    return json.loads((case_folder / "summary.json").read_text())["contact"]["p_max"]


def cells_agree(column, a, b):
    try:
        x, y = float(a), float(b)
    except ValueError:
        return a == b
    if math.isnan(x) or math.isnan(y):
        return a == b
    if column.startswith("error_"):
        return abs(x - y) <= ERROR_ABS_TOL
    return math.isclose(x, y, rel_tol=REL_TOL, abs_tol=ABS_TOL)


def table_differences(reference, other):
    """What differs between two tables of one study, times aside: one sentence per cell."""
    (columns, rows), (other_columns, other_rows) = reference, other
    if columns != other_columns:
        return [f"columns {other_columns} instead of {columns}"]
    if len(rows) != len(other_rows):
        return [f"{len(other_rows)} rows instead of {len(rows)}"]
    out = []
    for i, (r, o) in enumerate(zip(rows, other_rows)):
        for c in columns:
            if c.startswith("time_") or c in TIME_COLUMNS:
                continue
            if not cells_agree(c, r[c], o[c]):
                out.append(f"row {i} {c}: {o[c]!r} instead of {r[c]!r}")
    return out


def require_comparison_can_fail(reference):
    """The comparison itself, on a copy of the reference with p_max off by a relative 1e-7,
    an error_* column by 1e-8 and a status changed, must see all three (a comparison that
    passes everything proves nothing)."""
    columns, rows = reference
    error_column = next(c for c in columns if c.startswith("error_"))
    altered = [dict(r) for r in rows]
    altered[0]["p_max"] = repr(float(altered[0]["p_max"]) * (1 + 1e-7))
    altered[0][error_column] = repr(float(altered[0][error_column]) + 1e-8)
    altered[-1]["status"] = "failed: altered"
    found = table_differences(reference, (columns, altered))
    if len(found) != 3:
        fail(f"the table comparison does not see a changed p_max, {error_column} and status: "
             f"{found}")
