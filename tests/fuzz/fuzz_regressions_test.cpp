// Replays every kept fuzz input (tests/fuzz/regressions/<reader>/) and the seed corpus (the
// examples' scenes, .msh and .dat files) through the readers: each must be read or refused
// with an InputError; a crash or any other exception fails the test. (issue 16)
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "fuzz_targets.hpp"

namespace fs = std::filesystem;

namespace {

std::vector<fs::path> inputs(const std::string& reader, const std::string& extension) {
  std::vector<fs::path> out;
  const fs::path kept = fs::path(C2D_SOURCE_DIR) / "tests/fuzz/regressions" / reader;
  if (fs::exists(kept))
    for (const auto& e : fs::directory_iterator(kept)) out.push_back(e.path());
  for (const auto& e : fs::recursive_directory_iterator(fs::path(C2D_SOURCE_DIR) / "examples"))
    if (e.path().extension() == extension) out.push_back(e.path());
  return out;
}

std::string bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void replay(void (*reader)(const uint8_t*, size_t), const std::string& name,
            const std::string& extension) {
  const std::vector<fs::path> files = inputs(name, extension);
  EXPECT_FALSE(files.empty()) << name;
  for (const fs::path& p : files) {
    const std::string b = bytes(p);
    EXPECT_NO_THROW(reader(reinterpret_cast<const uint8_t*>(b.data()), b.size())) << p;
  }
}

}  // namespace

TEST(FuzzRegressions, SceneReader) { replay(c2d::fuzz::scene, "scene", ".toml"); }
TEST(FuzzRegressions, MshPreParseAndGmsh) { replay(c2d::fuzz::msh, "msh", ".msh"); }
TEST(FuzzRegressions, DatReader) { replay(c2d::fuzz::dat, "dat", ".dat"); }
TEST(FuzzRegressions, StudyAndSummaryJson) { replay(c2d::fuzz::json, "json", ".json"); }
TEST(FuzzRegressions, VtuReader) { replay(c2d::fuzz::vtu, "vtu", ".vtu"); }
