// The .msh pre-parse (issue 16, finding 3): one-token edits of a valid MSH 4.1 file that crashed
// gmsh's reader (a block count, a node tag of 2^31, a negative physical tag, a physical
// dimension of 9, ...) are refused with one line naming file:line, what was expected and what
// was found; the valid file and a valid MSH 2.2 file pass.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "core/msh_check.hpp"

using namespace c2d;

namespace {

std::string beam() {
  std::ifstream in(std::string(C2D_SOURCE_DIR) + "/examples/legacy/v1_beam.msh");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The file with line `line` (1-based) replaced.
std::string edit(const std::string& text, int line, const std::string& replacement) {
  std::istringstream in(text);
  std::string out, l;
  for (int k = 1; std::getline(in, l); ++k) out += (k == line ? replacement : l) + "\n";
  return out;
}

std::string refusal(const std::string& text) {
  try {
    core::check_msh_text(text, "part.msh");
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace

TEST(MshCheck, ValidFilesPass) {
  EXPECT_NO_THROW(core::check_msh_text(beam(), "v1_beam.msh"));
  const std::string v2 =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"plate\"\n$EndPhysicalNames\n"
      "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n"
      "$Elements\n2\n1 2 2 1 1 1 2 3\n2 2 2 1 1 1 3 4\n$EndElements\n"
      "$Comments\nanything here\n$EndComments\n";
  EXPECT_NO_THROW(core::check_msh_text(v2, "v2.msh"));
}

TEST(MshCheck, OneTokenEditsAreRefusedWithTheirLine) {
  const std::string text = beam();
  struct Case {
    int line;
    std::string replacement, expect;
  };
  // Line numbers of examples/legacy/v1_beam.msh: 2 format, 6-7 physical names, 15 the $Nodes
  // header, 16 a node block, 17 a node tag, 19 coordinates, 32 the $Elements header, 34 an
  // element, 30 $EndNodes.
  const std::vector<Case> cases = {
      {15, "3 6 1 6", "numNodesInBlock"},           // one block more than the file holds
      {15, "2 7 1 6", "declared 7 nodes"},          // total that the blocks do not add up to
      {15, "2 2000000000 1 6", "remaining lines"},  // a count no file of this size can hold
      {17, "2147483648", "node tag"},               // a tag beyond int
      {17, "3", "not used before"},                 // a repeated node tag
      {6, "1 -1 \"root\"", "physical tag"},
      {7, "9 2 \"beam\"", "physical dimension"},
      {19, "nan 0 0", "finite number"},
      {34, "1 1 99", "node defined in $Nodes"},
      {33, "1 1 99 1", "known element type"},
      {2, "4.1 1 8", "ASCII"},
      {2, "3.0 0 8", "version"},
      {30, "$EndNode", "$EndNodes"},
      {1, "$Nodes", "$MeshFormat"},
  };
  for (const Case& c : cases) {
    const std::string m = refusal(edit(text, c.line, c.replacement));
    EXPECT_NE(m.find("part.msh:"), std::string::npos) << c.replacement << ": " << m;
    EXPECT_NE(m.find(c.expect), std::string::npos) << c.replacement << ": " << m;
    EXPECT_NE(m.find("expected"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
  // The line named is the edited one (or, for counts that do not add up, where it shows).
  EXPECT_NE(refusal(edit(text, 17, "2147483648")).find("part.msh:17:"), std::string::npos);
  EXPECT_NE(refusal(edit(text, 7, "9 2 \"beam\"")).find("part.msh:7:"), std::string::npos);
  // A truncated file.
  EXPECT_NE(refusal(text.substr(0, text.find("$EndElements"))).find("end of the file"),
            std::string::npos);
}

// Issue 32, finding 9: a curve and the surface both named "root" were merged into one node set
// (a support on "root" clamped the whole body); the second name is refused on its line, naming
// both groups.
TEST(MshCheck, APhysicalNameGivenToTwoGroupsIsRefused) {
  const std::string m = refusal(edit(beam(), 7, "2 2 \"root\""));
  EXPECT_EQ(m.rfind("part.msh:7: expected a physical name given to one group", 0), 0u) << m;
  EXPECT_NE(m.find("'root' for both the physical curve 1 (line 6) and the physical surface 2"),
            std::string::npos)
      << m;
}

// Issue 32, finding 9: nodes off the first node's plane were read with z dropped; the node
// farthest off it is refused on its coordinate line with its tag and z. A mesh in another plane
// z = const, or with z off by round-off, is still read.
TEST(MshCheck, NodesOffThePlaneAreRefused) {
  const std::string m = refusal(edit(beam(), 27, "0.5 0.3 0.25"));
  EXPECT_EQ(m, "part.msh:27: expected every node in the plane of the first, z = 0 (a 2D mesh), "
               "found node 4 at z = 0.25");
  std::string lifted = beam();
  for (int line : {19, 20, 26, 27, 28, 29}) {
    std::istringstream in(lifted);
    std::string l;
    for (int k = 1; k <= line; ++k) std::getline(in, l);
    lifted = edit(lifted, line, l.substr(0, l.rfind(' ')) + " 5");
  }
  EXPECT_EQ(refusal(lifted), "accepted");
  EXPECT_EQ(refusal(edit(beam(), 27, "0.5 0.3 1e-12")), "accepted");
  const std::string v2 =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
      "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0.5\n4 0 1 0\n$EndNodes\n"
      "$Elements\n2\n1 2 2 1 1 1 2 3\n2 2 2 1 1 1 3 4\n$EndElements\n";
  EXPECT_EQ(refusal(v2), "part.msh:8: expected every node in the plane of the first, z = 0 (a 2D "
                         "mesh), found node 3 at z = 0.5");
}
