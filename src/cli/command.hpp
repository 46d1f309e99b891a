// Subcommands register themselves here; main.cpp builds the CLI11 app from the registry.
// Each command file: a struct deriving from Command, registered with AL_REGISTER_COMMAND.
// Commands are thin: parse flags into an options struct, call the library, print, write report.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace al::cli {

class Command {
 public:
  virtual ~Command() = default;
  virtual std::string Name() const = 0;
  virtual std::string Description() const = 0;
  // Declares flags on `app`, binding them to members.
  virtual void Setup(CLI::App& app) = 0;
  // Runs after a successful parse; returns the exit code. Throws al::Error on bad input.
  virtual int Run() = 0;
};

using CommandFactory = std::function<std::unique_ptr<Command>()>;
std::vector<CommandFactory>& CommandRegistry();

struct CommandRegistrar {
  explicit CommandRegistrar(CommandFactory factory) { CommandRegistry().push_back(std::move(factory)); }
};

}  // namespace al::cli

#define AL_REGISTER_COMMAND(Type) \
  static ::al::cli::CommandRegistrar al_registrar_##Type([] { return std::make_unique<Type>(); })
