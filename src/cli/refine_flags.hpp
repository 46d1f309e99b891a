// The flags `refine`, `compare` and `sweep` share (inputs, graph, decision), declared once so the
// subcommands cannot drift apart. A command owns a RefineFlags, calls the Add*Flags it needs in
// Setup and ToRefineOptions at the start of Run (CLI11 binds strings; the enums, the decision rule
// and the JSON are converted here, with usage errors).
#pragma once
#include <string>

#include <CLI/CLI.hpp>

#include "al/refine/refine.hpp"

namespace al::cli {

struct RefineFlags {
  static constexpr int kUnset = -2147483647;
  RefineOptions options;              // fields CLI11 can bind directly
  std::string removed_is;             // "", "removed", "remaining"
  std::string delta_mode = "distance";
  std::string spatial = "on";
  std::string centre = "on";
  std::string threshold = "0.5";
  std::string solver_options;         // JSON text (only when AddSolverFlags was called)
  int object_id = kUnset;
};

// --scene --removed --removed-is --method --features --decoder --labels --object-id
// --max-unmatched --match-tol --prompt-embeddings --positive --fgs-threshold
void AddInputFlags(CLI::App& app, RefineFlags& flags);

// --k --delta --delta-mode --lambda --spatial --hops --radius-scale --knn-checks --kl-smoothing
void AddGraphFlags(CLI::App& app, RefineFlags& flags);

// --threshold --restore --min-segment-share
void AddDecisionFlags(CLI::App& app, RefineFlags& flags);

// --solver --solver-options (refine: one solver; compare has its own --solvers)
void AddSolverFlags(CLI::App& app, RefineFlags& flags);

// The parsed flags as RefineOptions. Throws al::Error (usage) for a bad --threshold or
// --solver-options.
RefineOptions ToRefineOptions(const RefineFlags& flags);

}  // namespace al::cli
