// The output folder of a run or a study, created up front so that a path that cannot hold one
// is refused as bad input before any work.
#pragma once

#include <string>

namespace c2d::app {

/// Throws InputError naming `dir` when it names an existing file (a folder, or nothing yet, is
/// fine).
void refuse_file_as_folder(const std::string& dir);

/// Throws InputError naming `dir` when a run may not replace it whole: a name with control
/// characters, a folder holding the current folder (".", "..", "/"), or an existing folder
/// that is neither empty nor an earlier run's (a run's files only: its summary.json, run.log
/// or a study worker's stdout.log, and the .json, .csv, .vtu, .pvd, .png, .svg, .log, .dat,
/// .gp files runs and charts write). A run
/// replaces its output folder, so pointing --out at a project folder would delete its files.
void refuse_foreign_folder(const std::string& dir);

/// Creates `dir` (and its parents) if needed. Throws InputError naming `dir` when it names an
/// existing file or cannot be created (permissions, a file on the path).
void create_output_folder(const std::string& dir);

}  // namespace c2d::app
