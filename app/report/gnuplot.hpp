// Charts through gnuplot (PNG and SVG): scripts with quoted text and paths, run without a shell.
// A missing gnuplot is reported, not fatal.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace c2d::app {

/// Label text as a gnuplot single-quoted literal, shown as written: quotes doubled, control
/// characters blanked, and enhanced-text markup (_ ^ @ & ~ { } \\) escaped with a backslash, so
/// that `p_max` is not drawn as p with a subscript m. Single-quoted strings are the only ones
/// gnuplot substitutes nothing into (double-quoted ones run `backquoted` commands), so every
/// text from data goes into a script through this; the charts are enhanced text (for their
/// own 10^{n} tick labels), so no caller adds `noenhanced` (it would show the backslashes).
std::string gp_text(std::string_view text);

/// The colour map of every chart: `set palette defined` with viridis' nine control points
/// (perceptually uniform, readable by the colour blind and in grey; gnuplot 5.4 has no
/// built-in viridis). `maxcolors` > 0: that many discrete colours.
std::string gp_palette(int maxcolors = 0);

/// The terminal lines of both pictures: the same size, font, line width and white background,
/// so that STEM.png and STEM.svg look alike.
std::string gp_terminal(const std::string& term);

/// A file path as a gnuplot single-quoted literal, made absolute so that it never begins with
/// '<' or '|' (which gnuplot would run as a command). Throws InputError on a control character.
std::string gp_file(const std::string& path);

/// Runs gnuplot on a script (argument vector, no shell; output to SCRIPT.log, removed on
/// success); returns an empty string on success, else why it failed.
std::string run_gnuplot(const std::string& script_path);

/// Writes DIR/STEM.png and DIR/STEM.svg from gnuplot plot commands; "" or the failure reason
/// (then DIR/STEM.gp and DIR/STEM.gp.log are kept to read).
std::string plot_png_and_svg(const std::string& dir, const std::string& stem,
                             const std::string& commands);

/// A data file that plot commands read: where, and what it holds.
struct PlotData {
  std::string path, text;
};

/// plot_png_and_svg with the data files its commands read. The data files, the script and the
/// pictures are made in a private temporary folder (removed after, whatever happened) and only
/// the finished PNG and SVG are moved into DIR, each atomically: an interrupted chart leaves no
/// intermediate in DIR. The commands name each data file by its DIR path (through gp_file);
/// they are pointed at the temporary copy. Returns "" or the failure reason.
std::string plot_with_data(const std::string& dir, const std::string& stem,
                           const std::string& commands, const std::vector<PlotData>& data);

}  // namespace c2d::app
