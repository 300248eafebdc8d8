#include "app/output_folder.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <system_error>

#include "core/errors.hpp"

namespace c2d::app {

namespace fs = std::filesystem;

namespace {

constexpr const char* kManifestTitle = "contact2d run folder";
constexpr const char* kWorkTitle = "contact2d work folder";

/// The file names a manifest lists (and its run id); false when `dir` has no valid manifest.
bool read_manifest_names(const fs::path& dir, std::set<std::string>& names,
                         std::string* run_id = nullptr) {
  std::error_code ec;
  const fs::path file = dir / kRunManifest;
  if (!fs::is_regular_file(file, ec) || fs::file_size(file, ec) > (1u << 24)) return false;
  std::ifstream in(file);
  std::string line;
  if (!std::getline(in, line) || line != kManifestTitle) return false;
  if (!std::getline(in, line) || line.rfind("run ", 0) != 0) return false;
  if (run_id) *run_id = line.substr(4);
  while (std::getline(in, line))
    if (!line.empty()) names.insert(line);
  return true;
}

/// Writes the manifest of `dir` (atomically: a temporary file renamed over it).
void store_manifest(const std::string& dir, const std::string& run_id,
                    const std::set<std::string>& names) {
  std::ostringstream text;
  text << kManifestTitle << "\nrun " << run_id << "\n";
  for (const std::string& name : names)
    if (name.find('\n') == std::string::npos && name.find('/') == std::string::npos)
      text << name << "\n";
  const std::string path = dir + "/" + kRunManifest, tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << text.str();
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
}

/// Whether `p` lies inside folder `dir` (both made absolute, lexically).
bool inside(const fs::path& p, const fs::path& dir) {
  std::error_code ec;
  const fs::path a = fs::weakly_canonical(fs::absolute(p, ec), ec);
  const fs::path rel = a.lexically_relative(fs::weakly_canonical(dir, ec));
  return !rel.empty() && *rel.begin() != ".." && rel != ".";
}

/// Throws InputError naming `dir` for the first entry of `folder` its manifest does not list.
void refuse_unlisted_entries(const std::string& dir, const fs::path& folder) {
  std::error_code ec;
  std::set<std::string> listed;
  const bool manifest = read_manifest_names(folder, listed);
  for (const auto& e : fs::directory_iterator(folder, ec)) {
    const std::string name = e.path().filename().string();
    if (name == kRunManifest && manifest) continue;
    // A study's worker writes the case's stdout.log before the run starts.
    const bool ours = e.is_regular_file(ec) && (name == "stdout.log" || listed.count(name));
    if (ours) continue;
    throw InputError(dir + ": expected a new or empty output folder or an earlier run's (a run "
                     "replaces it whole), found a folder holding '" + name + "'" +
                     (manifest ? ", which the earlier run did not write"
                               : std::string(" and no ") + kRunManifest + " manifest"));
  }
}

}  // namespace

void refuse_file_as_folder(const std::string& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw InputError(dir + ": expected an output folder, found a file");
}

void refuse_foreign_folder(const std::string& dir, const std::vector<std::string>& inputs) {
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
  if (!fs::is_directory(folder, ec) || fs::is_empty(folder, ec)) return;
  refuse_unlisted_entries(dir, folder);
  for (const std::string& input : inputs)
    if (!input.empty() && inside(input, folder))
      throw InputError(dir + ": expected an output folder that does not hold the run's input "
                       "(a run replaces its output folder whole), found " + input + " inside");
}

void create_output_folder(const std::string& dir) {
  refuse_file_as_folder(dir);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec)
    throw InputError(dir + ": expected an output folder that can be created, found: " +
                     ec.message());
}

void write_run_manifest(const std::string& dir, const std::string& run_id,
                        const std::vector<std::string>& coming) {
  std::set<std::string> names(coming.begin(), coming.end());
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name != kRunManifest && name != kWorkMarker && e.is_regular_file(ec) &&
        name.find('\n') == std::string::npos)
      names.insert(name);
  }
  store_manifest(dir, run_id, names);
}

void add_to_run_manifest(const std::string& dir, const std::vector<std::string>& names) {
  std::set<std::string> listed;
  std::string run_id;
  if (!read_manifest_names(dir, listed, &run_id)) return;
  listed.insert(names.begin(), names.end());
  store_manifest(dir, run_id, listed);
}

std::vector<std::string> run_manifest_names(const std::string& dir) {
  std::set<std::string> listed;
  read_manifest_names(dir, listed);
  return {listed.begin(), listed.end()};
}

bool remove_run_folder(const std::string& dir) {
  std::set<std::string> listed;
  std::error_code ec;
  if (!read_manifest_names(dir, listed)) return false;
  for (const std::string& name : listed)
    if (name.find('/') == std::string::npos && name != "." && name != "..")
      fs::remove(fs::path(dir) / name, ec);
  fs::remove(fs::path(dir) / "stdout.log", ec);
  fs::remove(fs::path(dir) / kRunManifest, ec);
  return fs::remove(dir, ec) && !ec;  // only when empty
}

bool create_work_folder(const std::string& dir) {
  std::error_code ec;
  if (!fs::create_directory(dir, ec) || ec) return false;  // exists already, or cannot be made
  std::ofstream out(dir + "/" + kWorkMarker);
  out << kWorkTitle << "\npid " << ::getpid() << "\n";
  return static_cast<bool>(out);
}

long work_folder_owner(const std::string& dir) {
  std::error_code ec;
  const fs::path file = fs::path(dir) / kWorkMarker;
  if (!fs::is_regular_file(file, ec) || fs::file_size(file, ec) > 256) return -1;
  std::ifstream in(file);
  std::string title, word;
  long pid = -1;
  if (!std::getline(in, title) || title != kWorkTitle || !(in >> word >> pid) || word != "pid")
    return -1;
  return pid > 0 ? pid : -1;
}

}  // namespace c2d::app
