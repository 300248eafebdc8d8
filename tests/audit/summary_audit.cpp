// Audits every summary.json under a folder (the outputs the test suite wrote): no run may say
// "converged" while the penetration measured at its final positions exceeds the bound it
// reports, or while its solver section says otherwise. Usage: summary_audit DIR
// MIN_CONTACT_RUNS. Exit 0 when every file passes and at least MIN_CONTACT_RUNS converged
// contact runs were audited (so the audit cannot pass vacuously).
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: summary_audit DIR MIN_CONTACT_RUNS\n";
    return 2;
  }
  const fs::path root = argv[1];
  const int minimum = std::stoi(argv[2]);
  int files = 0, audited = 0, failures = 0;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(root, ec); !ec && it != fs::end(it); it.increment(ec)) {
    if (it->path().filename() != "summary.json") continue;
    ++files;
    std::ifstream in(it->path());
    const nlohmann::json s = nlohmann::json::parse(in, nullptr, false);
    if (s.is_discarded() || !s.is_object()) continue;  // a test of refused input may leave none
    if (!s.contains("status") || s["status"] != "converged") continue;
    // The solver section of a converged run says so (load-stepped contact runs had left it
    // at "failed" with no figures).
    if (s.contains("solver") && s["solver"].is_object() && s["solver"].value("status", "") != "converged") {
      std::cerr << it->path().string() << ": converged, but its solver section says "
                << s["solver"].value("status", "nothing") << '\n';
      ++failures;
    }
    if (!s.contains("contact") || !s["contact"].is_object()) continue;
    const auto& c = s["contact"];
    ++audited;
    if (!c.contains("measured_penetration") || !c["measured_penetration"].is_number() ||
        !c.contains("penetration_tolerance") || !c["penetration_tolerance"].is_number()) {
      std::cerr << it->path().string() << ": converged without a measured penetration\n";
      ++failures;
      continue;
    }
    const double measured = c["measured_penetration"], bound = c["penetration_tolerance"];
    if (measured > bound) {
      std::cerr << it->path().string() << ": converged, but the final state penetrates by "
                << measured << " > " << bound << '\n';
      ++failures;
    }
  }
  std::cout << files << " summary.json files, " << audited << " converged contact runs audited, "
            << failures << " failures\n";
  if (audited < minimum) {
    std::cerr << "expected at least " << minimum << " converged contact runs\n";
    return 1;
  }
  return failures == 0 ? 0 : 1;
}
