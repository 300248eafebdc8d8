#include "app/process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <optional>
#include <string_view>
#include <thread>

namespace c2d::app {

namespace {

// The process groups of the children running with a time limit, for the forwarding handler:
// lock-free slots (0: free), so that the handler reads them without a lock. More than --jobs'
// 1000 children at once would go unforwarded, not wrong.
constexpr size_t kGroupSlots = 1024;
std::atomic<pid_t> g_limited_groups[kGroupSlots];

size_t register_group(pid_t group) {
  for (size_t i = 0; i < kGroupSlots; ++i) {
    pid_t free = 0;
    if (g_limited_groups[i].compare_exchange_strong(free, group)) return i;
  }
  return kGroupSlots;
}

void unregister_group(size_t slot) {
  if (slot < kGroupSlots) g_limited_groups[slot].store(0);
}

extern "C" void forward_interrupt(int sig) {
  for (auto& group : g_limited_groups) {
    const pid_t g = group.load(std::memory_order_relaxed);
    if (g > 0) ::kill(-g, sig);
  }
  ::signal(sig, SIG_DFL);  // delivered when the handler returns: the default action, as before
  ::raise(sig);
}


/// Waits until the child `pid` has ended or `seconds` have passed, leaving it unreaped (a
/// zombie keeps its process group's id from being reused); true when it ended. Sleeps in poll
/// on a pidfd, so that the end is seen at once (a case's wall time is taken around this);
/// without pidfds (Linux before 5.3), in steps of 10 ms.
bool ended_within(pid_t pid, double seconds) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration<double>(seconds);
  const int pidfd = static_cast<int>(::syscall(SYS_pidfd_open, pid, 0));
  bool ended = false;
  for (;;) {
    siginfo_t info{};
    const int rc = ::waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOHANG | WNOWAIT);
    if ((rc == 0 && info.si_pid == pid) || (rc < 0 && errno != EINTR)) {
      ended = true;  // ended, or not ours to wait for: wait4 says which
      break;
    }
    const double left = std::chrono::duration<double>(deadline - Clock::now()).count();
    if (left <= 0) break;
    if (pidfd >= 0) {
      pollfd p{pidfd, POLLIN, 0};
      ::poll(&p, 1, static_cast<int>(std::ceil(1000 * std::min(left, 3600.0))));
    } else {
      std::this_thread::sleep_for(std::chrono::duration<double>(std::min(left, 0.01)));
    }
  }
  if (pidfd >= 0) ::close(pidfd);
  return ended;
}

}  // namespace

void handle_interrupts(void (*handler)(int)) {
  struct sigaction action {};
  action.sa_handler = handler;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

void forward_interrupts_to_limited_children() { handle_interrupts(forward_interrupt); }

ProcessOutcome run_process(const std::string& program, const std::vector<std::string>& args,
                           const std::string& log_path, const std::vector<std::string>& env,
                           const ProcessPlace& place, const ProcessLimit& limit) {
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
  const bool limited = limit.seconds > 0;
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  std::optional<InterruptsHeld> held;  // until the child's group is in the table
  if (limited) {
    held.emplace();
    // Its own group (id = its pid), which the limit ends as a whole; the child starts with this
    // thread's signal mask as it was, not with the interrupts held.
    posix_spawnattr_setpgroup(&attributes, 0);
    posix_spawnattr_setsigmask(&attributes, &held->saved());
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK);
  }
  pid_t pid = 0;
  const int rc =
      posix_spawnp(&pid, program.c_str(), &actions, &attributes, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  if (rc != 0) {
    out.error = program + " could not be started (" + std::strerror(rc) + ")";
    return out;
  }
  out.started = true;
  const size_t slot = limited ? register_group(pid) : kGroupSlots;
  held.reset();
  if (limited && !ended_within(pid, limit.seconds)) {
    out.timed_out = true;
    ::kill(-pid, SIGTERM);
    ended_within(pid, limit.grace_seconds);
    ::kill(-pid, SIGKILL);  // what is left of the group: the child if it ignored SIGTERM, and
                            // whatever it started
  }
  int status = 0;
  struct rusage usage {};
  pid_t waited;
  while ((waited = wait4(pid, &status, 0, &usage)) < 0 && errno == EINTR) {
  }
  const int wait_error = errno;
  unregister_group(slot);
  if (waited != pid) {
    out.error = program + ": wait failed (" + std::strerror(wait_error) + ")";
    return out;
  }
  out.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  out.peak_rss_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;  // KiB on Linux
  return out;
}

}  // namespace c2d::app
