// Warnings on stderr, each once per process: the output set tells some as soon as it finds them
// (a look-alike folder left alone, waiting for another writer), and the same words come back in
// the report's warnings that a command prints at the end.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace al::cli {

void PrintWarningOnce(const std::string& warning);
// Every string of report["warnings"] not printed yet, except `except` (a command's own message).
void PrintReportWarnings(const nlohmann::json& report, const std::string& except = "");

}  // namespace al::cli
