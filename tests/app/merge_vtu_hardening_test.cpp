// Issue 32, items 3 and 4, end to end through the executable where the finding was a crash or a
// hang: `contact2d merge DIR` on a study.json or a case's summary.json that is deeply nested, of
// the wrong types, a FIFO or too large (a bad study.json: one located line, exit 2; a bad case
// summary.json: that case listed as malformed, the others merged, exit 1), and `contact2d plot
// --deformed` on VTU files whose counts and arrays disagree (one located line, exit 2). Every run
// has a time limit, so a hang fails the test instead of stopping the suite. Study folders, case
// summaries and VTU files are written here, by hand, into a private temporary folder.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "app/process.hpp"
#include "app/report/json_file.hpp"
#include "app/report/vtu_reader.hpp"
#include "core/errors.hpp"
#include "read_text.hpp"


namespace fs = std::filesystem;

namespace {

struct Outcome {
  int code = -1;           ///< exit status, or 128 + the signal that ended the program
  bool timed_out = false;  ///< still running at the limit (then killed)
  std::string text;        ///< stdout and stderr
};

using c2d::test::read_text;

/// Runs the program with ARGS (argv[1..]; no shell) for at most `seconds`, its output into a log.
Outcome run_c2d(const std::vector<std::string>& args, int seconds = 60) {
  const fs::path log =
      fs::temp_directory_path() / ("c2d_merge_vtu_" + std::to_string(::getpid()) + ".log");
  c2d::app::ProcessLimit limit;
  limit.seconds = seconds;  // a hang is stopped (SIGTERM, then SIGKILL) and reported as such
  limit.grace_seconds = 1;
  const c2d::app::ProcessOutcome p =
      c2d::app::run_process(C2D_BINARY, args, log.string(), {}, {}, limit);
  Outcome o;
  o.code = p.started ? p.exit_code : -1;
  o.timed_out = p.timed_out;
  o.text = read_text(log);
  fs::remove(log);
  return o;
}

/// Ended on its own with CODE (no crash, no hang), every fragment in its output; for exit 2 the
/// output is one line starting "error: ".
void expect_outcome(const Outcome& o, int code, std::initializer_list<std::string> fragments) {
  ASSERT_FALSE(o.timed_out) << "hung; output: " << o.text;
  EXPECT_EQ(o.code, code) << o.text;
  if (code == 2) {
    EXPECT_EQ(o.text.rfind("error: ", 0), 0u) << o.text;
    EXPECT_EQ(o.text.find('\n'), o.text.size() - 1) << "not one line: " << o.text;
  }
  for (const auto& f : fragments)
    EXPECT_NE(o.text.find(f), std::string::npos) << "'" << f << "' missing in: " << o.text;
}

/// A private folder under the test output folder, removed at the end of the test.
class TempDir {
 public:
  explicit TempDir(const std::string& name)
      : path_(fs::temp_directory_path() /
              ("c2d_merge_vtu_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string str() const { return path_.string(); }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    fs::create_directories((path_ / name).parent_path());
    std::ofstream(path_ / name, std::ios::binary) << text;
    return (path_ / name).string();
  }

 private:
  fs::path path_;
};

// ---- merge ---------------------------------------------------------------------------------

/// A converged run's summary.json with the figures a sweep reads (case k of two).
nlohmann::json converged_summary(int k) {
  const double f = k + 1.0;
  return {{"status", "converged"},
          {"method", "penalty"},
          {"mesh", {{"dofs", 100 + k}}},
          {"contact",
           {{"iterations", 3 + k},
            {"p_max", f},
            {"length", 0.5},
            {"total_force", 1.0},
            {"max_penetration", 1e-5 * f},
            {"pivot_ratio", 1e-3 * f},
            {"penalty_max", 10 * f}}},
          {"time_s", {{"mesh", 0.1}, {"assemble", 0.1}, {"solve", 0.1 * f}, {"total", 0.3}}},
          {"reference", {{"relative_error", {{"p_max", 0.01 * f}}}}}};
}

/// A sweep study as `contact2d sweep --job-list` writes it, with cases c0 and c1, both run.
void write_sweep_study(const TempDir& dir) {
  const nlohmann::json manifest = {
      {"format", "contact2d study 1"},
      {"verb", "sweep"},
      {"executable", C2D_BINARY},
      {"options",
       {{"scene", "scene.toml"}, {"key", "contact.penalty"}, {"accuracy", 0.05}, {"units", ""}}},
      {"cases",
       {{{"value", 1.0}, {"folder", "c0"}, {"args", {"scene.toml"}}},
        {{"value", 2.0}, {"folder", "c1"}, {"args", {"scene.toml"}}}}}};
  dir.write("study.json", manifest.dump(2));
  for (int k = 0; k < 2; ++k)
    dir.write("c" + std::to_string(k) + "/summary.json", converged_summary(k).dump(2));
}

/// `merge DIR` with case c1's summary.json replaced: exit 1, its row's status cell
/// "malformed summary.json: " + REASON, and c0 merged as converged.
void expect_c1_malformed(const TempDir& dir, const std::string& reason) {
  expect_outcome(run_c2d({"merge", dir.str(), "--quiet"}), 1, {});
  const std::string csv = read_text(dir / "sweep.csv");
  EXPECT_NE(csv.find("\n1,contact.penalty,\"converged\",0,100,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\n2,contact.penalty,\"malformed summary.json: " + reason), std::string::npos)
      << csv;
  EXPECT_NE(read_text(dir / "sweep.md").find("malformed summary.json: "), std::string::npos);
}

TEST(MergeHardening, WellFormedStudyMergesWithExitZero) {
  // The baseline the cases below change one file of: both cases merged, exit 0.
  const TempDir dir("baseline");
  write_sweep_study(dir);
  expect_outcome(run_c2d({"merge", dir.str(), "--quiet"}), 0, {});
  EXPECT_NE(read_text(dir / "sweep.csv").find("\n2,contact.penalty,\"converged\""),
            std::string::npos);
}

TEST(MergeHardening, DeeplyNestedStudyJsonExitsTwo) {
  // 60,000 levels (120 kB): the manifest's message dumped the value and overflowed the stack.
  const TempDir dir("deep_study");
  dir.write("study.json",
            "{\"format\": " + std::string(60000, '[') + std::string(60000, ']') + "}");
  expect_outcome(run_c2d({"merge", dir.str()}), 2,
                 {dir / "study.json",
                  ": expected at most 64 levels of nested arrays and objects, "
                  "found more at byte 74"});
}

TEST(MergeHardening, StudyJsonFifoExitsTwo) {
  // A FIFO named study.json: opening it waited for a writer for ever.
  const TempDir dir("fifo_study");
  ASSERT_EQ(::mkfifo((dir / "study.json").c_str(), 0600), 0);
  expect_outcome(run_c2d({"merge", dir.str()}, 20), 2,
                 {dir / "study.json", ": expected a regular file, found a FIFO"});
}

TEST(MergeHardening, StudyJsonVerbWithALineBreakIsOneLine) {
  const TempDir dir("verb_study");
  write_sweep_study(dir);
  nlohmann::json m = nlohmann::json::parse(read_text(dir / "study.json"));
  m["verb"] = "sweep\nsecond line";
  dir.write("study.json", m.dump());
  expect_outcome(
      run_c2d({"merge", dir.str()}), 2,
      {dir / "study.json", ": verb: expected compare, sweep or bench, found 'sweep\\x0a"});
}

TEST(MergeHardening, StudyJsonOfTheWrongTypeExitsTwo) {
  const TempDir dir("type_study");
  write_sweep_study(dir);
  nlohmann::json m = nlohmann::json::parse(read_text(dir / "study.json"));
  m["cases"][1]["folder"] = 5;
  dir.write("study.json", m.dump());
  expect_outcome(run_c2d({"merge", dir.str()}), 2,
                 {dir / "study.json", ": cases[1].folder: expected a string, found number 5"});
}

TEST(MergeHardening, SummaryStatusNumberListsTheCaseAsMalformed) {
  // "status": 3 stopped the whole merge with [json.exception.type_error.302].
  const TempDir dir("status_number");
  write_sweep_study(dir);
  nlohmann::json s = converged_summary(1);
  s["status"] = 3;
  dir.write("c1/summary.json", s.dump());
  expect_c1_malformed(dir, "status: expected a string; found number 3");  // ',' -> ';' in CSV
}

TEST(MergeHardening, SummaryMethodNumberListsTheCaseAsMalformed) {
  const TempDir dir("method_number");
  write_sweep_study(dir);
  nlohmann::json s = converged_summary(1);
  s["method"] = 5;
  dir.write("c1/summary.json", s.dump());
  expect_c1_malformed(dir, "method: expected a string or null; found number 5");
}

TEST(MergeHardening, SummaryNumberOfTheWrongTypeListsTheCaseAsMalformed) {
  const TempDir dir("dofs_string");
  write_sweep_study(dir);
  nlohmann::json s = converged_summary(1);
  s["mesh"]["dofs"] = "many";
  dir.write("c1/summary.json", s.dump());
  expect_c1_malformed(dir, "mesh.dofs: expected a number; found string 'many'");
}

TEST(MergeHardening, DeeplyNestedSummaryListsTheCaseAsMalformed) {
  // A million levels (2 MB) as the status: copying the value overflowed the stack.
  const TempDir dir("deep_summary");
  write_sweep_study(dir);
  dir.write("c1/summary.json",
            "{\"status\": " + std::string(1000000, '[') + std::string(1000000, ']') + "}");
  expect_c1_malformed(dir, "expected at most 64 levels of nested arrays and objects");
}

TEST(MergeHardening, SummaryFifoListsTheCaseAsMalformed) {
  // A FIFO named summary.json: the merge waited for a writer for ever.
  const TempDir dir("fifo_summary");
  write_sweep_study(dir);
  fs::remove(dir / "c1/summary.json");
  ASSERT_EQ(::mkfifo((dir / "c1/summary.json").c_str(), 0600), 0);
  expect_c1_malformed(dir, "expected a regular file; found a FIFO");
}

TEST(MergeHardening, SummaryOver64MiBListsTheCaseAsMalformed) {
  const TempDir dir("huge_summary");
  write_sweep_study(dir);
  fs::resize_file(dir / "c1/summary.json", (std::uintmax_t{64} << 20) + 1);  // sparse
  expect_c1_malformed(dir, "expected a file of at most 67108864 bytes; found 67108865 bytes");
}

TEST(JsonFile, NestingIsCountedOutsideStringsUpToTheLimit) {
  using c2d::app::parse_json_text;
  const auto nested = [](int levels) {
    return std::string(levels, '[') + std::string(levels, ']');
  };
  EXPECT_TRUE(parse_json_text(nested(64)).ok());
  EXPECT_EQ(parse_json_text(nested(65)).error,
            "expected at most 64 levels of nested arrays and objects, found more at byte 64");
  // Brackets in strings (escaped quotes too) are text, not nesting.
  const std::string in_string = "[\"\\\"" + std::string(100, '[') + "\"]";
  EXPECT_TRUE(parse_json_text(in_string).ok()) << parse_json_text(in_string).error;
  EXPECT_EQ(parse_json_text("{\"a\": }").error.rfind("expected JSON, found a parse error at", 0),
            0u);
}

// ---- plot --deformed and the VTU reader --------------------------------------------------------

/// The parts of a hand-made ASCII VTU of a unit square in two T3 cells (what `contact2d run`
/// writes, in its layout); a test changes one part.
struct Vtu {
  std::string points = "4", cells = "2";
  std::string coordinates = "0 0 0  1 0 0  1 1 0  0 1 0";
  std::string connectivity = "0 1 2  0 2 3", offsets = "3 6", types = "5 5";
  std::string displacement_components = "3";
  std::string displacement = "0 0 0  0.1 0 0  0.1 0.1 0  0 0.1 0";
  std::string von_mises = "1 2 3 4";

  std::string text() const {
    const auto array = [](const std::string& attributes, const std::string& values) {
      return "        <DataArray " + attributes + " format=\"ascii\">\n          " + values +
             "\n        </DataArray>\n";
    };
    return "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
           "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <UnstructuredGrid>\n"
           "    <Piece NumberOfPoints=\"" +
           points + "\" NumberOfCells=\"" + cells + "\">\n" + "      <Points>\n" +
           array("type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"", coordinates) +
           "      </Points>\n      <Cells>\n" +
           array("type=\"Int32\" Name=\"connectivity\"", connectivity) +
           array("type=\"Int32\" Name=\"offsets\"", offsets) +
           array("type=\"UInt8\" Name=\"types\"", types) +
           "      </Cells>\n      <PointData Vectors=\"displacement\">\n" +
           array("type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"" +
                     displacement_components + "\"",
                 displacement) +
           array("type=\"Float64\" Name=\"von_mises_smoothed\"", von_mises) +
           "      </PointData>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  }
};

/// `plot DIR --field vm --deformed 1` on DIR/step_0001.vtu holding `v` (the von Mises field, so
/// that only the deformed positions read the displacement).
Outcome plot_deformed(const TempDir& dir, const Vtu& v) {
  dir.write("step_0001.vtu", v.text());
  return run_c2d({"plot", dir.str(), "--field", "vm", "--deformed", "1"});
}

TEST(PlotHardening, WellFormedVtuPlotsDeformed) {
  const TempDir dir("vtu_baseline");
  expect_outcome(plot_deformed(dir, Vtu{}), 0, {});
  EXPECT_TRUE(fs::exists(dir / "plot_vm.png"));
}

TEST(PlotHardening, DisplacementOfZeroComponentsExitsTwo) {
  // NumberOfComponents="0" and no values: the deformed positions read an empty array (SIGSEGV).
  const TempDir dir("vtu_zero_components");
  Vtu v;
  v.displacement_components = std::string("0");  // (GCC 12 -Wrestrict false positive on "0")
  v.displacement.clear();
  expect_outcome(plot_deformed(dir, v), 2,
                 {dir / "step_0001.vtu",
                  ": DataArray 'displacement': NumberOfComponents: "
                  "expected an integer from 1 to 9, found '0'"});
}

TEST(PlotHardening, ShortDisplacementExitsTwo) {
  // Fewer values than NumberOfPoints x 3: the deformed positions read past the array's end.
  const TempDir dir("vtu_short");
  Vtu v;
  v.displacement = "0 0 0";
  expect_outcome(plot_deformed(dir, v), 2,
                 {dir / "step_0001.vtu",
                  ": DataArray 'displacement': expected 12 values (4 "
                  "points x 3 components), found 3"});
}

TEST(PlotHardening, PointCountThatIsNotAnIntegerExitsTwo) {
  // atoi read "4x" as 4 and "1e9" as 1.
  const TempDir dir("vtu_points");
  Vtu v;
  v.points = "4x";
  expect_outcome(plot_deformed(dir, v), 2,
                 {dir / "step_0001.vtu",
                  ": NumberOfPoints: expected an integer from 1 to "
                  "100000000, found '4x'"});
}

TEST(PlotHardening, AttributeOf300kCharactersExitsTwo) {
  // std::regex read the attributes, recursing once per character: SIGSEGV.
  const TempDir dir("vtu_long_attribute");
  Vtu v;
  v.points = std::string(300000, '1');
  expect_outcome(plot_deformed(dir, v), 2,
                 {dir / "step_0001.vtu",
                  ": NumberOfPoints: expected an integer from 1 to "
                  "100000000, found '111111"});
}

/// read_vtu on `v`: refused with an InputError holding `fragment`.
void expect_vtu_refused(const Vtu& v, const std::string& fragment) {
  const TempDir dir("vtu_read");
  const std::string path = dir.write("read.vtu", v.text());
  try {
    c2d::app::read_vtu(path);
    ADD_FAILURE() << "accepted; expected: " << fragment;
  } catch (const c2d::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": " + fragment), std::string::npos) << e.what();
  }
}

TEST(VtuReaderHardening, CountsAndArraysAreCheckedBeforeUse) {
  Vtu v;
  v.cells = "99999999999999999999";
  expect_vtu_refused(v, "NumberOfCells: expected an integer from 1 to 100000000, found '9999");
  v = Vtu{};
  v.coordinates = "0 0 0  1 0 0  1 1 0";
  expect_vtu_refused(v,
                     "DataArray 'Points': expected 12 values (4 points x 3 components), found 9");
  v = Vtu{};
  v.connectivity = "0 1 2  0 2 7";
  expect_vtu_refused(v,
                     "DataArray 'connectivity': entry 5: expected an integer from 0 to 3, "
                     "found 7");
  v = Vtu{};
  v.connectivity = "0 1 2  0 2 1e300";
  expect_vtu_refused(v,
                     "DataArray 'connectivity': entry 5: expected an integer from 0 to 3, "
                     "found 1e+300");
  v = Vtu{};
  v.offsets = "3 9";  // beyond the 6 node ids of the connectivity
  expect_vtu_refused(v,
                     "DataArray 'offsets': entry 1: expected 6 (3 node ids per cell, within "
                     "the connectivity), found 9");
  v = Vtu{};
  v.types = "5 22";
  expect_vtu_refused(v, "DataArray 'types': entry 1: expected 5 (one cell type), found 22");
  v = Vtu{};
  v.displacement_components = "10";
  expect_vtu_refused(v,
                     "DataArray 'displacement': NumberOfComponents: expected an integer from "
                     "1 to 9, found '10'");
  // The well-formed file reads.
  const TempDir dir("vtu_good");
  const c2d::app::VtuData good = c2d::app::read_vtu(dir.write("good.vtu", Vtu{}.text()));
  EXPECT_EQ(good.cells.size(), 2u);
  EXPECT_EQ(good.point_data.at("displacement").size(), 12u);
}

TEST(PlotHardening, VtuFifoExitsTwo) {
  const TempDir dir("vtu_fifo");
  ASSERT_EQ(::mkfifo((dir / "step_0001.vtu").c_str(), 0600), 0);
  expect_outcome(run_c2d({"plot", dir.str(), "--field", "ux"}, 20), 2,
                 {dir / "step_0001.vtu", ": expected a regular file, found a FIFO"});
}

}  // namespace
