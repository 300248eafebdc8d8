#include "app/output_folder.hpp"

#include <array>
#include <filesystem>
#include <string_view>
#include <system_error>

#include "core/errors.hpp"

namespace c2d::app {

void refuse_file_as_folder(const std::string& dir) {
  std::error_code ec;
  if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec))
    throw InputError(dir + ": expected an output folder, found a file");
}

namespace {

/// What a run or its charts write into a run folder.
bool run_file(const std::filesystem::directory_entry& e) {
  static constexpr std::array<std::string_view, 9> kExtensions = {
      ".json", ".csv", ".vtu", ".pvd", ".png", ".svg", ".log", ".dat", ".gp"};
  std::error_code ec;
  if (!e.is_regular_file(ec)) return false;
  const std::string ext = e.path().extension().string();
  for (const std::string_view k : kExtensions)
    if (ext == k) return true;
  return false;
}

}  // namespace

void refuse_foreign_folder(const std::string& dir) {
  namespace fs = std::filesystem;
  for (size_t i = 0; i < dir.size(); ++i)
    if (static_cast<unsigned char>(dir[i]) < 0x20 || dir[i] == 0x7f)
      throw InputError("--out: expected a folder name without control characters, found "
                       "character " + std::to_string(static_cast<int>(dir[i])) +
                       " at position " + std::to_string(i + 1));
  std::error_code ec;
  fs::path folder = fs::absolute(dir, ec).lexically_normal();
  if (!folder.has_filename()) folder = folder.parent_path();
  const fs::path here = fs::current_path(ec).lexically_normal();
  const fs::path rel = here.lexically_relative(folder);
  if (!ec && !rel.empty() && *rel.begin() != "..")
    throw InputError(dir + ": expected an output folder that does not hold the current folder "
                     "(a run replaces its output folder whole), found " + folder.string());
  if (!fs::is_directory(folder, ec)) return;
  bool summary = false;
  std::string foreign;
  for (const auto& e : fs::directory_iterator(folder, ec)) {
    const std::string name = e.path().filename().string();
    // A run's summary or log, or the log a study's worker writes before its run starts.
    if (name == "summary.json" || name == "run.log" || name == "stdout.log") summary = true;
    if (!run_file(e) && foreign.empty()) foreign = e.path().filename().string();
  }
  const bool empty = fs::is_empty(folder, ec);
  if (!empty && (!summary || !foreign.empty()))
    throw InputError(dir + ": expected a new or empty output folder or an earlier run's (a run "
                     "replaces it whole), found a folder holding " +
                     (foreign.empty() ? std::string("no summary.json or run.log") : "'" + foreign + "'"));
}

void create_output_folder(const std::string& dir) {
  refuse_file_as_folder(dir);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": expected an output folder that can be created, found: " + ec.message());
}

}  // namespace c2d::app
