// The one exception type library code throws on bad input; the CLI maps it to an exit code.
#pragma once
#include <stdexcept>
#include <string>

namespace al {

// Exit codes of every subcommand (SPEC §1).
enum class ExitCode : int { kOk = 0, kUsage = 1, kBadInput = 2, kEmptyGraph = 3, kInternal = 4 };

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message, ExitCode code = ExitCode::kBadInput)
      : std::runtime_error(message), code_(code) {}
  ExitCode code() const { return code_; }

 private:
  ExitCode code_;
};

// Error about one input file: "<path>: <problem>".
inline Error FileError(const std::string& path, const std::string& problem) {
  return Error(path + ": " + problem, ExitCode::kBadInput);
}

}  // namespace al
