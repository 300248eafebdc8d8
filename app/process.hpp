// Child processes without a shell: an argument vector, never a command line built from data.
#pragma once

#include <string>
#include <vector>

namespace c2d::app {

/// How a child process ended.
struct ProcessOutcome {
  bool started = false;    ///< false: the program could not be started (see `error`)
  int exit_code = -1;      ///< the exit status, or 128 + the signal that ended it
  double peak_rss_mb = 0;  ///< the child's peak resident set (MiB)
  std::string error;       ///< why it could not be started or waited for; empty otherwise
};

/// Where a child reads its input and runs (defaults: /dev/null, this process's folder).
struct ProcessPlace {
  std::string stdin_path = "/dev/null";
  std::string work_dir;  ///< empty: this process's working directory
};

/// Runs `program` (a path, or a name looked up on PATH) with `args` as argv[1..], stdin from
/// `place.stdin_path` and stdout and stderr into `log_path`, in `place.work_dir`, and waits for it
/// (a relative `log_path` or `stdin_path` is taken from this process's folder, a relative
/// `program` path from `work_dir`). `env`
/// entries ("NAME=value") are set in the child's environment on top of this process's.
ProcessOutcome run_process(const std::string& program, const std::vector<std::string>& args,
                           const std::string& log_path, const std::vector<std::string>& env = {},
                           const ProcessPlace& place = {});

}  // namespace c2d::app
