// The OpenMP wait policy of the al-refine binary (docs/reliability.md "Time bounds";
// measured by bench/contention). libgomp reads its environment once, when it is loaded, so the
// default is set by re-executing the binary with it; an explicit OMP_WAIT_POLICY,
// or GOMP_SPINCOUNT from the user always wins, and AL_OMP_DEFAULTS=0 turns this off.
#include "src/cli/openmp_defaults.hpp"

#include <unistd.h>

#include <cstdlib>
#include <cstring>

namespace al::cli {

namespace {

// Waiting threads sleep at once instead of spinning. libgomp's default spins ~300000 pause
// instructions (milliseconds) per wait: with another process on the other core, every barrier
// then costs whole time slices (cp on 1M Gaussians: 143-169 s instead of ~10 s on this shared
// machine, bench/contention). The idle cost of sleeping is kept small by having few barriers
// (the cut-pursuit inner loop runs serially below 50k unknowns).
constexpr const char* kPolicyVar = "OMP_WAIT_POLICY";
constexpr const char* kPolicy = "passive";

bool Set(const char* name) {
  const char* v = std::getenv(name);
  return v != nullptr && v[0] != '\0';
}

}  // namespace

void ApplyOpenMpDefaults(char** argv) {
  if (Set("OMP_WAIT_POLICY") || Set("GOMP_SPINCOUNT")) return;
  const char* flag = std::getenv("AL_OMP_DEFAULTS");
  if (flag != nullptr && std::strcmp(flag, "0") == 0) return;
  ::setenv(kPolicyVar, kPolicy, 1);
  ::setenv("AL_OMP_DEFAULTS", "0", 1);  // the re-executed process keeps what it got
  ::execv("/proc/self/exe", argv);      // returns only on failure: run with libgomp's defaults
}

}  // namespace al::cli
