// Studies across machines: compare, sweep and bench --job-list write jobs.txt, slurm.sh and
// study.json; GNU parallel runs the job list (for real, as a user would: `cd DIR && parallel
// -j 2 < jobs.txt`); `contact2d merge DIR` reports from whatever case folders have finished and
// must reproduce the table of the same study run by contact2d itself, and name what is missing.
#include "app/studies/job_list.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "app/process.hpp"
#include "app/studies/bench.hpp"
#include "read_text.hpp"

namespace fs = std::filesystem;

namespace {

size_t count_of(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

using c2d::test::read_text;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::stringstream ss(text);
  for (std::string line; std::getline(ss, line);) lines.push_back(line);
  return lines;
}

/// Runs contact2d with `args` (an argument vector, no shell); returns its exit code and output.
int contact2d(const std::vector<std::string>& args, std::string* output = nullptr) {
  const fs::path log =
      fs::temp_directory_path() / ("c2d_job_list_test_" + std::to_string(::getpid()) + ".log");
  const c2d::app::ProcessOutcome p = c2d::app::run_process(C2D_BINARY, args, log.string());
  if (output) *output = read_text(log);
  return p.started ? p.exit_code : -1;
}

/// Runs jobs.txt of `study` with GNU parallel, two at a time, from the study folder, with
/// jobs.txt as its input; fails the test (never skips) when parallel cannot be started.
/// `seconds`: how long it took.
void run_with_parallel(const fs::path& study, double* seconds) {
  const auto t0 = std::chrono::steady_clock::now();
  const fs::path log = study.parent_path() / "parallel.log";
  const c2d::app::ProcessOutcome p = c2d::app::run_process(
      "parallel", {"-j", "2"}, log.string(), {}, {(study / "jobs.txt").string(), study.string()});
  ASSERT_TRUE(p.started) << "this test runs the job list with GNU parallel, which could not be "
                            "started ("
                         << p.error
                         << "); install it with `apt-get install parallel` (scripts/bootstrap.sh "
                            "lists it)";
  ASSERT_EQ(p.exit_code, 0) << read_text(log);
  *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The words of a POSIX shell line made of single-quoted words and \' (jobs.txt's quoting).
std::vector<std::string> shell_words(const std::string& line) {
  std::vector<std::string> words;
  std::string word;
  bool in_word = false;
  for (size_t i = 0; i < line.size(); ++i) {
    if (line[i] == '\'') {
      const size_t end = line.find('\'', i + 1);
      word += line.substr(i + 1, end - i - 1);
      i = end;
      in_word = true;
    } else if (line[i] == '\\') {
      word += line[++i];
      in_word = true;
    } else if (line[i] == ' ') {
      if (in_word) words.push_back(word);
      word.clear();
      in_word = false;
    } else {
      word += line[i];
      in_word = true;
    }
  }
  if (in_word) words.push_back(word);
  return words;
}

/// A CSV table (no quoted commas: the studies write none) as rows of named cells.
struct Table {
  std::vector<std::string> columns;
  std::vector<std::map<std::string, std::string>> rows;
};

Table read_table(const fs::path& path) {
  Table t;
  const std::vector<std::string> lines = lines_of(read_text(path));
  if (lines.empty()) return t;
  std::stringstream header(lines[0]);
  for (std::string c; std::getline(header, c, ',');) t.columns.push_back(c);
  for (size_t i = 1; i < lines.size(); ++i) {
    std::map<std::string, std::string> row;
    std::stringstream ss(lines[i]);
    size_t k = 0;
    for (std::string c; std::getline(ss, c, ',') && k < t.columns.size();) row[t.columns[k++]] = c;
    for (; k < t.columns.size(); ++k) row[t.columns[k]] = "";  // (getline drops a last empty)
    t.rows.push_back(row);
  }
  return t;
}

/// Two tables of the same study agree: the same rows in the same order, every cell equal but
/// the times (taken by different processes), `p_max` also checked as a number to 1e-12.
/// A cell of a table run in-process and the same cell after a merge of the same cases run as
/// separate processes. Text must match; numbers to 1e-9 relative (error_* columns 1e-9
/// absolute): the same run in two processes agrees to about 1e-13 in p_max, not bit for bit
/// (threaded reductions), and a fitted quantity can move a printed 8th digit.
void expect_same_cell(const std::string& column, const std::string& a, const std::string& b,
                      const std::string& what) {
  char* end_a = nullptr;
  char* end_b = nullptr;
  const double x = std::strtod(a.c_str(), &end_a), y = std::strtod(b.c_str(), &end_b);
  if (a.empty() || b.empty() || *end_a != '\0' || *end_b != '\0') {
    EXPECT_EQ(a, b) << what << " " << column;
    return;
  }
  const double tolerance =
      column.rfind("error_", 0) == 0 ? 1e-9 : 1e-9 * std::max(std::abs(x), std::abs(y));
  EXPECT_LE(std::abs(x - y), tolerance) << what << " " << column << ": " << a << " vs " << b;
}

void expect_same_table(const Table& run, const Table& merged, const std::string& what) {
  ASSERT_EQ(run.columns, merged.columns) << what;
  ASSERT_EQ(run.rows.size(), merged.rows.size()) << what;
  for (size_t i = 0; i < run.rows.size(); ++i) {
    for (const auto& c : run.columns) {
      if (c.rfind("time_", 0) == 0 || c == "wall") continue;
      expect_same_cell(c, run.rows[i].at(c), merged.rows[i].at(c), what + " row " + std::to_string(i));
    }
    const double a = std::stod(run.rows[i].at("p_max")), b = std::stod(merged.rows[i].at("p_max"));
    EXPECT_NEAR(b / a, 1.0, 1e-12) << what << " row " << i;
  }
}

/// A scene file in a folder whose name holds a space, a single quote and shell syntax, so that
/// every job line quotes it for real (no_injection() checks that nothing ran).
fs::path awkward_scene(const fs::path& root) {
  const fs::path dir = root / "scene's $(touch PWNED1) `touch PWNED2` dir";
  fs::create_directories(dir);
  fs::copy_file(std::string(C2D_SOURCE_DIR) + "/examples/hertz_rigid.toml", dir / "hertz.toml",
                fs::copy_options::overwrite_existing);
  return dir / "hertz.toml";
}

/// No file named PWNED* appeared anywhere under `root` (where the jobs ran).
void expect_no_injection(const fs::path& root) {
  for (const auto& e : fs::recursive_directory_iterator(root))
    EXPECT_NE(e.path().filename().string().rfind("PWNED", 0), 0u) << e.path();
}

}  // namespace

TEST(JobList, ShellQuotingKeepsEveryCharacterOneWord) {
  // Each word, quoted, goes through bash and comes back unchanged as one argument.
  for (const std::string word : {"plain", "with space", "it's", "'", "''", "a'b'c", "$HOME", "`id`",
                                 "back\\slash", "\"double\"", "*", "; ls", ""}) {
    const std::string quoted = c2d::app::shell_quote(word);
    const fs::path log = fs::temp_directory_path() / "c2d_shell_quote.log";
    const auto p =
        c2d::app::run_process("bash", {"-c", "printf '[%s]\\n' " + quoted}, log.string());
    ASSERT_TRUE(p.started) << p.error;
    EXPECT_EQ(read_text(log), "[" + word + "]\n") << quoted;
  }
  EXPECT_EQ(c2d::app::shell_quote("it's"), "'it'\\''s'");
}

TEST(JobList, CompareRunByParallelMergesToTheSameTable) {
  const fs::path root = fs::temp_directory_path() / "c2d_job_list_compare";
  fs::remove_all(root);
  const fs::path scene = awkward_scene(root);
  const std::vector<std::string> study = {
      "compare",   scene.string(),     "--set",  "analysis.mesh_scale=8", "--levels", "1",
      "--methods", "lagrange,penalty", "--quiet"};
  // The study run by contact2d itself.
  std::vector<std::string> args = study;
  args.insert(args.end(), {"--jobs", "2", "--out", (root / "run").string()});
  std::string output;
  ASSERT_EQ(contact2d(args, &output), 0) << output;
  // Two at a time: the times come from a second pass, each case alone, whose folders go.
  EXPECT_NE(read_text(root / "run" / "compare.md").find("their times come from a separate pass"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(root / "run" / "timing"));
  for (const auto& row : read_table(root / "run" / "compare.csv").rows)
    EXPECT_GT(std::stod(row.at("time_solve")), 0.0) << row.at("method");

  // The same study as a job list, in a folder whose name holds a space and a quote.
  const fs::path dir = root / "study it's";
  args = study;
  args.insert(args.end(), {"--job-list", "--out", dir.string()});
  ASSERT_EQ(contact2d(args, &output), 0) << output;
  const std::vector<std::string> jobs = lines_of(read_text(dir / "jobs.txt"));
  ASSERT_EQ(jobs.size(), 2u);
  const std::string prefix =
      "OPENBLAS_NUM_THREADS=\"${OPENBLAS_NUM_THREADS:-1}\" "
      "OMP_NUM_THREADS=\"${OMP_NUM_THREADS:-1}\" ";
  const std::vector<std::string> methods{"lagrange", "penalty"};
  for (size_t i = 0; i < jobs.size(); ++i) {
    ASSERT_EQ(jobs[i].rfind(prefix, 0), 0u) << jobs[i];
    const std::vector<std::string> words = shell_words(jobs[i].substr(prefix.size()));
    const std::vector<std::string> expected{fs::canonical(C2D_BINARY).string(),
                                            "run",
                                            scene.string(),
                                            "--method",
                                            methods[i],
                                            "--set",
                                            "analysis.mesh_scale=8",
                                            "--set",
                                            "analysis.mesh_scale=8",
                                            "--out",
                                            "level0/" + methods[i],
                                            "--quiet"};
    EXPECT_EQ(words, expected) << jobs[i];
  }
  const std::string slurm = read_text(dir / "slurm.sh");
  EXPECT_NE(slurm.find("#SBATCH --array=1-2\n"), std::string::npos) << slurm;
  EXPECT_NE(slurm.find("sed -n \"${SLURM_ARRAY_TASK_ID}p\" jobs.txt | bash"), std::string::npos);
  EXPECT_NE(fs::status(dir / "slurm.sh").permissions() & fs::perms::owner_exec, fs::perms::none);
  const nlohmann::json manifest = nlohmann::json::parse(read_text(dir / "study.json"));
  EXPECT_EQ(manifest["verb"], "compare");
  ASSERT_EQ(manifest["cases"].size(), 2u);
  EXPECT_EQ(manifest["cases"][1]["folder"], "level0/penalty");
  EXPECT_FALSE(fs::exists(dir / "level0")) << "a job list runs nothing";

  // Before any job ran: a merge lists both cases as missing (exit 1).
  EXPECT_EQ(contact2d({"merge", dir.string()}, &output), 1) << output;
  EXPECT_NE(output.find("missing    level0/lagrange (no summary.json; jobs.txt line 1)"),
            std::string::npos)
      << output;

  double seconds = 0;
  ASSERT_NO_FATAL_FAILURE(run_with_parallel(dir, &seconds));
  RecordProperty("parallel_seconds", std::to_string(seconds));
  expect_no_injection(root);
  ASSERT_EQ(contact2d({"merge", dir.string(), "--quiet"}, &output), 0) << output;
  expect_same_table(read_table(root / "run" / "compare.csv"), read_table(dir / "compare.csv"),
                    "compare.csv");
  for (const auto& row : read_table(dir / "compare.csv").rows)
    EXPECT_EQ(row.at("status"), "\"converged\"") << row.at("method");
  // Beyond the table's 8 digits: each job's p_max as its summary.json holds it (17 digits).
  for (const auto& m : methods) {
    const auto p_max = [&](const fs::path& study_dir) {
      return nlohmann::json::parse(read_text(study_dir / "level0" / m / "summary.json"))
          .at("contact")
          .at("p_max")
          .get<double>();
    };
    EXPECT_NEAR(p_max(dir) / p_max(root / "run"), 1.0, 1e-12) << m;
    // Each job's own account of its process, which a merge reads: a wall time between the
    // solve's and a minute, a peak memory between 10 MB and the machine's 24 GB.
    const auto j = nlohmann::json::parse(read_text(dir / "level0" / m / "summary.json"));
    const double wall = j.at("process").at("wall_s").get<double>();
    EXPECT_GE(wall, j.at("time_s").at("total").get<double>() - 0.02) << m;
    EXPECT_LT(wall, 60.0) << m;
    const double rss = j.at("process").at("peak_rss_mb").get<double>();
    EXPECT_GT(rss, 10.0) << m;
    EXPECT_LT(rss, 24.0 * 1024) << m;
  }
  EXPECT_EQ(read_text(dir / "compare.md").find("Missing cases"), std::string::npos);
  // The merge writes the HTML page through the same report: a row per case, the three charts.
  const std::string html = read_text(dir / "compare.html");
  EXPECT_EQ(count_of(html, "<td data-value=\"converged\">"), 2u);
  EXPECT_EQ(count_of(html, "<svg class=\"chart\""), 3u);

  // One case lost: the merge reports the other and names the lost one, with its jobs.txt line.
  fs::remove_all(dir / "level0" / "penalty");
  EXPECT_EQ(contact2d({"merge", dir.string()}, &output), 1) << output;
  EXPECT_NE(output.find("missing    level0/penalty (no summary.json; jobs.txt line 2)"),
            std::string::npos)
      << output;
  const std::string md = read_text(dir / "compare.md");
  EXPECT_NE(md.find("## Missing cases"), std::string::npos) << md;
  EXPECT_NE(md.find("| level0/penalty | 2 |"), std::string::npos) << md;
  EXPECT_NE(read_text(dir / "compare.html").find("<td>level0/penalty</td><td>2</td>"),
            std::string::npos);
  const Table partial = read_table(dir / "compare.csv");
  ASSERT_EQ(partial.rows.size(), 1u);
  EXPECT_EQ(partial.rows[0].at("method"), "lagrange");

  // slurm.sh's task 2 (as sbatch would start it, from the study folder) runs line 2 again.
  const auto task = c2d::app::run_process("bash", {"slurm.sh"}, (root / "slurm.log").string(),
                                          {"SLURM_ARRAY_TASK_ID=2"}, {"/dev/null", dir.string()});
  ASSERT_TRUE(task.started) << task.error;
  EXPECT_EQ(task.exit_code, 0) << read_text(root / "slurm.log");
  ASSERT_EQ(contact2d({"merge", dir.string(), "--quiet"}, &output), 0) << output;
  expect_same_table(read_table(root / "run" / "compare.csv"), read_table(dir / "compare.csv"),
                    "compare.csv after slurm.sh");

  // A second job list into the same folder would mix old results with new: refused.
  args = study;
  args.insert(args.end(), {"--job-list", "--out", dir.string()});
  EXPECT_EQ(contact2d(args, &output), 2) << output;
  EXPECT_NE(output.find("level0/lagrange: already exists"), std::string::npos) << output;
}

TEST(JobList, SweepRunByParallelMergesToTheSameTable) {
  const fs::path root = fs::temp_directory_path() / "c2d_job_list_sweep";
  fs::remove_all(root);
  const fs::path scene = awkward_scene(root);
  const std::vector<std::string> study = {
      "sweep",  scene.string(),          "--method", "penalty",
      "--set",  "analysis.mesh_scale=8", "--set",    "contact.penalty.k=1e6:1e10:log:3",
      "--quiet"};
  std::vector<std::string> args = study;
  args.insert(args.end(), {"--jobs", "2", "--out", (root / "run").string()});
  std::string output;
  ASSERT_EQ(contact2d(args, &output), 0) << output;
  const fs::path dir = root / "sweep";
  args = study;
  args.insert(args.end(), {"--job-list", "--out", dir.string()});
  ASSERT_EQ(contact2d(args, &output), 0) << output;
  const std::vector<std::string> jobs = lines_of(read_text(dir / "jobs.txt"));
  // Three values, then the baseline: lagrange on the same mesh, without the swept key.
  ASSERT_EQ(jobs.size(), 4u);
  EXPECT_NE(jobs[2].find("'--set' 'contact.penalty.k=1e+10' '--out' 'case2' '--quiet'"),
            std::string::npos)
      << jobs[2];
  EXPECT_NE(jobs[3].find("'--method' 'lagrange'"), std::string::npos) << jobs[3];
  EXPECT_NE(jobs[3].find("'--out' 'baseline'"), std::string::npos) << jobs[3];
  EXPECT_EQ(jobs[3].find("contact.penalty.k"), std::string::npos) << jobs[3];
  EXPECT_NE(read_text(dir / "slurm.sh").find("#SBATCH --array=1-4\n"), std::string::npos);

  double seconds = 0;
  ASSERT_NO_FATAL_FAILURE(run_with_parallel(dir, &seconds));
  RecordProperty("parallel_seconds", std::to_string(seconds));
  ASSERT_EQ(contact2d({"merge", dir.string(), "--quiet"}, &output), 0) << output;
  const Table run = read_table(root / "run" / "sweep.csv");
  ASSERT_EQ(run.rows.size(), 3u);
  expect_same_table(run, read_table(dir / "sweep.csv"), "sweep.csv");
  for (const auto& row : run.rows) EXPECT_EQ(row.at("status"), "\"converged\"") << row.at("value");

  fs::remove_all(dir / "case1");
  EXPECT_EQ(contact2d({"merge", dir.string()}, &output), 1) << output;
  EXPECT_NE(output.find("missing    case1 (no summary.json; jobs.txt line 2)"), std::string::npos)
      << output;
  EXPECT_NE(read_text(dir / "sweep.md").find("| case1 | 2 |"), std::string::npos);
  const std::string html = read_text(dir / "sweep.html");
  EXPECT_NE(html.find("<td>case1</td><td>2</td>"), std::string::npos);
  EXPECT_EQ(count_of(html, "<td data-value=\"converged\">"), 2u);
  EXPECT_EQ(count_of(html, "<svg class=\"chart\""), 1u);
  EXPECT_EQ(read_table(dir / "sweep.csv").rows.size(), 2u);
}

namespace {

/// The #SBATCH lines of slurm.sh, in order.
std::vector<std::string> sbatch_lines(const fs::path& study) {
  std::vector<std::string> lines;
  for (const auto& line : lines_of(read_text(study / "slurm.sh")))
    if (line.rfind("#SBATCH ", 0) == 0) lines.push_back(line);
  return lines;
}

}  // namespace

TEST(JobList, SlurmScriptCarriesTheClusterSettings) {
  // What a real cluster asks of a job (tests/ecosystem/slurm_array_study.py submits one):
  // partition, time limit, memory and CPUs per task, from the --slurm-* options or defaults.
  const fs::path root = fs::temp_directory_path() / "c2d_job_list_slurm";
  fs::remove_all(root);
  const std::string scene = std::string(C2D_SOURCE_DIR) + "/examples/hertz_rigid_fast.toml";
  const auto job_list = [&](const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> args = {"compare",    scene,     "--methods", "lagrange,penalty",
                                     "--job-list", "--quiet", "--out",     (root / name).string()};
    args.insert(args.end(), extra.begin(), extra.end());
    std::string output;
    return std::make_pair(contact2d(args, &output), output);
  };
  // Defaults: the cluster's default partition (no line), the case timeout (1800 s) in whole
  // minutes and one more, 4G (the bench's largest case peaks at 3.4 GB), one CPU.
  ASSERT_EQ(job_list("defaults", {}).first, 0);
  EXPECT_EQ(
      sbatch_lines(root / "defaults"),
      (std::vector<std::string>{"#SBATCH --job-name=c2d-compare", "#SBATCH --array=1-2",
                                "#SBATCH --time=0-00:31:00", "#SBATCH --mem=4G",
                                "#SBATCH --cpus-per-task=1", "#SBATCH --output=slurm-%A_%a.out"}));
  // Every option, the forms of --name value and --name=value.
  ASSERT_EQ(job_list("set", {"--slurm-partition", "short,debug", "--slurm-time=1-02:30:00",
                             "--slurm-mem", "512M", "--slurm-cpus-per-task=3"})
                .first,
            0);
  EXPECT_EQ(
      sbatch_lines(root / "set"),
      (std::vector<std::string>{"#SBATCH --job-name=c2d-compare", "#SBATCH --array=1-2",
                                "#SBATCH --partition=short,debug", "#SBATCH --time=1-02:30:00",
                                "#SBATCH --mem=512M", "#SBATCH --cpus-per-task=3",
                                "#SBATCH --output=slurm-%A_%a.out"}));
  // The task's threads follow --cpus-per-task.
  EXPECT_NE(read_text(root / "set" / "slurm.sh")
                .find("export OPENBLAS_NUM_THREADS=\"${SLURM_CPUS_PER_TASK:-1}\""),
            std::string::npos);
  // Without a per-case limit and no --slurm-time: no --time line (the partition's limit).
  ASSERT_EQ(job_list("unlimited", {"--case-timeout", "0"}).first, 0);
  for (const auto& line : sbatch_lines(root / "unlimited"))
    EXPECT_EQ(line.find("--time"), std::string::npos) << line;
  ASSERT_EQ(job_list("minutes", {"--case-timeout", "0", "--slurm-time", "45"}).first, 0);
  EXPECT_EQ(sbatch_lines(root / "minutes")[2], "#SBATCH --time=45");

  // A value that is not what Slurm takes, or that would put a line of its own into the script,
  // is refused as bad input (exit 2) naming the option; no study folder is written.
  const std::vector<std::pair<std::vector<std::string>, std::string>> refused = {
      {{"--slurm-partition", "a\n#SBATCH --wrap=id"}, "--slurm-partition: expected a partition"},
      {{"--slurm-partition", "a b"}, "--slurm-partition: expected a partition"},
      {{"--slurm-partition", ""}, "--slurm-partition: expected a partition"},
      {{"--slurm-time", "1h"}, "--slurm-time: expected a Slurm time limit"},
      {{"--slurm-time", "1:2:3:4"}, "--slurm-time: expected a Slurm time limit"},
      {{"--slurm-mem", "0"}, "--slurm-mem: expected a memory size"},
      {{"--slurm-mem", "4GB"}, "--slurm-mem: expected a memory size"},
      {{"--slurm-cpus-per-task", "0"}, "--slurm-cpus-per-task: expected a positive integer"}};
  for (size_t i = 0; i < refused.size(); ++i) {
    const auto [code, output] = job_list("refused" + std::to_string(i), refused[i].first);
    EXPECT_EQ(code, 2) << output;
    EXPECT_NE(output.find(refused[i].second), std::string::npos) << output;
    EXPECT_FALSE(fs::exists(root / ("refused" + std::to_string(i)))) << refused[i].second;
  }
  // Only the verbs that write slurm.sh take them; the help names each.
  std::string output;
  EXPECT_EQ(contact2d({"run", scene, "--slurm-mem", "4G"}, &output), 2);
  EXPECT_NE(output.find("--slurm-mem: unknown option for run"), std::string::npos) << output;
  EXPECT_EQ(contact2d({"sweep", "--help"}, &output), 0);
  for (const char* option :
       {"--slurm-partition", "--slurm-time", "--slurm-mem", "--slurm-cpus-per-task"})
    EXPECT_NE(output.find(option), std::string::npos) << option;
}

TEST(JobList, BenchWritesItsLadderAndAMergeListsWhatHasNotRun) {
  // The quick ladder as a job list: a line per rung; merged before anything ran, every case is
  // listed as missing and bench.md still names every target.
  const fs::path dir = fs::temp_directory_path() / "c2d_job_list_bench";
  fs::remove_all(dir);
  std::string output;
  ASSERT_EQ(
      contact2d({"bench", "--quick", "--job-list", "--quiet", "--out", dir.string()}, &output), 0)
      << output;
  const size_t rungs = c2d::app::bench_ladder(true).size();
  EXPECT_EQ(lines_of(read_text(dir / "jobs.txt")).size(), rungs);
  EXPECT_NE(read_text(dir / "slurm.sh").find("#SBATCH --array=1-" + std::to_string(rungs) + "\n"),
            std::string::npos);
  EXPECT_EQ(contact2d({"merge", dir.string(), "--quiet"}, &output), 1) << output;
  const std::string md = read_text(dir / "bench.md");
  EXPECT_NE(md.find(std::to_string(rungs) + " of " + std::to_string(rungs) +
                    " cases have no "
                    "summary.json"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("contact overhead"), std::string::npos);
  // Nothing ran, so nothing was drawn: bench.html says so for each chart instead of an image.
  const std::string html = read_text(dir / "bench.html");
  EXPECT_EQ(count_of(html, "<svg"), 0u);
  EXPECT_NE(html.find("(time_vs_dofs.svg) not shown: not written: no run converged"),
            std::string::npos);
  EXPECT_NE(html.find("(accuracy_vs_time.svg) not shown: not written"), std::string::npos);
  EXPECT_NE(html.find("<tbody>\n</tbody>"), std::string::npos) << "no rows yet";
}

TEST(JobList, MergeRefusesAFolderWithoutAValidManifest) {
  const fs::path dir = fs::temp_directory_path() / "c2d_job_list_bad";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string output;
  EXPECT_EQ(contact2d({"merge", dir.string()}, &output), 2);
  EXPECT_EQ(lines_of(output).size(), 1u) << output;
  EXPECT_NE(output.find((dir / "study.json").string() + ": cannot open the study manifest"),
            std::string::npos)
      << output;
  std::ofstream(dir / "study.json")
      << R"({"format": "contact2d study 1", "verb": "sweep", "cases": [{"args": "x"}]})";
  EXPECT_EQ(contact2d({"merge", dir.string()}, &output), 2);
  EXPECT_NE(output.find("study.json: cases[0].args: expected an array, found string \"x\""),
            std::string::npos)
      << output;
  std::ofstream(dir / "study.json")
      << R"({"format": "contact2d study 1", "verb": "sweep", "cases": [{"args": [], "folder": "../x"}]})";
  EXPECT_EQ(contact2d({"merge", dir.string()}, &output), 2);
  EXPECT_NE(output.find("cases[0].folder: expected a folder inside the study's"), std::string::npos)
      << output;
  EXPECT_EQ(contact2d({"merge"}, &output), 2);
  EXPECT_NE(output.find("merge: expected a study folder"), std::string::npos) << output;
  // The option and the verb are in the help.
  EXPECT_EQ(contact2d({"--help"}, &output), 0);
  EXPECT_NE(output.find("merge DIR"), std::string::npos);
  EXPECT_NE(output.find("--job-list"), std::string::npos);
  for (const char* verb : {"compare", "sweep", "bench"}) {
    EXPECT_EQ(contact2d({verb, "--help"}, &output), 0);
    EXPECT_NE(output.find("--job-list"), std::string::npos) << verb;
  }
  EXPECT_EQ(contact2d({"merge", "--help"}, &output), 0);
  EXPECT_NE(output.find("usage: contact2d merge DIR"), std::string::npos);
  EXPECT_EQ(contact2d({"run", "x.toml", "--job-list"}, &output), 2);
}
