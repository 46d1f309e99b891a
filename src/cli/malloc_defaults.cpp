// The malloc policy of the al-refine binary. glibc serves a large block with its own mmap and
// unmaps it on free, so every big array a stage allocates after another stage freed one arrives
// as fresh pages the kernel must fault in and zero, one page at a time. On this project's VMs
// that first touch is dear (docs/solvers.md "Memory and first touch at 3M"): on the 3M scene of
// issue 33 the graph, the level-set start and the max-flow networks reuse what earlier stages
// freed when large blocks come from the heap and free memory is not trimmed: cp 3.29-3.52 ->
// 3.14-3.20 s, bk within noise, peak RSS +12 MB (docs/solvers.md "Fast at scale: stop 39").
// Memory is returned when the process exits; a user's GLIBC_TUNABLES for malloc always wins.
#include "src/cli/malloc_defaults.hpp"

#include <malloc.h>

#include <climits>
#include <cstdlib>
#include <cstring>

namespace al::cli {

void ApplyMallocDefaults() {
  const char* flag = std::getenv("AL_MALLOC_DEFAULTS");
  if (flag != nullptr && std::strcmp(flag, "0") == 0) return;
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (tunables != nullptr && std::strstr(tunables, "glibc.malloc.") != nullptr) return;
  // No block gets its own mapping (a thread's arena that cannot hold one falls back to the main
  // heap), and the heap's free top is never trimmed.
  ::mallopt(M_MMAP_MAX, 0);
  ::mallopt(M_TRIM_THRESHOLD, INT_MAX);
}

}  // namespace al::cli
