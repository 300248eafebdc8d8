// A study's cases as a job list that any scheduler can run, and the manifest a merge reports
// from. Every study writes, into its folder:
//   jobs.txt    one `contact2d run` command line per case, to be run from the study folder
//               (each writes its own case folder, relative to it), e.g. by GNU parallel
//   slurm.sh    an sbatch array script: task K runs line K of jobs.txt, with the partition,
//               time limit, memory and CPUs per task of SlurmSettings (#SBATCH lines); the
//               time limit, unless set, is the study's per-case limit
//   study.json  the manifest: the verb, its options, this executable, and every case's folder,
//               arguments and the verb's keys for its row; all `contact2d merge` needs
// This program never runs these lines (it starts its cases with an argument vector): they are
// text for the user's shell, each argument single-quoted so that it arrives as one word.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "app/studies/slurm_settings.hpp"
#include "app/studies/study.hpp"

namespace c2d::app {

/// `word` as one POSIX shell word: in single quotes, each ' written as '\''.
std::string shell_quote(std::string_view word);

/// The line of jobs.txt that runs case `c` of a study from the study folder: `exe run ARGS
/// --out FOLDER --quiet`, every word quoted, after OPENBLAS_NUM_THREADS and OMP_NUM_THREADS
/// set to 1 unless the environment sets them (cases run side by side; one case's BLAS threads
/// on another's cores slowed a factorisation 20-fold). Throws InputError naming the argument
/// when one holds a line break (a line per job cannot hold it).
std::string job_line(const std::string& exe, const StudyCase& c);

/// Writes DIR/jobs.txt, DIR/slurm.sh and DIR/study.json: the verb, its `options`, this
/// executable, and per case its folder, its arguments and `case_keys[i]` (the verb's own).
/// `case_timeout_s` (0: none), the study's per-case limit, becomes study.json's
/// case_timeout_s and, unless `slurm` sets a time, each Slurm task's time limit; `slurm` gives
/// slurm.sh's other #SBATCH lines. jobs.txt's lines stay a plain `contact2d run` (a runner
/// sets its own limit, e.g. `parallel --timeout`).
void write_study_files(const std::string& dir, const std::string& verb,
                       const nlohmann::json& options, const std::vector<StudyCase>& cases,
                       const std::vector<nlohmann::json>& case_keys, double case_timeout_s,
                       const SlurmSettings& slurm);

/// A job list goes into a folder without the case folders it names: until its job has run, a
/// merge would report an earlier result as this study's. Throws InputError naming the first
/// that exists.
void refuse_existing_cases(const std::string& dir, const std::vector<StudyCase>& cases);

/// For the terminal after a job list was written: where, and how to run (each case within
/// `case_timeout_s`, 0: no limit) and merge it.
std::string job_list_note(const std::string& dir, size_t cases, double case_timeout_s);

/// A value of a manifest and where it is ("DIR/study.json: cases[2].level"), so that a missing
/// or mistyped value is refused as bad input naming the file and the key.
class ManifestNode {
 public:
  ManifestNode(const nlohmann::json& value, std::string file, std::string path = "")
      : value_(&value), file_(std::move(file)), path_(std::move(path)) {}
  ManifestNode operator[](const std::string& key) const;  ///< throws when absent
  ManifestNode operator[](size_t index) const;            ///< throws when out of range
  bool has(const std::string& key) const;
  size_t size() const;  ///< of an array (throws for anything else)
  std::string text() const;
  double number() const;
  int integer() const;
  bool boolean() const;
  std::vector<std::string> texts() const;
  const nlohmann::json& json() const { return *value_; }

 private:
  [[noreturn]] void refuse(const std::string& expected) const;
  const nlohmann::json* value_;
  std::string file_, path_;  ///< the manifest, and the key path within it
};

/// A study's manifest, read back.
struct StudyManifest {
  std::string dir;   ///< the study folder
  std::string file;  ///< DIR/study.json
  std::string verb;  ///< compare, sweep or bench
  nlohmann::json root;
  std::vector<StudyCase> cases;
  ManifestNode options() const { return ManifestNode(root, file)["options"]; }
  ManifestNode case_keys(size_t i) const { return ManifestNode(root, file)["cases"][i]; }
};

/// Reads DIR/study.json and its cases. Throws InputError naming the file and what was
/// expected when it is missing, not JSON, not a study manifest, or a key is missing or wrong.
StudyManifest read_manifest(const std::string& dir);

}  // namespace c2d::app
