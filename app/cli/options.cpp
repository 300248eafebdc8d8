#include "app/cli/options.hpp"

#include <cstdlib>
#include <regex>
#include <sstream>

#include "constraints/method_registry.hpp"
#include "core/errors.hpp"

namespace c2d::app {

namespace {

int parse_count(const std::string& flag, const std::string& text) {
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || v < 1 || v > 1000)
    throw InputError(flag + ": expected a positive integer, found '" + text + "'");
  return static_cast<int>(v);
}

double parse_accuracy(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !(v > 0 && v < 1))
    throw InputError("--accuracy: expected a relative error in (0, 1), found '" + text + "'");
  return v;
}

/// Only the verbs that run cases and write slurm.sh (compare, sweep, bench) take --case-timeout
/// and the --slurm-* options.
void require_study_verb(const Options& o, const std::string& flag) {
  if (o.verb != "compare" && o.verb != "sweep" && o.verb != "bench")
    throw InputError(flag + ": unknown option for " + o.verb +
                     " (compare, sweep and bench take it; see --help)");
}

/// --case-timeout: seconds, 0 for no limit.
double parse_case_timeout(const Options& o, const std::string& text) {
  require_study_verb(o, "--case-timeout");
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  // A year bounds it: the limit becomes a deadline on a steady clock.
  if (text.empty() || *end != '\0' || !(v >= 0 && v <= 3.2e7))
    throw InputError("--case-timeout: expected seconds from 0 (no limit) to 3.2e7, found '" + text +
                     "'");
  return v;
}

/// A value for an #SBATCH line of slurm.sh: it must match `pattern` (`expected` says what that
/// is), which also keeps line breaks, spaces and shell syntax out of the script.
std::string slurm_value(const Options& o, const std::string& flag, const std::string& text,
                        const char* pattern, const std::string& expected) {
  require_study_verb(o, flag);
  if (!std::regex_match(text, std::regex(pattern)))
    throw InputError(flag + ": expected " + expected + ", found '" + text + "'");
  return text;
}

void append_list(std::vector<std::string>& to, const std::string& text) {
  for (auto& item : split_list(text)) to.push_back(std::move(item));
}

using Setter = void (*)(Options& o, const std::string& flag, const std::string& value);

/// An option that takes a value: `--flag value`, and where `inline_form` also `--flag=value`;
/// `verb`, when given, is the only verb that knows it.
struct ValueOption {
  const char* flag;
  bool inline_form;
  Setter set;
  const char* verb = nullptr;
};

const ValueOption kValueOptions[] = {
    {"--set", true,
     [](Options& o, const std::string&, const std::string& v) { o.sets.push_back(v); }},
    {"--out", true,
     [](Options& o, const std::string&, const std::string& v) {
       if (v.empty()) throw InputError("--out: expected a folder name, found an empty string");
       o.out = v;
     }},
    {"--method", true,
     [](Options& o, const std::string&, const std::string& v) {
       if (!constraints::find_method(v))
         throw InputError("--method: expected " + constraints::method_list(" | ") + ", found '" + v + "'");
       o.method = v;
     }},
    {"--methods", true,
     [](Options& o, const std::string&, const std::string& v) { o.methods = v; }},
    {"--data", false, [](Options& o, const std::string&, const std::string& v) { o.data = v; }},
    {"--fit", false,
     [](Options& o, const std::string&, const std::string& v) { append_list(o.fits, v); }},
    {"--levels", true,
     [](Options& o, const std::string& f, const std::string& v) { o.levels = parse_count(f, v); }},
    {"--jobs", true,
     [](Options& o, const std::string& f, const std::string& v) { o.jobs = parse_count(f, v); }},
    {"--case-timeout", true,
     [](Options& o, const std::string&, const std::string& v) {
       o.case_timeout = parse_case_timeout(o, v);
     }},
    {"--metric", true,
     [](Options& o, const std::string&, const std::string& v) {
       if (v.empty()) throw InputError("--metric: expected a reference key or a probe, found ''");
       o.metric = v;
     }},
    {"--slurm-partition", true,
     [](Options& o, const std::string& f, const std::string& v) {
       o.slurm.partition = slurm_value(o, f, v, "[A-Za-z0-9_.-]+(,[A-Za-z0-9_.-]+)*",
                                       "a partition name or a comma-separated list of them");
     }},
    {"--slurm-time", true,
     [](Options& o, const std::string& f, const std::string& v) {
       o.slurm.time =
           slurm_value(o, f, v, "[0-9]+-[0-9]+(:[0-9]+){0,2}|[0-9]+(:[0-9]+){0,2}",
                       "a Slurm time limit (minutes, M:S, H:M:S, D-H, D-H:M or D-H:M:S)");
     }},
    {"--slurm-mem", true,
     [](Options& o, const std::string& f, const std::string& v) {
       o.slurm.mem =
           slurm_value(o, f, v, "[1-9][0-9]*[KMGT]?",
                       "a memory size per task (megabytes, or a number with K, M, G or T)");
     }},
    {"--slurm-cpus-per-task", true,
     [](Options& o, const std::string& f, const std::string& v) {
       require_study_verb(o, f);
       o.slurm.cpus_per_task = parse_count(f, v);
     }},
    {"--accuracy", false,
     [](Options& o, const std::string&, const std::string& v) { o.accuracy = parse_accuracy(v); }},
    {"--field", false,
     [](Options& o, const std::string&, const std::string& v) { append_list(o.fields, v); }},
    {"--zoom", false, [](Options& o, const std::string&, const std::string& v) { o.zoom = v; }},
    {"--deformed", false,
     [](Options& o, const std::string&, const std::string& v) { o.deformed = v; }},
    {"--step", false,
     [](Options& o, const std::string& f, const std::string& v) { o.step = parse_count(f, v); }},
    {"--cycle", false,
     [](Options& o, const std::string& f, const std::string& v) {
       o.cycle = v == "0" ? 0 : parse_count(f, v);
     }},
    {"--examples", false,
     [](Options& o, const std::string&, const std::string& v) { o.examples = v; }, "bench"},
};

/// An option with a value at argv[i] (its value, if separate, at argv[i + 1], and then i moves
/// past it); false when argv[i] is none.
bool take_value_option(Options& o, const std::string& a, int argc, char** argv, int& i) {
  for (const auto& option : kValueOptions) {
    if (option.verb && o.verb != option.verb) continue;
    const std::string flag = option.flag;
    if (a == flag) {
      if (i + 1 >= argc) throw InputError(flag + ": expected a value, found the end of the line");
      option.set(o, flag, argv[++i]);
      return true;
    }
    if (option.inline_form && a.rfind(flag + "=", 0) == 0) {
      option.set(o, flag, a.substr(flag.size() + 1));
      return true;
    }
  }
  return false;
}

/// --adapt [target=0.05] [max_cycles=8] [max_shrink=0.2] [max_growth=2]: the [adapt] table.
/// Returns the index of the last argument it took.
int take_adapt(Options& o, int argc, char** argv, int i) {
  o.adapt = true;
  o.adapt_sets.push_back("adapt.enabled=true");
  while (i + 1 < argc) {
    const std::string kv = argv[i + 1];
    const auto eq = kv.find('=');
    const std::string key = kv.substr(0, eq);
    if (eq == std::string::npos ||
        (key != "target" && key != "max_cycles" && key != "max_shrink" && key != "max_growth"))
      break;
    o.adapt_sets.push_back("adapt." + kv);
    ++i;
  }
  return i;
}

/// An option without a value; false when `a` is none.
bool take_flag(Options& o, const std::string& a) {
  if (a == "--help" || a == "-h")
    o.help = true;
  else if (a == "--edges")
    o.edges = true;
  else if (a == "--quick" && o.verb == "bench")
    o.quick = true;
  else if (a == "--job-list" && (o.verb == "compare" || o.verb == "sweep" || o.verb == "bench"))
    o.job_list = true;
  else if (a == "--quiet" || a == "-q")
    o.quiet = true;
  else
    return false;
  return true;
}

}  // namespace

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream list(text);
  for (std::string item; std::getline(list, item, ',');)
    if (!item.empty()) items.push_back(item);
  return items;
}

Options parse_args(int argc, char** argv) {
  Options o;
  if (argc < 2) return o;
  o.verb = argv[1];
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (take_value_option(o, a, argc, argv, i) || take_flag(o, a)) continue;
    if (a == "--adapt")
      i = take_adapt(o, argc, argv, i);
    else if (!a.empty() && a[0] == '-')
      throw InputError(a + ": unknown option (see --help)");
    else if (o.scene.empty())
      o.scene = a;
    else
      throw InputError(a + ": unexpected argument (one scene per run)");
  }
  return o;
}

}  // namespace c2d::app
