// The files of one `contact2d run`, each written once into its output folder: the VTU series
// while the solve goes on (load steps, adaptive cycles), then the tables, the charts and
// summary.json from what the solve returned.
#pragma once

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "app/run/adapt.hpp"
#include "app/run/solve_scene.hpp"
#include "core/scene.hpp"
#include "core/writers.hpp"

namespace c2d::app {

/// For programs, never called by the library or the Python module: SIGINT and SIGTERM end the
/// process with exit 130; while a RunOutput is armed (end_on_interrupt) its files are put in
/// place first. Install it before any work, so an early interrupt also exits 130.
void install_interrupt_handler();

/// summary.json's content for a solved run (`adapt` for adaptive runs, else null).
nlohmann::json run_summary(const core::Scene& scene, const SceneRun& run, const AdaptRun* adapt);

class RunOutput {
 public:
  using Clock = std::chrono::steady_clock;

  /// Writes into a fresh work folder beside `dir` (DIR.part.PID), which commit() renames to
  /// `dir`, replacing an earlier run's folder whole (the files its manifest lists): a folder
  /// never mixes two runs, and a run refused or ended by an exception leaves neither. Throws
  /// InputError when `dir` names a file, cannot be created, holds the scene or its meshes, or
  /// holds anything an earlier run did not write (refuse_foreign_folder). [output] of `scene` decides whether fields and charts are written;
  /// `scene` must outlive this object.
  RunOutput(const core::Scene& scene, std::string dir);
  ~RunOutput();
  RunOutput(const RunOutput&) = delete;
  RunOutput& operator=(const RunOutput&) = delete;

  /// The output folder as the user named it (the files appear there at commit()).
  const std::string& dir() const { return target_; }
  /// The work folder the files are written to until commit().
  const std::string& work_dir() const { return dir_; }
  /// Puts the finished run in place of the output folder.
  void commit();
  /// From now until commit(), the handler of install_interrupt_handler() (if the program
  /// installed it) ends the run with exit 130, leaving the files written so far in the output
  /// folder with a summary.json whose status is "interrupted" (an earlier run's folder is set
  /// aside as DIR.part.PID.interrupted-aside and removed). Changes no signal disposition.
  void end_on_interrupt();

  /// A converged load step: step_NNNN.vtu, and results.pvd rewritten to list it.
  void write_step(const nonlinear::StepRecord& step, const core::Model& model,
                  const core::Results& results);

  /// A solved adaptive cycle: cycle_NN.vtu (adapt.pvd rewritten) and adapt.csv with every
  /// cycle so far.
  void write_cycle(const AdaptCycle& cycle, const SceneRun& run);

  /// After the solve: the final state's VTU where no load step left it, nodes.csv, and for
  /// contact or load-stepped runs contact.csv, trace.csv and contact_steps.csv; charts of a
  /// converged run. Sets the output and total times of `run.results` (total from `start`).
  /// Returns "" or why a chart was not written.
  std::string write_results(SceneRun& run, Clock::time_point start);

  /// summary.json of the run (after write_results, whose times it reports); `adapt` for
  /// adaptive runs. Returns what it wrote.
  nlohmann::json write_summary(const SceneRun& run, const AdaptRun* adapt);

  /// A file of this run that could not be written, as the user sees it: the output folder they
  /// named (not the work folder beside it, which is gone once the run ends), the file, and the
  /// system's reason; the path and errno are kept.
  core::WriteError in_output_folder(const core::WriteError& e) const;

  /// Appends to run.log as the run goes.
  void log(const std::string& text);

 private:
  using Series = std::vector<std::pair<double, std::string>>;  ///< (time, file) per VTU
  /// A VTU of a series: the file, then its collection rewritten, so the .pvd always lists what
  /// exists.
  void write_series(Series& files, const std::string& pvd, const char* pattern, int number,
                    double time, const core::Model& model, const core::Results& results);
  void write_tables(const SceneRun& run);
  std::string write_charts(const SceneRun& run);

  /// Removes the work folders (marked as such) of earlier runs into this target whose process
  /// is gone.
  static void remove_stale_work_folders(const std::filesystem::path& folder);

  const core::Scene& scene_;
  std::string target_, dir_, run_id_;
  std::string created_parent_;  ///< the topmost folder this run created above its target
  bool committed_ = false;
  bool interrupt_armed_ = false;
  std::ofstream log_;
  Series step_files_, cycle_files_;
  std::vector<AdaptCycle> cycles_;
};

}  // namespace c2d::app
