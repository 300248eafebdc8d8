#include "app/process.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string_view>

namespace c2d::app {

ProcessOutcome run_process(const std::string& program, const std::vector<std::string>& args,
                           const std::string& log_path, const std::vector<std::string>& env,
                           const ProcessPlace& place) {
  ProcessOutcome out;
  // The child's environment: this process's, with the entries of `env` replacing theirs.
  std::vector<std::string> settings = env;
  std::vector<char*> envp;
  for (auto& e : settings) envp.push_back(e.data());
  for (char** e = environ; *e; ++e) {
    const std::string_view entry(*e);
    const auto name = entry.substr(0, entry.find('='));
    bool replaced = false;
    for (const auto& s : env) replaced = replaced || s.compare(0, name.size() + 1, std::string(name) + "=") == 0;
    if (!replaced) envp.push_back(*e);
  }
  envp.push_back(nullptr);
  std::vector<std::string> words{program};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  // The files are opened before the change of folder, so relative paths are this process's.
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, place.stdin_path.c_str(), O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_path.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  if (!place.work_dir.empty())
    posix_spawn_file_actions_addchdir_np(&actions, place.work_dir.c_str());
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, program.c_str(), &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) {
    out.error = program + " could not be started (" + std::strerror(rc) + ")";
    return out;
  }
  out.started = true;
  int status = 0;
  struct rusage usage {};
  pid_t waited;
  while ((waited = wait4(pid, &status, 0, &usage)) < 0 && errno == EINTR) {
  }
  if (waited != pid) {
    out.error = program + ": wait failed (" + std::strerror(errno) + ")";
    return out;
  }
  out.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  out.peak_rss_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;  // KiB on Linux
  return out;
}

}  // namespace c2d::app
