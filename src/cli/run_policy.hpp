// Flags and process settings every subcommand shares (docs/reliability.md): --max-memory, --force,
// and what an allocation failure does.
#pragma once
#include <string>

#include <CLI/CLI.hpp>

namespace al::cli {

struct RunPolicyFlags {
  std::string max_memory;
  bool force = false;
  bool no_wait = false;
};
// --max-memory on every subcommand; --force and --no-wait where the subcommand writes --out.
void AddRunPolicyFlags(CLI::App& sub, RunPolicyFlags& flags);
// After parsing: the memory limit and the --force / --no-wait defaults of every output set, whose
// notices (waiting for the lock, look-alike folders left alone) go to stderr.
void ApplyRunPolicy(const RunPolicyFlags& flags);
// std::set_new_handler target: exit 2 with a message, never 4 (see run_policy.cpp).
void OnOutOfMemory();

}  // namespace al::cli
