#include "app/studies/job_list.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "app/report/json_file.hpp"
#include "core/errors.hpp"
#include "core/writers.hpp"

namespace fs = std::filesystem;

namespace c2d::app {

namespace {

constexpr const char* kManifestFormat = "contact2d study 1";

/// Slurm's --time for a task that runs one case within `seconds`: whole minutes (Slurm's unit),
/// one more for the start-up; "" for no limit.
std::string slurm_time(double seconds) {
  if (!(seconds > 0)) return "";
  const long minutes = static_cast<long>(std::ceil(seconds / 60.0)) + 1;
  char text[32];
  std::snprintf(text, sizeof text, "%ld-%02ld:%02ld:00", minutes / 1440, minutes / 60 % 24,
                minutes % 60);
  return text;
}

/// The time limit of each task: the one asked for, else the study's per-case limit.
std::string task_time(const SlurmSettings& slurm, double case_timeout_s) {
  return slurm.time.empty() ? slurm_time(case_timeout_s) : slurm.time;
}

/// slurm.sh's opening comment: what it runs, how to submit it, where its settings come from.
std::string slurm_comment(const std::string& verb, size_t cases, const std::string& time,
                          double case_timeout_s, const SlurmSettings& slurm) {
  std::ostringstream sh;
  sh << "# Slurm array job of a contact2d " << verb << " study: task K runs line K of jobs.txt\n"
     << "# (" << cases << " cases), each writing its own case folder here.\n"
     << "# Submit from this folder (jobs.txt and the case folders are relative to it):\n"
     << "#   cd STUDY_FOLDER && sbatch slurm.sh\n"
     << "# The program, the scene and this folder must be at the same paths on the compute\n"
     << "# nodes (a shared filesystem). The #SBATCH lines below come from the study's\n"
     << "# --slurm-partition, --slurm-time, --slurm-mem and --slurm-cpus-per-task; edit them\n"
     << "# here or give sbatch the same options, which override them.\n"
     << (slurm.partition.empty() ? "# No --partition: the cluster's default partition.\n" : "");
  if (time.empty())
    sh << "# No --time: the study set no per-case limit (--case-timeout 0).\n";
  else if (slurm.time.empty())
    sh << "# --time: the study's per-case limit (--case-timeout " << csv_number(case_timeout_s)
       << " s) and a minute to start;\n";
  if (!time.empty())
    sh << "# Slurm ends a task over its --time with SIGTERM, then SIGKILL (its\n"
       << "# summary.json then says \"interrupted\").\n";
  sh << "# Rerun chosen cases with sbatch --array=2,5 slurm.sh (the jobs.txt lines that\n"
     << "# `contact2d merge` lists as missing). When the tasks have finished:\n"
     << "#   contact2d merge STUDY_FOLDER\n";
  return sh.str();
}

/// slurm.sh's #SBATCH lines: what each task (one case) asks of the cluster.
std::string sbatch_lines(const std::string& verb, size_t cases, const std::string& time,
                         const SlurmSettings& slurm) {
  std::ostringstream sh;
  sh << "#SBATCH --job-name=c2d-" << verb << "\n";
  sh << "#SBATCH --array=1-" << cases << "\n";
  if (!slurm.partition.empty()) sh << "#SBATCH --partition=" << slurm.partition << "\n";
  if (!time.empty()) sh << "#SBATCH --time=" << time << "\n";
  sh << "#SBATCH --mem=" << slurm.mem << "\n";
  sh << "#SBATCH --cpus-per-task=" << slurm.cpus_per_task << "\n";
  sh << "#SBATCH --output=slurm-%A_%a.out\n";
  return sh.str();
}

/// slurm.sh: an array job whose task K runs line K of jobs.txt from the study folder.
std::string slurm_script(const std::string& verb, size_t cases, double case_timeout_s,
                         const SlurmSettings& slurm) {
  const std::string time = task_time(slurm, case_timeout_s);
  std::ostringstream sh;
  sh << "#!/bin/bash\n"
     << slurm_comment(verb, cases, time, case_timeout_s, slurm)
     << sbatch_lines(verb, cases, time, slurm) << "set -euo pipefail\n"
     << "if [ ! -f jobs.txt ]; then\n"
     << "  echo \"slurm.sh: no jobs.txt in $(pwd); submit from the study folder\" >&2\n"
     << "  exit 2\n"
     << "fi\n"
     << "export OPENBLAS_NUM_THREADS=\"${SLURM_CPUS_PER_TASK:-1}\"\n"
     << "export OMP_NUM_THREADS=\"${SLURM_CPUS_PER_TASK:-1}\"\n"
     << "sed -n \"${SLURM_ARRAY_TASK_ID}p\" jobs.txt | bash\n";
  return sh.str();
}

}  // namespace

std::string shell_quote(std::string_view word) {
  std::string quoted = "'";
  for (const char c : word) {
    if (c == '\'')
      quoted += "'\\''";
    else
      quoted += c;
  }
  return quoted + "'";
}

std::string job_line(const std::string& exe, const StudyCase& c) {
  std::string line =
      "OPENBLAS_NUM_THREADS=\"${OPENBLAS_NUM_THREADS:-1}\" "
      "OMP_NUM_THREADS=\"${OMP_NUM_THREADS:-1}\" ";
  line += shell_quote(exe);
  for (const auto& word : run_arguments(c, c.folder)) {
    if (word.find_first_of("\n\r") != std::string::npos)
      throw InputError("'" + word +
                       "': a case argument with a line break cannot go into a job list (one "
                       "job per line)");
    line += ' ';
    line += shell_quote(word);
  }
  return line;
}

void write_study_files(const std::string& dir, const std::string& verb,
                       const nlohmann::json& options, const std::vector<StudyCase>& cases,
                       const std::vector<nlohmann::json>& case_keys, double case_timeout_s,
                       const SlurmSettings& slurm) {
  const std::string exe = this_executable();
  std::string jobs;
  nlohmann::json entries = nlohmann::json::array();
  for (size_t i = 0; i < cases.size(); ++i) {
    jobs += job_line(exe, cases[i]) + "\n";
    nlohmann::json entry = i < case_keys.size() ? case_keys[i] : nlohmann::json::object();
    entry["folder"] = cases[i].folder;
    entry["args"] = cases[i].args;
    entries.push_back(entry);
  }
  const nlohmann::json manifest = {{"format", kManifestFormat},
                                   {"verb", verb},
                                   {"executable", exe},
                                   {"options", options},
                                   {"case_timeout_s", case_timeout_s},
                                   {"cases", entries}};
  core::write_file_atomic(dir + "/jobs.txt", jobs);
  core::write_file_atomic(dir + "/slurm.sh",
                          slurm_script(verb, cases.size(), case_timeout_s, slurm));
  fs::permissions(dir + "/slurm.sh", fs::perms::owner_exec | fs::perms::group_exec,
                  fs::perm_options::add);
  core::write_file_atomic(dir + "/study.json", manifest.dump(2) + "\n");
}

void refuse_existing_cases(const std::string& dir, const std::vector<StudyCase>& cases) {
  for (const auto& c : cases)
    if (fs::exists(dir + "/" + c.folder))
      throw InputError(dir + "/" + c.folder +
                       ": already exists; a job list needs a study folder without earlier case "
                       "results, which a merge would report as this study's (choose another "
                       "--out, or remove it)");
}

std::string job_list_note(const std::string& dir, size_t cases, double case_timeout_s) {
  const std::string d = shell_quote(dir);
  std::ostringstream os;
  os << "job list   " << cases << " cases, one `contact2d run` per line of " << dir
     << "/jobs.txt (run from that folder); also slurm.sh and study.json\n"
     << "run them   cd " << d << " && parallel -j 2"
     << (case_timeout_s > 0 ? " --timeout " + csv_number(case_timeout_s) : std::string())
     << " < jobs.txt    (or: sbatch slurm.sh)\n"
     << "then       contact2d merge " << d << "\n";
  return os.str();
}

ManifestNode ManifestNode::operator[](const std::string& key) const {
  const std::string path = path_.empty() ? key : path_ + "." + key;
  if (!value_->is_object() || !value_->contains(key))
    throw InputError(file_ + ": " + path +
                     ": expected a value, found none (a study manifest as contact2d compare, "
                     "sweep or bench write it)");
  return ManifestNode((*value_)[key], file_, path);
}

ManifestNode ManifestNode::operator[](size_t index) const {
  if (index >= size()) refuse("an array with an entry " + std::to_string(index));
  return ManifestNode((*value_)[index], file_, path_ + "[" + std::to_string(index) + "]");
}

bool ManifestNode::has(const std::string& key) const {
  return value_->is_object() && value_->contains(key);
}

size_t ManifestNode::size() const {
  if (!value_->is_array()) refuse("an array");
  return value_->size();
}

std::string ManifestNode::text() const {
  if (!value_->is_string()) refuse("a string");
  return value_->get<std::string>();
}

double ManifestNode::number() const {
  if (!value_->is_number()) refuse("a number");
  return value_->get<double>();
}

int ManifestNode::integer() const {
  if (!value_->is_number_integer()) refuse("an integer");
  return value_->get<int>();
}

bool ManifestNode::boolean() const {
  if (!value_->is_boolean()) refuse("true or false");
  return value_->get<bool>();
}

std::vector<std::string> ManifestNode::texts() const {
  std::vector<std::string> out;
  for (size_t i = 0; i < size(); ++i) out.push_back((*this)[i].text());
  return out;
}

void ManifestNode::refuse(const std::string& expected) const {
  throw InputError(file_ + ": " + (path_.empty() ? "the whole file" : path_) + ": expected " +
                   expected + ", found " + shown_json(*value_));
}

StudyManifest read_manifest(const std::string& dir) {
  StudyManifest m;
  m.dir = dir;
  m.file = dir + "/study.json";
  std::error_code ec;
  const fs::file_type type = fs::status(m.file, ec).type();
  if (type == fs::file_type::not_found || type == fs::file_type::directory)
    throw InputError(m.file +
                     ": cannot open the study manifest (expected the folder of a compare, sweep "
                     "or bench study, which writes study.json beside jobs.txt)");
  m.root = read_json_file(m.file);  // a FIFO, a huge or deeply nested file: refused, named
  const ManifestNode root(m.root, m.file);
  if (root["format"].text() != kManifestFormat)
    throw InputError(m.file + ": format: expected '" + kManifestFormat + "', found " +
                     quoted_found(root["format"].text()));
  m.verb = root["verb"].text();
  const ManifestNode cases = root["cases"];
  for (size_t i = 0; i < cases.size(); ++i) {
    StudyCase c{cases[i]["args"].texts(), cases[i]["folder"].text()};
    const fs::path folder(c.folder);
    if (c.folder.empty() || folder.is_absolute() || c.folder.find("..") != std::string::npos)
      throw InputError(m.file + ": cases[" + std::to_string(i) +
                       "].folder: expected a folder inside the study's, found " +
                       quoted_found(c.folder));
    m.cases.push_back(c);
  }
  return m;
}

}  // namespace c2d::app
