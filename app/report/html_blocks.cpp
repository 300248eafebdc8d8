#include "app/report/html_blocks.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "core/errors.hpp"

namespace c2d::app {

namespace {

std::string trimmed(std::string_view s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return std::string(s.substr(a, b - a));
}

/// **bold** and `code` of one line of markdown, the rest escaped. A marker opens only when a
/// closing one follows, so the tags always pair up.
std::string inline_md(std::string_view text) {
  const std::string e = html_escape(text);
  std::string out;
  bool bold = false, code = false;
  for (size_t i = 0; i < e.size(); ++i) {
    if (!code && e.compare(i, 2, "**") == 0 && (bold || e.find("**", i + 2) != std::string::npos)) {
      out += bold ? "</strong>" : "<strong>";
      bold = !bold;
      ++i;
    } else if (e[i] == '`' && (code || e.find('`', i + 1) != std::string::npos)) {
      out += code ? "</code>" : "<code>";
      code = !code;
    } else {
      out += e[i];
    }
  }
  return out;
}

std::vector<std::string> table_cells(const std::string& line) {
  std::string row = trimmed(line);
  if (!row.empty() && row.front() == '|') row.erase(0, 1);
  if (!row.empty() && row.back() == '|') row.pop_back();
  std::vector<std::string> cells;
  std::stringstream ss(row);
  for (std::string c; std::getline(ss, c, '|');) cells.push_back(trimmed(c));
  return cells;
}

bool is_separator_row(const std::vector<std::string>& cells) {
  return !cells.empty() && std::all_of(cells.begin(), cells.end(), [](const std::string& c) {
    return !c.empty() && c.find_first_not_of("-: ") == std::string::npos;
  });
}

std::string markdown_table(const std::vector<std::string>& lines) {
  std::ostringstream out;
  out << "<div class=\"scroll\"><table>\n";
  for (size_t i = 0; i < lines.size(); ++i) {
    const std::vector<std::string> cells = table_cells(lines[i]);
    if (i == 1 && is_separator_row(cells)) continue;
    const char* tag = i == 0 ? "th" : "td";
    out << "<tr>";
    for (const auto& c : cells) out << '<' << tag << '>' << inline_md(c) << "</" << tag << '>';
    out << "</tr>\n";
  }
  out << "</table></div>\n";
  return out.str();
}

/// The number a cell holds, if the whole cell is one finite number.
bool cell_number(const std::string& cell, double& value) {
  if (cell.empty() || std::isspace(static_cast<unsigned char>(cell.front()))) return false;
  char* end = nullptr;
  value = std::strtod(cell.c_str(), &end);
  return end != cell.c_str() && *end == '\0' && std::isfinite(value);
}

/// The name of the attribute whose '=' ends `out` (what precedes an opening quote).
std::string attribute_before(const std::string& out) {
  if (out.empty() || out.back() != '=') return "";
  size_t b = out.size() - 1;
  while (b > 0 && (std::isalnum(static_cast<unsigned char>(out[b - 1])) || out[b - 1] == ':' ||
                   out[b - 1] == '-' || out[b - 1] == '_'))
    --b;
  return out.substr(b, out.size() - 1 - b);
}

/// Prefixes ids and local references inside the tags of `svg` (text between tags is left as
/// it is, except CSS url(#x), which a <style> element may hold).
std::string prefix_ids(const std::string& svg, const std::string& prefix) {
  std::string out;
  out.reserve(svg.size() + svg.size() / 8);
  bool in_tag = false;
  char quote = 0;
  for (size_t i = 0; i < svg.size(); ++i) {
    const char c = svg[i];
    if (svg.compare(i, 5, "url(#") == 0) {
      out += "url(#" + prefix;
      i += 4;
      continue;
    }
    if (!in_tag) {
      in_tag = c == '<';
    } else if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
      const std::string name = attribute_before(out);
      out += c;
      if (name == "id") out += prefix;
      if ((name == "href" || name == "xlink:href") && i + 1 < svg.size() && svg[i + 1] == '#')
        out += "#" + prefix, ++i;
      continue;
    } else if (c == '>') {
      in_tag = false;
    }
    out += c;
  }
  return out;
}

std::string lowercase(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

}  // namespace

std::string html_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string markdown_html(std::string_view md) {
  std::vector<std::string> lines;
  std::stringstream ss{std::string(md)};
  for (std::string line; std::getline(ss, line);) lines.push_back(line);
  std::ostringstream out;
  std::string paragraph;
  auto flush = [&] {
    if (!paragraph.empty()) out << "<p>" << inline_md(paragraph) << "</p>\n";
    paragraph.clear();
  };
  for (size_t i = 0; i < lines.size();) {
    const std::string line = trimmed(lines[i]);
    const size_t hashes = line.find_first_not_of('#');
    if (line.empty() || line.rfind("![", 0) == 0) {
      flush();
      ++i;
    } else if (hashes >= 1 && hashes <= 3 && line[hashes] == ' ') {
      flush();
      out << "<h" << hashes << '>' << inline_md(trimmed(line.substr(hashes))) << "</h" << hashes
          << ">\n";
      ++i;
    } else if (line.front() == '|') {
      flush();
      std::vector<std::string> rows;
      for (; i < lines.size() && trimmed(lines[i]).rfind('|', 0) == 0; ++i)
        rows.push_back(lines[i]);
      out << markdown_table(rows);
    } else {
      paragraph += (paragraph.empty() ? "" : " ") + line;
      ++i;
    }
  }
  flush();
  return out.str();
}

std::vector<std::vector<std::string>> parse_csv_rows(std::string_view csv) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> row;
  std::string cell;
  bool quoted = false, any = false;  // any: the line holds something (a cell or a separator)
  auto end_row = [&] {
    if (any) row.push_back(cell), rows.push_back(row);
    row.clear(), cell.clear(), any = false;
  };
  for (size_t i = 0; i < csv.size(); ++i) {
    const char c = csv[i];
    if (quoted) {
      if (c != '"')
        cell += c;
      else if (i + 1 < csv.size() && csv[i + 1] == '"')
        cell += '"', ++i;
      else
        quoted = false;
    } else if (c == '"') {
      quoted = any = true;
    } else if (c == ',') {
      row.push_back(cell), cell.clear(), any = true;
    } else if (c == '\n' || c == '\r') {
      end_row();
    } else {
      cell += c, any = true;
    }
  }
  end_row();
  return rows;
}

std::string readable_cell(const std::string& cell) {
  double v = 0;
  if (cell.empty()) return "–";
  if (!cell_number(cell, v) || cell.find_first_of(".eE") == std::string::npos) return cell;
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", v);
  return text;
}

std::vector<size_t> column_order(const std::vector<std::string>& header,
                                 const std::vector<std::string>& lead) {
  std::vector<size_t> order;
  for (const auto& name : lead) {
    const auto at = std::find(header.begin(), header.end(), name);
    if (at != header.end()) order.push_back(static_cast<size_t>(at - header.begin()));
  }
  for (size_t c = 0; c < header.size(); ++c)
    if (std::find(order.begin(), order.end(), c) == order.end()) order.push_back(c);
  return order;
}

namespace {

/// A column name that may wrap after each underscore: "error_p_max" is three short lines, not
/// one wide column.
std::string header_html(const std::string& name) {
  std::string out;
  for (char c : html_escape(name)) {
    out += c;
    if (c == '_') out += "<wbr>";
  }
  return out;
}

}  // namespace

std::string csv_table_html(std::string_view csv, const std::string& name,
                           const std::vector<std::string>& lead) {
  const std::vector<std::vector<std::string>> rows = parse_csv_rows(csv);
  if (rows.empty()) return "<p>" + html_escape(name) + " is empty.</p>\n";
  const std::vector<size_t> order = column_order(rows.front(), lead);
  std::ostringstream out;
  out << "<div class=\"scroll\"><table id=\"study-table\">\n<thead><tr>";
  for (size_t c : order) out << "<th>" << header_html(rows.front()[c]) << "</th>";
  out << "</tr></thead>\n<tbody>\n";
  for (size_t r = 1; r < rows.size(); ++r) {
    if (rows[r].size() != rows.front().size())
      throw InputError(name + ": row " + std::to_string(r + 1) + ": expected " +
                       std::to_string(rows.front().size()) + " cells, found " +
                       std::to_string(rows[r].size()));
    out << "<tr>";
    for (size_t c : order) {
      const std::string& cell = rows[r][c];
      double v = 0;
      const std::string shown = readable_cell(cell);
      const std::string exact = html_escape(cell);
      out << "<td" << (cell_number(cell, v) ? " class=\"n\"" : "") << " data-value=\"" << exact
          << '"' << (shown != cell && !cell.empty() ? " title=\"" + exact + '"' : std::string())
          << '>' << html_escape(shown) << "</td>";
    }
    out << "</tr>\n";
  }
  out << "</tbody>\n</table></div>\n";
  return out.str();
}

std::string inline_svg(std::string_view svg, const std::string& id_prefix, const std::string& label,
                       std::string& error) {
  const size_t start = svg.find("<svg");
  const size_t end = svg.rfind("</svg>");
  if (start == std::string_view::npos || end == std::string_view::npos || end < start) {
    error = "the file holds no <svg> element";
    return "";
  }
  const std::string element(svg.substr(start, end + 6 - start));
  const std::string lower = lowercase(element);
  if (lower.find("<script") != std::string::npos ||
      lower.find("<foreignobject") != std::string::npos) {
    error = "the SVG holds a script or foreignObject, which a report does not inline";
    return "";
  }
  error.clear();
  return "<svg class=\"chart\" role=\"img\" aria-label=\"" + html_escape(label) + '"' +
         prefix_ids(element.substr(4), id_prefix);
}

}  // namespace c2d::app
