#include "app/report/gnuplot.hpp"

#include <algorithm>
#include <filesystem>
#include <sstream>

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
  std::string clean(text);
  std::replace_if(clean.begin(), clean.end(), is_control, ' ');
  return single_quoted(clean);
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

std::string plot_png_and_svg(const std::string& dir, const std::string& stem,
                             const std::string& commands) {
  std::ostringstream gp;
  for (const char* term : {"png", "svg"}) {
    gp << (std::string(term) == "png" ? "set terminal pngcairo size 1200,800 font 'Sans,11'\n"
                                      : "set terminal svg size 1200,800 font 'Sans,11'\n")
       << "set output " << gp_file(dir + "/" + stem + "." + term) << "\n"
       << commands << "unset output\n";
  }
  const std::string script = dir + "/" + stem + ".gp";
  core::write_file_atomic(script, gp.str());
  const std::string err = run_gnuplot(script);
  if (err.empty()) std::filesystem::remove(script);
  return err;
}

std::string plot_with_data(const std::string& dir, const std::string& stem,
                           const std::string& commands, const std::vector<PlotData>& data) {
  for (const auto& d : data) core::write_file_atomic(d.path, d.text);
  const std::string err = plot_png_and_svg(dir, stem, commands);
  for (const auto& d : data) std::filesystem::remove(d.path);
  return err;
}

}  // namespace c2d::app
