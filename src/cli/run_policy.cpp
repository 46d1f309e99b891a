#include "src/cli/run_policy.hpp"

#include <omp.h>
#include <unistd.h>

#include <new>

#include "al/core/error.hpp"
#include "al/core/memory_limit.hpp"
#include "al/core/output_set.hpp"
#include "src/cli/warnings.hpp"

namespace al::cli {

void AddRunPolicyFlags(CLI::App& sub, RunPolicyFlags& flags) {
  sub.add_option("--max-memory", flags.max_memory,
                 "Refuse inputs whose estimated memory exceeds this (8G, 512M, 60%); default: half of physical memory");
  if (!sub.get_option_no_throw("--out")) return;
  sub.add_flag("--force", flags.force, "Replace files in --out that no earlier al-refine manifest lists");
  sub.add_flag("--no-wait", flags.no_wait,
               "When another al-refine is writing into --out, refuse (exit 2) instead of waiting for it");
}

void ApplyRunPolicy(const RunPolicyFlags& flags) {
  if (!flags.max_memory.empty()) SetMemoryLimitBytes(ParseMemorySize(flags.max_memory));
  SetForceOutputs(flags.force);
  SetWaitForOutputs(!flags.no_wait);
  SetOutputNotices(PrintWarningOnce);
}

// Allocation failure is bad input (too big for this machine): exit 2 with a message, never 4.
// Outside parallel regions it unwinds (outputs staged so far are dropped); inside one it cannot
// cross the region, so the process ends here (the next run cleans the staging it leaves).
void OnOutOfMemory() {
  if (!omp_in_parallel()) throw std::bad_alloc();
  static const char msg[] = "al-refine: error: out of memory (the input is too large for this machine; see --max-memory)\n";
  (void)!::write(2, msg, sizeof msg - 1);
  ::_exit(static_cast<int>(ExitCode::kBadInput));
}

}  // namespace al::cli
