// Giving freed heap memory back to the system at a moment of our choosing.
#pragma once
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace al {

// Returns the heap's free pages to the system (glibc's malloc_trim; elsewhere nothing). The CLI
// keeps freed memory for reuse (src/cli/malloc_defaults.cpp), so without this every page a run
// ever touched is freed by the kernel at exit, on one thread after the work is done; a stage that
// has freed big blocks and is about to wait (on the disk) frees their pages in that wait instead.
inline void ReleaseFreeHeap() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

}  // namespace al
