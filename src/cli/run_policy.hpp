// Flags and process settings every subcommand shares (docs/reliability.md): --max-memory, --force,
// and what an allocation failure does.
#pragma once
#include <string>

#include <CLI/CLI.hpp>

namespace al::cli {

// --max-memory on every subcommand; --force where the subcommand writes --out.
void AddRunPolicyFlags(CLI::App& sub, std::string& max_memory, bool& force);
// After parsing: the memory limit and the --force default of every output set.
void ApplyRunPolicy(const std::string& max_memory, bool force);
// std::set_new_handler target: exit 2 with a message, never 4 (see run_policy.cpp).
void OnOutOfMemory();

}  // namespace al::cli
