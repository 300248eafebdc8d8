#include "app/report/html_report.hpp"

#include <algorithm>
#include <cctype>
#include <ctime>
#include <fstream>
#include <sstream>

#include "app/report/html_blocks.hpp"
#include "core/writers.hpp"

namespace c2d::app {

namespace {

// Readable on screen and on paper; wide tables scroll inside their box, charts shrink to the
// page's width (their viewBox keeps the aspect).
constexpr const char* kStyle = R"(
:root { color-scheme: light; }
body { font: 15px/1.45 system-ui, -apple-system, "Segoe UI", sans-serif; color: #1b1f24;
       background: #fff; margin: 0; }
main { max-width: 1240px; margin: 0 auto; padding: 1.5rem 1.25rem 3rem; }
h1 { font-size: 1.5rem; margin: 0 0 .25rem; overflow-wrap: anywhere; }
h2 { font-size: 1.2rem; margin: 2rem 0 .5rem; border-bottom: 1px solid #d0d7de;
     padding-bottom: .2rem; }
h3 { font-size: 1.05rem; }
.meta { color: #57606a; margin: 0 0 1rem; }
#verdict { background: #f0f6ff; border-left: 4px solid #0969da; padding: .25rem 1rem; }
code { font: .9em ui-monospace, "DejaVu Sans Mono", monospace; background: #f3f4f6;
       padding: 0 .2em; border-radius: 3px; }
.scroll { overflow-x: auto; max-width: 100%; }
table { border-collapse: collapse; font-size: .85rem; margin: .5rem 0; }
th, td { border: 1px solid #d0d7de; padding: .2rem .45rem; text-align: left;
         vertical-align: top; }
th { background: #f6f8fa; position: sticky; top: 0; min-width: 3.5em; max-width: 7em;
     vertical-align: bottom; }
td.n { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
tbody tr:nth-child(even) { background: #fafbfc; }
figure { margin: 1.5rem 0; }
svg.chart { display: block; width: 100%; height: auto; max-width: 1200px;
            border: 1px solid #eaeef2; }
figcaption { color: #57606a; font-size: .9rem; margin-top: .3rem; }
.chart-missing { color: #9a6700; background: #fff8c5; padding: .4rem .7rem; }
@media print { .scroll { overflow: visible; } th { position: static; } }
)";

std::string read_text(const std::string& path, bool& ok) {
  std::ifstream in(path, std::ios::binary);
  ok = static_cast<bool>(in);
  std::ostringstream text;
  if (ok) text << in.rdbuf();
  return text.str();
}

/// Letters, digits, '-' and '_' of a chart's stem: what its element ids start with.
std::string id_of(const std::string& stem) {
  std::string id;
  for (char c : stem)
    id += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' ? c : '_';
  return id;
}

std::string missing_chart(const ReportChart& c, const std::string& id, const std::string& why) {
  return "<p class=\"chart-missing\" id=\"" + id + "\">Chart “" + html_escape(c.caption) + "” (" +
         html_escape(c.stem) + ".svg) not shown: " + html_escape(why) + "</p>\n";
}

std::string chart_html(const ReportChart& c, const std::string& dir) {
  const std::string id = "chart-" + id_of(c.stem);
  if (!c.written()) return missing_chart(c, id, "not written: " + c.not_written);
  bool read = false;
  const std::string svg = read_text(dir + "/" + c.stem + ".svg", read);
  if (!read) return missing_chart(c, id, "the file cannot be read");
  std::string error;
  const std::string element = inline_svg(svg, id_of(c.stem) + "-", c.caption, error);
  if (element.empty()) return missing_chart(c, id, error);
  return "<figure id=\"" + id + "\">\n" + element + "\n<figcaption>" + html_escape(c.caption) +
         " (also as " + html_escape(c.stem) + ".png and " + html_escape(c.stem) +
         ".svg)</figcaption>\n</figure>\n";
}

}  // namespace

std::string markdown_images(const std::vector<ReportChart>& charts) {
  std::string md;
  for (const auto& c : charts) {
    if (!c.written()) continue;
    if (!md.empty()) md += '\n';
    md.append("![").append(c.caption).append("](").append(c.stem).append(".png)\n");
  }
  return md;
}

std::string utc_now_text() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", &utc);
  return date;
}

std::string html_page(const HtmlReport& r, const std::string& dir) {
  const size_t rows = std::max<size_t>(parse_csv_rows(r.csv).size(), 1) - 1;
  std::ostringstream page;
  page << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
       << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
       << "<meta name=\"generator\" content=\"contact2d\">\n"
       << "<title>" << html_escape(r.title) << "</title>\n<style>" << kStyle
       << "</style>\n</head>\n<body>\n<main>\n<header>\n<h1>" << html_escape(r.title) << "</h1>\n"
       << "<p class=\"meta\">Written " << html_escape(r.date.empty() ? utc_now_text() : r.date)
       << " by contact2d from " << html_escape(r.csv_name) << " (" << rows
       << (rows == 1 ? " row" : " rows") << ") and the charts' SVG files.</p>\n"
       << markdown_html(r.intro_md) << "</header>\n"
       << "<section id=\"verdict\">\n<h2>Verdict</h2>\n"
       << markdown_html(r.verdict_md) << "</section>\n";
  if (!r.notes_md.empty())
    page << "<section id=\"notes\">\n" << markdown_html(r.notes_md) << "</section>\n";
  page << "<section id=\"table\">\n<h2>Table</h2>\n<p>Every column of " << html_escape(r.csv_name)
       << (r.lead_columns.empty() ? "" : ", the columns to compare first")
       << "; numbers to 4 significant digits (hover a cell for the file's value).</p>\n"
       << csv_table_html(r.csv, r.csv_name, r.lead_columns) << "</section>\n"
       << "<section id=\"charts\">\n<h2>Charts</h2>\n";
  if (r.charts.empty()) page << "<p>This study draws no chart.</p>\n";
  for (const auto& c : r.charts) page << chart_html(c, dir);
  page << "</section>\n</main>\n</body>\n</html>\n";
  return page.str();
}

void write_html_report(const std::string& dir, const std::string& name, const HtmlReport& report) {
  core::write_file_atomic(dir + "/" + name, html_page(report, dir));
}

}  // namespace c2d::app
