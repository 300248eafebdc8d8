// The pieces of a study's HTML page (html_report.hpp): escaped text, the small markdown subset
// the studies' reports use, a CSV table with each cell's exact value kept beside its readable
// form, and a gnuplot SVG made fit to sit inline beside others in one document.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace c2d::app {

/// Text as HTML: & < > " ' replaced by their entities, so data (a scene path, a status) can
/// only ever be text, in an element or in a quoted attribute.
std::string html_escape(std::string_view text);

/// The markdown the study reports write, as HTML: `#`/`##`/`###` headings, paragraphs (lines
/// joined), pipe tables (the first row the header, the |---| row dropped), **bold** and
/// `code`; image lines (`![..](..)`) are dropped (the page inlines the charts itself). Every
/// other character is text, escaped.
std::string markdown_html(std::string_view md);

/// The rows of a CSV text (RFC 4180: quoted cells, "" for a quote inside one); empty lines
/// skipped.
std::vector<std::vector<std::string>> parse_csv_rows(std::string_view csv);

/// A CSV cell as a reader sees it: a number with 4 significant digits (an integer in full),
/// "–" when empty, any other text as it is.
std::string readable_cell(const std::string& cell);

/// The CSV as <table id="study-table">: the header row as <th> (each name may wrap after its
/// underscores), one <tr> per CSV row; each <td> shows readable_cell() and keeps the cell's
/// exact text in data-value (and, when they differ, in its title). The columns named in
/// `lead` come first, in that order (the ones a reader compares, visible without scrolling
/// sideways), then the others in the file's order. Throws InputError naming `name` on a ragged
/// row.
std::string csv_table_html(std::string_view csv, const std::string& name,
                           const std::vector<std::string>& lead = {});

/// The order in which csv_table_html shows the columns of `header`: the indices of the `lead`
/// names it has, then the rest in order.
std::vector<size_t> column_order(const std::vector<std::string>& header,
                                 const std::vector<std::string>& lead);

/// An SVG file's text as an element to inline into a page: the XML prolog, DOCTYPE and
/// comments before <svg> dropped, every id prefixed with `id_prefix` and every local reference
/// (href="#x", url(#x)) with it, so that charts that share ids (gnuplot's point symbols) stay
/// apart in one document; `label` becomes its aria-label. Returns "" and says why in `error`
/// when the text holds no <svg> element or holds a script or foreignObject.
std::string inline_svg(std::string_view svg, const std::string& id_prefix, const std::string& label,
                       std::string& error);

}  // namespace c2d::app
