// `contact2d merge DIR`: the report of a compare, sweep or bench study from the case folders
// that have finished, wherever they ran (DIR/study.json says which study and which cases).
#pragma once

#include <string>

namespace c2d::app {

/// Reads DIR/study.json and writes the study's table, verdict and charts from the cases whose
/// folders hold a summary.json, listing the others (terminal and markdown). Returns 0 when every
/// case has finished, 1 when some are missing (or a case crashed or a chart failed); throws
/// InputError (exit 2) naming the file when DIR holds no valid manifest.
int run_merge(const std::string& dir, bool quiet);

}  // namespace c2d::app
