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

/// Runs `program` (a path, or a name looked up on PATH) with `args` as argv[1..], stdin from
/// /dev/null and stdout and stderr into `log_path`, and waits for it. `env` entries
/// ("NAME=value") are set in the child's environment on top of this process's.
ProcessOutcome run_process(const std::string& program, const std::vector<std::string>& args,
                           const std::string& log_path, const std::vector<std::string>& env = {});

}  // namespace c2d::app
