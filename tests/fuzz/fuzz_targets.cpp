#include "fuzz_targets.hpp"

#include <gmsh.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>

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

}  // namespace c2d::fuzz
