// Self-contained HTML pages for reports (al/core/html.hpp).
#include "al/core/html.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>

namespace al {

std::string HtmlEscape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string UrlPath(const std::string& path) {
  static const char* kHex = "0123456789ABCDEF";
  std::string out;
  for (unsigned char c : path) {
    const bool keep = std::isalnum(c) || c == '-' || c == '.' || c == '_' || c == '~' || c == '/';
    if (keep) {
      out += char(c);
    } else {
      out += '%';
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

std::string HtmlNumber(double value, int digits) {
  if (!std::isfinite(value)) return "–";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, value);
  return buffer;
}

std::string HtmlTable(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
                      const std::string& css_class) {
  std::string s = "<table" + (css_class.empty() ? std::string() : " class=\"" + css_class + "\"") + "><thead><tr>";
  for (const auto& h : header) s += "<th>" + HtmlEscape(h) + "</th>";
  s += "</tr></thead><tbody>\n";
  for (const auto& row : rows) {
    s += "<tr>";
    for (std::size_t i = 0; i < row.size(); ++i) s += (i == 0 ? "<th>" : "<td>") + row[i] + (i == 0 ? "</th>" : "</td>");
    s += "</tr>\n";
  }
  return s + "</tbody></table>\n";
}

std::string HtmlPage(const std::string& title, const std::string& body, const std::string& script) {
  static const char* kStyle = R"css(
body{font:14px/1.4 system-ui,-apple-system,"Segoe UI",sans-serif;margin:1.5em;color:#222;background:#fafafa}
h1{font-size:1.5em;margin:0 0 .3em}h2{font-size:1.2em;margin:1.4em 0 .4em;border-bottom:1px solid #ccc}
table{border-collapse:collapse;margin:.4em 0;background:#fff}
th,td{border:1px solid #ddd;padding:.25em .6em;text-align:right}thead th{background:#eee;text-align:center}
tbody th{text-align:left;font-weight:normal}td.best{font-weight:bold}
.note{color:#666;font-size:.9em}.warn{color:#9a5b00}
.view{background:#fff;border:1px solid #ddd;border-radius:6px;margin:1em 0;padding:.6em}
.view.flagged{border-color:#d08000;box-shadow:0 0 0 2px #f3c77a}
.view h3{margin:.1em 0 .4em;font-size:1.05em}.flag{background:#f3c77a;border-radius:3px;padding:0 .4em;margin-left:.4em}
.strip{display:flex;flex-wrap:wrap;gap:.5em}.strip figure{margin:0}.strip img{display:block;width:240px;image-rendering:pixelated}
figcaption{font-size:.85em;color:#555;text-align:center}
.compare{position:relative;display:inline-block;margin-top:.5em}.compare img{display:block;width:480px}
.compare img.top{position:absolute;left:0;top:0;clip-path:inset(0 50% 0 0)}
.controls{margin:.3em 0}.controls label{margin-right:.8em}
)css";
  return "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>" + HtmlEscape(title) +
         "</title>\n<style>" + kStyle + "</style></head>\n<body>\n" + body +
         (script.empty() ? std::string() : "<script>\n" + script + "\n</script>\n") + "</body></html>\n";
}

}  // namespace al
