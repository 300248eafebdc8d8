#include "app/studies/merge.hpp"

#include <iostream>

#include "app/studies/bench.hpp"
#include "app/studies/compare.hpp"
#include "app/studies/job_list.hpp"
#include "app/studies/sweep.hpp"
#include "core/errors.hpp"

namespace c2d::app {

int run_merge(const std::string& dir, bool quiet) {
  const StudyManifest m = read_manifest(dir);
  int (*merge)(const StudyManifest&, bool) = m.verb == "compare" ? merge_compare
                                             : m.verb == "sweep" ? merge_sweep
                                             : m.verb == "bench" ? merge_bench
                                                                 : nullptr;
  if (!merge)
    throw InputError(m.file + ": verb: expected compare, sweep or bench, found " +
                     quoted_found(m.verb));
  if (!quiet)
    std::cout << "merge      " << m.verb << " study of " << m.cases.size() << " cases in " << dir
              << "\n";
  return merge(m, quiet);
}

}  // namespace c2d::app
