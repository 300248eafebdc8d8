// contact2d: the command-line program (libcontact2d_cli.so, loaded and called by the
// executable, cli/launcher.cpp). Dispatch only: parse the arguments, run the verb, turn
// exceptions into exit codes (DESIGN §5).
#include <signal.h>

#include <iostream>
#include <string>
#include <string_view>

#include "app/cli/help.hpp"
#include "app/cli/options.hpp"
#include "app/cli/verbs.hpp"
#include "app/run/run_output.hpp"
#include "core/errors.hpp"
#include "core/writers.hpp"

using namespace c2d;

namespace {

int dispatch(const app::Options& o) {
  if (o.verb.empty() || o.verb == "--help" || o.verb == "-h" || o.verb == "help") {
    std::cout << app::main_help();
    return o.verb.empty() ? app::kExitBadInput : app::kExitOk;
  }
  const char* help = app::verb_help(o.verb);
  if (!help)
    throw InputError(
        o.verb +
        ": unknown verb; expected run, mesh, info, compare, sweep, calibrate, bench, merge, trace "
        "or plot (see --help)");
  if (o.help) {
    std::cout << help;
    return app::kExitOk;
  }
  if (o.verb == "bench") return app::cmd_bench(o);
  if (o.scene.empty())
    throw InputError(o.verb + ": expected " +
                     (o.verb == "trace" || o.verb == "plot" ? "an output folder"
                      : o.verb == "merge"                   ? "a study folder"
                                                            : "a scene file") +
                     ", found none");
  if (o.verb == "run") return app::cmd_run(o);
  if (o.verb == "trace") return app::cmd_trace(o);
  if (o.verb == "plot") return app::cmd_plot(o);
  if (o.verb == "compare") return app::cmd_compare(o);
  if (o.verb == "sweep") return app::cmd_sweep(o);
  if (o.verb == "calibrate") return app::cmd_calibrate(o);
  if (o.verb == "merge") return app::cmd_merge(o);
  if (o.verb == "mesh") return app::cmd_mesh(o);
  return app::cmd_info(o);
}

}  // namespace

/// Called by the launcher with SIGINT and SIGTERM held since before this library was loaded;
/// `caller_mask` is the mask to restore (null: nothing held).
extern "C" __attribute__((visibility("default"))) int contact2d_main(int argc, char** argv,
                                                                    const sigset_t* caller_mask) {
  // First thing: the run verb's handler, then the interrupts are let through. One that came
  // while the libraries loaded reaches the handler now: exit 130 and its line, no folder yet.
  // (The other verbs keep the default action, or install their own when they start.)
  if (argc > 1 && std::string_view(argv[1]) == "run") app::install_interrupt_handler();
  if (caller_mask) sigprocmask(SIG_SETMASK, caller_mask, nullptr);
  try {
    return dispatch(app::parse_args(argc, argv));
  } catch (const InputError& e) {
    std::cerr << "error: " << e.what() << '\n';
    return app::kExitBadInput;
  } catch (const core::WriteError& e) {
    std::cerr << "error: " << e.what() << '\n';
    return app::kExitWriteFailed;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << '\n';
    return app::kExitSolveFailed;
  }
}
