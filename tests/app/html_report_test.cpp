// The studies' HTML pages (app/report/html_report.hpp): text from data is escaped everywhere it
// lands, the table holds the CSV's rows with their exact values, one inline <svg> per chart
// written (ids kept apart between charts), and a chart not written is a sentence saying why.
// tests/browser/test_html_report.py opens real pages in Chromium.
#include "app/report/html_report.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <string>

#include "app/report/html_blocks.hpp"
#include "core/errors.hpp"
#include "read_text.hpp"

namespace fs = std::filesystem;
using namespace c2d::app;

namespace {

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

/// A gnuplot-like SVG: prolog, DOCTYPE, a symbol and a gradient defined and used by id.
std::string gnuplot_like_svg(const std::string& title) {
  return "<?xml version=\"1.0\" encoding=\"utf-8\"  standalone=\"no\"?>\n"
         "<!DOCTYPE svg PUBLIC \"-//W3C//DTD SVG 1.1//EN\" "
         "\"http://www.w3.org/Graphics/SVG/1.1/DTD/svg11.dtd\">\n"
         "<svg \n width=\"600\" height=\"400\"\n viewBox=\"0 0 600 400\"\n"
         " xmlns=\"http://www.w3.org/2000/svg\"\n xmlns:xlink=\"http://www.w3.org/1999/xlink\"\n>\n"
         "<g id=\"gnuplot_canvas\">\n<defs>\n"
         "\t<circle id='gpPt5' r='1'/>\n\t<linearGradient id=\"fade\"/>\n</defs>\n"
         "<use xlink:href='#gpPt5' x='10' y='20'/>\n<rect fill=\"url(#fade)\" width='5'/>\n"
         "<path d='M0,0 L10,10'/>\n<text>" +
         title + "</text>\n</g>\n</svg>\n";
}

using c2d::test::read_text;

}  // namespace

TEST(HtmlReport, EscapesEveryMarkupCharacter) {
  EXPECT_EQ(html_escape("a<script>&\"'>b"), "a&lt;script&gt;&amp;&quot;&#39;&gt;b");
  EXPECT_EQ(html_escape("plain text, 1.5 %"), "plain text, 1.5 %");
}

TEST(HtmlReport, MarkdownSubsetKeepsDataAsText) {
  const std::string html = markdown_html(
      "# Title <b>\n\nthe fastest was **lagrange** (`contact2d run`), x < 1 & y\n"
      "continued\n\n| method | status |\n|---|---|\n| ssn | failed: <script>alert(1)</script> |\n\n"
      "![chart](chart.png)\n\na ** stray marker\n");
  EXPECT_NE(html.find("<h1>Title &lt;b&gt;</h1>"), std::string::npos) << html;
  EXPECT_NE(html.find("<p>the fastest was <strong>lagrange</strong> (<code>contact2d run</code>), "
                      "x &lt; 1 &amp; y continued</p>"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("<tr><th>method</th><th>status</th></tr>"), std::string::npos) << html;
  EXPECT_NE(html.find("<td>failed: &lt;script&gt;alert(1)&lt;/script&gt;</td>"), std::string::npos)
      << html;
  EXPECT_EQ(html.find("---"), std::string::npos) << "the separator row is dropped";
  EXPECT_EQ(html.find("chart.png"), std::string::npos) << "image lines are dropped";
  EXPECT_NE(html.find("<p>a ** stray marker</p>"), std::string::npos) << "unpaired: text";
  EXPECT_EQ(html.find("<script"), std::string::npos);
}

// Issue 35, item 6: the columns a reader compares come first (compare.html's error columns
// were the 18th to 29th, off the screen to the right), the rest after in the file's order, and
// header names wrap after their underscores.
TEST(HtmlReport, LeadColumnsFirstAndHeadersWrap) {
  const std::vector<std::string> header = {"level", "method", "status", "p_max", "error_p_max"};
  EXPECT_EQ(column_order(header, {"level", "error_p_max", "absent", "method"}),
            (std::vector<size_t>{0, 4, 1, 2, 3}));
  EXPECT_EQ(column_order(header, {}), (std::vector<size_t>{0, 1, 2, 3, 4}));
  const std::string table =
      csv_table_html("level,method,status,p_max,error_p_max\n0,ssn,converged,383.3,0.00072\n",
                     "c.csv", {"level", "error_p_max"});
  EXPECT_NE(table.find("<tr><th>level</th><th>error_<wbr>p_<wbr>max</th><th>method</th>"
                       "<th>status</th><th>p_<wbr>max</th></tr>"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("<tr><td class=\"n\" data-value=\"0\">0</td><td class=\"n\" "
                       "data-value=\"0.00072\">0.00072</td><td data-value=\"ssn\">ssn</td>"),
            std::string::npos)
      << table;
}

TEST(HtmlReport, CsvCellsParseWithQuotesAndReadBackWithinTheirPrecision) {
  const auto rows = parse_csv_rows("a,b,c\n1,\"x, \"\"y\"\"\",\n\n2,,3\n");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[1], (std::vector<std::string>{"1", "x, \"y\"", ""}));
  EXPECT_EQ(rows[2], (std::vector<std::string>{"2", "", "3"}));
  EXPECT_EQ(readable_cell("0.014694924"), "0.01469");
  EXPECT_EQ(readable_cell("632"), "632");
  EXPECT_EQ(readable_cell("1e+10"), "1e+10");
  EXPECT_EQ(readable_cell("-2.3023018e-07"), "-2.302e-07");
  EXPECT_EQ(readable_cell(""), "–");
  EXPECT_EQ(readable_cell("converged"), "converged");
  EXPECT_THROW(csv_table_html("a,b\n1,2,3\n", "t.csv"), c2d::InputError);
}

TEST(HtmlReport, InlineSvgPrefixesIdsAndRefusesScripts) {
  std::string error;
  const std::string svg = inline_svg(gnuplot_like_svg("t"), "p1-", "a <label>", error);
  EXPECT_TRUE(error.empty()) << error;
  EXPECT_EQ(svg.rfind("<svg class=\"chart\" role=\"img\" aria-label=\"a &lt;label&gt;\"", 0), 0u)
      << svg.substr(0, 120);
  EXPECT_EQ(svg.find("<?xml"), std::string::npos);
  EXPECT_EQ(svg.find("DOCTYPE"), std::string::npos);
  for (const char* expected : {"id='p1-gpPt5'", "id=\"p1-fade\"", "id=\"p1-gnuplot_canvas\"",
                               "xlink:href='#p1-gpPt5'", "url(#p1-fade)"})
    EXPECT_NE(svg.find(expected), std::string::npos) << expected;
  EXPECT_EQ(svg.substr(svg.size() - 6), "</svg>");

  EXPECT_EQ(inline_svg("<svg><script>alert(1)</script></svg>", "p-", "x", error), "");
  EXPECT_NE(error.find("script"), std::string::npos);
  EXPECT_EQ(inline_svg("<svg><foreignObject/></svg>", "p-", "x", error), "");
  EXPECT_EQ(inline_svg("not an svg", "p-", "x", error), "");
  EXPECT_NE(error.find("no <svg>"), std::string::npos);
}

TEST(HtmlReport, PageHoldsTheCsvRowsAndOneSvgPerChartWritten) {
  const fs::path dir = fs::temp_directory_path() / ("c2d_html_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "first.svg") << gnuplot_like_svg("a &lt; b");
  std::ofstream(dir / "second.svg") << gnuplot_like_svg("c");
  HtmlReport r;
  r.title = "contact2d compare: /tmp/a&b <script>x</script>.toml";
  r.date = "2026-01-01 00:00 UTC";
  r.intro_md = "Times: `contact2d run` each.\n\n";
  r.verdict_md = "The fastest was **lagrange** & <i>not</i> ssn.";
  r.notes_md = "## Missing cases\n\n| case folder | jobs.txt line |\n|---|---|\n| level0/x | 2 |\n";
  r.csv_name = "compare.csv";
  r.csv =
      "level,method,status,p_max\n0,lagrange,\"converged\",384.89572123\n"
      "0,ssn,\"failed: <script>alert('x')</script> & more\",\n1,penalty,\"converged\",1e+10\n";
  r.charts = {{"first", "first chart", ""},
              {"second", "second chart", ""},
              {"third", "third <chart>", "gnuplot failed (exit 1) & more"},
              {"gone", "gone", ""}};  // said to be written, but the file is not there
  const std::string page = html_page(r, dir.string());

  EXPECT_EQ(page.rfind("<!DOCTYPE html>\n", 0), 0u);
  EXPECT_EQ(count(page, "<!DOCTYPE"), 1u) << "the SVGs' DOCTYPEs are dropped";
  EXPECT_EQ(count(page, "<?xml"), 0u);
  EXPECT_EQ(count(page, "<script"), 0u) << "data markup stays text";
  EXPECT_NE(page.find("<h1>contact2d compare: /tmp/a&amp;b &lt;script&gt;x&lt;/script&gt;.toml"),
            std::string::npos);
  EXPECT_NE(page.find("data-value=\"failed: &lt;script&gt;alert(&#39;x&#39;)&lt;/script&gt; &amp; "
                      "more\""),
            std::string::npos);
  EXPECT_NE(page.find("<strong>lagrange</strong> &amp; &lt;i&gt;not&lt;/i&gt; ssn"),
            std::string::npos);
  EXPECT_NE(page.find("Written 2026-01-01 00:00 UTC"), std::string::npos);

  // Table: the CSV's header and rows, exact values kept, readable ones shown.
  const size_t body = page.find("<tbody>"), body_end = page.find("</tbody>");
  ASSERT_NE(body, std::string::npos);
  EXPECT_EQ(count(page.substr(body, body_end - body), "<tr>"), 3u);
  EXPECT_NE(page.find("<th>level</th><th>method</th><th>status</th><th>p_<wbr>max</th>"),
            std::string::npos);
  EXPECT_NE(page.find("data-value=\"384.89572123\" title=\"384.89572123\">384.9</td>"),
            std::string::npos);
  EXPECT_NE(page.find("data-value=\"\">–</td>"), std::string::npos);

  // Charts: one <svg> per chart written; the others said in text.
  EXPECT_EQ(count(page, "<svg"), 2u);
  EXPECT_NE(page.find("<figure id=\"chart-first\">"), std::string::npos);
  EXPECT_NE(page.find("id='first-gpPt5'"), std::string::npos);
  EXPECT_NE(page.find("id='second-gpPt5'"), std::string::npos);
  EXPECT_NE(page.find("Chart “third &lt;chart&gt;” (third.svg) not shown: not written: gnuplot "
                      "failed (exit 1) &amp; more"),
            std::string::npos);
  EXPECT_NE(page.find("(gone.svg) not shown: the file cannot be read"), std::string::npos);
  std::set<std::string> ids;
  const std::regex id_attr(R"re(\sid=["']([^"']+)["'])re");
  for (auto it = std::sregex_iterator(page.begin(), page.end(), id_attr);
       it != std::sregex_iterator(); ++it)
    EXPECT_TRUE(ids.insert((*it)[1]).second) << "duplicate id " << (*it)[1];

  // Written beside the other files; markdown shows only the written charts.
  write_html_report(dir.string(), "compare.html", r);
  EXPECT_EQ(read_text(dir / "compare.html").size(), html_page(r, dir.string()).size());
  EXPECT_EQ(markdown_images(r.charts),
            "![first chart](first.png)\n\n![second chart](second.png)\n\n![gone](gone.png)\n");
  fs::remove_all(dir);
}
