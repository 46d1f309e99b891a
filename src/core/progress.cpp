#include "al/core/progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace al {

Progress::Progress(std::string label, std::size_t total, bool enabled)
    : label_(std::move(label)), total_(total), enabled_(enabled), tty_(::isatty(2) != 0) {}

void Progress::Step(std::size_t done) {
  if (!enabled_) return;
  const double t = timer_.Seconds();
  // Redraw at most 10 times a second on a terminal; in logs only every 10 %.
  if (tty_) {
    if (done != total_ && t - last_print_s_ < 0.1) return;
    std::fprintf(stderr, "\r%s %zu/%zu  %.1f s", label_.c_str(), done, total_, t);
  } else {
    const std::size_t step = total_ >= 10 ? total_ / 10 : 1;
    if (done % step != 0 && done != total_) return;
    std::fprintf(stderr, "%s %zu/%zu  %.1f s\n", label_.c_str(), done, total_, t);
  }
  last_print_s_ = t;
  std::fflush(stderr);
}

void Progress::Finish() {
  if (!enabled_ || finished_) return;
  finished_ = true;
  if (tty_) std::fprintf(stderr, "\r%s %zu/%zu  %.1f s\n", label_.c_str(), total_, total_, timer_.Seconds());
}

Progress::~Progress() { Finish(); }

}  // namespace al
