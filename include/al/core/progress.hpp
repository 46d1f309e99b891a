// A progress line on stderr for long work ("render  12/24 views  3.1 s"). Quiet when stderr is
// not a terminal unless forced, so logs of sweeps stay readable.
#pragma once
#include <cstddef>
#include <string>

#include "al/core/timer.hpp"

namespace al {

class Progress {
 public:
  Progress(std::string label, std::size_t total, bool enabled = true);
  void Step(std::size_t done);  // absolute count
  void Finish();
  ~Progress();

 private:
  std::string label_;
  std::size_t total_;
  bool enabled_;
  bool finished_ = false;
  bool tty_;
  double last_print_s_ = -1.0;
  Timer timer_;
};

}  // namespace al
