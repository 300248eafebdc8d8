#include "core/scene.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/legacy_reader.hpp"
#include "core/rigid_plate.hpp"
#include "core/scene_sections.hpp"
#include "core/toml_view.hpp"

namespace c2d::core {

namespace {

/// [output]: the default folder, which files a run writes, and the VTU encoding.
void parse_output(const TomlView& root, Scene& scene) {
  if (!root.has("output")) return;
  const TomlView o = root["output"];
  o.require_table();
  o.check_keys({"dir", "fields", "charts", "vtu"});
  scene.output_dir = o["dir"].string_or("");
  scene.output_fields = o["fields"].boolean_or(true);
  scene.output_charts = o["charts"].boolean_or(true);
  scene.output_vtu = o["vtu"].choice_or({"binary", "ascii"}, "binary") == "ascii"
                         ? VtuEncoding::kAscii
                         : VtuEncoding::kBinary;
}

Scene build_scene(const toml::table& root_table, const std::string& file) {
  Scene scene;
  scene.path = file;
  const TomlView root(&root_table, "", &scene.path);
  root.check_keys({"title", "units", "analysis", "material", "body", "support", "load", "probe",
                   "contact", "obstacle", "constraint", "spring", "plate", "reference", "output",
                   "adapt"});
  scene.title = root["title"].string_or("");
  scene.units = root["units"].string_or("");
  parse_analysis(root["analysis"], scene.analysis);
  parse_adapt(root["adapt"], scene.adapt);
  for (const auto& m : root["material"].tables())
    scene.materials.push_back(parse_material(m, scene.materials));
  if (scene.materials.empty()) root["material"].fail("at least one [[material]]");
  for (const auto& b : root["body"].tables()) scene.bodies.push_back(parse_body(b, scene));
  if (scene.bodies.empty()) root["body"].fail("at least one [[body]]");

  auto check_body = [&](const SelectionSpec& s, const TomlView& v) {
    if (s.body.empty()) return;
    std::vector<std::string> names;
    for (const auto& b : scene.bodies) {
      if (b.name == s.body) return;
      names.push_back(b.name);
    }
    v["on"]["body"].fail("the name of a [[body]]" + did_you_mean(s.body, names));
  };
  for (const auto& s : root["support"].tables()) {
    scene.supports.push_back(parse_support(s));
    check_body(scene.supports.back().on, s);
  }
  for (const auto& sp : root["spring"].tables()) {
    SpringSpec spring = parse_spring(sp, static_cast<int>(scene.springs.size()), scene.materials);
    for (const auto& other : scene.springs)
      if (other.name == spring.name) sp["name"].fail("a unique spring name");
    scene.springs.push_back(std::move(spring));
    const SpringSpec& added = scene.springs.back();
    if (added.to_ground) check_body(added.on, sp);
    else check_body(added.a, sp), check_body(added.b, sp);
  }
  for (const auto& pl : root["plate"].tables()) {
    PlateSpec ps = parse_plate(pl, static_cast<int>(scene.plates.size()));
    for (const auto& other : scene.plates)
      if (other.name == ps.name) pl["name"].fail("a unique plate name");
    check_body(ps.on, pl);
    scene.plates.push_back(ps);
  }
  for (const auto& l : root["load"].tables()) {
    LoadSpec load = parse_load(l, static_cast<int>(scene.loads.size()));
    for (const auto& other : scene.loads)
      if (other.name == load.name) l["name"].fail("a unique load name");
    check_body(load.on, l);
    scene.loads.push_back(std::move(load));
  }
  for (const auto& p : root["probe"].tables()) {
    ProbeSpec ps = parse_probe(p);
    for (const auto& other : scene.probes)
      if (other.name == ps.name) p["name"].fail("a unique probe name");
    if (ps.on) check_body(*ps.on, p);
    if (!ps.plate.empty()) {
      std::vector<std::string> names;
      for (const auto& pl : scene.plates) names.push_back(pl.name);
      if (std::find(names.begin(), names.end(), ps.plate) == names.end())
        p["plate"].fail("the name of a [[plate]]" + did_you_mean(ps.plate, names));
    }
    scene.probes.push_back(ps);
  }
  // [[contact]] and [[obstacle]] belong to the constraints module, which parses them from
  // Scene::raw (constraints/contact_scene.hpp).
  parse_reference(root, scene);
  parse_output(root, scene);
  return scene;
}

}  // namespace

namespace {

/// The arrays of tables whose unnamed entries have a default name, the key and the entry's
/// number from 1 ("contact1", as messages and summary.json call it).
bool has_default_names(const std::string& key) {
  return key == "contact" || key == "constraint" || key == "spring" || key == "plate" ||
         key == "load";
}

/// An entry's name: its `name`, else its default one (empty when the array has none).
std::string entry_name(const toml::node& entry, const std::string& key, size_t index) {
  if (const auto n = (*entry.as_table())["name"].value<std::string>()) return *n;
  return has_default_names(key) ? key + std::to_string(index + 1) : std::string();
}

/// `key[i]` or `key.i` with i digits: i, else -1 (and `key` without its brackets).
int path_index(std::string& key, const std::string& where) {
  const auto lb = key.find('[');
  if (lb == std::string::npos || key.back() != ']') return -1;
  const std::string digits = key.substr(lb + 1, key.size() - lb - 2);
  int index = -1;
  size_t used = 0;
  try {
    index = std::stoi(digits, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (digits.empty() || used != digits.size() || index < 0 ||
      digits.find_first_not_of("0123456789") != std::string::npos)
    throw InputError(where + ": expected an index 0, 1, ... in '" + key + "', found '" + digits +
                     "'");
  key = key.substr(0, lb);
  return index;
}

bool all_digits(const std::string& text) {
  return !text.empty() && text.size() <= 9 &&
         text.find_first_not_of("0123456789") == std::string::npos;
}

}  // namespace

std::vector<toml::table*> tables_on_path(toml::table& root, const std::vector<std::string>& keys,
                                         bool create, const std::string& where) {
  std::vector<toml::table*> current{&root};
  for (size_t i = 0; i < keys.size(); ++i) {
    std::string key = keys[i];
    const int bracket = path_index(key, where);
    const std::string next_key = i + 1 < keys.size() ? keys[i + 1] : std::string();
    std::vector<toml::table*> next;
    bool consumed = false;  // the next key named an entry (by name or number)
    for (toml::table* t : current) {
      toml::node* child = t->get(key);
      if (!child) {
        // An index picks an entry that exists: plate[5] on a scene without plates made a table
        // 'plate' and then complained about plate[0].on.
        if (bracket >= 0)
          throw InputError(where + ": expected a table at index " + std::to_string(bracket) +
                           " of '" + key + "', found no '" + key + "'");
        if (!create) continue;
        t->insert_or_assign(key, toml::table{});
        next.push_back(t->get(key)->as_table());
      } else if (child->is_table()) {
        if (bracket >= 0)
          throw InputError(where + ": expected an array of tables '" + key + "' for the index " +
                           std::to_string(bracket) + ", found a table");
        next.push_back(child->as_table());
      } else if (child->is_array()) {
        auto& arr = *child->as_array();
        // key[i], key.NAME (an entry's name or default name, "contact1"), key.i, else every
        // entry.
        std::vector<toml::table*> picked;
        int index = bracket;
        if (index < 0 && !next_key.empty()) {
          for (size_t e = 0; e < arr.size(); ++e)
            if (arr[e].is_table() && entry_name(arr[e], key, e) == next_key)
              picked.push_back(arr[e].as_table());
          if (picked.empty() && all_digits(next_key)) index = std::stoi(next_key);
          consumed = consumed || !picked.empty() || index >= 0;
        }
        if (index >= 0) {
          if (index >= static_cast<int>(arr.size()) || !arr[index].is_table())
            throw InputError(where + ": expected a table at index " + std::to_string(index) +
                             " of '" + key + "', found " +
                             (index >= static_cast<int>(arr.size())
                                  ? std::to_string(arr.size()) + " entries"
                                  : std::string("a value there")));
          picked = {arr[index].as_table()};
        } else if (picked.empty()) {
          for (auto& entry : arr)
            if (entry.is_table()) picked.push_back(entry.as_table());
        }
        next.insert(next.end(), picked.begin(), picked.end());
      } else {
        throw InputError(where + ": expected '" + key + "' to be a table, found a value");
      }
    }
    if (consumed) ++i;
    current = std::move(next);
  }
  return current;
}

void apply_override(toml::table& root, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set " + quoted_found(assignment) + ": expected key.path=value, found no '='");
  const std::string path = assignment.substr(0, eq), text = assignment.substr(eq + 1);
  // TOML would read the line after a break as more keys (then dropped): "1\nx = 2" set 1.
  if (assignment.find_first_of("\n\r") != std::string::npos)
    throw InputError("--set " + quoted_found(assignment) +
                     ": expected a value on one line, found a line break");
  // The value: any TOML value; a bare word is taken as a string.
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + text);
  } catch (const toml::parse_error&) {
    parsed = toml::table{{"v", text}};
  }
  const toml::node& value = *parsed.get("v");

  std::vector<std::string> keys;
  std::stringstream ss(path);
  for (std::string k; std::getline(ss, k, '.');) {
    if (k.empty()) throw InputError("--set " + assignment + ": expected KEY.KEY...=VALUE, found an empty key in '" +
                       path + "'");
    keys.push_back(k);
  }
  const std::string last = keys.back();
  if (last.find('[') != std::string::npos && last.back() == ']')
    throw InputError("--set " + assignment + ": expected a key after the last index, found none");
  keys.pop_back();
  for (toml::table* t : tables_on_path(root, keys, true, "--set " + assignment))
    t->insert_or_assign(last, value);
}

Scene parse_scene(const std::string& text, const std::string& name,
                  const std::vector<std::string>& overrides) {
  auto root = std::make_shared<toml::table>();
  try {
    *root = toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << name << ':' << e.source().begin.line << ':' << e.source().begin.column
       << ": TOML syntax error: " << e.description();
    throw InputError(os.str());
  }
  for (const auto& o : overrides) apply_override(*root, o);
  Scene scene = build_scene(*root, name);
  scene.raw = root;
  return scene;
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (fs::is_directory(st))
    throw InputError(path + ": expected a scene file (.toml or .dat), found a folder");
  // A device or a pipe (/dev/zero) would be read without end.
  if (fs::exists(st) && !fs::is_regular_file(st))
    throw InputError(path + ": expected a scene file (.toml or .dat), found a device, pipe or "
                     "socket");
  constexpr std::uintmax_t kMaxSceneBytes = std::uintmax_t{1} << 30;
  if (fs::exists(st) && fs::file_size(path, ec) > kMaxSceneBytes)
    throw InputError(path + ": expected a scene file of at most 1 GiB, found " +
                     std::to_string(fs::file_size(path, ec)) + " bytes");
  std::ifstream in(path);
  if (!in) throw InputError(path + ": expected a readable scene file, found none (no such file, or no "
                              "permission to read it)");
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".dat" || ext == ".txt") {
    if (!overrides.empty()) throw InputError(path + ": expected a TOML scene for --set, found a legacy data file");
    return read_legacy_scene(path);
  }
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_scene(buffer.str(), path, overrides);
}

}  // namespace c2d::core
