#include "app/report/gnuplot.hpp"

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include <stdlib.h>
#include <unistd.h>

#include "app/process.hpp"
#include "core/errors.hpp"
#include "core/writers.hpp"

#ifndef C2D_GNUPLOT
#define C2D_GNUPLOT "gnuplot"
#endif

namespace c2d::app {

namespace {

bool is_control(char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }

/// Doubles every single quote: inside '...' gnuplot substitutes nothing (no backquotes, no
/// macros, no escapes), and '' stands for one quote.
std::string single_quoted(std::string_view text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

}  // namespace

std::string gp_text(std::string_view text) {
  std::string clean;
  for (char c : text) {
    if (std::string_view("_^@&~{}\\").find(c) != std::string_view::npos) clean += '\\';
    clean += is_control(c) ? ' ' : c;
  }
  return single_quoted(clean);
}

std::string gp_palette(int maxcolors) {
  std::string out =
      "set palette defined (0 '#440154', 1 '#472c7a', 2 '#3b518b', 3 '#2c718e', 4 '#21908d', "
      "5 '#27ad81', 6 '#5cc863', 7 '#aadc32', 8 '#fde725')";
  if (maxcolors > 0) out += " maxcolors " + std::to_string(maxcolors);
  return out + "\n";
}

std::string gp_terminal(const std::string& term) {
  // Cairo sizes fonts in points at 96 dpi, the SVG terminal in pixels: the SVG's fonts are
  // scaled by 4/3 (measured: then 11 pt has the same cap height in both, as has a key's ',9').
  // Line widths are pixels in both.
  const std::string common = " size 1200,800 enhanced font 'Sans,11' linewidth 1";
  return term == "png" ? "set terminal pngcairo" + common + "\n"
                       : "set terminal svg" + common + " fontscale 1.3333 background rgb 'white'\n";
}

std::string gp_file(const std::string& path) {
  if (std::any_of(path.begin(), path.end(), is_control))
    throw InputError(path + ": expected a file path without control characters, found one");
  // Absolute, so that the name can never start with '<' or '|' (gnuplot runs those as commands).
  return single_quoted(std::filesystem::absolute(path).lexically_normal().string());
}

std::string run_gnuplot(const std::string& script_path) {
  const std::string exe = std::filesystem::exists(C2D_GNUPLOT) ? C2D_GNUPLOT : "gnuplot";
  const std::string script = std::filesystem::absolute(script_path).string();
  const std::string log = script + ".log";
  const ProcessOutcome run = run_process(exe, {script}, log);
  if (!run.started) return run.error;
  if (run.exit_code != 0)
    return "gnuplot failed (exit " + std::to_string(run.exit_code) + "), see " + log;
  std::filesystem::remove(log);
  return "";
}

namespace {

/// A private folder in the system's temporary directory (mkdtemp: mode 0700, a fresh name),
/// removed with everything in it when the scope ends. A chart's script and data live there, so
/// an interrupted chart leaves nothing half-written in the output folder.
class ScratchDir {
 public:
  ScratchDir() {
    std::string name =
        (std::filesystem::temp_directory_path() / "contact2d-chart-XXXXXX").string();
    if (!::mkdtemp(name.data())) throw std::runtime_error("cannot create a temporary folder");
    path_ = name;
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

void replace_all(std::string& text, const std::string& from, const std::string& to) {
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
}

/// Draws STEM.png and STEM.svg in `scratch`, then moves each into `dir` atomically. On failure
/// the script and gnuplot's log are kept in `dir` (STEM.gp, STEM.gp.log) for the user to read.
std::string plot_in(const ScratchDir& scratch, const std::string& dir, const std::string& stem,
                    const std::string& commands) {
  std::ostringstream gp;
  for (const char* term : {"png", "svg"}) {
    gp << gp_terminal(term) << "set output " << gp_file(scratch.file(stem + "." + term)) << "\n"
       << commands << "unset output\n";
  }
  const std::string script = scratch.file(stem + ".gp");
  core::write_file_atomic(script, gp.str());
  const std::string err = run_gnuplot(script);
  if (!err.empty()) {
    std::error_code ec;
    for (const std::string ext : {".gp", ".gp.log"})
      std::filesystem::copy_file(scratch.file(stem + ext), dir + "/" + stem + ext,
                                 std::filesystem::copy_options::overwrite_existing, ec);
    return "gnuplot failed, see " + dir + "/" + stem + ".gp.log";
  }
  for (const char* ext : {".png", ".svg"}) {
    const std::string target = dir + "/" + stem + ext;
    const std::string staged = target + ".tmp." + std::to_string(::getpid());
    std::filesystem::copy_file(scratch.file(stem + ext), staged,
                               std::filesystem::copy_options::overwrite_existing);
    std::filesystem::rename(staged, target);
  }
  return "";
}

}  // namespace

std::string plot_png_and_svg(const std::string& dir, const std::string& stem,
                             const std::string& commands) {
  const ScratchDir scratch;
  return plot_in(scratch, dir, stem, commands);
}

std::string plot_with_data(const std::string& dir, const std::string& stem,
                           const std::string& commands, const std::vector<PlotData>& data) {
  // Each data file goes into the scratch folder under its own name; the commands name it there.
  const ScratchDir scratch;
  std::string cmd = commands;
  for (const auto& d : data) {
    const std::string staged = scratch.file(std::filesystem::path(d.path).filename().string());
    core::write_file_atomic(staged, d.text);
    replace_all(cmd, gp_file(d.path), gp_file(staged));
  }
  return plot_in(scratch, dir, stem, cmd);
}

}  // namespace c2d::app
