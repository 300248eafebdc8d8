// Result files: VTU/PVD for ParaView, nodal CSV, and the atomic file write they share.
#pragma once

#include <stdexcept>
#include <string>

#include "core/model.hpp"
#include "core/results.hpp"

namespace c2d::core {

/// A file that could not be written (a full disk, a quota, a lost mount, no permission): the
/// input was fine, the machine refused the output. Names the file and the system's reason
/// (strerror of the errno the failing call set).
class WriteError : public std::runtime_error {
 public:
  /// "PATH: cannot write: REASON", or `message` when given.
  WriteError(const std::string& path, int error_number, const std::string& message = "");
  const std::string& path() const { return path_; }
  /// The system's text for the error ("No space left on device").
  const std::string& reason() const { return reason_; }
  int error_number() const { return error_number_; }

 private:
  std::string path_, reason_;
  int error_number_;
};

/// Writes `content` to `path` through a temporary file in the same folder and a rename, so a
/// reader never sees a half-written file. Throws WriteError when a call fails (the temporary
/// file is removed).
void write_file_atomic(const std::string& path, const std::string& content);

/// VTK XML unstructured grid (format version 1.0, UInt64 block headers): displacement,
/// reaction, element and smoothed stresses, von Mises, principal stresses, ZZ local parameter,
/// body id, material id.
std::string vtu_document(const Model& model, const Results& results,
                         VtuEncoding encoding = VtuEncoding::kBinary);

/// ParaView collection listing (time, file) pairs.
std::string pvd_document(const std::vector<std::pair<double, std::string>>& steps);

/// One row per node: node, x, y, ux, uy, sx, sy, sxy, vm, rx, ry.
std::string nodes_csv(const Model& model, const Results& results);

}  // namespace c2d::core
