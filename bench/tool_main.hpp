// main() of the bench tools (bench_report, bench_scale_collect, bench_problem): an al::Error exits
// with its code and message, anything else with "NAME: what" and the internal-error code.
#pragma once
#include <exception>
#include <iostream>

#include "al/core/error.hpp"

namespace al::bench {

template <class Main>
int RunTool(const char* name, Main&& run) {
  try {
    return run();
  } catch (const al::Error& e) {
    std::cerr << e.what() << "\n";
    return static_cast<int>(e.code());
  } catch (const std::exception& e) {
    std::cerr << name << ": " << e.what() << "\n";
    return static_cast<int>(al::ExitCode::kInternal);
  }
}

}  // namespace al::bench
