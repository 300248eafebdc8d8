// Child processes without a shell: an argument vector, never a command line built from data.
#pragma once

#include <pthread.h>

#include <csignal>
#include <string>
#include <vector>

namespace c2d::app {

/// How a child process ended.
struct ProcessOutcome {
  bool started = false;    ///< false: the program could not be started (see `error`)
  int exit_code = -1;      ///< the exit status, or 128 + the signal that ended it
  double peak_rss_mb = 0;  ///< the child's peak resident set (MiB)
  bool timed_out = false;  ///< it outlived its ProcessLimit and was stopped
  std::string error;       ///< why it could not be started or waited for; empty otherwise
};

/// Where a child reads its input and runs (defaults: /dev/null, this process's folder).
struct ProcessPlace {
  std::string stdin_path = "/dev/null";
  std::string work_dir;  ///< empty: this process's working directory
};

/// How long a child may run. With `seconds` > 0 the child leads a process group of its own;
/// when it is still running after `seconds`, the group is sent SIGTERM (a `contact2d run`
/// writes its "interrupted" summary and ends), and `grace_seconds` later, or as soon as the
/// child has ended, SIGKILL, so that nothing the child started outlives it.
struct ProcessLimit {
  double seconds = 0;  ///< 0: no limit (the child stays in this process's group)
  double grace_seconds = 5;
};

/// Runs `program` (a path, or a name looked up on PATH) with `args` as argv[1..], stdin from
/// `place.stdin_path` and stdout and stderr into `log_path`, in `place.work_dir`, and waits for it
/// (a relative `log_path` or `stdin_path` is taken from this process's folder, a relative
/// `program` path from `work_dir`). `env`
/// entries ("NAME=value") are set in the child's environment on top of this process's.
/// Thread-safe: study workers run one child each.
/// SIGINT and SIGTERM held back on this thread while the object lives (their dispositions
/// untouched; a signal that comes meanwhile is delivered at the end): a child is in the table
/// of groups before an interrupt can look for it, a run folder's renames are not cut in half.
class InterruptsHeld {
 public:
  InterruptsHeld() {
    sigset_t held;
    sigemptyset(&held);
    sigaddset(&held, SIGINT);
    sigaddset(&held, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &held, &saved_);
  }
  ~InterruptsHeld() { pthread_sigmask(SIG_SETMASK, &saved_, nullptr); }
  InterruptsHeld(const InterruptsHeld&) = delete;
  InterruptsHeld& operator=(const InterruptsHeld&) = delete;
  const sigset_t& saved() const { return saved_; }

 private:
  sigset_t saved_;
};

ProcessOutcome run_process(const std::string& program, const std::vector<std::string>& args,
                           const std::string& log_path, const std::vector<std::string>& env = {},
                           const ProcessPlace& place = {}, const ProcessLimit& limit = {});

/// A child with a time limit leads its own process group, which a terminal's Ctrl-C (sent to
/// the terminal's foreground group) no longer reaches. After this call, SIGINT and SIGTERM sent
/// to this process are passed on to the groups of the children running with a limit, and then
/// end this process as they would have (default action). It sets this process's signal
/// dispositions, so programs call it (the CLI's study verbs), never a library.
void forward_interrupts_to_limited_children();

/// Installs `handler` for SIGINT and SIGTERM (for programs only, as above).
void handle_interrupts(void (*handler)(int));

}  // namespace c2d::app
