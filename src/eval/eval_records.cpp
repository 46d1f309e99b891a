// Flat records of an evaluation (al/eval/records.hpp).
#include "al/eval/records.hpp"

#include <cstdlib>
#include <sstream>

namespace al::eval {
namespace {

using json = nlohmann::json;

// One CSV line split into fields (RFC 4180 quotes, as CsvField writes them).
std::vector<std::string> SplitCsvLine(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') fields.back() += '"', ++i;
      else if (c == '"') quoted = false;
      else fields.back() += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

// A cell as JSON: empty → null, a full number → number, anything else the text.
json Cell(const std::string& text) {
  if (text.empty()) return nullptr;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end == text.c_str() + text.size()) return v;
  return text;
}

}  // namespace

void FlattenScalars(const json& value, const std::string& prefix, json& out) {
  if (value.is_object()) {
    for (const auto& [key, item] : value.items()) FlattenScalars(item, prefix.empty() ? key : prefix + "." + key, out);
  } else if (!value.is_array() && !prefix.empty()) {
    out[prefix] = value;
  }
}

json ColumnRecords(const json& report) {
  json records = json::array();
  if (!report.contains("metrics") || !report["metrics"].contains("columns")) return records;
  for (const json& column : report["metrics"]["columns"]) {
    json flat = json::object();
    FlattenScalars(column, "", flat);
    records.push_back(std::move(flat));
  }
  return records;
}

json ViewRecords(const std::vector<EvalColumn>& columns, const EvalResult& result) {
  std::istringstream csv(MetricsCsv(columns, result));
  std::string line;
  std::getline(csv, line);
  const std::vector<std::string> header = SplitCsvLine(line);
  json records = json::array();
  while (std::getline(csv, line)) {
    if (line.empty()) continue;
    const std::vector<std::string> cells = SplitCsvLine(line);
    json record = json::object();
    for (std::size_t i = 0; i < header.size(); ++i) record[header[i]] = i < cells.size() ? Cell(cells[i]) : json();
    record["view"] = cells.empty() ? "" : cells[0];  // a view name is text even when it reads as a number
    records.push_back(std::move(record));
  }
  return records;
}

}  // namespace al::eval
