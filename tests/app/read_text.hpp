// The whole of a file as text, for tests that look into what a run wrote ("" when the file
// cannot be read, so a missing file fails the test's own assertion on its content).
#pragma once

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace c2d::test {

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace c2d::test
