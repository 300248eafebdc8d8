// A study's report as one HTML page (compare.html, sweep.html, bench.html beside the .md): the
// title and how the times were taken, the verdict, the CSV's table with every column, and each
// chart's SVG inline. Self-contained (inline CSS, no script, no external resource), so it opens
// offline and can be mailed as one file. Built from the same strings as the markdown report.
#pragma once

#include <string>
#include <vector>

namespace c2d::app {

/// A chart a study drew, or meant to: DIR/STEM.svg (and STEM.png).
struct ReportChart {
  std::string stem;
  std::string caption;
  std::string not_written;  ///< "" when gnuplot wrote it, else why not (the page shows this)
  bool written() const { return not_written.empty(); }
};

/// The markdown image lines of the written charts ("![caption](STEM.png)", blank-line apart).
std::string markdown_images(const std::vector<ReportChart>& charts);

/// What the page shows, in order. The *_md fields are the markdown report's own text.
struct HtmlReport {
  std::string title;       ///< plain text: the markdown report's heading
  std::string date;        ///< when the report was written; "" for now (UTC)
  std::string intro_md;    ///< how the times were taken (and, for bench, where)
  std::string verdict_md;  ///< the verdict paragraph (bench: the targets beside the figures)
  std::string notes_md;    ///< the rest: missing cases, orders of convergence, fits, slopes
  std::string csv_name;    ///< the CSV file the table shows, e.g. "compare.csv"
  std::string csv;         ///< that file's text
  std::vector<ReportChart> charts;
  std::vector<std::string> lead_columns;  ///< the table's first columns (csv_table_html)
};

/// "2026-11-24 17:43 UTC".
std::string utc_now_text();

/// The page. Each written chart's `dir`/STEM.svg is read and inlined with its ids prefixed by
/// "STEM-"; a chart not written, unreadable or unsafe to inline is a sentence saying so.
std::string html_page(const HtmlReport& report, const std::string& dir);

/// Writes `dir`/`name` (atomically) from html_page(report, dir).
void write_html_report(const std::string& dir, const std::string& name, const HtmlReport& report);

}  // namespace c2d::app
