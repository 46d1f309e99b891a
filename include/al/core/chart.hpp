// Charts for reports (compare, sweep, eval, benchmarks) are drawn by gnuplot, a Debian package the
// set-up installs. The script and its data are always written next to the PNG so a user can restyle
// the chart; when gnuplot is missing or fails, the PNG is skipped with a reason instead of failing
// the whole run.
#pragma once
#include <filesystem>
#include <string>

namespace al {

struct ChartResult {
  bool drawn = false;     // the PNG exists
  std::string message;    // why not, when not drawn
};

// Writes `script` to png_path with extension ".gp" (atomically), then runs
// `gnuplot <script>` with the working directory set to the PNG's folder, so data files can be
// referenced by bare name. The script itself must set the terminal and `set output '<name>.png'`.
// The PNG is first drawn to a temporary name and renamed, so a failure leaves no half-written image.
ChartResult DrawChart(const std::filesystem::path& png_path, const std::string& script);

// Quotes a string for a gnuplot script (single quotes, embedded quotes doubled).
std::string GnuplotQuote(const std::string& text);

}  // namespace al
