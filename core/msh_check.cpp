#include "core/msh_check.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "core/errors.hpp"

namespace c2d::core {

namespace {

constexpr long long kMaxTag = 2147483647;  // gmsh stores tags as int

/// 'text', built without operator+ on a literal (GCC 12 warns falsely about it, -Wrestrict).
std::string quoted(const std::string& text) { return quoted_found(text); }

/// Node count of each element type gmsh can write (types 1-11 and the common higher orders).
int nodes_of_type(long long type) {
  static const std::map<long long, int> kNodes = {
      {1, 2},  {2, 3},  {3, 4},   {4, 4},   {5, 8},   {6, 6},   {7, 5},   {8, 3},
      {9, 6},  {10, 9}, {11, 10}, {12, 27}, {13, 18}, {14, 14}, {15, 1},  {16, 8},
      {17, 20}, {18, 15}, {19, 13}, {20, 9}, {21, 10}, {26, 4}, {27, 5}, {28, 6}};
  const auto it = kNodes.find(type);
  return it == kNodes.end() ? -1 : it->second;
}

/// The file as lines of whitespace-separated tokens, read with line numbers.
class Reader {
 public:
  Reader(const std::string& text, const std::string& path) : path_(path) {
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      lines_.push_back(std::move(line));
    }
  }

  bool done() const { return next_ >= lines_.size(); }
  int line_number() const { return static_cast<int>(current_) + 1; }
  /// Lines not yet read: no count may exceed what they could hold.
  long long remaining() const { return static_cast<long long>(lines_.size() - next_); }

  /// The next line's tokens.
  std::vector<std::string> line() {
    if (done()) fail("more lines", "the end of the file");
    current_ = next_++;
    std::vector<std::string> tokens;
    std::istringstream in(lines_[current_]);
    for (std::string t; in >> t;) tokens.push_back(t);
    return tokens;
  }
  /// The next line, which must hold exactly `count` tokens (`what` names them).
  std::vector<std::string> line(size_t count, const std::string& what) {
    std::vector<std::string> t = line();
    if (t.size() != count)
      fail(what + " (" + std::to_string(count) + (count == 1 ? " value)" : " values)"),
           std::to_string(t.size()) + (t.size() == 1 ? " value " : " values ") +
               quoted(lines_[current_]));
    return t;
  }
  std::string raw_line() const { return lines_[current_]; }

  long long integer(const std::string& token, long long lo, long long hi, const std::string& what) {
    long long v = 0;
    const char* end = token.data() + token.size();
    const auto [ptr, ec] = std::from_chars(token.data(), end, v);
    if (ec != std::errc() || ptr != end) fail(what + " (an integer)", quoted(token));
    if (v < lo || v > hi)
      fail(what + " in " + std::to_string(lo) + ".." + std::to_string(hi), std::to_string(v));
    return v;
  }
  double real(const std::string& token, const std::string& what) {
    double v = 0;
    const char* end = token.data() + token.size();
    const auto [ptr, ec] = std::from_chars(token.data(), end, v);
    if (ec != std::errc() || ptr != end || !std::isfinite(v))
      fail(what + " (a finite number)", quoted(token));
    return v;
  }
  /// A count that the rest of the file (`per_line` lines each) can hold.
  long long count(const std::string& token, const std::string& what, long long per_line = 1) {
    const long long n = integer(token, 0, kMaxTag, what);
    if (n * per_line > remaining())
      fail(what + " that the " + std::to_string(remaining()) + " remaining lines can hold",
           std::to_string(n));
    return n;
  }
  void expect_marker(const std::string& marker) {
    const std::vector<std::string> t = line();
    if (t.size() != 1 || t[0] != marker)
      fail(marker, t.empty() ? std::string("an empty line") : quoted(raw_line()));
  }

  [[noreturn]] void fail(const std::string& expected, const std::string& found) const {
    fail_at(line_number(), expected, found);
  }
  /// The same, naming line `line` (1-based): a check that could only be made after the line.
  [[noreturn]] void fail_at(int line, const std::string& expected, const std::string& found) const {
    throw InputError(path_ + ":" + std::to_string(line) + ": expected " + expected + ", found " +
                     found);
  }

 private:
  std::string path_;
  std::vector<std::string> lines_;
  size_t next_ = 0, current_ = 0;
};

class MshCheck {
 public:
  MshCheck(const std::string& text, const std::string& path) : r_(text, path) {}

  void run() {
    format();
    while (!r_.done()) {
      const std::vector<std::string> t = r_.line();
      if (t.empty()) continue;
      if (t.size() != 1 || t[0].size() < 2 || t[0][0] != '$')
        r_.fail("a section header such as $Nodes", quoted(r_.raw_line()));
      const std::string name = t[0].substr(1);
      if (name == "PhysicalNames") physical_names();
      else if (name == "Entities" && v4_) entities();
      else if (name == "PartitionedEntities") r_.fail("an unpartitioned mesh", "$PartitionedEntities");
      else if (name == "Nodes") v4_ ? nodes4() : nodes2();
      else if (name == "Elements") v4_ ? elements4() : elements2();
      else if (name.rfind("End", 0) == 0) r_.fail("a section header", t[0] + " without its section");
      else skip(name);
    }
    if (!seen_nodes_) r_.fail("a $Nodes section", "none");
    if (!seen_elements_) r_.fail("an $Elements section", "none");
  }

 private:
  void format() {
    while (!r_.done()) {
      const std::vector<std::string> t = r_.line();
      if (t.empty()) continue;
      if (t.size() != 1 || t[0] != "$MeshFormat")
        r_.fail("$MeshFormat on the first line of a .msh file", quoted(r_.raw_line()));
      const std::vector<std::string> f = r_.line(3, "version, file type and data size");
      if (f[0] == "4.1") v4_ = true;
      else if (f[0] != "2.2") r_.fail("MSH version 4.1 or 2.2 (save the file again in gmsh)", f[0]);
      if (f[1] != "0")
        r_.fail("an ASCII file (file type 0; binary .msh files are not read)", "file type " + f[1]);
      r_.integer(f[2], 4, 16, "data size");
      r_.expect_marker("$EndMeshFormat");
      return;
    }
    r_.fail("$MeshFormat", "an empty file");
  }

  /// A name the scene selects by: one physical group each. gmsh merges the node sets of every
  /// group of a name, so a curve and the surface both named "fixed" made a support on "fixed"
  /// clamp the whole body.
  void physical_names() {
    const long long n = r_.count(r_.line(1, "the number of physical names")[0], "physical names");
    struct Group {
      long long dim, tag;
      int line;
    };
    std::map<std::string, Group> groups;
    for (long long i = 0; i < n; ++i) {
      const std::vector<std::string> t = r_.line();
      if (t.size() < 3) r_.fail("dimension, tag and \"name\"", quoted(r_.raw_line()));
      const long long dim = r_.integer(t[0], 0, 3, "a physical dimension");
      const long long tag = r_.integer(t[1], 1, kMaxTag, "a physical tag");
      const std::string raw = r_.raw_line();
      const size_t open = raw.find('"'), close = raw.rfind('"');
      if (open == std::string::npos || close == open) r_.fail("a quoted name", quoted(raw));
      const std::string name = raw.substr(open + 1, close - open - 1);
      const auto [it, fresh] = groups.emplace(name, Group{dim, tag, r_.line_number()});
      if (!fresh)
        r_.fail("a physical name given to one group",
                quoted(name) + " for both " + group_text(it->second.dim, it->second.tag) +
                    " (line " + std::to_string(it->second.line) + ") and " +
                    group_text(dim, tag));
    }
    r_.expect_marker("$EndPhysicalNames");
  }
  static std::string group_text(long long dim, long long tag) {
    static const char* const kKind[] = {"point", "curve", "surface", "volume"};
    return std::string("the physical ") + kKind[dim] + " " + std::to_string(tag);
  }

  void entities() {
    const std::vector<std::string> c = r_.line(4, "the numbers of points, curves, surfaces and volumes");
    long long counts[4];
    for (int d = 0; d < 4; ++d) counts[d] = r_.count(c[d], "an entity count");
    for (int d = 0; d < 4; ++d)
      for (long long i = 0; i < counts[d]; ++i) entity(d);
    r_.expect_marker("$EndEntities");
  }
  /// tag, coordinates (3 for a point, a 6-value box otherwise), physical tags, bounding tags.
  void entity(int dim) {
    const std::vector<std::string> t = r_.line();
    const size_t coords = dim == 0 ? 3 : 6;
    size_t at = 0;
    auto need = [&](size_t k) {
      if (t.size() < at + k) r_.fail("a complete entity line", quoted(r_.raw_line()));
    };
    need(1 + coords + 1);
    r_.integer(t[at++], 1, kMaxTag, "an entity tag");
    for (size_t k = 0; k < coords; ++k) r_.real(t[at++], "an entity coordinate");
    const long long physicals = r_.integer(t[at++], 0, 1000000, "a number of physical tags");
    need(static_cast<size_t>(physicals));
    for (long long k = 0; k < physicals; ++k) r_.integer(t[at++], 1, kMaxTag, "a physical tag");
    if (dim > 0) {
      need(1);
      const long long bounding = r_.integer(t[at++], 0, 1000000, "a number of bounding entities");
      need(static_cast<size_t>(bounding));
      for (long long k = 0; k < bounding; ++k)
        r_.integer(t[at++], -kMaxTag, kMaxTag, "a bounding entity tag");
    }
    if (at != t.size()) r_.fail("the end of the entity line", quoted(t[at]));
  }

  void nodes4() {
    const std::vector<std::string> h = r_.line(4, "numEntityBlocks numNodes minNodeTag maxNodeTag");
    const long long blocks = r_.count(h[0], "a number of node blocks");
    const long long total = r_.count(h[1], "a number of nodes", 2);
    const long long lo = r_.integer(h[2], 0, kMaxTag, "the smallest node tag");
    const long long hi = r_.integer(h[3], 0, kMaxTag, "the largest node tag");
    if (total > 0 && (lo < 1 || hi < lo)) r_.fail("1 <= minNodeTag <= maxNodeTag", h[2] + " " + h[3]);
    long long seen = 0;
    for (long long b = 0; b < blocks; ++b) {
      const std::vector<std::string> t = r_.line(4, "entityDim entityTag parametric numNodesInBlock");
      const long long dim = r_.integer(t[0], 0, 3, "an entity dimension");
      r_.integer(t[1], 1, kMaxTag, "an entity tag");
      const long long parametric = r_.integer(t[2], 0, 1, "parametric (0 or 1)");
      const long long n = r_.count(t[3], "a number of nodes in the block", 2);
      if (seen + n > total)
        r_.fail("blocks holding the declared " + std::to_string(total) + " nodes",
                std::to_string(seen + n) + " nodes so far");
      std::vector<long long> tags;
      for (long long i = 0; i < n; ++i) tags.push_back(add_node(r_.line(1, "a node tag")[0], lo, hi));
      const size_t values = 3 + static_cast<size_t>(parametric ? dim : 0);
      for (long long i = 0; i < n; ++i) {
        const std::vector<std::string> c = r_.line(values, "node coordinates");
        for (const std::string& v : c) r_.real(v, "a coordinate");
        add_coordinates(tags[i], c[0], c[1], c[2]);
      }
      seen += n;
    }
    end_blocks(seen, total, "nodes", "$EndNodes");
    check_plane();
    seen_nodes_ = true;
  }

  void nodes2() {
    const long long n = r_.count(r_.line(1, "the number of nodes")[0], "a number of nodes");
    for (long long i = 0; i < n; ++i) {
      const std::vector<std::string> t = r_.line(4, "node tag and x y z");
      const long long tag = add_node(t[0], 1, kMaxTag);
      for (int k = 1; k < 4; ++k) r_.real(t[k], "a coordinate");
      add_coordinates(tag, t[1], t[2], t[3]);
    }
    r_.expect_marker("$EndNodes");
    check_plane();
    seen_nodes_ = true;
  }

  /// A node's x and y, and its z against the first node's (gmsh keeps z, the solver drops it).
  void add_coordinates(long long tag, const std::string& x, const std::string& y,
                       const std::string& z) {
    const double px = r_.real(x, "a coordinate"), py = r_.real(y, "a coordinate");
    const double pz = r_.real(z, "a coordinate");
    xy_[tag] = {px, py};
    extent_ = std::max({extent_, std::abs(px), std::abs(py)});
    if (!plane_z_) plane_z_ = pz;
    if (!off_plane_ || std::abs(pz - *plane_z_) > std::abs(off_plane_->z - *plane_z_))
      off_plane_ = OffPlane{tag, r_.line_number(), pz};
  }
  /// A 2D mesh lies in one plane z = const: the node farthest off it (beyond round-off of the
  /// model's size) is refused, as dropping its z would solve another body.
  void check_plane() {
    if (!off_plane_ ||
        std::abs(off_plane_->z - *plane_z_) <= 1e-9 * std::max(extent_, std::abs(*plane_z_)))
      return;
    const OffPlane& o = *off_plane_;
    r_.fail_at(o.line,
               "every node in the plane of the first, z = " + number_text(*plane_z_) +
                   " (a 2D mesh)",
               "node " + std::to_string(o.tag) + " at z = " + number_text(o.z));
  }

  long long add_node(const std::string& token, long long lo, long long hi) {
    const long long tag = r_.integer(token, std::max(1LL, lo), hi, "a node tag");
    if (!nodes_.insert(tag).second) r_.fail("a node tag not used before", std::to_string(tag));
    return tag;
  }

  void elements4() {
    const std::vector<std::string> h =
        r_.line(4, "numEntityBlocks numElements minElementTag maxElementTag");
    const long long blocks = r_.count(h[0], "a number of element blocks");
    const long long total = r_.count(h[1], "a number of elements");
    r_.integer(h[2], 0, kMaxTag, "the smallest element tag");
    r_.integer(h[3], 0, kMaxTag, "the largest element tag");
    long long seen = 0;
    for (long long b = 0; b < blocks; ++b) {
      const std::vector<std::string> t = r_.line(4, "entityDim entityTag elementType numElementsInBlock");
      r_.integer(t[0], 0, 3, "an entity dimension");
      r_.integer(t[1], 1, kMaxTag, "an entity tag");
      const int per = element_nodes(t[2]);
      const long long n = r_.count(t[3], "a number of elements in the block");
      if (seen + n > total)
        r_.fail("blocks holding the declared " + std::to_string(total) + " elements",
                std::to_string(seen + n) + " elements so far");
      for (long long i = 0; i < n; ++i) {
        const std::vector<std::string> e = r_.line(1 + per, "an element tag and its nodes");
        add_element(e[0]);
        for (int k = 1; k <= per; ++k) referenced_node(e[k]);
        check_shape(t[2], e, 1, per);
      }
      seen += n;
    }
    end_blocks(seen, total, "elements", "$EndElements");
    seen_elements_ = true;
  }

  void elements2() {
    const long long n = r_.count(r_.line(1, "the number of elements")[0], "a number of elements");
    for (long long i = 0; i < n; ++i) {
      const std::vector<std::string> t = r_.line();
      if (t.size() < 3) r_.fail("elm-number elm-type number-of-tags ...", quoted(r_.raw_line()));
      add_element(t[0]);
      const int per = element_nodes(t[1]);
      const long long tags = r_.integer(t[2], 0, 100, "a number of tags");
      if (static_cast<long long>(t.size()) != 3 + tags + per)
        r_.fail(std::to_string(3 + tags + per) + " values on the element line",
                std::to_string(t.size()));
      for (long long k = 0; k < tags; ++k) r_.integer(t[3 + k], -kMaxTag, kMaxTag, "an element tag");
      if (tags > 0) r_.integer(t[3], 0, kMaxTag, "a physical tag");
      for (long long k = 0; k < per; ++k) referenced_node(t[3 + tags + k]);
      check_shape(t[1], t, static_cast<size_t>(3 + tags), per);
    }
    r_.expect_marker("$EndElements");
    seen_elements_ = true;
  }

  /// The blocks of a 4.1 section read: they must hold the total its header declared.
  void end_blocks(long long seen, long long total, const std::string& what,
                  const std::string& marker) {
    if (seen != total)
      r_.fail("blocks holding the declared " + std::to_string(total) + " " + what,
              std::to_string(seen));
    r_.expect_marker(marker);
  }

  int element_nodes(const std::string& token) {
    const long long type = r_.integer(token, 1, 1000, "an element type");
    const int per = nodes_of_type(type);
    if (per < 0) r_.fail("a known element type", "type " + std::to_string(type));
    return per;
  }
  void add_element(const std::string& token) {
    const long long tag = r_.integer(token, 1, kMaxTag, "an element tag");
    if (!elements_.insert(tag).second) r_.fail("an element tag not used before", std::to_string(tag));
  }
  void referenced_node(const std::string& token) {
    const long long tag = r_.integer(token, 1, kMaxTag, "a node tag");
    if (!nodes_.count(tag)) r_.fail("a node defined in $Nodes", "node " + std::to_string(tag));
  }

  /// An element's nodes (tokens first..first+per of `t`) are distinct, and a triangle's (types 2
  /// and 9) corners span a positive area: a degenerate element would reach the solver as a
  /// singular or non-finite stiffness.
  void check_shape(const std::string& type, const std::vector<std::string>& t, size_t first, int per) {
    std::vector<long long> tags;
    for (int k = 0; k < per; ++k) tags.push_back(std::stoll(t[first + k]));
    for (int a = 0; a < per; ++a)
      for (int b = a + 1; b < per; ++b)
        if (tags[a] == tags[b])
          r_.fail("distinct nodes in an element", "node " + std::to_string(tags[a]) + " twice");
    if (type != "2" && type != "9") return;
    const auto& p = xy_[tags[0]];
    const auto& q = xy_[tags[1]];
    const auto& r = xy_[tags[2]];
    const double ux = q[0] - p[0], uy = q[1] - p[1], vx = r[0] - p[0], vy = r[1] - p[1];
    const double scale = std::max({ux * ux + uy * uy, vx * vx + vy * vy,
                                   (r[0] - q[0]) * (r[0] - q[0]) + (r[1] - q[1]) * (r[1] - q[1])});
    if (!(std::abs(ux * vy - uy * vx) > 1e-12 * scale))
      r_.fail("a triangle with positive area", "corners on one line (zero area)");
  }

  /// An unknown section ($Periodic, $NodeData, ...): skipped to its end marker.
  void skip(const std::string& name) {
    while (true) {
      if (r_.done()) r_.fail("$End" + name, "the end of the file");
      const std::vector<std::string> t = r_.line();
      if (t.size() == 1 && t[0] == "$End" + name) return;
    }
  }

  Reader r_;
  bool v4_ = false, seen_nodes_ = false, seen_elements_ = false;
  std::unordered_map<long long, std::array<double, 2>> xy_;  ///< node coordinates by tag
  struct OffPlane {
    long long tag;
    int line;
    double z;
  };
  std::optional<double> plane_z_;      ///< the first node's z
  std::optional<OffPlane> off_plane_;  ///< the node farthest from the first node's z
  double extent_ = 0.0;                ///< the largest |x| or |y|
  std::unordered_set<long long> nodes_, elements_;
};

}  // namespace

void check_msh_text(const std::string& text, const std::string& path) {
  MshCheck(text, path).run();
}

void check_msh_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": expected a readable mesh file, found none (no such file, or no "
                              "permission to read it)");
  std::ostringstream text;
  text << in.rdbuf();
  check_msh_text(text.str(), path);
}

}  // namespace c2d::core
