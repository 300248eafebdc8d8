// Result files: VTU/PVD for ParaView, nodal CSV, and the atomic file write they share.
#pragma once

#include <string>

#include "core/model.hpp"
#include "core/results.hpp"

namespace c2d::core {

/// Writes `content` to `path` through a temporary file in the same folder and a rename, so a
/// reader never sees a half-written file. Throws std::runtime_error on I/O failure.
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
