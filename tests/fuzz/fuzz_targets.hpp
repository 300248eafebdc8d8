// The readers the fuzz targets drive, one function each: feed bytes, accept a located
// InputError, anything else (a crash, a hang, another exception) is a finding. Shared by the
// libFuzzer executables (scripts/fuzz.sh) and the regression test that replays every kept input.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace c2d::fuzz {

/// The scene reader (TOML text → Scene, selections and all; no meshing).
void scene(const uint8_t* data, size_t size);
/// The .msh pre-parse; an input it accepts is then read by gmsh itself.
void msh(const uint8_t* data, size_t size);
/// The seed's .dat reader.
void dat(const uint8_t* data, size_t size);
/// The JSON files a user can edit, the same bytes as both: a study's study.json (the manifest
/// `contact2d merge` reads) and a case's summary.json (read with every figure a study takes).
void json(const uint8_t* data, size_t size);
/// The VTU reader of `contact2d plot`; a file it accepts must keep what the plots index by
/// (cell node ids within the points, every data array its points' or cells' size).
void vtu(const uint8_t* data, size_t size);

}  // namespace c2d::fuzz
