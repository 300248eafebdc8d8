#include "app/cli/options.hpp"

#include <cstdlib>
#include <sstream>

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
    auto value = [&](const std::string& flag) -> std::string {
      if (i + 1 >= argc) throw InputError(flag + ": expected a value, found the end of the line");
      return argv[++i];
    };
    if (a == "--help" || a == "-h")
      o.help = true;
    else if (a == "--set")
      o.sets.push_back(value(a));
    else if (a.rfind("--set=", 0) == 0)
      o.sets.push_back(a.substr(6));
    else if (a == "--out")
      o.out = value(a);
    else if (a == "--method")
      o.method = value(a);
    else if (a == "--methods")
      o.methods = value(a);
    else if (a == "--data")
      o.data = value(a);
    else if (a == "--fit") {
      for (auto& f : split_list(value(a))) o.fits.push_back(std::move(f));
    } else if (a.rfind("--methods=", 0) == 0)
      o.methods = a.substr(10);
    else if (a == "--levels")
      o.levels = parse_count(a, value(a));
    else if (a.rfind("--levels=", 0) == 0)
      o.levels = parse_count("--levels", a.substr(9));
    else if (a == "--jobs")
      o.jobs = parse_count(a, value(a));
    else if (a == "--accuracy") {
      const std::string v = value(a);
      char* end = nullptr;
      o.accuracy = std::strtod(v.c_str(), &end);
      if (v.empty() || *end != '\0' || !(o.accuracy > 0 && o.accuracy < 1))
        throw InputError("--accuracy: expected a relative error in (0, 1), found '" + v + "'");
    } else if (a.rfind("--jobs=", 0) == 0)
      o.jobs = parse_count("--jobs", a.substr(7));
    else if (a.rfind("--method=", 0) == 0)
      o.method = a.substr(9);
    else if (a.rfind("--out=", 0) == 0)
      o.out = a.substr(6);
    else if (a == "--field") {
      for (auto& f : split_list(value(a))) o.fields.push_back(std::move(f));
    } else if (a == "--zoom")
      o.zoom = value(a);
    else if (a == "--deformed")
      o.deformed = value(a);
    else if (a == "--step")
      o.step = parse_count(a, value(a));
    else if (a == "--cycle") {
      const std::string v = value(a);
      o.cycle = v == "0" ? 0 : parse_count(a, v);
    } else if (a == "--edges")
      o.edges = true;
    else if (a == "--quick" && o.verb == "bench")
      o.quick = true;
    else if (a == "--examples" && o.verb == "bench")
      o.examples = value(a);
    else if (a == "--levels" && o.verb == "plot")
      o.plot_levels = parse_count(a, value(a));
    else if (a == "--adapt") {
      // --adapt [target=0.05] [max_cycles=8] [max_shrink=0.2] [max_growth=2]: the [adapt] table.
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
    } else if (a == "--quiet" || a == "-q")
      o.quiet = true;
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
