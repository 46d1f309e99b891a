// al-refine's malloc policy (see malloc_defaults.cpp).
#pragma once

namespace al::cli {

// Early in main(): freed memory stays with the process for the next allocation instead of going
// back to the kernel, unless the user tuned malloc (GLIBC_TUNABLES names glibc.malloc) or set
// AL_MALLOC_DEFAULTS=0.
void ApplyMallocDefaults();

}  // namespace al::cli
