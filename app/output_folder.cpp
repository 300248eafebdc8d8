#include "app/output_folder.hpp"

#include <filesystem>
#include <system_error>

#include "core/errors.hpp"

namespace c2d::app {

void create_output_folder(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw InputError(dir + ": expected an output folder, found a file");
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": expected an output folder that can be created, found: " + ec.message());
}

}  // namespace c2d::app
