// What a study's slurm.sh asks of the cluster for each array task: its #SBATCH lines for the
// partition, the time limit, the memory and the CPUs (--slurm-partition, --slurm-time,
// --slurm-mem, --slurm-cpus-per-task). The command line checks each value before it gets here:
// every one becomes a line of a script, so none may hold a line break or a space.
#pragma once

#include <string>

namespace c2d::app {

struct SlurmSettings {
  /// Empty: no --partition line, the cluster's default partition (a cluster without one
  /// refuses the job).
  std::string partition;
  /// Slurm's time format (minutes, M:S, H:M:S, D-H, D-H:M, D-H:M:S). Empty: the study's
  /// per-case limit in whole minutes and one more to start; no line without that limit.
  std::string time;
  /// Per task (each case is a task), Slurm's size format: the bench ladder's largest case, a
  /// 1.2M-DOF Hertz run, peaks at 3.4 GB; a cluster's default can be a few hundred MB.
  std::string mem = "4G";
  /// Threads per case (OPENBLAS_NUM_THREADS and OMP_NUM_THREADS follow it in the task).
  int cpus_per_task = 1;
};

}  // namespace c2d::app
