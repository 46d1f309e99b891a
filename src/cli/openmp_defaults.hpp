// al-refine's OpenMP wait policy (see openmp_defaults.cpp).
#pragma once

namespace al::cli {

// First thing in main(): sets OMP_WAIT_POLICY=passive unless the user chose a policy, by re-executing the
// binary (libgomp has already read the environment). Returns when nothing needs to change.
void ApplyOpenMpDefaults(char** argv);

}  // namespace al::cli
