// results.jsonl reading (tolerant of a killed writer), canonical record order and results.csv
// (al/refine/sweep.hpp).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>

#include "al/core/error.hpp"
#include "al/core/input_file.hpp"
#include "al/refine/sweep.hpp"

namespace al {
namespace {

// CSV columns: header and JSON pointer into a record.
struct Column {
  const char* header;
  const char* pointer;
};

constexpr Column kColumns[] = {
    {"id", "/id"},
    {"scene", "/scene"},
    {"k", "/params/k"},
    {"delta", "/params/delta"},
    {"hops", "/params/hops"},
    {"radius_scale", "/params/radius_scale"},
    {"lambda", "/params/lambda"},
    {"solver", "/params/solver"},
    {"threshold", "/params/threshold"},
    {"segment_share", "/params/segment_share"},
    {"status", "/status"},
    {"nodes", "/graph/nodes"},
    {"edges", "/graph/edges"},
    {"edges_knn", "/graph/edges_knn"},
    {"components", "/graph/components"},
    {"isolated", "/graph/isolated"},
    {"objective", "/solver/objective"},
    {"iterations", "/solver/iterations"},
    {"converged", "/solver/converged"},
    {"removed_input", "/counts/removed_input"},
    {"added", "/counts/added"},
    {"restored", "/counts/restored"},
    {"refined", "/counts/refined"},
    {"precision_before", "/gt/before/precision"},
    {"recall_before", "/gt/before/recall"},
    {"f1_before", "/gt/before/f1"},
    {"iou_before", "/gt/before/iou"},
    {"precision_after", "/gt/after/precision"},
    {"recall_after", "/gt/after/recall"},
    {"f1_after", "/gt/after/f1"},
    {"iou_after", "/gt/after/iou"},
    {"f1_w_after", "/gt/after/f1_w"},
    {"iou_w_after", "/gt/after/iou_w"},
    {"eval_acc_delta_depth", "/eval/acc_delta_depth"},
    {"eval_acc_delta_depth_float", "/eval/acc_delta_depth_float"},
    {"eval_collateral_depth", "/eval/collateral_depth"},
    {"eval_collateral_psnr", "/eval/collateral_psnr"},
    {"seconds_graph", "/seconds/graph"},
    {"seconds_solve", "/seconds/solve"},
    {"seconds_point", "/seconds/point"},
};

std::string CsvCell(const nlohmann::json& v) {
  if (v.is_null()) return "";
  std::string s = v.is_string() ? v.get<std::string>() : v.dump();
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += (c == '"') ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

nlohmann::json At(const nlohmann::json& j, const char* pointer) {
  const nlohmann::json::json_pointer p(pointer);
  return j.contains(p) ? j.at(p) : nlohmann::json();
}

}  // namespace

JsonlContents ReadResultsJsonl(const std::string& path, Links links) {
  std::error_code ec;
  if (!std::filesystem::exists(std::filesystem::symlink_status(path, ec))) return {};
  return ParseResultsJsonl(ReadInputFile(path, std::uint64_t(1) << 31, links), path);  // a FIFO is refused
}

JsonlContents ParseResultsJsonl(const std::string& text, const std::string& path) {
  JsonlContents out;
  std::size_t pos = 0, line_no = 0;
  while (pos < text.size()) {
    ++line_no;
    const std::size_t nl = text.find('\n', pos);
    const bool complete = nl != std::string::npos;
    const std::string line = text.substr(pos, (complete ? nl : text.size()) - pos);
    nlohmann::json record;
    bool parsed = false;
    try {
      record = nlohmann::json::parse(line);
      parsed = record.is_object() && record.contains("id") && record["id"].is_string();
    } catch (const std::exception&) {
      parsed = false;
    }
    if (!complete) {
      // The writer appends "<json>\n" and flushes; no newline means it was killed mid-line.
      if (parsed) {
        out.records.push_back(std::move(record));
        out.good_bytes = text.size();
      } else {
        out.truncated_tail = true;
      }
      break;
    }
    if (!parsed && !line.empty())
      throw FileError(path, "line " + std::to_string(line_no) +
                                " is not a sweep record (only a truncated last line is tolerated)");
    if (parsed) out.records.push_back(std::move(record));
    pos = nl + 1;
    out.good_bytes = pos;
  }
  return out;
}

void SortRecords(std::vector<nlohmann::json>& records) {
  auto key = [](const nlohmann::json& r) {
    const nlohmann::json& p = r.contains("params") ? r["params"] : nlohmann::json::object();
    return std::make_tuple(r.value("scene", std::string()), p.value("k", 0), p.value("delta", 0.0),
                           p.value("hops", 0), p.value("radius_scale", 0.0), p.value("lambda", 0.0),
                           p.value("solver", std::string()), p.value("threshold", std::string()),
                           p.value("segment_share", 0.0),
                           r.value("id", std::string()));
  };
  std::stable_sort(records.begin(), records.end(),
                   [&](const nlohmann::json& a, const nlohmann::json& b) { return key(a) < key(b); });
}

nlohmann::json RecordWithoutTimings(const nlohmann::json& record) {
  nlohmann::json r = record;
  r.erase("seconds");
  r.erase("run");
  return r;
}

std::string ResultsCsv(const std::vector<nlohmann::json>& records) {
  std::string out;
  // Appended piecewise: `"," + std::string` trips GCC 12's -Wrestrict false positive.
  for (std::size_t c = 0; c < std::size(kColumns); ++c) {
    if (c) out += ',';
    out += kColumns[c].header;
  }
  out += "\n";
  for (const auto& r : records) {
    for (std::size_t c = 0; c < std::size(kColumns); ++c) {
      if (c) out += ',';
      out += CsvCell(At(r, kColumns[c].pointer));
    }
    out += "\n";
  }
  return out;
}

}  // namespace al
