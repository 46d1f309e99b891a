// Every subcommand writes a machine-readable report.json (SPEC §1) with at least:
// status, command, params, inputs, counts, timings_s, warnings.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "al/core/input_file.hpp"

namespace al {

// A report skeleton for `command` (e.g. "refine"), status "ok".
nlohmann::json NewReport(const std::string& command);

// Records an input file under report["inputs"][role]: path, size in bytes and, for files up to
// 64 MiB, its SHA-256.
void AddInputFile(nlohmann::json& report, const std::string& role, const std::filesystem::path& path);

// Writes report.json into dir atomically (pretty-printed).
void WriteReport(const std::filesystem::path& dir, const nlohmann::json& report,
                 const std::string& file_name = "report.json");

// Hex SHA-256 of a regular file's bytes (of its first max_bytes bytes when given); a FIFO or a
// device is refused (al::Error) before a byte is read, and so is a link with Links::kRefuse.
std::string Sha256File(const std::filesystem::path& path, std::uintmax_t max_bytes = UINTMAX_MAX,
                       Links links = Links::kFollow);

// Peak resident set size of this process so far, in MiB (0 if the OS does not say).
// WriteReport stamps it into every report as "peak_rss_mib".
double PeakRssMiB();

}  // namespace al
