// How the evaluator writes: into its output set's staging folder (al/core/output_set.hpp: a
// failure in view 37 leaves nothing half-written), and the many small PNGs of a view are encoded
// in parallel (compression dominates the I/O time).
#pragma once
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "al/io/image.hpp"

namespace al::eval {

// Writes the PNGs on `num_threads` threads (0 = OpenMP default); the first error in job order is
// rethrown as al::Error after all jobs ran.
void WritePngsParallel(const std::vector<std::pair<std::filesystem::path, Image8>>& jobs, int num_threads);

// File-name-safe view name (ReadCameras already makes names safe and unique; cameras built in
// code may not be).
std::string SafeName(std::string name);

}  // namespace al::eval
