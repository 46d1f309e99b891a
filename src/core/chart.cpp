#include "al/core/chart.hpp"

#include <sys/wait.h>

#include <cstdlib>
#include <system_error>

#include "al/core/atomic_file.hpp"

namespace al {
namespace fs = std::filesystem;

std::string GnuplotQuote(const std::string& text) {
  std::string out = "'";
  for (char c : text) {
    out += c;
    if (c == '\'') out += '\'';
  }
  return out + "'";
}

namespace {

// Quotes a path for /bin/sh.
std::string ShellQuote(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

ChartResult DrawChart(const fs::path& png_path, const std::string& script) {
  ChartResult result;
  const fs::path dir = png_path.parent_path().empty() ? fs::path(".") : png_path.parent_path();
  fs::path script_path = png_path;
  script_path.replace_extension(".gp");
  WriteFileAtomically(script_path, script);
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) {
    result.message = "gnuplot not found (install gnuplot-nox); wrote " + script_path.string() + " only";
    return result;
  }
  // gnuplot writes to the name the script sets; draw into a temporary copy of the script whose
  // output is redirected, then rename, so an interrupted run never leaves a partial PNG.
  const std::string tmp_name = png_path.filename().string() + ".tmp.png";
  const std::string wrapper = "set output " + GnuplotQuote(tmp_name) + "\n";
  std::string patched;
  // Later `set output` lines in the script would win; so rewrite the script's own output line.
  std::size_t pos = 0;
  bool replaced = false;
  while (pos < script.size()) {
    std::size_t end = script.find('\n', pos);
    if (end == std::string::npos) end = script.size();
    const std::string line = script.substr(pos, end - pos);
    if (!replaced && line.rfind("set output", 0) == 0) {
      patched += wrapper;
      replaced = true;
    } else {
      patched += line + "\n";
    }
    pos = end + 1;
  }
  if (!replaced) patched = wrapper + patched;
  const fs::path tmp_script = dir / (png_path.filename().string() + ".tmp.gp");
  WriteFileAtomically(tmp_script, patched);
  const std::string command = "cd " + ShellQuote(dir.string()) + " && gnuplot " +
                              ShellQuote(tmp_script.filename().string()) + " 2>" +
                              ShellQuote(png_path.filename().string() + ".gnuplot.log");
  const int status = std::system(command.c_str());
  std::error_code ec;
  fs::remove(tmp_script, ec);
  const fs::path tmp_png = dir / tmp_name;
  const fs::path log = dir / (png_path.filename().string() + ".gnuplot.log");
  if (status != 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0 || !fs::exists(tmp_png) ||
      fs::file_size(tmp_png, ec) == 0) {
    fs::remove(tmp_png, ec);
    result.message = "gnuplot failed for " + png_path.string() + " (see " + log.string() + ")";
    return result;
  }
  fs::remove(log, ec);
  fs::rename(tmp_png, png_path, ec);
  if (ec) {
    result.message = "cannot rename the chart to " + png_path.string() + ": " + ec.message();
    return result;
  }
  result.drawn = true;
  return result;
}

}  // namespace al
