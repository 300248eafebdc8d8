// `contact2d merge DIR`: the report of a compare, sweep or bench study from the case folders
// that have finished, wherever they ran (DIR/study.json says which study and which cases).
#pragma once

#include <string>

namespace c2d::app {

/// Reads DIR/study.json and writes the study's table, verdict and charts from the cases whose
/// folders hold a summary.json, listing the others (terminal and markdown); a case whose
/// summary.json cannot be read (read_case_folder) is a row whose status says why. Returns 0 when
/// every case has finished, 1 when some are missing (or a case crashed, a summary was malformed
/// or a chart failed); throws InputError (exit 2) naming the file when DIR holds no valid
/// manifest (including one that is not a regular file, over 64 MiB or nested deeper than 64).
int run_merge(const std::string& dir, bool quiet);

}  // namespace c2d::app
