// A validating pre-parse of Gmsh .msh files, run before gmsh reads them.
//
// gmsh's MSH reader trusts its input: a wrong block count, a node tag of 2^31, a negative
// physical tag or an element that names a missing node corrupt its heap or crash it, and no
// exception reaches the caller. check_msh_file reads the file once, token by token with line
// numbers, and refuses anything gmsh could choke on with one line naming file:line, what was
// expected and what was found:
//   - $MeshFormat first: ASCII MSH 4.1 or 2.2 (binary files and other versions refused);
//   - every section closed by its $End marker; unknown sections skipped to their end;
//   - $PhysicalNames: dimension 0..3, tag 1..2^31−1, a quoted name, each name given to one
//     group (gmsh would merge a curve and a surface of the same name into one node set);
//   - $Entities (4.1): counts, tags and physical tags in range;
//   - $Nodes: block counts that add up to the declared total, node tags unique and in
//     1..2^31−1 (and within the declared min/max in 4.1), finite coordinates, every node in
//     the first node's plane z = const (the solver drops z);
//   - $Elements: block counts that add up, known element types with their node counts, tags in
//     range, every referenced node defined.
// Counts are checked against what is left of the file before anything is sized by them, so a
// huge count cannot allocate: the memory used is O(file size).
#pragma once

#include <string>

namespace c2d::core {

/// Throws InputError (one line: path:line: expected …, found …) unless `path` is a well-formed
/// ASCII MSH 4.1 or 2.2 file.
void check_msh_file(const std::string& path);

/// The same check on the file's contents (`path` names it in messages).
void check_msh_text(const std::string& text, const std::string& path);

}  // namespace c2d::core
