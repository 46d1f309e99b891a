// al-refine: thin command-line front end over the library. Exit codes: SPEC §1.
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <map>
#include <new>

#include "al/core/error.hpp"
#include "al/core/interrupts.hpp"
#include "src/cli/command.hpp"
#include "src/cli/malloc_defaults.hpp"
#include "src/cli/openmp_defaults.hpp"
#include "src/cli/run_policy.hpp"

namespace al::cli {

std::vector<CommandFactory>& CommandRegistry() {
  static std::vector<CommandFactory> registry;
  return registry;
}

}  // namespace al::cli

namespace {

// `al-refine --method fgs ...` without a subcommand means `refine` (SPEC §1).
std::vector<std::string> WithDefaultSubcommand(int argc, char** argv,
                                               const std::map<std::string, int>& names) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty()) return args;
  const std::string& first = args.front();
  const bool is_flag = !first.empty() && first[0] == '-';
  const bool is_global = first == "-h" || first == "--help" || first == "--version";
  if (is_flag && !is_global && names.count("refine")) args.insert(args.begin(), "refine");
  return args;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace al::cli;
  ApplyOpenMpDefaults(argv);
  ApplyMallocDefaults();
  al::InstallInterruptCleanup();  // before any thread: every thread leaves the signals to it
  CLI::App app{
      "al-refine: refine and score object removals in 3D Gaussian Splatting scenes.\n"
      "Without a subcommand, flags are passed to `refine`. Every subcommand writes report.json.\n"
      "Exit codes: 0 ok, 1 usage, 2 bad input, 3 empty graph, 4 internal error."};
  app.require_subcommand(0, 1);
  app.set_version_flag("--version", "al-refine 0.1.0");
  app.footer("Run `al-refine SUBCOMMAND --help` for the flags of a subcommand.");

  std::vector<std::unique_ptr<Command>> commands;
  std::map<std::string, int> names;
  for (const auto& factory : CommandRegistry()) commands.push_back(factory());
  std::sort(commands.begin(), commands.end(),
            [](const auto& a, const auto& b) { return a->Name() < b->Name(); });
  std::vector<CLI::App*> subs;
  RunPolicyFlags policy;
  for (std::size_t i = 0; i < commands.size(); ++i) {
    CLI::App* sub = app.add_subcommand(commands[i]->Name(), commands[i]->Description());
    commands[i]->Setup(*sub);
    AddRunPolicyFlags(*sub, policy);
    subs.push_back(sub);
    names[commands[i]->Name()] = int(i);
  }

  std::vector<std::string> args = WithDefaultSubcommand(argc, argv, names);
  std::reverse(args.begin(), args.end());  // CLI11 parses a reversed vector
  const bool no_arguments = args.empty();    // parse() consumes args, so remember this first
  try {
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : static_cast<int>(al::ExitCode::kUsage);
  }
  if (no_arguments) {
    std::cout << app.help();
    return static_cast<int>(al::ExitCode::kUsage);
  }
  std::set_new_handler(OnOutOfMemory);
  for (std::size_t i = 0; i < subs.size(); ++i) {
    if (!subs[i]->parsed()) continue;
    try {
      ApplyRunPolicy(policy);
      return commands[i]->Run();
    } catch (const al::Error& e) {
      std::cerr << "al-refine " << commands[i]->Name() << ": error: " << e.what() << "\n";
      return static_cast<int>(e.code());
    } catch (const std::bad_alloc&) {
      std::cerr << "al-refine " << commands[i]->Name()
                << ": error: out of memory (the input is too large for this machine; see --max-memory)\n";
      return static_cast<int>(al::ExitCode::kBadInput);
    } catch (const std::exception& e) {
      std::cerr << "al-refine " << commands[i]->Name() << ": internal error: " << e.what() << "\n";
      return static_cast<int>(al::ExitCode::kInternal);
    }
  }
  std::cout << app.help();
  return static_cast<int>(al::ExitCode::kUsage);
}
