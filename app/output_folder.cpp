#include "app/output_folder.hpp"

#include <filesystem>
#include <system_error>

#include "core/errors.hpp"

namespace c2d::app {

void refuse_file_as_folder(const std::string& dir) {
  std::error_code ec;
  if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec))
    throw InputError(dir + ": expected an output folder, found a file");
}

void create_output_folder(const std::string& dir) {
  refuse_file_as_folder(dir);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": expected an output folder that can be created, found: " + ec.message());
}

}  // namespace c2d::app
