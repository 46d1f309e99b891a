// Outputs are written to a temporary name and renamed when complete, so a failed run never
// leaves a half-written file behind (SPEC §9).
#pragma once
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>

namespace al {

// Calls write(stream) on "<path>.tmp.<pid>", then renames it to path. Throws al::Error on failure
// (and removes the temporary).
void WriteFileAtomically(const std::filesystem::path& path,
                         const std::function<void(std::ostream&)>& write, bool binary = true);

// The file descriptor under a stream that WriteFileAtomically handed to its callback, after
// flushing the stream, so that bytes written to the descriptor directly (e.g. pwrite at offsets by
// the kept-records writer) follow the stream's; -1 for any other stream.
int FlushedDescriptor(std::ostream& os);

// Convenience: whole buffer.
void WriteFileAtomically(const std::filesystem::path& path, const std::string& bytes);

// Creates the directory (and parents); throws al::Error naming it on failure.
void EnsureDirectory(const std::filesystem::path& dir);

}  // namespace al
