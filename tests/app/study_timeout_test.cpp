// The studies' per-case time limit (issue 32, item 12): a case that does not end within
// --case-timeout is stopped (SIGTERM to its process group, SIGKILL after a grace period), its row
// says `timeout`, the report names it and the limit, nothing it started is left running, the
// other cases still run, and the study exits 1. No assertion on speed: the slow cases take tens
// of seconds where the limit is one or fifteen.
#include <dirent.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "app/process.hpp"
#include "app/studies/study.hpp"
#include "read_text.hpp"

namespace fs = std::filesystem;

namespace {

using c2d::test::read_text;

/// A fresh folder of this test under the suite's temporary folder.
fs::path fresh_dir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("c2d_study_timeout_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// Runs contact2d with `args` (an argument vector, no shell); returns its exit code and output.
int contact2d(const std::vector<std::string>& args, const fs::path& log, std::string* output) {
  const c2d::app::ProcessOutcome p = c2d::app::run_process(C2D_BINARY, args, log.string());
  *output = read_text(log);
  return p.started ? p.exit_code : -1;
}

std::string example(const std::string& name) {
  return std::string(C2D_SOURCE_DIR) + "/examples/" + name;
}

/// The ids of the live processes (not zombies) whose command line mentions `text`.
std::vector<int> processes_mentioning(const std::string& text) {
  std::vector<int> found;
  DIR* proc = ::opendir("/proc");
  if (!proc) return found;
  for (dirent* e; (e = ::readdir(proc));) {
    const std::string name = e->d_name;
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::string cmdline = read_text("/proc/" + name + "/cmdline");
    for (char& c : cmdline)
      if (c == '\0') c = ' ';
    const std::string stat = read_text("/proc/" + name + "/stat");
    const size_t paren = stat.rfind(')');
    const bool zombie =
        paren != std::string::npos && paren + 2 < stat.size() && stat[paren + 2] == 'Z';
    if (!zombie && cmdline.find(text) != std::string::npos) found.push_back(std::stoi(name));
  }
  ::closedir(proc);
  return found;
}

/// Whether process `pid` has ended (gone, or a zombie nobody has reaped yet), waiting up to 5 s
/// for an orphan's parent to notice.
bool ended(int pid) {
  for (int i = 0; i < 100; ++i) {
    const std::string stat = read_text("/proc/" + std::to_string(pid) + "/stat");
    const size_t paren = stat.rfind(')');
    if (stat.empty() ||
        (paren != std::string::npos && paren + 2 < stat.size() && stat[paren + 2] == 'Z'))
      return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

/// The CSV's rows as maps from column to cell (the studies quote only the status: no commas).
std::vector<std::map<std::string, std::string>> csv_rows(const fs::path& path) {
  std::vector<std::map<std::string, std::string>> rows;
  std::stringstream text(read_text(path));
  std::string line;
  std::getline(text, line);
  std::vector<std::string> columns;
  std::stringstream header(line);
  for (std::string c; std::getline(header, c, ',');) columns.push_back(c);
  while (std::getline(text, line)) {
    std::map<std::string, std::string> row;
    std::stringstream cells(line);
    size_t k = 0;
    for (std::string c; std::getline(cells, c, ',') && k < columns.size();) row[columns[k++]] = c;
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

// The limit itself: a child that ignores SIGTERM and started another that ignores it too is
// killed with its whole group after the grace period; one that ends in time is left alone.
TEST(StudyTimeout, ALimitedChildAndWhatItStartedAreKilled) {
  const fs::path dir = fresh_dir("process");
  const fs::path pid_file = dir / "sleeper.pid";
  const std::string script = "trap '' TERM; sleep 60 & echo $! > '" + pid_file.string() + "'; wait";
  const auto t0 = std::chrono::steady_clock::now();
  const c2d::app::ProcessOutcome p =
      c2d::app::run_process("sh", {"-c", script}, (dir / "sh.log").string(), {}, {}, {0.5, 0.5});
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(p.started) << p.error;
  EXPECT_TRUE(p.timed_out);
  EXPECT_EQ(p.exit_code, 128 + SIGKILL);  // SIGTERM was ignored
  EXPECT_LT(seconds, 30.0);               // the limit ended it, not the sleep's 60 s
  const std::string pid_text = read_text(pid_file);
  ASSERT_FALSE(pid_text.empty()) << "the script did not start its sleeper";
  EXPECT_TRUE(ended(std::stoi(pid_text))) << "the grandchild outlived the limit";

  const c2d::app::ProcessOutcome quick =
      c2d::app::run_process("sh", {"-c", "exit 3"}, (dir / "quick.log").string(), {}, {}, {60, 1});
  EXPECT_FALSE(quick.timed_out);
  EXPECT_EQ(quick.exit_code, 3);
}

// compare with two methods on a scene that takes tens of seconds, limited to 1 s: both rows
// `timeout`, the report names the limit, exit 1, no case process left.
TEST(StudyTimeout, CompareStopsEveryCaseOverTheLimit) {
  const fs::path dir = fresh_dir("compare");
  const fs::path study = dir / "study";
  std::string output;
  const int code =
      contact2d({"compare", example("cattaneo_mindlin.toml"), "--methods", "lagrange,penalty",
                 "--jobs", "2", "--case-timeout", "1", "--out", study.string()},
                dir / "compare.log", &output);
  EXPECT_EQ(code, 1) << output;
  EXPECT_EQ(output.find("chart not written"), std::string::npos) << output;  // 1: the timeouts
  const auto rows = csv_rows(study / "compare.csv");
  ASSERT_EQ(rows.size(), 2u) << read_text(study / "compare.csv");
  for (const auto& row : rows) EXPECT_EQ(row.at("status"), "\"timeout\"") << row.at("method");
  const std::string md = read_text(study / "compare.md");
  EXPECT_NE(md.find("## Timed out"), std::string::npos) << md;
  EXPECT_NE(md.find("| level0/lagrange | 1 s | 1 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| level0/penalty | 1 s | 2 |"), std::string::npos) << md;
  EXPECT_NE(md.find("lagrange at level 0 (timeout)"), std::string::npos) << md;
  EXPECT_NE(read_text(study / "compare.html").find("Timed out"), std::string::npos);
  EXPECT_NE(output.find("timeout    level0/lagrange stopped at the per-case limit of 1 s"),
            std::string::npos)
      << output;
  EXPECT_FALSE(fs::exists(study / "timing")) << "a timed-out case is not timed again";
  // What a stopped run left: its "interrupted" summary, now saying timeout (or nothing, when
  // the limit came before the run had a folder).
  for (const char* method : {"lagrange", "penalty"}) {
    const fs::path summary = study / "level0" / method / "summary.json";
    if (!fs::exists(summary)) continue;
    const nlohmann::json s = nlohmann::json::parse(read_text(summary));
    EXPECT_EQ(s.value("status", ""), "timeout") << method;
    EXPECT_EQ(s.value("time_limit_s", 0.0), 1.0) << method;
  }
  EXPECT_TRUE(processes_mentioning(study.string()).empty())
      << "a case of the study is still running";

  // A merge of the same folder says the same of the cases that left a summary.
  const int merged = contact2d({"merge", study.string()}, dir / "merge.log", &output);
  EXPECT_EQ(merged, 1) << output;
  for (const auto& row : csv_rows(study / "compare.csv"))
    EXPECT_EQ(row.at("status"), "\"timeout\"");
}

// sweep over a mesh scale where one value takes seconds and the other far longer than the
// limit: the first converges, the second is stopped, the study reports both and exits 1.
TEST(StudyTimeout, SweepGoesOnWithTheOtherCases) {
  const fs::path dir = fresh_dir("sweep");
  const fs::path study = dir / "study";
  std::string output;
  const int code =
      contact2d({"sweep", example("two_cantilevers.toml"), "--set", "analysis.mesh_scale=4,0.15",
                 "--case-timeout", "15", "--out", study.string()},
                dir / "sweep.log", &output);
  EXPECT_EQ(code, 1) << output;
  EXPECT_EQ(output.find("chart not written"), std::string::npos) << output;  // 1: the timeout
  const auto rows = csv_rows(study / "sweep.csv");
  ASSERT_EQ(rows.size(), 2u) << read_text(study / "sweep.csv");
  EXPECT_EQ(rows[0].at("status"), "\"converged\"") << read_text(study / "sweep.csv");
  EXPECT_EQ(rows[1].at("status"), "\"timeout\"") << read_text(study / "sweep.csv");
  const std::string md = read_text(study / "sweep.md");
  EXPECT_NE(md.find("1 of 2 cases did not finish within the per-case time limit"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| case1 | 15 s | 2 |"), std::string::npos) << md;
  EXPECT_NE(md.find("0.15 (timeout)"), std::string::npos) << md;
  EXPECT_TRUE(processes_mentioning(study.string()).empty())
      << "a case of the study is still running";
}

// The option: seconds for the verbs that run cases, 0 for none; refused elsewhere and when
// malformed. The job list carries the limit into slurm.sh.
TEST(StudyTimeout, TheOptionIsCheckedAndReachesTheJobList) {
  const fs::path dir = fresh_dir("option");
  std::string output;
  for (const char* bad : {"-1", "abc", "", "1e9"})
    EXPECT_EQ(contact2d({"compare", example("hertz_rigid_fast.toml"), "--case-timeout", bad},
                        dir / "bad.log", &output),
              2)
        << bad << ": " << output;
  EXPECT_EQ(contact2d({"run", example("hertz_rigid_fast.toml"), "--case-timeout", "5"},
                      dir / "run.log", &output),
            2)
      << output;
  EXPECT_NE(output.find("--case-timeout: unknown option for run"), std::string::npos) << output;

  const fs::path study = dir / "list";
  ASSERT_EQ(contact2d({"compare", example("hertz_rigid_fast.toml"), "--methods", "lagrange",
                       "--case-timeout", "600", "--job-list", "--out", study.string()},
                      dir / "list.log", &output),
            0)
      << output;
  const std::string slurm = read_text(study / "slurm.sh");
  EXPECT_NE(slurm.find("#SBATCH --time=0-00:11:00\n"), std::string::npos) << slurm;
  EXPECT_NE(output.find("parallel -j 2 --timeout 600 < jobs.txt"), std::string::npos) << output;
  const nlohmann::json manifest = nlohmann::json::parse(read_text(study / "study.json"));
  EXPECT_EQ(manifest.value("case_timeout_s", 0.0), 600.0);

  const fs::path none = dir / "none";
  ASSERT_EQ(contact2d({"compare", example("hertz_rigid_fast.toml"), "--methods", "lagrange",
                       "--case-timeout=0", "--job-list", "--out", none.string()},
                      dir / "none.log", &output),
            0)
      << output;
  EXPECT_EQ(read_text(none / "slurm.sh").find("#SBATCH --time"), std::string::npos);
}

// A case that left no summary.json is listed by the exit code the run documents (issue 32, a
// full disk): 3 is a write failure, 2 bad input, a signal (128 + N) or anything else a crash.
// Before, every one of them read "crashed (exit N, no summary.json)". Each is a failed case: the
// study exits 1 (any_case_failed), a converged case alone does not.
TEST(StudyStatus, ACaseWithoutSummaryNamesItsExitCode) {
  const std::map<int, std::string> expected{{3, "write_failed (exit 3, no summary.json)"},
                                            {2, "bad_input (exit 2, no summary.json)"},
                                            {128 + SIGSEGV, "crashed (exit 139, no summary.json)"},
                                            {1, "crashed (exit 1, no summary.json)"}};
  for (const auto& [code, status] : expected) {
    c2d::app::CaseOutcome outcome;
    outcome.exit_code = code;
    c2d::app::RunFigures row;
    EXPECT_FALSE(row.read(outcome)) << code;
    EXPECT_EQ(row.status, status);
    EXPECT_TRUE(row.crashed()) << code;
    EXPECT_FALSE(row.timed_out()) << code;
    EXPECT_TRUE(c2d::app::any_case_failed({&row})) << code;
  }
  c2d::app::CaseOutcome converged;
  converged.exit_code = 0;
  converged.has_summary = true;
  converged.summary = {{"status", "converged"}};
  c2d::app::RunFigures row;
  EXPECT_TRUE(row.read(converged));
  EXPECT_FALSE(c2d::app::any_case_failed({&row}));
}
