#include "fuzz_targets.hpp"

#include <gmsh.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "app/report/vtu_reader.hpp"
#include "app/studies/job_list.hpp"
#include "app/studies/study.hpp"
#include "core/errors.hpp"
#include "core/legacy_reader.hpp"
#include "core/msh_check.hpp"
#include "core/scene.hpp"

namespace c2d::fuzz {

namespace {

/// The bytes in a private temporary file (readers that take a path), removed afterwards.
class TempFile {
 public:
  TempFile(const uint8_t* data, size_t size, const char* suffix) {
    const char* dir = std::getenv("TMPDIR");
    path_ = std::string(dir && *dir ? dir : "/tmp") + "/c2d_fuzz_" + std::to_string(::getpid()) +
            suffix;
    std::ofstream out(path_, std::ios::binary);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  ~TempFile() { std::remove(path_.c_str()); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

/// The bytes as NAME in a private temporary folder.
std::string write_in_folder(const uint8_t* data, size_t size, const std::string& folder,
                            const char* name) {
  const std::string path = folder + "/" + name;
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

/// Stops the fuzzer on a broken invariant of an accepted input.
void require(bool invariant) {
  if (!invariant) std::abort();
}

}  // namespace

void scene(const uint8_t* data, size_t size) {
  try {
    core::parse_scene(std::string(reinterpret_cast<const char*>(data), size), "fuzz.toml");
  } catch (const InputError&) {
  }
}

void msh(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    core::check_msh_text(text, "fuzz.msh");
  } catch (const InputError&) {
    return;
  }
  // Accepted: gmsh must read it without crashing.
  static const bool initialised = [] {
    gmsh::initialize();
    gmsh::option::setNumber("General.Terminal", 0);
    return true;
  }();
  (void)initialised;
  const TempFile file(data, size, ".msh");
  try {
    gmsh::clear();
    gmsh::open(file.path());
  } catch (...) {
  }
}

void dat(const uint8_t* data, size_t size) {
  const TempFile file(data, size, ".dat");
  try {
    core::read_legacy_scene(file.path());
  } catch (const InputError&) {
  }
}

void json(const uint8_t* data, size_t size) {
  const char* tmp = std::getenv("TMPDIR");
  const std::string dir =
      std::string(tmp && *tmp ? tmp : "/tmp") + "/c2d_fuzz_json_" + std::to_string(::getpid());
  std::filesystem::create_directories(dir);
  write_in_folder(data, size, dir, "study.json");
  write_in_folder(data, size, dir, "summary.json");
  try {
    app::read_manifest(dir);
  } catch (const InputError&) {
  }
  // A case folder is read whatever it holds: a malformed summary is a status, never a throw.
  app::RunFigures figures;
  figures.read(app::read_case_folder(dir));
  std::filesystem::remove_all(dir);
}

void vtu(const uint8_t* data, size_t size) {
  const TempFile file(data, size, ".vtu");
  app::VtuData v;
  try {
    v = app::read_vtu(file.path());
  } catch (const InputError&) {
    return;
  }
  const int nodes = v.order == 1 ? 3 : 6;
  for (const auto& cell : v.cells)
    for (int i = 0; i < nodes; ++i)
      require(cell[i] >= 0 && static_cast<size_t>(cell[i]) < v.points.size());
  for (const auto& [name, values] : v.point_data)
    require(values.size() == static_cast<size_t>(v.components.at(name)) * v.points.size());
  for (const auto& [name, values] : v.cell_data)
    require(values.size() == static_cast<size_t>(v.components.at(name)) * v.cells.size());
}

}  // namespace c2d::fuzz
