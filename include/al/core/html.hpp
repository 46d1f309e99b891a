// Self-contained HTML pages for reports (eval's and sweep's report.html): one file, styles and the
// little script inline, images referenced relative to the page. No network, no external JS, so a
// page opens the same from a laptop, a cluster's file share or an archive.
#pragma once
#include <string>
#include <vector>

namespace al {

// Text for HTML content and attribute values (& < > " ' escaped).
std::string HtmlEscape(const std::string& text);

// A relative URL from a relative file path: each path segment percent-encoded (RFC 3986
// unreserved characters kept), separators kept.
std::string UrlPath(const std::string& relative_path);

// A number for a table cell: fixed with `digits` decimals, "–" for NaN / infinity.
std::string HtmlNumber(double value, int digits = 3);

// The whole page: doctype, UTF-8, the shared style sheet, `title`, then `body` and `script` (inline,
// may be empty).
std::string HtmlPage(const std::string& title, const std::string& body, const std::string& script = "");

// A table: `header` cells (escaped), then rows of ready HTML cells (the caller escapes).
std::string HtmlTable(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
                      const std::string& css_class = "");

}  // namespace al
